// The whole generator as one call: load -> repair -> orient and place -> sample overhangs ->
// grow the tree -> size struts -> bodies, plus the columns baseline for the same samples.
// Nothing is written here; output/ writes what this computes.
#pragma once

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "ceilings/hybrid.hpp"
#include "core/geometry.hpp"
#include "core/params.hpp"
#include "job/job.hpp"
#include "job/result.hpp"

namespace cs {

class ModelQuery;

// Throws InputError for unusable input and ParameterError for bad parameters.
// `progress` (may be empty) is told each stage's name as it starts.
Result run_job(const Job& job, const std::function<void(const std::string&)>& progress = {});

// The names run_job tells `progress`, in order, for this job (the progress line counts them).
// Example: job_stages(job).size() is 10 with the self-intersection count, 9 without.
std::vector<std::string> job_stages(const Job& job);

// Builds supports for an already placed model (used by run_job and orientation scoring).
Supports build_supports(const Mesh& placed, const std::vector<Sample>& samples, const Params& p);
// The same, with an index of the placed model already built; struts in `omit` (indices into the
// grown tree) are pruned with their branches before sizing.
Supports build_supports(const ModelQuery& placed, const std::vector<Sample>& samples, const Params& p,
                        const std::vector<int>& omit = {});
// The tree grown each way of GrowOptions (tree.hpp: plainly, leaning merging leaves, pairing
// leaves first), keeping the one estimate_slicer_cost finds cheapest for PrusaSlicer (its
// prusa_seconds: tree/slicer_cost.hpp says why that route's price), but never one
// that gives up more samples than the plain growth (on a tie, the earlier way). Each way is a
// greedy choice that helps some models and costs others; the estimate picked PrusaSlicer's faster
// tree on 9 of 9 models between the first two ways. The columns baseline is grown once (no merges).
// Returned sized (size_struts, struts/struts.hpp), as it was sized to be priced: each tree is sized
// once. Its tree carries the estimate (SupportTree::slicer_cost) for the strategy tree.
// Example: Supports s = finish_supports(grow_cheaper_tree(q, samples, p), p);
SizedTree grow_cheaper_tree(const ModelQuery& placed, const std::vector<Sample>& samples, const Params& p);
// The same from the leaves hang_leaves (tree.hpp) hung for the samples, none entering the user's
// support blockers (placed-model coordinates).
SizedTree grow_cheaper_tree(const ModelQuery& placed, const SupportTree& hung, const Params& p,
                            const std::vector<Box3>& support_blockers = {});
// What ceilings/ weighs walls against: the tree grown_cheaper_tree grows from some samples alone
// (leaves hung clear of the support blockers), counted as estimate_slicer_cost counts it. It
// keeps a reference to `placed` and copies of the rest.
TreeCounter tree_counter(const ModelQuery& placed, const Params& p, const std::vector<Box3>& support_blockers = {});
// The same with a tip under each of some feet (the hybrid's, ceilings/hybrid.hpp, tree/feet.hpp).
// It remembers its answers (its copies share them): asked again for the same samples and feet, bit
// for bit, it gives the same count without growing the tree again.
FeetTreeCounter feet_tree_counter(const ModelQuery& placed, const Params& p,
                                  const std::vector<Box3>& support_blockers = {});
// Supports from a grown tree (and the ceiling walls beside it): struts in `omit` (indices into
// `grown`) are pruned with their branches first, and the hybrid pieces on them (prune_pieces;
// Supports::grown_walls keeps them, as the .scad records them). A tree already sized
// (grow_cheaper_tree) is sized again only when struts are pruned; its estimate is kept unless
// struts are pruned.
Supports finish_supports(SupportTree grown, const Params& p, const std::vector<int>& omit = {},
                         std::vector<CeilingWall> walls = {});
Supports finish_supports(SizedTree grown, const Params& p, const std::vector<int>& omit = {},
                         std::vector<CeilingWall> walls = {});

// The tree without the struts in `omit` and everything that hangs from them (the struts above, up
// to the leaves), and without the pillars in `omit` (pillar i is index struts + i). Nodes keep
// their indices; those left without a strut become Dropped. Throws ParameterError for an index
// that is neither a strut nor a pillar of the tree.
SupportTree prune_struts(SupportTree tree, const std::vector<int>& omit);

// `walls` without the hybrid pieces an omission took out: a piece stands on the tip under the
// middle of its foot (ceilings/hybrid.hpp feet_of), and goes with that tip when `grown` carries it
// (tree/feet.hpp feet_carried, as near as a .scad's 4 decimals put it: `apply` prunes the walls a
// file records) and `pruned` (prune_struts of `grown`) no longer does. Every other wall
// stays: no tip stands under a wall on the bed or on the model. Without the rule the piece stays,
// resting on nothing (`check`: grounding fails).
// Example: the arches example, omit_struts [28] (strut 28 leaves the tip under piece 0): every wall
// but piece 0.
std::vector<CeilingWall> prune_pieces(std::vector<CeilingWall> walls, const SupportTree& grown, const SupportTree& pruned);

// The samples a user's edits leave: none over a blocker or whose tip would pass through one (a
// sample beside a blocker whose tip would only graze it is moved out, just clear of the box, onto
// the underside there), plus each support point on the model's underside near it. Throws ParameterError for a support
// point that is not near the model's underside. Sorted as sample_overhangs sorts.
std::vector<Sample> edited_samples(const ModelQuery& model, std::vector<Sample> samples, const ManualEdits& edits,
                                   const Params& p);

// The mesh of an input file; a .scad part is rendered by OpenSCAD first (with `defines`).
// Throws InputError with OpenSCAD's message when the part does not render.
// `contents` (when given) gets what a container input held (read_mesh).
Mesh load_input(const std::string& path, const std::vector<std::string>& defines, std::string* contents = nullptr);

// The placement as 13 numbers: scale, the rotation's rows, the translation. A user's edits are
// in the placed model's coordinates: a regrow compares these to know whether they still fit.
std::vector<double> pose_numbers(const Placement& placement);

}  // namespace cs

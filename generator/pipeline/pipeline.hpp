// The whole generator as one call: load -> repair -> orient and place -> sample overhangs ->
// grow the tree -> size struts -> bodies, plus the columns baseline for the same samples.
// Nothing is written here; output/ writes what this computes.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"
#include "ceilings/ceilings.hpp"
#include "core/sha256.hpp"
#include "mesh/repair.hpp"
#include "orient/orient.hpp"
#include "overhang/overhang.hpp"
#include "struts/struts.hpp"

namespace cs {

class ModelQuery;

// A user's edits to the supports: a generated .scad's [Manual edits] section, or --block and
// --support-point on the command line. Coordinates are the placed model's (as in <name>.model.stl).
struct ManualEdits {
    std::vector<Box3> blockers;        // no support solid inside; overhangs inside are not sampled
    std::vector<Vec3> support_points;  // extra points to support, on the model's underside
    std::vector<int> omit_struts;      // struts of the grown tree left out, with what hangs from them
    int highlight_strut = -1;          // shown in colour in the .scad; no effect on the supports

    bool empty() const { return blockers.empty() && support_points.empty() && omit_struts.empty(); }
};

struct Job {
    std::string input;           // mesh file, or an OpenSCAD part (.scad) rendered first
    std::string input_name;      // how the report and the .scad name the input (default: input)
    std::vector<std::string> defines;  // name=value for a .scad input (OpenSCAD -D)
    ManualEdits edits;
    double scale = 1;            // applied first
    std::optional<double> fit;   // then scale so the largest side is this (mm)
    std::string orient = "auto"; // auto | keep | RX,RY,RZ
    bool self_intersection_check = true;
    bool timings = true;          // stage times in the report (the only part that differs run to run)
    Params params;

    const std::string& shown_input() const { return input_name.empty() ? input : input_name; }
};

// What one strategy built for the placed model.
struct Supports {
    SizedTree sized;
    std::vector<Strut> grown_struts;  // before omit_struts pruned them: the numbering edits refer to
    std::vector<Body> bodies;
    std::vector<CeilingWall> walls;  // under ceilings low over the bed (ceilings/ceilings.hpp)
    Mesh mesh;                       // the bodies, then the walls
    double volume = 0;         // of the support solid, overlaps at joints counted once (solid_volume), mm^3
    double bodies_volume = 0;  // the bodies' volumes added up, overlaps counted twice, mm^3
                               // (both volumes add the walls' own, their joins' ends counted twice)
    double length = 0;  // total strut length (mm)
};

struct Stage {
    std::string name;
    double seconds;
};

struct Result {
    std::string name;          // input file name without folder and extension
    std::string input_sha256;
    Mesh model;                // placed on the bed
    RepairReport repair;
    std::size_t self_intersections = 0;  // pairs, counted up to a limit
    Placement placement;
    Orientation orientation;
    OverhangSamples samples;
    Supports supports;         // by params.strategy
    Supports columns;          // the baseline, same samples
    std::vector<Stage> stages;
    std::vector<std::string> warnings;
    std::size_t blocked_samples = 0;  // overhang samples left unsupported by a user's blockers
};

// Throws InputError for unusable input and ParameterError for bad parameters.
// `progress` (may be empty) is told each stage's name as it starts.
Result run_job(const Job& job, const std::function<void(const std::string&)>& progress = {});

// Builds supports for an already placed model (used by run_job and orientation scoring).
Supports build_supports(const Mesh& placed, const std::vector<Sample>& samples, const Params& p);
// The same, with an index of the placed model already built; struts in `omit` (indices into the
// grown tree) are pruned with their branches before sizing.
Supports build_supports(const ModelQuery& placed, const std::vector<Sample>& samples, const Params& p,
                        const std::vector<int>& omit = {});
// The tree grown each way of GrowOptions (tree.hpp: plainly, leaning merging leaves, pairing
// leaves first), keeping the one estimate_slicer_cost finds cheapest for a slicer, but never one
// that gives up more samples than the plain growth (on a tie, the earlier way). Each way is a
// greedy choice that helps some models and costs others; the estimate picked PrusaSlicer's faster
// tree on 9 of 9 models between the first two ways. The columns baseline is grown once (no merges).
SupportTree grow_cheaper_tree(const ModelQuery& placed, const std::vector<Sample>& samples, const Params& p);
// The same from the leaves hang_leaves (tree.hpp) hung for the samples.
SupportTree grow_cheaper_tree(const ModelQuery& placed, const SupportTree& hung, const Params& p);
// Sizes a grown tree into supports: struts in `omit` (indices into `grown`) are pruned with their
// branches first. `walls` (support_ceilings) join the supports as they are.
Supports finish_supports(SupportTree grown, const Params& p, const std::vector<int>& omit = {},
                         std::vector<CeilingWall> walls = {});

// The tree without the struts in `omit` and everything that hangs from them (the struts above, up
// to the leaves). Nodes keep their indices; those left without a strut become Dropped. Throws
// ParameterError for an index that is not a strut of the tree.
SupportTree prune_struts(SupportTree tree, const std::vector<int>& omit);

// The samples a user's edits leave: none inside a blocker or whose tip would pass through one,
// plus each support point on the model's underside near it. Throws ParameterError for a support
// point that is not near the model's underside. Sorted as sample_overhangs sorts.
std::vector<Sample> edited_samples(const ModelQuery& model, std::vector<Sample> samples, const ManualEdits& edits,
                                   const Params& p);

// The mesh of an input file; a .scad part is rendered by OpenSCAD first (with `defines`).
// Throws InputError with OpenSCAD's message when the part does not render.
Mesh load_input(const std::string& path, const std::vector<std::string>& defines);
bool is_scad_input(const std::string& path);

// The placement as 13 numbers: scale, the rotation's rows, the translation. A user's edits are
// in the placed model's coordinates: a regrow compares these to know whether they still fit.
std::vector<double> pose_numbers(const Placement& placement);

}  // namespace cs

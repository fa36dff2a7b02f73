// The support tree: greedy cone merging, top down (docs/algorithm.md section 3).
//
// Every overhang sample hangs a leaf node one tip below it. Sweeping from the highest active node
// down, each node ranks its candidates (fewest layers left as an island of its own, then
// shortest): a meeting point with another active node's cone (merge_point), or where a ray of its
// cone fan meets the model or the bed (collect_contacts).
// Each candidate strut is tried against the model with clearance (strut_is_clear); the first that
// passes wins. With `supports_on_model = false` the model is an obstacle only and nodes route down
// to the bed around it. The `columns` strategy is the same sweep without merges or slanted struts:
// plain vertical columns, the baseline every run reports against.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"
#include "core/rules.hpp"
#include "overhang/overhang.hpp"
#include "tree/candidates.hpp"
#include "tree/clearance.hpp"

namespace cs {

class ModelQuery;

enum class NodeKind {
    Leaf,          // below an overhang sample, carries a tip up to it
    Merge,         // where two cones meet
    Bend,          // on the way out of a tight spot or around the model
    Bed,           // on z = 0
    ModelContact,  // above a point of the model; a tip goes down to it
    Dropped,       // given up: no strut fits from here (counted in stats; nothing is built)
};

struct Node {
    Vec3 p;
    NodeKind kind = NodeKind::Leaf;
    Vec3 contact;  // Leaf: the overhang sample; ModelContact: the model point below
    Vec3 tip;      // Leaf: top of its tip, a z gap below the model (more under a slope)
    double room = INFINITY;  // Bed: horizontal room for a foot: to the model, or half way to the next foot
};

struct Strut {
    int top = -1, bottom = -1;  // node indices; top.z > bottom.z
};

// A support too short for a tree: the overhang hangs less than one tip above the bed or the model.
struct Pillar {
    Vec3 top;     // one gap below the overhang sample
    Vec3 bottom;  // on the bed, or one gap above the model
    bool on_model = false;
    Vec3 sample;  // the overhang sample it carries (the top may stand beside it, off a wall)
};

struct TreeStats {
    std::size_t merges = 0, bed_contacts = 0, model_contacts = 0, pillars = 0, touching = 0;
    std::size_t internal = 0;  // samples on faces with material right below (overlapping shells)
    std::size_t steps = 0;                // bends taken to get out of a tight spot
    std::size_t tight = 0;                // struts that touch the model's clearance zone (no air)
    std::size_t dropped = 0;              // samples given up: no tip keeps the gap, or no strut gets down
    std::size_t bridged = 0;              // under a slot too low for a pillar between its gaps: bridged
    std::size_t dropped_branches = 0;     // dead ends that lost a leaf (its leaves went down again alone)
    std::size_t undone = 0;               // joins taken back because the joined node had nowhere to go
};

// Ways to grow the same tree. Each is a greedy choice that helps some models and costs others;
// the pipeline grows the tree each way and keeps the one estimate_slicer_cost (tree/slicer_cost.hpp)
// finds cheaper.
struct GrowOptions {
    // Two leaves about to merge lean their tips towards each other first (as far as a tip may
    // slant), so they meet a layer or two below the tips. Locally always fewer islands; but the
    // merged node then sits higher and the sweep's later choices change. Over nine benchmark
    // models in PrusaSlicer: support time -7 to -21 % on five, +2 to +12 % on four.
    bool lean_merging_leaves = false;
    // Before the sweep, neighbouring leaves at one height pair up (nearest first) and lean their
    // tips towards each other, so the sweep finds each pair about to merge. Same nine models:
    // -2 to -23 % on six, +2 to +6 % on two.
    bool pair_leaves_first = false;
    // With pair_leaves_first: then neighbouring pairs, nearest first, lean all four tips towards
    // their middle, so the four feet stand within a strut of each other (one island in a slicer)
    // and meet layers sooner than two pairs 2.5 mm apart. Sliced (bench/handoff.py, against the
    // pairs alone): never slower on six flat-ceiling models, u_overhang -5 % Cura, -7 % PrusaSlicer;
    // but on others the pairs alone are faster, so both are grown.
    bool lean_quads = false;
};

// What a slicer spends printing a tree (estimate_slicer_cost, tree/slicer_cost.hpp): what it
// counts, and those counts priced for each route by core/slicer_time.hpp.
struct SlicerCost {
    double island_layers = 0;  // islands, summed over the layers
    double outline_mm = 0;     // outline drawn, summed over the layers
    double travel_mm = 0;      // travel between the islands of each layer, nearest island next
    double cura_seconds = 0;   // all three priced for CuraEngine from our support mesh (kCuraRoute)
    double prusa_seconds = 0;  // and for PrusaSlicer from our .prusa.3mf (kPrusaRoute)
    double seconds = 0;        // the mean of the two routes: a user prints with one or the other
    std::size_t most_islands = 0;  // islands in the busiest layer
};

struct SupportTree {
    std::vector<Node> nodes;
    std::vector<Strut> struts;
    std::vector<Pillar> pillars;
    std::vector<Vec3> no_pillar;  // samples too low for a tree that got no pillar (hang_leaves): none fits
                                  // (stats.dropped), or the slot is too low for one (stats.bridged)
    TreeStats stats;
    GrowOptions grown_with;  // how the sweep grew it
    // The estimate of the tree as size_struts sizes it, where the one who chose the tree computed it
    // (grow_cheaper_tree): finish_supports takes it instead of computing it again.
    std::optional<SlicerCost> slicer_cost;

    double total_length() const;
};

// touching_space and contact_tolerance: core/rules.hpp. merge_point and collect_contacts:
// tree/candidates.hpp. strut_is_clear: tree/clearance.hpp.

// Grows the support tree (or the columns baseline, by p.strategy) for the given samples. No tip,
// strut, foot or pillar enters one of the user's `support_blockers` (placed-model coordinates).
// The sweep (tree.cpp) grows it, keeping one record per node (tree/sweep_books.hpp);
// tree/candidates.hpp finds where a node may go, tree/clearance.hpp whether it fits,
// tree/tuning.hpp holds the search's constants. After the sweep, merges of two leaves rise to meet
// the leaves (their tips leaning towards each other), and merges below them follow
// (tree/raise_merges.cpp); the tree keeps its shape.
SupportTree grow_tree(const ModelQuery& model, const std::vector<Sample>& samples, const Params& p,
                      GrowOptions options = {}, const std::vector<Box3>& support_blockers = {});
// The same, from the leaves hang_leaves hung for these samples (same model and parameters): the
// leaves are placed once when a tree is grown several ways.
SupportTree grow_tree(const ModelQuery& model, SupportTree hung, const Params& p, GrowOptions options = {},
                      const std::vector<Box3>& support_blockers = {});

// The tree before it grows: each sample's leaf (its tip placed), pillar, or the reason it has
// neither (touching, bridged, dropped), exactly as grow_tree starts from them; no struts. What
// holds the overhang up is known from this alone, so the coverage top-up judges it without
// growing a tree it would grow again.
SupportTree hang_leaves(const ModelQuery& model, const std::vector<Sample>& samples, const Params& p,
                        const std::vector<Box3>& support_blockers = {});
// `hung` (from hang_leaves for some samples) with the leaves of `more` hung into it: the same tree
// as hang_leaves for all of them, node for node, at the cost of the new samples alone (the
// coverage top-up adds a few samples to thousands).
SupportTree hang_more_leaves(const ModelQuery& model, SupportTree hung, std::vector<Sample> more, const Params& p,
                             const std::vector<Box3>& support_blockers = {});

}  // namespace cs

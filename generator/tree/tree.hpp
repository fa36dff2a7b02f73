// The support tree: greedy cone merging, top down (docs/algorithm.md section 3).
//
// Every overhang sample hangs a leaf node one tip below it. Sweeping from the highest active node
// down, each node ranks its candidates (fewest layers left as an island of its own, then
// shortest): a meeting point with another active node's cone (merge_point), the first model point
// in its cone (first_hit_in_cone), or the bed straight below.
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
    Chain,         // a bend on the way out of a tight spot or around the model
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
// the pipeline grows the tree each way and keeps the one estimate_slicer_cost finds cheaper.
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
};

struct SupportTree {
    std::vector<Node> nodes;
    std::vector<Strut> struts;
    std::vector<Pillar> pillars;
    TreeStats stats;
    GrowOptions grown_with;  // how the sweep grew it

    double total_length() const;
};

// touching_space and contact_tolerance: core/rules.hpp. merge_point and first_hit_in_cone:
// tree/candidates.hpp. strut_is_clear: tree/clearance.hpp.

// What a slicer spends printing a tree as a support mesh (CuraEngine with one support wall and no
// infill, the route of shared/notes/slicer-handoff.md). On every layer each strut, tip and pillar
// crossing it is an island: the nozzle travels to it and draws its outline once. The tree's sweep
// ranks its candidates by the first term (the layers a node stays an island of its own).
struct SlicerCost {
    double island_layers = 0;  // islands, summed over the layers
    double outline_mm = 0;     // outline drawn, summed over the layers
    double travel_mm = 0;      // travel between the islands of each layer, nearest island next
    double seconds = 0;        // all three, priced by kTreeTuning (tree/tuning.hpp)
    std::size_t most_islands = 0;  // islands in the busiest layer
};

// `strut_width`: the mean width of each strut of `t` (parallel to t.struts).
SlicerCost estimate_slicer_cost(const SupportTree& t, const std::vector<double>& strut_width, const Params& p);

// Grows the support tree (or the columns baseline, by p.strategy) for the given samples.
// The sweep (tree.cpp) grows it, keeping one record per node (tree/sweep_books.hpp);
// tree/candidates.hpp finds where a node may go, tree/clearance.hpp whether it fits,
// tree/tuning.hpp holds the search's constants. After the sweep, merges of two leaves rise to meet
// the leaves (their tips leaning towards each other), and merges below them follow
// (tree/raise_merges.cpp); the tree keeps its shape.
SupportTree grow_tree(const ModelQuery& model, const std::vector<Sample>& samples, const Params& p,
                      GrowOptions options = {});
// The same, from the leaves hang_leaves hung for these samples (same model and parameters): the
// leaves are placed once when a tree is grown several ways.
SupportTree grow_tree(const ModelQuery& model, SupportTree hung, const Params& p, GrowOptions options = {});

// The tree before it grows: each sample's leaf (its tip placed), pillar, or the reason it has
// neither (touching, bridged, dropped), exactly as grow_tree starts from them; no struts. What
// holds the overhang up is known from this alone, so the coverage top-up judges it without
// growing a tree it would grow again.
SupportTree hang_leaves(const ModelQuery& model, const std::vector<Sample>& samples, const Params& p);

}  // namespace cs

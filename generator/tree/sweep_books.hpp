// The books the sweep (tree/tree.cpp) keeps on the tree it grows: one record per node, the struts
// as each node's one way down, and what the sweep and the passes around it (tree/lean_tips.cpp,
// tree/raise_merges.cpp) ask of them: how wide a strut from a node comes out, and whether it
// clears the model. Internal to tree/.
//
// A node's strut is its `down` link. Taking a join back (undo_joins, release_branches) clears that
// link, so no undone strut lingers to be skipped or erased later; the tree's struts are listed
// from the links when the sweep ends, in the order they were made.
#pragma once

#include <array>
#include <cmath>
#include <cstddef>
#include <optional>
#include <utility>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"
#include "core/rules.hpp"
#include "tree/candidates.hpp"
#include "tree/tree.hpp"

namespace cs {

class ModelQuery;

// What the sweep knows of one node besides the node itself (Node, in the tree).
struct SweepNode {
    double width = 0;      // estimated width at the node, for clearance
    bool active = false;   // waiting in the sweep for its way down
    int down = -1;         // the node its strut goes down to; -1: none (yet, or taken back)
    std::size_t made = 0;  // when that strut was made: the tree lists its struts in this order
    std::vector<int> up;   // the nodes whose struts end here, in the order they came
    double run = 0;        // bends: length of the unbranched run above them
    int retries = 0;       // how often the node was sent back by undo_joins
    std::vector<int> banned;         // nodes it may not join again
    bool alone = false;    // released from a dead end twice: merges with no one (its bends inherit it)
    // Released from a dead end once: it merges only within its pool (the leaves released from that
    // dead end and what they grow into; 0: every node never released) and only into nodes
    // thinner than width_cap (the dead end's width). Merges and bends inherit both.
    int pool = 0;
    double width_cap = INFINITY;
    std::vector<Vec3> failed_bends;  // bends below it that led to dead ends
};

class SweepBooks {
public:
    SweepBooks(const ModelQuery& model, const Params& p, const std::vector<Box3>& support_blockers);

    // A node, with its record: not active, no strut.
    int add_node(const Vec3& p, NodeKind kind, const Vec3& contact, double width);
    // A strut from `top` (which has none yet) down to `bottom`.
    void connect(int top, int bottom);
    // The struts the links make, in the order they were made: the tree's struts.
    std::vector<Strut> struts() const;

    // Widths a strut from node `from` to `to` will have at its ends (estimates for clearance, by
    // the struts stage's rules; a run of several struts may come out a little wider).
    EndWidths widths(int from, const Vec3& to) const;
    double top_width(int from, const Vec3& to) const { return widths(from, to).top; }
    double bottom_width(int from, const Vec3& to) const { return widths(from, to).bottom; }
    // Does a strut from node `from` to `to` clear the model (by `clearance`, default
    // model_clearance; `onto_model`: it lands on the model) and the user's blockers?
    bool clear(int from, const Vec3& to, double clearance = -1, bool onto_model = false) const;
    bool can_escape(const Vec3& a, double w) const;

    // Tips that lean (tree/lean_tips.cpp). How far a tip of this height may lean: 0.9 of the
    // critical angle, clear_tip_foot's limit.
    double max_tip_slant(double height) const;
    // Leaned tips keep their feet half a strut apart, so the merge below them is a real strut.
    double leaned_feet_apart() const;
    // How far the foot of leaf w may move along the horizontal unit `dir` with its tip's top
    // staying put: as far as the tip may slant from under its top (a tip already slanting, beside
    // a wall or under a slope, has less left one way and more the other).
    double lean_reach(int w, const Vec3& dir) const;
    // Two fresh leaves (nothing joined into them yet) lean their tips towards each other, each as
    // far as its tip may slant from its top (clear_tip_foot's limit; lean_reach) while their feet
    // stay half a strut apart: where the feet go, or nothing when neither can lean
    // (kTreeTuning.least_lean) or either tip would not clear the model there.
    std::optional<std::pair<Vec3, Vec3>> leaned_pair(int u, int v) const;
    // Four fresh leaves (two leaned pairs) lean their tips towards the middle of their four tips,
    // as far as a tip may slant, every two feet still half a strut apart: where the feet go, or
    // nothing when any tip would not clear the model there.
    std::optional<std::array<Vec3, 4>> leaned_quad(const std::array<int, 4>& leaves) const;

    const ModelQuery& model_;
    const Params& p_;
    const std::vector<Box3>& support_blockers_;  // the user's: no tip, strut, foot or pillar inside
    ConeFan fan_;
    SupportTree t_;  // its struts are filled from the links when the sweep ends (struts())
    std::vector<SweepNode> books_;  // parallel to t_.nodes

private:
    bool run_stays_clear(int from, const Vec3& to, double air) const;
    bool fresh_leaf(int w) const;
    // May the tip of leaf w lean so that its foot stands at `to` (within its slant, clear of the model)?
    bool tip_leans_to(int w, const Vec3& to) const;

    std::size_t struts_made_ = 0;
};

// GrowOptions::pair_leaves_first: neighbouring leaves at one height, nearest pairs first, lean
// their tips towards each other before the sweep starts (leaned_pair); with `quads`
// (GrowOptions::lean_quads) neighbouring pairs, nearest first, then lean all four tips towards their
// middle (leaned_quad). tree/lean_tips.cpp.
void lean_tips_in_pairs(SweepBooks& b, const std::vector<int>& leaves, bool quads);

// After the sweep: where two leaves merge, they lean their tips towards each other and the merge
// rises to meet them; a merge below a raised one rises too, to where the cones of its parents now
// meet. Under a flat ceiling each leaf's own strut down to its first merge is an island on every
// layer, and a slicer pays for each. The tree keeps its shape; a node stays where it was when
// anything would not fit. tree/raise_merges.cpp.
void raise_merges(SweepBooks& b);

}  // namespace cs

// Leaves under the feet of the hybrid's walls (ceilings/hybrid.hpp): a tip whose top is the foot
// (a wall's foot is fused to it, no air gap: the wall is support, not model), a tip length above
// its leaf. The hybrid checked that the tip keeps its air from the model (hybrid.cpp, tip_fits),
// so the leaf stands right under its foot.
//
// Example:
//   SupportTree leaves = hang_feet(hang_leaves(q, rest, p), hybrid.feet, p);
//   SupportTree t = grow_tree(q, leaves, p);
//   if (!feet_carried(t, hybrid.feet)) ...  // the tree lost a foot: drop that foot's piece
//   lost_feet(t, hybrid.feet)                 // which feet it lost
#pragma once

#include <vector>

#include "tree/tree.hpp"

namespace cs {

// `hung` (from hang_leaves) with a leaf under each foot, merged in hang_leaves' order (by the
// point each leaf holds, top down, then x, then y): the same leaves, whichever way they came.
SupportTree hang_feet(SupportTree hung, const std::vector<Vec3>& feet, const Params& p);

// Does the grown tree carry every foot: a leaf whose tip's top is the foot (within `within` mm:
// a .scad read back writes 4 decimals), with a strut below it?
bool feet_carried(const SupportTree& grown, const std::vector<Vec3>& feet, double within = 1e-9);

// The feet the grown tree does not carry, in the order given.
std::vector<Vec3> lost_feet(const SupportTree& grown, const std::vector<Vec3>& feet, double within = 1e-9);

}  // namespace cs

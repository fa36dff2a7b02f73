// What a slicer spends printing a tree. On every layer each strut, tip and pillar crossing it is
// an island: the nozzle travels to it and draws its outline once. The counts (island-layers,
// outline, travel) are priced for both routes the generator writes, CuraEngine from our support
// mesh and PrusaSlicer from our .prusa.3mf, by core/slicer_time.hpp's tree_route_seconds: the one
// price list, fitted to the slicers' G-code. `seconds`, the one number the summary gives, is the
// mean of the two (we do not know which slicer a user prints with).
//
// The chooser (grow_cheaper_tree) ranks the ways of growing a tree by the PrusaSlicer price alone.
// Where a price list changes the pick, the two ways' estimates differ by 0.02-2.5 %, below either
// route's error on one model, so only prices that hold their ranking may choose. PrusaSlicer's do: fitted again on the 11 tuning models
// (bench/results/tuning.json at 4eb6aa6) they move by less than a third, and its per-island price,
// the largest, is what trees with fewer islands save. Cura's do not: fitted again, its island
// price falls 0.058 -> 0.020 s and its outline price rises 0.0036 -> 0.0285 s/mm (its three terms
// grow together from tree to tree, so the fit cannot tell them apart). Ranked by the two routes'
// sum, Cura's 0.058 s per mm of hop picked trees with less travel on 5 tuning models, and Cura's
// G-code got 0-11 s slower on all 5 (README, "Which tree is kept"). The tree's sweep
// ranks its candidates by the first term (the layers a node stays an island of its own).
//
// Example:
//   const SizedTree sized = size_struts(tree, p);
//   SlicerCost c = estimate_slicer_cost(sized.tree, mean_strut_widths(sized), p);
//   // c.island_layers, c.most_islands, c.cura_seconds, c.prusa_seconds, c.seconds
#pragma once

#include <cstddef>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"
#include "tree/tree.hpp"

namespace cs {

// SlicerCost, the result, is a plain struct of tree/tree.hpp (a SupportTree carries the one its
// chooser computed).

// Input: the tree, the mean width of each strut of `t` (parallel to t.struts), the parameters
// (layer height, tip and strut widths). Output: the counts summed over the layers from the bed up,
// and their price per route.
// Near-linear: each piece of support is filed under the layers it spans (their count is the
// island-layers), and each layer's islands are ordered nearest-next on a grid.
SlicerCost estimate_slicer_cost(const SupportTree& t, const std::vector<double>& strut_width, const Params& p);

// Length of the path that starts at pts[0] and always goes on to the nearest point not yet
// visited (XY distance). Ties go where the plain O(n^2) walk sends them (to the point it holds
// earliest), so the path is the same as that walk's; found on a grid, about n log n for a layer's
// islands. Example: nearest_next_path({{0,0,0}, {3,0,0}, {1,0,0}}) == 3.
double nearest_next_path(const std::vector<Vec3>& pts);

}  // namespace cs

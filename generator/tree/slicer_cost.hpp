// What a slicer spends printing a tree as a support mesh (CuraEngine with one support wall and no
// infill, the route of shared/notes/slicer-handoff.md). On every layer each strut, tip and pillar
// crossing it is an island: the nozzle travels to it and draws its outline once. The tree's sweep
// ranks its candidates by the first term (the layers a node stays an island of its own).
//
// Example:
//   const SizedTree sized = size_struts(tree, p);
//   SlicerCost c = estimate_slicer_cost(sized.tree, mean_strut_widths(sized), p);
//   // c.island_layers, c.most_islands, c.seconds
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
// (layer height, tip and strut widths). Output: the cost summed over the layers from the bed up.
// Near-linear: each piece of support is filed under the layers it spans (their count is the
// island-layers), and each layer's islands are ordered nearest-next on a grid.
SlicerCost estimate_slicer_cost(const SupportTree& t, const std::vector<double>& strut_width, const Params& p);

// Length of the path that starts at pts[0] and always goes on to the nearest point not yet
// visited (XY distance). Ties go where the plain O(n^2) walk sends them (to the point it holds
// earliest), so the path is the same as that walk's; found on a grid, about n log n for a layer's
// islands. Example: nearest_next_path({{0,0,0}, {3,0,0}, {1,0,0}}) == 3.
double nearest_next_path(const std::vector<Vec3>& pts);

}  // namespace cs

// Unfolding sliver triangles that fold back over their neighbour: a defect of scanned meshes.
//
// A cap is a triangle whose apex lies almost on its opposite edge (an angle near 180 degrees
// there). When its apex sits on the wrong side of that edge, the cap faces against the triangle
// across the edge: the surface folds back on itself over a sliver. nefertiti has one of
// 0.0045 mm^2 in the near-vertical wall behind the headdress; the fold's edge is a hanging keel
// by any overhang test (two downward faces rising away from it), under which no tip fits.
//
// unfold_caps flips the cap's long edge: the cap (a, b, c) and the triangle across (b, a, d)
// become (c, a, d) and (d, b, c), which face the way the triangle across did. It does so only
// when the two faces lie folded back on each other (normals more than 120 degrees apart),
// both new triangles face within 60 degrees of the triangle across, and the edge c-d is not in
// the mesh already: the surface moves by the fold's thickness, the solid stays closed and
// edge-manifold. A sliver along a sharp edge of the shape (a CAD box's 90-degree edge) is not a
// fold and is left alone: flipping it would chamfer the edge.
//
// Input: `m` with consistently oriented faces (repair_mesh's orientation step).
// Output: the number of caps unfolded; `m` changed in place (no vertex added or moved).
//
// Example:
//   Mesh cube = ...;             // its top's diagonal with a folded cap beside it
//   size_t n = unfold_caps(cube);  // n == 1; every top face faces up again
#pragma once

#include <cstddef>

#include "core/geometry.hpp"

namespace cs {

size_t unfold_caps(Mesh& m);

}  // namespace cs

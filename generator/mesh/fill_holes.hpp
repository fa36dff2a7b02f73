// Closing the holes of an oriented mesh, so that the generator and the slicers agree on what is solid.
//
// A scanned model often has holes in its base (stanford_bunny: 5 loops, 223 open edges). A slicer
// closes every open outline of a layer and prints the inside solid; our generator, which reads the
// surfaces as they are, saw the inner side of the base through the holes and grew ~100 struts there,
// inside what the slicer prints as model. Filling the holes gives both the same solid.
//
// fill_holes finds each boundary loop (edges used by one face), triangulates it with CGAL's hole
// filling (a 2D constrained Delaunay triangulation for a near-planar loop, else a 3D Delaunay search;
// never the cubic fallback, so a huge loop cannot stall a run), and appends the patch facing the way
// its neighbours face. A loop that passes through the same vertex twice, that CGAL cannot
// triangulate, or whose patch would reuse an edge the mesh has, is left open and counted.
//
// Input: `m` with consistently oriented faces (repair_mesh's orientation step).
// Output: `m` with patch faces appended (vertices are not added); the counts below.
//
// Example:
//   Mesh box = ...;                    // a cube missing its top two triangles
//   HoleFilling h = fill_holes(box);   // h.filled == 1, h.edges_left_open == 0; box is closed again
#pragma once

#include <cstddef>

#include "core/geometry.hpp"

namespace cs {

struct HoleFilling {
    size_t filled = 0;           // loops closed
    size_t edges_closed = 0;     // open edges those loops had
    size_t edges_left_open = 0;  // open edges of loops left as they were
    size_t patch_faces = 0;      // triangles added
};

HoleFilling fill_holes(Mesh& m);

}  // namespace cs

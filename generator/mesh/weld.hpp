// Identical vertices as one vertex: the first step of repairing a mesh (mesh/repair.hpp), of
// telling a support mesh's solids apart (check/), and of writing an indexed 3MF mesh (output/).
// Only exactly equal coordinates weld (-0 and +0 are equal); nothing near is snapped, no face
// is dropped or added.
#pragma once

#include <cstdint>
#include <vector>

#include "core/geometry.hpp"

namespace cs {

struct Welded {
    Mesh mesh;                         // the distinct vertices in order of first appearance; the
                                       // faces renumbered (degenerate ones kept)
    std::vector<std::uint32_t> remap;  // each input vertex -> its vertex in `mesh`
};

// Finite coordinates only (the mesh readers refuse others). Found by sorting rather than a hash
// map: a 5M-triangle scan stays within a few hundred megabytes.
// Example: a cube as STL (36 corners, 12 faces) welds to 8 vertices and the same 12 faces.
Welded weld_vertices(const Mesh& m);

}  // namespace cs

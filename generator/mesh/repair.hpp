// Making a raw triangle soup into a mesh the pipeline can trust, and putting it on the bed.
//
// repair_mesh welds identical vertices, drops degenerate and duplicate triangles, orients every
// shell consistently and outward (a shell wholly inside another follows its container: facing
// against it, it is a cavity and kept; facing like it, a solid inside a solid, and dropped), closes
// holes (fill_holes.hpp), unfolds sliver triangles folded back over a neighbour (unfold_caps.hpp),
// and counts what it cannot fix (holes it could not close, non-manifold
// edges). Every change is reported as a warning; only a mesh with nothing printable left is an
// InputError.
#pragma once

#include <string>
#include <vector>

#include "core/geometry.hpp"

namespace cs {

struct RepairReport {
    size_t input_triangles = 0;
    size_t welded_vertices = 0;       // vertices merged into an identical one
    size_t degenerate_removed = 0;    // zero-area or repeated-index triangles
    size_t duplicates_removed = 0;    // the same triangle twice
    size_t flipped = 0;               // triangles turned to face outward
    size_t boundary_edges = 0;        // edges of holes, as found
    size_t holes_filled = 0;          // holes closed with a patch (fill_holes)
    size_t boundary_edges_left = 0;   // edges of holes that could not be closed
    size_t caps_unfolded = 0;         // sliver triangles folded back over a neighbour, flipped flat (unfold_caps)
    size_t nonmanifold_edges = 0;     // edges shared by more than two triangles
    size_t inner_shells_removed = 0;  // solids wholly inside another solid
    size_t shells = 0;
    std::vector<std::string> warnings;
};

// Throws InputError (naming `name`) when no triangle survives or the mesh encloses no volume.
Mesh repair_mesh(const Mesh& raw, const std::string& name, RepairReport& report);

// Connected components by shared vertices; returns a component id per face and the count.
std::vector<int> face_components(const Mesh& m, int& count);

// How the mesh was put on the bed: p_placed = R * (scale * p_input) + translation.
struct Placement {
    double scale = 1;
    double rotation[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Vec3 translation;
};

// Rotation matrix for Euler angles in degrees, applied X then Y then Z (as OpenSCAD's rotate([x,y,z])).
void rotation_from_euler_deg(double rx, double ry, double rz, double out[3][3]);
// The inverse: angles {x, y, z} in degrees (-180..180; y in -90..90) with
// rotation_from_euler_deg(x, y, z) == r. Where y is +-90 degrees, x is 0.
Vec3 euler_deg_from_rotation(const double r[3][3]);

// Applies scale and rotation, then translates so min z = 0 and the XY bounding box is centred at
// the origin. Fills `placement` with what was applied.
Mesh place_on_bed(const Mesh& m, double scale, const double rotation[3][3], Placement& placement);

}  // namespace cs

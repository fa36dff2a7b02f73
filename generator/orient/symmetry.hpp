// Whether a rotation maps a model onto itself: one of the model's own symmetries.
//
// The orientation search uses it to find candidate poses that are the same print: pose B is pose A
// turned about the vertical when some turn T makes B^T T A map the model onto itself. The bed does
// not care which way a part faces; only the sampling lattice, which is fixed to the axes, falls
// differently on the two (a cube's faces down: coarse trees up to 6 % apart).
#pragma once

#include "core/geometry.hpp"
#include "orient/orient.hpp"
#include "query/model_query.hpp"

namespace cs {

// The centre of the surface: its triangles' centroids weighted by area. Any symmetry of the surface
// keeps it in place, however the surface is split into triangles.
Vec3 surface_centroid(const Mesh& mesh);

// True when `q`, turning about `centroid` (surface_centroid of the indexed mesh), takes every vertex
// and every triangle's centroid of the model to within `tolerance` (mm) of its surface. The surface
// is compared, not the triangle lists: a symmetric part's triangulation need not be symmetric (a
// CSG export splits faces along one diagonal, or adds vertices along the edges on one side only),
// and the print does not see it. A turned copy lying on a closed surface of the same area is that
// surface. False at the first point off it: a part without the symmetry costs a few questions.
//
// Example: a cube is mapped onto itself by a quarter turn about any axis:
//   const ModelQuery q(cube);
//   maps_onto_itself(q, surface_centroid(cube), turn_about_z(90), 1e-6);  // true
bool maps_onto_itself(const ModelQuery& surface, const Vec3& centroid, const Rotation& q, double tolerance);

// a * b.
Rotation compose(const Rotation& a, const Rotation& b);

// The transpose (the inverse of a rotation).
Rotation transposed(const Rotation& r);

// A turn by `degrees` about the vertical (z) axis; exact for multiples of 90.
Rotation turn_about_z(int degrees);

}  // namespace cs

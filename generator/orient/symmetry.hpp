// Whether a rotation maps a model onto itself: one of the model's own symmetries.
//
// The orientation search uses it to find candidate poses that are the same print: pose B is pose A
// turned about the vertical when some turn T makes B^T T A map the model onto itself. The bed does
// not care which way a part faces; only the sampling lattice, which is fixed to the axes, falls
// differently on the two (a cube's faces down: coarse trees up to 6 % apart).
#pragma once

#include <memory>

#include "core/geometry.hpp"
#include "orient/orient.hpp"

namespace cs {

// A model's surface, indexed once for the question whether a rotation maps it onto itself.
class SurfaceSymmetry {
public:
    // `mesh` must outlive this. `tolerance`: how far (mm) a turned point may lie from the surface.
    SurfaceSymmetry(const Mesh& mesh, double tolerance);
    ~SurfaceSymmetry();
    SurfaceSymmetry(const SurfaceSymmetry&) = delete;
    SurfaceSymmetry& operator=(const SurfaceSymmetry&) = delete;

    // True when `q`, turning about the surface's centroid (its triangles' centroids weighted by
    // area: any symmetry keeps it in place, however the surface is split into triangles), takes
    // every vertex and every triangle's centroid of the model to within the tolerance of its
    // surface. The surface is compared, not the triangle lists: a symmetric part's triangulation
    // need not be symmetric (a CSG export splits faces along one diagonal, or adds vertices along
    // the edges on one side only), and the print does not see it. False at the first point off
    // it: a part without the symmetry costs a few questions.
    //
    // Example: a cube is mapped onto itself by a quarter turn about any axis:
    //   SurfaceSymmetry(cube, 1e-6).maps_onto_itself(turn_about_z(90));  // true
    bool maps_onto_itself(const Rotation& q) const;

private:
    struct Index;
    std::unique_ptr<const Index> index_;
};

// a * b.
Rotation compose(const Rotation& a, const Rotation& b);

// The transpose (the inverse of a rotation).
Rotation transposed(const Rotation& r);

// A turn by `degrees` about the vertical (z) axis; exact for multiples of 90.
Rotation turn_about_z(int degrees);

}  // namespace cs

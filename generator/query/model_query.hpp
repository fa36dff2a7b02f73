// Geometric questions about the placed model, answered by a CGAL AABB tree.
//
// This is one of the two translation units that include CGAL (the other is orient/hull.cpp):
// CGAL headers compile slowly, so every other stage talks to the model through this class.
#pragma once

#include <cstddef>
#include <memory>
#include <optional>

#include "core/geometry.hpp"

namespace cs {

struct RayHit {
    Vec3 point;
    double distance = 0;
    std::size_t face = 0;
};

class ModelQuery {
public:
    explicit ModelQuery(const Mesh& model);
    ~ModelQuery();
    ModelQuery(const ModelQuery&) = delete;
    ModelQuery& operator=(const ModelQuery&) = delete;

    // Nearest intersection of the ray origin + t * dir (t > 0, dir need not be unit).
    std::optional<RayHit> first_hit(const Vec3& origin, const Vec3& dir) const;
    // Does the closed segment a-b touch the model?
    bool segment_hits(const Vec3& a, const Vec3& b) const;
    // Does the triangle abc touch the model's surface?
    bool triangle_hits(const Vec3& a, const Vec3& b, const Vec3& c) const;
    double squared_distance(const Vec3& p) const;
    Vec3 closest_point(const Vec3& p) const;
    // Inside the solid, by the majority of three rays' winding numbers (sound for closed meshes,
    // overlapping shells included; a fair guess for meshes with small holes).
    bool inside(const Vec3& p) const;

    const Mesh& mesh() const { return model_; }

private:
    struct Impl;
    const Mesh& model_;
    std::unique_ptr<Impl> impl_;
};

// Number of pairs of triangles that intersect (not counting neighbours sharing a vertex or edge),
// stopping at `limit`.
std::size_t count_self_intersections(const Mesh& mesh, std::size_t limit);

}  // namespace cs

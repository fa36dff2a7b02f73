// Geometric questions about the placed model, answered by a CGAL AABB tree.
//
// This is one of the two translation units that include CGAL (the other is orient/hull.cpp):
// CGAL headers compile slowly, so every other stage talks to the model through this class.
#pragma once

#include <array>
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
    // The indexed model moved rigidly: `moved` is `indexed.mesh()` with every vertex v taken to
    // rotation * v + translation (a proper rotation, as place_on_bed does). It shares `indexed`'s
    // index, which must outlive it: each question is moved into the indexed frame and its answer
    // back, so answers agree with an index of `moved` itself up to rounding (a grazing question may
    // go either way). Building an index takes about as long as a tree grows on a big scan; the
    // orientation search judges each candidate pose this way from one index.
    // Example: ModelQuery base(scaled); ModelQuery q(placed, base, R, t); q.inside(p);
    ModelQuery(const Mesh& moved, const ModelQuery& indexed, const double rotation[3][3], const Vec3& translation);
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

    // A verdict a caller decides from this model's answers alone, remembered like the model's own
    // answers by the question's exact bits: `question` holds everything besides the model that the
    // verdict depends on, its first value telling the callers' kinds of question apart (the tree's:
    // tree/verdicts.hpp, which says why they are asked again). `decide` runs only for a question not
    // asked before; should two threads race on one, both get the answer kept first.
    using Question = std::array<double, 12>;
    template <typename Decide>
    bool verdict(const Question& question, Decide&& decide) const {
        if (const std::optional<bool> known = known_verdict(question)) return *known;
        return keep_verdict(question, decide());
    }

    const Mesh& mesh() const { return model_; }

private:
    struct Impl;
    // Where this model stands relative to the indexed one: placed = r * indexed + t.
    struct Frame {
        double r[3][3];
        Vec3 t;
        Vec3 to_index(const Vec3& p) const;   // r^T (p - t)
        Vec3 from_index(const Vec3& q) const;  // r q + t
        Vec3 dir_to_index(const Vec3& d) const;  // r^T d
    };
    // Answers already given, by the question's exact bits: the tree is grown three ways from the
    // same leaves, and the ways ask many of the same questions (a third to a half of them on the
    // benchmark models). Guarded by a mutex, so a query may be shared between threads.
    struct Memo;
    const Mesh& model_;
    std::shared_ptr<const Impl> impl_;
    std::unique_ptr<Memo> memo_;
    std::optional<Frame> frame_;  // none: the index is of model_ itself
    Vec3 in_index(const Vec3& p) const { return frame_ ? frame_->to_index(p) : p; }
    Vec3 out_of_index(const Vec3& q) const { return frame_ ? frame_->from_index(q) : q; }
    std::optional<RayHit> first_hit_in_index(const Vec3& origin, const Vec3& dir) const;
    std::optional<bool> known_verdict(const Question& question) const;
    bool keep_verdict(const Question& question, bool answer) const;
    std::optional<RayHit> first_hit_uncached(const Vec3& origin, const Vec3& dir) const;
    bool inside_uncached(const Vec3& p) const;
};

// The share of `mesh`'s faces (0 to 1) that lie along its axes: faces whose normal's coordinate
// across some axis is at most kAlongAxis of the normal's length (walls, floors and ceilings of a
// CAD part). A question asked of a moved index (the constructor above) is turned, and turning
// rounds: where faces lie along the axes, questions graze them (a vertical ray along a wall), and
// such a question may be answered the other way than by an index of the moved mesh itself.
// Example: share_along_axes(box) == 1; the same box turned by 30 degrees about x and y: 0.
double share_along_axes(const Mesh& mesh);

// A CAD face meant to be vertical or flat is within 1e-15 of it after turning; a scan's face comes
// this near with odds of a few in a billion.
constexpr double kAlongAxis = 1e-9;

// Number of pairs of triangles that intersect (not counting neighbours sharing a vertex or edge),
// stopping at `limit`.
std::size_t count_self_intersections(const Mesh& mesh, std::size_t limit);

}  // namespace cs

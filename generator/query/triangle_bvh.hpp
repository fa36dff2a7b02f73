// A bounding-volume hierarchy over a mesh's triangles that only narrows a question down to the
// triangles that may touch it; the caller decides each one exactly (ModelQuery does so with CGAL's
// own predicates, so its answers stay those of CGAL's AABB tree while far fewer triangles and boxes
// are visited: the tree's questions were most of a big model's generation time).
//
// Conservative by construction: every box is widened by a relative 1e-9 beyond its triangles, far
// more than the rounding of the box tests here, so a triangle that touches a segment or ray is
// always offered (a few that miss by a hair are offered too, and rejected by the exact test).
// Immutable once built: one BVH may be searched from many threads at once.
//
// Example:
//   TriangleBvh bvh(mesh);
//   bool hit = false;
//   bvh.along_segment(a, b, [&](std::uint32_t face) { return hit = exact_test(face, a, b); });
// (visit returns true to stop the search.)
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/geometry.hpp"

namespace cs {

class TriangleBvh {
public:
    explicit TriangleBvh(const Mesh& mesh);

    // Calls visit(face) for every face whose box the closed segment a-b may touch, until visit
    // returns true (stop). Returns whether it was stopped.
    template <typename Visit>
    bool along_segment(const Vec3& a, const Vec3& b, Visit&& visit) const;

    // The same for the ray origin + s * dir (s >= 0), and for the whole line (any s).
    template <typename Visit>
    bool along_ray(const Vec3& origin, const Vec3& dir, Visit&& visit) const {
        return along(origin, dir, 0, INFINITY, visit);
    }
    template <typename Visit>
    bool along_line(const Vec3& origin, const Vec3& dir, Visit&& visit) const {
        return along(origin, dir, -INFINITY, INFINITY, visit);
    }

    // The same for the vertical line through (x, y): what along_line offers a line straight up or
    // down there (its box tests then ask x and y alone), in the same order, at any height.
    template <typename Visit>
    bool along_vertical(double x, double y, Visit&& visit) const;

    // Calls visit(face) for every face whose box lies within squared distance bound() of p, nearer
    // boxes first; bound() is asked again as the search goes, so the caller narrows it.
    template <typename Visit, typename Bound>
    void near_point(const Vec3& p, Visit&& visit, Bound&& bound) const;

    std::size_t size() const { return faces_.size(); }

private:
    struct Box {
        double lo[3], hi[3];
    };
    struct Node {
        Box box;
        std::uint32_t first = 0;  // inner node: index of the second child (the first is next); leaf: first slot
        std::uint32_t count = 0;  // 0: inner node; else the leaf's faces_[first, first + count)
    };
    std::vector<Node> nodes_;
    std::vector<std::uint32_t> faces_;  // face ids in leaf order
    std::vector<Box> boxes_;            // each slot's face box (widened), in leaf order

    // Parameter interval [t0, t1] of origin + t * dir inside the box, clipped to [lo, hi]; false if empty.
    template <typename Visit>
    bool along(const Vec3& o, const Vec3& d, double from, double to, Visit& visit) const;
    // Depth first (a node's first child, the node after it, before its second) through the nodes
    // whose boxes `holds` lets through, visiting the faces whose own boxes it lets through: along
    // and along_vertical, whose callers' answers depend on that order.
    template <typename Holds, typename Visit>
    bool walk(Holds&& holds, Visit& visit) const;
    static double squared_gap(const Box& b, const Vec3& p);
    static bool clip(const Box& b, const Vec3& o, const Vec3& d, const Vec3& inv, double& lo, double& hi);
};

inline bool TriangleBvh::clip(const Box& b, const Vec3& o, const Vec3& d, const Vec3& inv, double& lo, double& hi) {
    const double oc[3] = {o.x, o.y, o.z}, dc[3] = {d.x, d.y, d.z}, ic[3] = {inv.x, inv.y, inv.z};
    for (int k = 0; k < 3; ++k) {
        if (dc[k] == 0) {
            if (oc[k] < b.lo[k] || oc[k] > b.hi[k]) return false;
            continue;
        }
        double t0 = (b.lo[k] - oc[k]) * ic[k], t1 = (b.hi[k] - oc[k]) * ic[k];
        if (t0 > t1) std::swap(t0, t1);
        // A relative hair beyond the rounding of the two products above.
        t0 -= 1e-12 * (1 + std::abs(t0));
        t1 += 1e-12 * (1 + std::abs(t1));
        if (t0 > lo) lo = t0;
        if (t1 < hi) hi = t1;
        if (lo > hi) return false;
    }
    return true;
}

inline double TriangleBvh::squared_gap(const Box& b, const Vec3& p) {
    const double c[3] = {p.x, p.y, p.z};
    double d2 = 0;
    for (int k = 0; k < 3; ++k) {
        const double g = c[k] < b.lo[k] ? b.lo[k] - c[k] : c[k] > b.hi[k] ? c[k] - b.hi[k] : 0;
        d2 += g * g;
    }
    return d2;
}

template <typename Visit, typename Bound>
void TriangleBvh::near_point(const Vec3& p, Visit&& visit, Bound&& bound) const {
    if (nodes_.empty()) return;
    // A box is skipped only when clearly beyond the bound (a relative 1e-12 above the rounding).
    auto beyond = [&](double d2) { return d2 > bound() * (1 + 1e-12); };
    struct Entry {
        std::uint32_t node;
        double d2;
    };
    Entry stack[128];
    int top = 0;
    stack[top++] = {0, squared_gap(nodes_[0].box, p)};
    while (top > 0) {
        const Entry e = stack[--top];
        if (beyond(e.d2)) continue;
        const Node& n = nodes_[e.node];
        if (n.count == 0) {
            Entry a{e.node + 1, squared_gap(nodes_[e.node + 1].box, p)}, b{n.first, squared_gap(nodes_[n.first].box, p)};
            if (a.d2 < b.d2) std::swap(a, b);  // the nearer on top
            stack[top++] = a;
            stack[top++] = b;
            continue;
        }
        for (std::uint32_t s = n.first; s < n.first + n.count; ++s)
            if (!beyond(squared_gap(boxes_[s], p))) visit(faces_[s]);
    }
}

template <typename Visit>
bool TriangleBvh::along_segment(const Vec3& a, const Vec3& b, Visit&& visit) const {
    return along(a, b - a, 0, 1, visit);
}

template <typename Visit>
bool TriangleBvh::along_vertical(double x, double y, Visit&& visit) const {
    // clip's tests for a direction (0, 0, +-1): x and y inside the box (the z slab always passes).
    return walk([x, y](const Box& b) { return !(x < b.lo[0] || x > b.hi[0] || y < b.lo[1] || y > b.hi[1]); }, visit);
}

template <typename Visit>
bool TriangleBvh::along(const Vec3& o, const Vec3& d, double from, double to, Visit& visit) const {
    const Vec3 inv{1 / d.x, 1 / d.y, 1 / d.z};
    return walk(
        [&](const Box& b) {
            double lo = from, hi = to;
            return clip(b, o, d, inv, lo, hi);
        },
        visit);
}

template <typename Holds, typename Visit>
bool TriangleBvh::walk(Holds&& holds, Visit& visit) const {
    if (nodes_.empty()) return false;
    std::uint32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
        const std::uint32_t at = stack[--top];
        const Node& n = nodes_[at];
        if (!holds(n.box)) continue;
        if (n.count == 0) {
            stack[top++] = n.first;
            stack[top++] = at + 1;
            continue;
        }
        for (std::uint32_t s = n.first; s < n.first + n.count; ++s)
            if (holds(boxes_[s]) && visit(faces_[s])) return true;
    }
    return false;
}

}  // namespace cs

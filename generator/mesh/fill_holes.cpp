#include "mesh/fill_holes.hpp"

#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/utility.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <unordered_map>
#include <vector>

namespace cs {
namespace {

using K = CGAL::Simple_cartesian<double>;
using Point = K::Point_3;
constexpr std::uint32_t kNoVertex = std::numeric_limits<std::uint32_t>::max();

std::uint64_t undirected(std::uint32_t a, std::uint32_t b) {
    return (std::uint64_t(std::min(a, b)) << 32) | std::max(a, b);
}

// Where a patch continues from each boundary vertex: the open edge a->b of a face becomes the patch
// edge b->a (the patch must run against its neighbour), with the neighbour's third corner beside it.
struct PatchEdges {
    std::vector<std::uint32_t> next;   // per vertex: the patch edge's end, or kNoVertex
    std::vector<std::uint32_t> third;  // per vertex: the neighbouring face's third corner
    std::vector<char> pinched;         // per vertex: more than one open edge leaves it
    std::unordered_map<std::uint64_t, int> edge_uses;  // every mesh edge, undirected
};

PatchEdges open_edges(const Mesh& m) {
    PatchEdges p;
    const size_t nv = m.vertices.size();
    p.next.assign(nv, kNoVertex);
    p.third.assign(nv, kNoVertex);
    p.pinched.assign(nv, 0);
    p.edge_uses.reserve(3 * m.faces.size() / 2 + 1);
    for (const auto& f : m.faces)
        for (int k = 0; k < 3; ++k) ++p.edge_uses[undirected(f[k], f[(k + 1) % 3])];
    for (const auto& f : m.faces)
        for (int k = 0; k < 3; ++k) {
            std::uint32_t a = f[k], b = f[(k + 1) % 3];
            if (p.edge_uses[undirected(a, b)] != 1) continue;
            if (p.next[b] != kNoVertex) p.pinched[b] = 1;
            p.next[b] = a;
            p.third[b] = f[(k + 2) % 3];
        }
    return p;
}

// The loop of patch edges through `start`, or empty when it meets a pinched vertex or breaks off.
std::vector<std::uint32_t> trace_loop(const PatchEdges& p, std::uint32_t start, std::vector<char>& seen) {
    std::vector<std::uint32_t> loop;
    for (std::uint32_t v = start;;) {
        if (p.pinched[v] || p.next[v] == kNoVertex || seen[v]) return {};
        seen[v] = 1;
        loop.push_back(v);
        v = p.next[v];
        if (v == start) return loop;
    }
}

// What the loop tests below share, computed once per loop: its bounding box and its Newell normal
// (twice its area vector).
struct LoopShape {
    Vec3 lo, hi;
    Vec3 normal;
};

LoopShape loop_shape(const std::vector<Vec3>& pts) {
    LoopShape s{pts[0], pts[0], {0, 0, 0}};
    for (size_t i = 0; i < pts.size(); ++i) {
        const Vec3 &a = pts[i], &b = pts[(i + 1) % pts.size()];
        const Vec3& n = s.normal;
        s.normal = {n.x + (a.y - b.y) * (a.z + b.z), n.y + (a.z - b.z) * (a.x + b.x), n.z + (a.x - b.x) * (a.y + b.y)};
        s.lo = {std::min(s.lo.x, a.x), std::min(s.lo.y, a.y), std::min(s.lo.z, a.z)};
        s.hi = {std::max(s.hi.x, a.x), std::max(s.hi.y, a.y), std::max(s.hi.z, a.z)};
    }
    return s;
}

// The loop's largest side of its bounding box.
double extent_of(const LoopShape& s) { return std::max({s.hi.x - s.lo.x, s.hi.y - s.lo.y, s.hi.z - s.lo.z}); }

// Whether two points of the loop (not only neighbours) are closer than a billionth of the loop's
// extent. CGAL's hole triangulations work in inexact doubles: such a loop (say, vertices a
// denormal apart, as a corrupt file gives) crashed its constrained Delaunay path and hung its 3D
// Delaunay path (found by fuzz_ply, fuzz_obj and fuzz_stl). A real hole has no such points, so the
// loop is left open, as the loops CGAL refuses are.
bool has_near_duplicates(const std::vector<Vec3>& pts, const LoopShape& shape) {
    const Vec3 &lo = shape.lo, &hi = shape.hi;
    const double tol = 1e-9 * std::max({1.0, hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    std::vector<Vec3> by_x = pts;
    std::sort(by_x.begin(), by_x.end(), [](const Vec3& a, const Vec3& b) { return a.x < b.x; });
    for (size_t i = 0; i < by_x.size(); ++i)
        for (size_t j = i + 1; j < by_x.size() && by_x[j].x - by_x[i].x < tol; ++j)
            if (std::abs(by_x[j].y - by_x[i].y) < tol && std::abs(by_x[j].z - by_x[i].z) < tol) return true;
    return false;
}

// Whether the loop encloses no area seen from any side: its Newell normal vanishes next to the
// square of its extent, as for points along one line. CGAL projects such a loop along that normal
// for its 2D triangulation, and a zero normal crashed it (fuzz_obj).
bool encloses_no_area(const LoopShape& shape) {
    const Vec3& n = shape.normal;
    const double extent = extent_of(shape);
    return std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z) <= 1e-9 * extent * extent;
}

// Whether the loop, seen along its Newell normal's main axis, crosses or touches itself: then it is
// no polygon for a 2D triangulation.
bool crosses_itself(const std::vector<Vec3>& pts, const LoopShape& shape) {
    const Vec3& n = shape.normal;
    const double ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
    std::vector<std::pair<double, double>> q;  // the loop with its main axis dropped
    for (const Vec3& a : pts)
        q.push_back(az >= ax && az >= ay ? std::pair{a.x, a.y} : ay >= ax ? std::pair{a.z, a.x} : std::pair{a.y, a.z});
    auto orient = [](std::pair<double, double> p, std::pair<double, double> r, std::pair<double, double> t) {
        const double d = (r.first - p.first) * (t.second - p.second) - (r.second - p.second) * (t.first - p.first);
        return (d > 0) - (d < 0);
    };
    // The textbook test: proper crossings, and an end point lying on the other segment (collinear
    // pieces of one straight side of a hole meet only where their extents overlap).
    auto on_segment = [](std::pair<double, double> p, std::pair<double, double> r, std::pair<double, double> t) {
        return std::min(p.first, r.first) <= t.first && t.first <= std::max(p.first, r.first) &&
               std::min(p.second, r.second) <= t.second && t.second <= std::max(p.second, r.second);
    };
    auto segments_meet = [&](auto a, auto b, auto c, auto d) {
        const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
        if (o1 * o2 < 0 && o3 * o4 < 0) return true;
        return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) || (o3 == 0 && on_segment(c, d, a)) ||
               (o4 == 0 && on_segment(c, d, b));
    };
    const size_t m = q.size();
    for (size_t i = 0; i < m; ++i)
        for (size_t j = i + 2; j < m; ++j) {
            if (i == 0 && j == m - 1) continue;  // neighbours through the loop's end
            const auto &a = q[i], &b = q[(i + 1) % m], &c = q[j], &d = q[(j + 1) % m];
            if (segments_meet(a, b, c, d)) return true;
        }
    return false;
}

// CGAL's triangulation of the loop, as mesh faces facing like their neighbours; empty if none was
// found or if it would reuse an edge the mesh already has (a chord across the hole).
std::vector<Triangle> patch_for(const Mesh& m, const PatchEdges& p, const std::vector<std::uint32_t>& loop) {
    const int n = static_cast<int>(loop.size());
    if (n < 3) return {};
    std::vector<Vec3> corners;
    for (std::uint32_t v : loop) corners.push_back(m.vertices[v]);
    const LoopShape shape = loop_shape(corners);
    if (has_near_duplicates(corners, shape) || encloses_no_area(shape)) return {};
    // CGAL checks this itself before its 2D path, yet crashed on a loop that fails it (fuzz_obj):
    // such a loop (a hole bent round an edge, say) goes to its 3D path only.
    const bool flat_path = !crosses_itself(corners, shape);
    std::vector<Point> points, thirds;
    for (std::uint32_t v : loop) {
        const Vec3 &a = m.vertices[v], &c = m.vertices[p.third[v]];
        points.emplace_back(a.x, a.y, a.z);
        thirds.emplace_back(c.x, c.y, c.z);
    }
    std::vector<CGAL::Triple<int, int, int>> tris;
    namespace PMP = CGAL::Polygon_mesh_processing;
    try {
        PMP::triangulate_hole_polyline(points, thirds, std::back_inserter(tris),
                                       CGAL::parameters::use_2d_constrained_delaunay_triangulation(flat_path)
                                           .use_delaunay_triangulation(true)
                                           .do_not_use_cubic_algorithm(true));
    } catch (const std::exception&) {
        return {};  // CGAL's checks refused this loop (say, its points all in a line): leave it open
    }
    if (tris.size() != size_t(n - 2)) return {};
    // The loop runs the way the patch must; count the triangles' edges that follow it or oppose it.
    int along = 0;
    auto follows = [n](int i, int j) { return (i + 1) % n == j ? 1 : (j + 1) % n == i ? -1 : 0; };
    for (const auto& t : tris) along += follows(t.first, t.second) + follows(t.second, t.third) + follows(t.third, t.first);
    std::vector<Triangle> faces;
    for (const auto& t : tris) {
        Triangle f = {loop[t.first], loop[t.second], loop[t.third]};
        if (along < 0) std::swap(f[1], f[2]);
        for (int k = 0; k < 3; ++k) {
            int i = (k == 0 ? t.first : k == 1 ? t.second : t.third), j = (k == 0 ? t.second : k == 1 ? t.third : t.first);
            if (follows(i, j) == 0 && p.edge_uses.count(undirected(f[k], f[(k + 1) % 3]))) return {};
        }
        faces.push_back(f);
    }
    return faces;
}

}  // namespace

HoleFilling fill_holes(Mesh& m) {
    HoleFilling h;
    const PatchEdges p = open_edges(m);
    std::vector<char> seen(m.vertices.size(), 0);
    std::vector<Triangle> added;
    for (std::uint32_t v = 0; v < m.vertices.size(); ++v) {
        if (p.next[v] == kNoVertex || seen[v]) continue;
        std::vector<std::uint32_t> loop = trace_loop(p, v, seen);
        std::vector<Triangle> patch = loop.empty() ? std::vector<Triangle>{} : patch_for(m, p, loop);
        if (patch.empty()) continue;
        ++h.filled;
        h.edges_closed += loop.size();
        added.insert(added.end(), patch.begin(), patch.end());
    }
    size_t open = 0;
    for (const auto& [edge, uses] : p.edge_uses) open += uses == 1;
    h.edges_left_open = open - h.edges_closed;
    h.patch_faces = added.size();
    m.faces.insert(m.faces.end(), added.begin(), added.end());
    return h;
}

}  // namespace cs

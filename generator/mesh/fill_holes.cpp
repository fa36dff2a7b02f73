#include "mesh/fill_holes.hpp"

#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/utility.h>

#include <algorithm>
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

// CGAL's triangulation of the loop, as mesh faces facing like their neighbours; empty if none was
// found or if it would reuse an edge the mesh already has (a chord across the hole).
std::vector<Triangle> patch_for(const Mesh& m, const PatchEdges& p, const std::vector<std::uint32_t>& loop) {
    const int n = static_cast<int>(loop.size());
    if (n < 3) return {};
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
                                       CGAL::parameters::use_2d_constrained_delaunay_triangulation(true)
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

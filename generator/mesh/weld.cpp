#include "mesh/weld.hpp"

#include <algorithm>
#include <numeric>
#include <tuple>

namespace cs {

Welded weld_vertices(const Mesh& m) {
    const auto& mv = m.vertices;
    const auto n = static_cast<std::uint32_t>(mv.size());
    // Sorted by (x, y, z, index), a total order: the coordinates sorted beside their index (not
    // indices sorted by coordinates looked up, a cache miss per comparison on a scan).
    struct Keyed {
        double x, y, z;
        std::uint32_t i;
    };
    std::vector<Keyed> sorted(n);
    for (std::uint32_t i = 0; i < n; ++i) sorted[i] = {mv[i].x, mv[i].y, mv[i].z, i};
    std::sort(sorted.begin(), sorted.end(), [](const Keyed& a, const Keyed& b) {
        return std::tie(a.x, a.y, a.z) != std::tie(b.x, b.y, b.z) ? std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z)
                                                                  : a.i < b.i;
    });
    std::vector<std::uint32_t> by_coords(n);
    for (std::uint32_t i = 0; i < n; ++i) by_coords[i] = sorted[i].i;
    sorted = {};
    auto key = [&](std::uint32_t i) { return std::make_tuple(mv[i].x, mv[i].y, mv[i].z); };
    // Each vertex -> the first vertex with its coordinates (the lowest index of its run).
    std::vector<std::uint32_t> first(n);
    for (std::uint32_t i = 0; i < n; ++i)
        first[by_coords[i]] = i > 0 && key(by_coords[i]) == key(by_coords[i - 1]) ? first[by_coords[i - 1]] : by_coords[i];
    Welded w;
    w.remap.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        if (first[i] == i) {
            w.remap[i] = static_cast<std::uint32_t>(w.mesh.vertices.size());
            w.mesh.vertices.push_back(mv[i]);
        } else {
            w.remap[i] = w.remap[first[i]];  // first[i] < i: already numbered
        }
    }
    w.mesh.faces.reserve(m.faces.size());
    for (const auto& f : m.faces) w.mesh.faces.push_back({w.remap[f[0]], w.remap[f[1]], w.remap[f[2]]});
    return w;
}

}  // namespace cs

#include "mesh/weld.hpp"

#include <algorithm>
#include <numeric>
#include <tuple>

namespace cs {

Welded weld_vertices(const Mesh& m) {
    const auto& mv = m.vertices;
    const auto n = static_cast<std::uint32_t>(mv.size());
    std::vector<std::uint32_t> by_coords(n);
    std::iota(by_coords.begin(), by_coords.end(), 0u);
    auto key = [&](std::uint32_t i) { return std::make_tuple(mv[i].x, mv[i].y, mv[i].z); };
    std::sort(by_coords.begin(), by_coords.end(), [&](std::uint32_t a, std::uint32_t b) {
        return key(a) != key(b) ? key(a) < key(b) : a < b;
    });
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

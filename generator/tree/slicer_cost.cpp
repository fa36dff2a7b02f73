// The slicer cost model of tree.hpp (estimate_slicer_cost): what a slicer spends printing a
// tree as a support mesh, layer by layer. Prices in tree/tuning.hpp.
#include <algorithm>
#include <cmath>

#include "tree/tree.hpp"
#include "tree/tuning.hpp"

namespace cs {
namespace {

// Outline of one layer of a strut of width w: its square. CuraEngine closes the N-profile's narrow
// holes in a support area and walls the outside only (the G-code of four models drew 0.49-0.56 of
// the length that walling the holes too would take).
double outline_per_layer(double w) { return 4 * w; }

// A piece of support between two heights, an island on every layer in between.
struct Upright {
    Vec3 top, bottom;
    double width;
};

std::vector<Upright> uprights(const SupportTree& t, const std::vector<double>& strut_width, const Params& p) {
    std::vector<Upright> out;
    for (size_t i = 0; i < t.struts.size(); ++i)
        out.push_back({t.nodes[t.struts[i].top].p, t.nodes[t.struts[i].bottom].p, strut_width[i]});
    const double tip_width = 0.5 * (p.tip_diameter + p.d_min);
    for (const auto& n : t.nodes) {
        if (n.kind == NodeKind::Leaf) out.push_back({n.tip, n.p, tip_width});
        if (n.kind == NodeKind::ModelContact) out.push_back({n.p, n.contact, tip_width});
    }
    for (const auto& pl : t.pillars) out.push_back({pl.top, pl.bottom, p.d_min});
    return out;
}

// Length of a path through the points, always on to the nearest one not yet visited.
double nearest_next_path(std::vector<Vec3> pts) {
    double len = 0;
    // Compared by squared distance (no square root in the inner loop: a layer of the columns
    // baseline has hundreds of islands).
    auto d2 = [](const Vec3& a, const Vec3& b) { return (a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y); };
    for (size_t i = 0; i + 1 < pts.size(); ++i) {
        size_t best = i + 1;
        double best_d2 = d2(pts[i], pts[best]);
        for (size_t j = i + 2; j < pts.size(); ++j)
            if (double dj = d2(pts[i], pts[j]); dj < best_d2) best = j, best_d2 = dj;
        std::swap(pts[i + 1], pts[best]);
        len += horizontal_distance(pts[i], pts[i + 1]);
    }
    return len;
}

}  // namespace

SlicerCost estimate_slicer_cost(const SupportTree& t, const std::vector<double>& strut_width, const Params& p) {
    SlicerCost c;
    auto ups = uprights(t, strut_width, p);
    double top = 0;
    for (const auto& u : ups) top = std::max(top, u.top.z);
    const double h = p.layer_height;
    for (double z = 0.5 * h; z < top; z += h) {
        std::vector<Vec3> islands;
        for (const auto& u : ups) {
            if (u.top.z < z || u.bottom.z > z || u.top.z == u.bottom.z) continue;
            islands.push_back(u.bottom + (u.top - u.bottom) * ((z - u.bottom.z) / (u.top.z - u.bottom.z)));
            c.outline_mm += outline_per_layer(u.width);
        }
        c.island_layers += islands.size();
        c.most_islands = std::max(c.most_islands, islands.size());
        c.travel_mm += nearest_next_path(std::move(islands));
    }
    const TreeTuning& k = kTreeTuning;
    c.seconds = c.island_layers * k.island_seconds + c.outline_mm / k.outline_mm_per_second + c.travel_mm / k.travel_mm_per_second;
    return c;
}

}  // namespace cs

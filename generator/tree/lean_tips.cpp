// Tips that lean towards each other, so two leaves meet a layer or two below their tips instead of
// a strut's drop further down: before the sweep (GrowOptions::pair_leaves_first), during it
// (lean_merging_leaves, tree.cpp) and after it (raise_merges.cpp).
#include <algorithm>
#include <cmath>
#include <tuple>

#include "core/xy_grid.hpp"
#include "tree/placement.hpp"
#include "tree/sweep_books.hpp"

namespace cs {

double SweepBooks::max_tip_slant(double height) const { return 0.9 * fan_.tan_c * height; }

double SweepBooks::leaned_feet_apart() const { return 0.5 * p_.d_min; }

std::optional<std::pair<Vec3, Vec3>> SweepBooks::leaned_pair(int u, int v) const {
    auto fresh_leaf = [&](int w) { return t_.nodes[w].kind == NodeKind::Leaf && books_[w].up.empty(); };
    if (!fresh_leaf(u) || !fresh_leaf(v)) return std::nullopt;
    const Vec3 a = t_.nodes[u].p, b = t_.nodes[v].p;
    const double keep = leaned_feet_apart();
    const double d = horizontal_distance(a, b);
    if (d <= keep) return std::nullopt;
    // Over its own height: a tip under a slope is shorter than tip_length.
    auto slant = [&](int w) { return max_tip_slant(t_.nodes[w].tip.z - t_.nodes[w].p.z); };
    const Vec3 dir = Vec3{b.x - a.x, b.y - a.y, 0} / d;
    const double shift = std::min({0.5 * (d - keep), slant(u), slant(v)});
    const Vec3 a2 = a + dir * shift, b2 = b - dir * shift;
    auto leans = [&](int w, const Vec3& to) {
        const Vec3& tip = t_.nodes[w].tip;
        return horizontal_distance(to, tip) <= slant(w) && square_is_clear(model_, to, p_.d_min) &&
               prism_is_clear(model_, to, p_.d_min, tip, p_.tip_diameter) && can_escape(to, p_.d_min);
    };
    if (!leans(u, a2) || !leans(v, b2)) return std::nullopt;
    return std::pair{a2, b2};
}

void lean_tips_in_pairs(SweepBooks& b, const std::vector<int>& leaves) {
    auto& nodes = b.t_.nodes;
    const double reach = 2 * b.max_tip_slant(b.p_.tip_length) + b.leaned_feet_apart();  // leaned_pair's farthest
    XyGrid<int> grid(std::max(reach, 1.0));
    for (int v : leaves) grid.insert(nodes[v].p, v);
    std::vector<std::tuple<double, int, int>> pairs;
    for (int v : leaves)
        grid.visit_near(nodes[v].p, 1, [&](int u) {
            if (u <= v) return;
            const Vec3 &a = nodes[v].p, &c = nodes[u].p;
            const double d = horizontal_distance(a, c);
            if (d <= reach && std::abs(a.z - c.z) <= b.p_.layer_height) pairs.emplace_back(d, v, u);
        });
    std::sort(pairs.begin(), pairs.end());
    std::vector<char> taken(nodes.size(), 0);
    for (const auto& [d, v, u] : pairs) {
        if (taken[v] || taken[u]) continue;
        auto l = b.leaned_pair(v, u);
        if (!l) continue;
        nodes[v].p = l->first;
        nodes[u].p = l->second;
        taken[v] = taken[u] = 1;
    }
}

}  // namespace cs

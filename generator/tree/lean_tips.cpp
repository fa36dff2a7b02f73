// Tips that lean towards each other, so two leaves meet a layer or two below their tips instead of
// a strut's drop further down: before the sweep (GrowOptions::pair_leaves_first), during it
// (lean_merging_leaves, tree.cpp) and after it (raise_merges.cpp).
#include <algorithm>
#include <array>
#include <cmath>
#include <tuple>

#include "core/xy_grid.hpp"
#include "tree/placement.hpp"
#include "tree/sweep_books.hpp"
#include "tree/tuning.hpp"

namespace cs {

double SweepBooks::max_tip_slant(double height) const { return 0.9 * fan_.tan_c * height; }

double SweepBooks::leaned_feet_apart() const { return 0.5 * p_.d_min; }

bool SweepBooks::fresh_leaf(int w) const { return t_.nodes[w].kind == NodeKind::Leaf && books_[w].up.empty(); }

bool SweepBooks::tip_leans_to(int w, const Vec3& to) const {
    // Over its own height: a tip under a slope is shorter than tip_length.
    const Vec3& tip = t_.nodes[w].tip;
    return horizontal_distance(to, tip) <= max_tip_slant(tip.z - t_.nodes[w].p.z) &&
           square_is_clear(model_, to, p_.d_min) && prism_is_clear(model_, to, p_.d_min, tip, p_.tip_diameter) &&
           can_escape(to, p_.d_min);
}

double SweepBooks::lean_reach(int w, const Vec3& dir) const {
    // The foot at p + dir s stays within the tip's slant of the point under its top: the larger
    // root of |p + dir s - top|^2 = slant^2 (horizontally), 0 where none is ahead.
    const Node& n = t_.nodes[w];
    const double r = max_tip_slant(n.tip.z - n.p.z) * (1 - 1e-9);
    const double qx = n.p.x - n.tip.x, qy = n.p.y - n.tip.y;
    const double bq = qx * dir.x + qy * dir.y, c = qx * qx + qy * qy - r * r;
    const double disc = bq * bq - c;
    return disc < 0 ? 0.0 : std::max(0.0, -bq + std::sqrt(disc));
}

std::optional<std::pair<Vec3, Vec3>> SweepBooks::leaned_pair(int u, int v) const {
    if (!fresh_leaf(u) || !fresh_leaf(v)) return std::nullopt;
    const Vec3 a = t_.nodes[u].p, b = t_.nodes[v].p;
    const double keep = leaned_feet_apart();
    const double d = horizontal_distance(a, b);
    if (d <= keep) return std::nullopt;
    const Vec3 dir = Vec3{b.x - a.x, b.y - a.y, 0} / d;
    // Each foot goes towards the other as far as its tip may slant from its top (a hair short,
    // which tip_leans_to measures back with rounding), half the way each where both can.
    const double ra = lean_reach(u, dir), rb = lean_reach(v, dir * -1.0), room = d - keep;
    double sa = std::min(ra, 0.5 * room);
    const double sb = std::min(rb, room - sa);
    sa = std::min(ra, room - sb);
    if (sa + sb < kTreeTuning.least_lean) return std::nullopt;
    const Vec3 a2 = a + dir * sa, b2 = b - dir * sb;
    if (!tip_leans_to(u, a2) || !tip_leans_to(v, b2)) return std::nullopt;
    return std::pair{a2, b2};
}

std::optional<std::array<Vec3, 4>> SweepBooks::leaned_quad(const std::array<int, 4>& leaves) const {
    Vec3 mid{0, 0, 0};
    for (int w : leaves) {
        if (!fresh_leaf(w)) return std::nullopt;
        mid = mid + t_.nodes[w].tip * 0.25;
    }
    // Each foot goes from under its tip straight towards the middle, stopping where four feet on a
    // square around it would be half a strut apart.
    const double keep = leaned_feet_apart();
    std::array<Vec3, 4> to;
    for (std::size_t k = 0; k < 4; ++k) {
        const Node& n = t_.nodes[leaves[k]];
        const Vec3 under{n.tip.x, n.tip.y, n.p.z}, centre{mid.x, mid.y, n.p.z};
        const double d = horizontal_distance(under, centre);
        // (a hair short of the slant, which tip_leans_to then measures back with rounding)
        const double shift = std::min(max_tip_slant(n.tip.z - n.p.z) * (1 - 1e-9), d - keep / std::sqrt(2.0));
        if (shift <= 0) return std::nullopt;
        to[k] = under + (centre - under) * (shift / d);
    }
    for (std::size_t i = 0; i < 4; ++i) {
        for (std::size_t j = i + 1; j < 4; ++j)
            if (horizontal_distance(to[i], to[j]) < keep * (1 - 1e-9)) return std::nullopt;  // a square's sides: keep, rounded
        if (!tip_leans_to(leaves[i], to[i])) return std::nullopt;
    }
    return to;
}

namespace {

// Pairs of items whose points lie within `reach` and one layer of each other, nearest first.
template <typename At>
std::vector<std::tuple<double, int, int>> nearest_pairs(int count, At at, double reach, double layer) {
    XyGrid<int> grid(std::max(reach, 1.0));
    for (int v = 0; v < count; ++v) grid.insert(at(v), v);
    std::vector<std::tuple<double, int, int>> pairs;
    for (int v = 0; v < count; ++v)
        grid.visit_near(at(v), 1, [&](int u) {
            if (u <= v) return;
            const Vec3 a = at(v), c = at(u);
            const double d = horizontal_distance(a, c);
            if (d <= reach && std::abs(a.z - c.z) <= layer) pairs.emplace_back(d, v, u);
        });
    std::sort(pairs.begin(), pairs.end());
    return pairs;
}

}  // namespace

void lean_tips_in_pairs(SweepBooks& b, const std::vector<int>& leaves, bool quads) {
    auto& nodes = b.t_.nodes;
    // leaned_pair's farthest for leaves standing under their tips (a foot already slanting away
    // from its partner reaches a little further; such pairs are left to the sweep)
    const double reach = 2 * b.max_tip_slant(b.p_.tip_length) + b.leaned_feet_apart();
    const int n = static_cast<int>(leaves.size());
    std::vector<char> taken(n, 0);
    std::vector<std::pair<int, int>> leaned;  // the pairs, as leaves
    for (const auto& [d, i, j] : nearest_pairs(n, [&](int k) { return nodes[leaves[k]].p; }, reach, b.p_.layer_height)) {
        if (taken[i] || taken[j]) continue;
        const int v = leaves[i], u = leaves[j];
        auto l = b.leaned_pair(v, u);
        if (!l) continue;
        nodes[v].p = l->first;
        nodes[u].p = l->second;
        taken[i] = taken[j] = 1;
        leaned.emplace_back(v, u);
    }
    if (!quads) return;
    // Pairs of pairs whose middles are as near as two leaves of a pair may be.
    auto middle = [&](int k) { return (nodes[leaned[k].first].p + nodes[leaned[k].second].p) * 0.5; };
    std::vector<char> joined(leaned.size(), 0);
    for (const auto& [d, i, j] : nearest_pairs(static_cast<int>(leaned.size()), middle, reach, b.p_.layer_height)) {
        if (joined[i] || joined[j]) continue;
        const std::array<int, 4> four{leaned[i].first, leaned[i].second, leaned[j].first, leaned[j].second};
        auto q = b.leaned_quad(four);
        if (!q) continue;
        for (std::size_t k = 0; k < 4; ++k) nodes[four[k]].p = (*q)[k];
        joined[i] = joined[j] = 1;
    }
}

}  // namespace cs

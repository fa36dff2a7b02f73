// Small closed test shapes for the unit tests, built from cells of a (non-uniform) grid so that a
// T or a bridge is ONE closed, manifold, outward-facing mesh (no coplanar faces inside it, no
// overlapping shells): only faces between a filled and an empty cell are emitted.
#pragma once

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>
#include <vector>

#include "core/geometry.hpp"

namespace cs::test {

struct CellGrid {
    std::vector<double> xs, ys, zs;  // cell boundaries along each axis
    std::vector<char> filled;        // (nx-1)*(ny-1)*(nz-1) cells

    CellGrid(std::vector<double> x, std::vector<double> y, std::vector<double> z)
        : xs(std::move(x)), ys(std::move(y)), zs(std::move(z)),
          filled((xs.size() - 1) * (ys.size() - 1) * (zs.size() - 1), 0) {}
    int nx() const { return static_cast<int>(xs.size()) - 1; }
    int ny() const { return static_cast<int>(ys.size()) - 1; }
    int nz() const { return static_cast<int>(zs.size()) - 1; }
    bool at(int i, int j, int k) const {
        if (i < 0 || j < 0 || k < 0 || i >= nx() || j >= ny() || k >= nz()) return false;
        return filled[(k * ny() + j) * nx() + i];
    }
    void set(int i, int j, int k) { filled[(k * ny() + j) * nx() + i] = 1; }
    // Fills every cell whose box lies inside [lo, hi].
    void fill(Vec3 lo, Vec3 hi) {
        for (int k = 0; k < nz(); ++k)
            for (int j = 0; j < ny(); ++j)
                for (int i = 0; i < nx(); ++i)
                    if (xs[i] >= lo.x && xs[i + 1] <= hi.x && ys[j] >= lo.y && ys[j + 1] <= hi.y && zs[k] >= lo.z &&
                        zs[k + 1] <= hi.z)
                        set(i, j, k);
    }

    Mesh mesh() const {
        Mesh m;
        std::map<std::tuple<int, int, int>, std::uint32_t> index;
        auto vid = [&](int i, int j, int k) {
            auto [it, fresh] = index.emplace(std::tuple{i, j, k}, static_cast<std::uint32_t>(m.vertices.size()));
            if (fresh) m.vertices.push_back({xs[i], ys[j], zs[k]});
            return it->second;
        };
        // Quad with corners c0..c3 counter-clockwise seen from outside.
        auto quad = [&](std::array<int, 3> c0, std::array<int, 3> c1, std::array<int, 3> c2, std::array<int, 3> c3) {
            auto a = vid(c0[0], c0[1], c0[2]), b = vid(c1[0], c1[1], c1[2]), c = vid(c2[0], c2[1], c2[2]),
                 d = vid(c3[0], c3[1], c3[2]);
            m.faces.push_back({a, b, c});
            m.faces.push_back({a, c, d});
        };
        for (int k = 0; k < nz(); ++k)
            for (int j = 0; j < ny(); ++j)
                for (int i = 0; i < nx(); ++i) {
                    if (!at(i, j, k)) continue;
                    if (!at(i - 1, j, k)) quad({i, j, k}, {i, j, k + 1}, {i, j + 1, k + 1}, {i, j + 1, k});
                    if (!at(i + 1, j, k)) quad({i + 1, j, k}, {i + 1, j + 1, k}, {i + 1, j + 1, k + 1}, {i + 1, j, k + 1});
                    if (!at(i, j - 1, k)) quad({i, j, k}, {i + 1, j, k}, {i + 1, j, k + 1}, {i, j, k + 1});
                    if (!at(i, j + 1, k)) quad({i, j + 1, k}, {i, j + 1, k + 1}, {i + 1, j + 1, k + 1}, {i + 1, j + 1, k});
                    if (!at(i, j, k - 1)) quad({i, j, k}, {i, j + 1, k}, {i + 1, j + 1, k}, {i + 1, j, k});
                    if (!at(i, j, k + 1)) quad({i, j, k + 1}, {i + 1, j, k + 1}, {i + 1, j + 1, k + 1}, {i, j + 1, k + 1});
                }
        return m;
    }
};

// A T: a 4 x 4 stem from the bed to z = 10 under a 20 x 10 x 2 plate (z 10..12), centred at the origin.
// The plate's underside outside the stem (|x| or |y| > 2, z = 10) is the only overhang.
inline Mesh t_shape() {
    CellGrid g({-10, -2, 2, 10}, {-5, -2, 2, 5}, {0, 10, 12});
    g.fill({-2, -2, 0}, {2, 2, 10});
    g.fill({-10, -5, 10}, {10, 5, 12});
    return g.mesh();
}

// A table: a 40 x 30 x 2 top (z 10..12) on one 4 x 4 leg at the centre.
inline Mesh table_shape() {
    CellGrid g({-20, -2, 2, 20}, {-15, -2, 2, 15}, {0, 10, 12});
    g.fill({-2, -2, 0}, {2, 2, 10});
    g.fill({-20, -15, 10}, {20, 15, 12});
    return g.mesh();
}

// A hanging keel: a 9 mm prism along x whose two faces lean 30 degrees from vertical (steep
// enough to print on their own) down to a level ridge at z = 10, held at its end by a post from
// the bed. Only the ridge line hangs.
inline Mesh keel_shape() {
    const double zr = 10, zt = 10 + 3 / std::tan(30 * 3.14159265358979 / 180), x0 = -4.5, x1 = 4.5;
    Mesh m;
    m.vertices = {{x0, 0, zr}, {x1, 0, zr}, {x0, -3, zt}, {x1, -3, zt}, {x0, 3, zt}, {x1, 3, zt}};
    m.faces = {{0, 3, 2}, {0, 1, 3}, {0, 5, 1}, {0, 4, 5}, {2, 5, 4}, {2, 3, 5}, {0, 2, 4}, {1, 5, 3}};  // outward
    CellGrid post({x0 - 2, x0}, {-3, 3}, {0, zt});
    post.fill({x0 - 2, -3, 0}, {x0, 3, zt});
    append(m, post.mesh());
    return m;
}

// A bridge: two 4 x 6 pillars (x -12..-8 and 8..12) from the bed to z = 8 under a 24 x 6 x 2 deck.
// The deck's underside between the pillars (|x| < 8, z = 8) is the overhang.
inline Mesh bridge_shape() {
    CellGrid g({-12, -8, 8, 12}, {-3, 3}, {0, 8, 10});
    g.fill({-12, -3, 0}, {-8, 3, 8});
    g.fill({8, -3, 0}, {12, 3, 8});
    g.fill({-12, -3, 8}, {12, 3, 10});
    return g.mesh();
}

// A cantilever from a 4 mm column (x 0..4, z 0..20) reaching to x = 30 at z 20..22, over a low
// separate box (x 12..24, y 2..8, z 0..5) standing on the bed below it.
inline Mesh cantilever_over_box() {
    CellGrid g({0, 4, 12, 24, 30}, {0, 2, 8, 10}, {0, 5, 20, 22});
    g.fill({0, 0, 0}, {4, 10, 20});
    g.fill({0, 0, 20}, {30, 10, 22});
    g.fill({12, 2, 0}, {24, 8, 5});
    return g.mesh();
}

// A tapered, twisted blade (a propeller's, bench/validation/propeller): a plate 40 mm long along x,
// 14 mm wide at its root (x = 0) narrowing to 8 at its tip, 1.6 mm thick, its middle line 8 mm over
// the bed, pitched 35 degrees at its root to 20 at its tip about that line, standing on a post
// (x -4..0) at its root; triangulated on a 1 mm grid along x. Its underside is level nearly along
// its length, and its edges turn in towards the tip.
inline Mesh tapered_blade() {
    std::vector<double> xs{-4}, ys;
    for (int i = 0; i <= 40; ++i) xs.push_back(i);
    for (int j = -7; j <= 7; ++j) ys.push_back(j);
    CellGrid g(xs, ys, {0, 8, 9.6});
    g.fill({-4, -7, 0}, {0, 7, 9.6});
    g.fill({0, -7, 8}, {40, 7, 9.6});
    Mesh m = g.mesh();
    for (auto& v : m.vertices) {
        const double f = std::clamp(v.x, 0.0, 40.0) / 40;
        v.y *= 1 - f * 3.0 / 7;  // half-width 7 -> 4
        if (v.z < 8 - 1e-9) continue;
        v.z += v.y * std::tan((35 - 15 * f) * 3.14159265358979323846 / 180);
    }
    return m;
}

// A delta wing: a flat plate 5 mm over the bed (z 5..6.6), 50 mm long, narrowing from 40 mm wide
// at its root (x 0, on a 4 mm block) to 6 mm at its tip. Its two rims run diagonally across rows
// along its length, which end one by one along them.
inline Mesh delta_plate() {
    std::vector<double> xs{-4}, ys;
    for (int i = 0; i <= 50; ++i) xs.push_back(i);
    for (int j = -20; j <= 20; ++j) ys.push_back(j);
    CellGrid g(xs, ys, {0, 5, 6.6});
    g.fill({-4, -20, 0}, {0, 20, 6.6});
    g.fill({0, -20, 5}, {50, 20, 6.6});
    Mesh m = g.mesh();
    for (auto& v : m.vertices) v.y *= 1 - std::clamp(v.x, 0.0, 50.0) / 50 * 17.0 / 20;  // half-width 20 -> 3
    return m;
}

// A triangular shelf: a flat plate 5 mm over the bed (z 5..6.6) standing out 18 mm from a 4 mm
// block (y < 0), 36 mm wide at the block and 2 mm at its apex: its two rims run at 45 degrees to
// rows along the block, which end on them a row's spacing shorter each (bench/validation's
// wedge_ledge has such a shelf).
inline Mesh triangle_shelf() {
    std::vector<double> xs, ys{-4};
    for (int i = -18; i <= 18; ++i) xs.push_back(i);
    for (int j = 0; j <= 18; ++j) ys.push_back(j);
    CellGrid g(xs, ys, {0, 5, 6.6});
    g.fill({-18, -4, 0}, {18, 0, 6.6});
    g.fill({-18, 0, 5}, {18, 18, 6.6});
    Mesh m = g.mesh();
    for (auto& v : m.vertices) v.x *= 1 - std::clamp(v.y, 0.0, 18.0) / 18 * 17.0 / 18;  // half-width 18 -> 1
    return m;
}

}  // namespace cs::test

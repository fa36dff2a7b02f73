// overhang/: which faces need support, the global sampling lattice, edge and point overhangs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <map>
#include <set>

#include "core/rules.hpp"
#include "overhang/overhang.hpp"
#include "query/model_query.hpp"
#include "shapes.hpp"
#include "support.hpp"

using namespace cs;
using cs::test::box;

namespace {

constexpr double kDeg = M_PI / 180.0;

// Lattice index of a sample point (it must be ON the lattice).
std::pair<long, long> lattice_index(const Vec3& p, double s) {
    long i = std::lround(p.x / s), j = std::lround(p.y / s);
    EXPECT_EQ(p.x, i * s) << "x not on the lattice";
    EXPECT_EQ(p.y, j * s) << "y not on the lattice";
    return {i, j};
}

// How often each lattice point is produced by rasterising all `tris`.
std::map<std::pair<long, long>, int> coverage(const std::vector<std::array<Vec3, 3>>& tris, double s) {
    std::vector<Vec3> pts;
    for (const auto& t : tris) rasterize_triangle(t[0], t[1], t[2], s, pts);
    std::map<std::pair<long, long>, int> c;
    for (const auto& p : pts) ++c[lattice_index(p, s)];
    return c;
}

// Lattice points of the half-open rectangle [i0, i1) x [j0, j1) (in lattice steps): what one
// rectangle gives under the top-left rule (its left and bottom edges own their points).
std::map<std::pair<long, long>, int> half_open_rect(long i0, long i1, long j0, long j1) {
    std::map<std::pair<long, long>, int> c;
    for (long i = i0; i < i1; ++i)
        for (long j = j0; j < j1; ++j) c[{i, j}] = 1;
    return c;
}

// A rectangle of cells with corners on the lattice (corner (a, b) at (a*s, b*s) computed exactly as
// the rasteriser computes lattice points), each cell split along one of its diagonals.
std::vector<std::array<Vec3, 3>> split_cells(double s, int cells_x, int cells_y, int step, bool alternate) {
    std::vector<std::array<Vec3, 3>> tris;
    auto at = [&](long a, long b) { return Vec3{double(a) * s, double(b) * s, 5.0 + 0.01 * a}; };
    for (int cx = 0; cx < cells_x; ++cx)
        for (int cy = 0; cy < cells_y; ++cy) {
            long a = cx * step, b = cy * step;
            Vec3 p00 = at(a, b), p10 = at(a + step, b), p01 = at(a, b + step), p11 = at(a + step, b + step);
            if (alternate && (cx + cy) % 2) {
                tris.push_back({p00, p10, p01});
                tris.push_back({p10, p11, p01});
            } else {
                tris.push_back({p00, p10, p11});
                tris.push_back({p00, p11, p01});
            }
        }
    return tris;
}

std::string describe(const std::map<std::pair<long, long>, int>& got, const std::map<std::pair<long, long>, int>& want) {
    std::string s;
    for (const auto& [k, n] : want)
        if (!got.count(k)) s += " gap at (" + std::to_string(k.first) + "," + std::to_string(k.second) + ")";
    for (const auto& [k, n] : got) {
        if (n > 1) s += " double at (" + std::to_string(k.first) + "," + std::to_string(k.second) + ")";
        if (!want.count(k)) s += " extra at (" + std::to_string(k.first) + "," + std::to_string(k.second) + ")";
    }
    return s.substr(0, 600);
}

OverhangOptions default_options() { return {50, 1.5, 0.2}; }

// The coverage rule, written out here on its own: a support within (sqrt 2 / 2) * spacing
// horizontally, and no further up or down than the steepest overhang rises over that distance.
bool covered_by(const std::vector<Vec3>& supports, const Vec3& x, const OverhangOptions& o) {
    const double reach = std::sqrt(0.5) * o.sampling_distance;
    const double rise = reach * std::tan((90 - o.critical_angle) * kDeg);
    for (const auto& q : supports)
        if (std::hypot(q.x - x.x, q.y - x.y) <= reach && std::abs(q.z - x.z) <= rise) return true;
    return false;
}

// Overhang points judged far more densely than the sampler looks: a sixteenth of the spacing inside
// faces, every corner and centroid, and every overhang face's edges at a thirty-second. With
// `between`, also that lattice shifted by half its step (the points between any two of the
// sampler's refined lattice, where a gap would hide) and edges at a 128th.
std::vector<Vec3> dense_overhang_points(const Mesh& m, const OverhangOptions& o, bool between = false) {
    auto cls = classify_faces(m, o);
    std::vector<Vec3> pts;
    const double h = o.sampling_distance / 16;
    const Vec3 half{0.5 * h, 0.5 * h, 0};
    for (size_t i = 0; i < m.faces.size(); ++i) {
        if (!cls[i]) continue;
        const auto& f = m.faces[i];
        rasterize_triangle(m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]], h, pts);
        std::vector<Vec3> shifted;
        if (between)
            rasterize_triangle(m.vertices[f[0]] - half, m.vertices[f[1]] - half, m.vertices[f[2]] - half, h, shifted);
        for (const auto& q : shifted) pts.push_back(q + half);
        pts.push_back((m.vertices[f[0]] + m.vertices[f[1]] + m.vertices[f[2]]) / 3.0);
        for (int k = 0; k < 3; ++k) {
            const Vec3 &a = m.vertices[f[k]], &b = m.vertices[f[(k + 1) % 3]];
            int n = std::max(1, static_cast<int>(std::ceil(distance(a, b) / (o.sampling_distance / (between ? 128 : 32)))));
            for (int t = 0; t <= n; ++t) pts.push_back(a + (b - a) * (double(t) / n));
        }
    }
    std::erase_if(pts, [&](const Vec3& p) { return p.z < o.bed_height; });
    return pts;
}

// Dense overhang points with no sample or anchor covering them.
std::vector<Vec3> uncovered(const Mesh& m, const OverhangSamples& res, const OverhangOptions& o, bool between = false) {
    std::vector<Vec3> supports = res.anchors;
    for (const auto& s : res.samples) supports.push_back(s.p);
    std::vector<Vec3> out;
    for (const auto& x : dense_overhang_points(m, o, between))
        if (!covered_by(supports, x, o)) out.push_back(x);
    return out;
}

// The bottom of a UV sphere (radius r, centre c) with `rings` x `segments` faces: a curved
// overhang whose rim lies between faces, with a pole at its lowest point.
Mesh uv_sphere(const Vec3& c, double r, int rings, int segments) {
    Mesh m;
    m.vertices.push_back(c - Vec3{0, 0, r});
    for (int i = 1; i < rings; ++i) {
        double th = M_PI * i / rings;
        for (int j = 0; j < segments; ++j) {
            double ph = 2 * M_PI * j / segments + 0.37 * i;  // twisted rings: faces off the lattice
            m.vertices.push_back(c + Vec3{r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), -r * std::cos(th)});
        }
    }
    m.vertices.push_back(c + Vec3{0, 0, r});
    auto at = [&](int i, int j) { return static_cast<std::uint32_t>(1 + (i - 1) * segments + (j % segments)); };
    const auto top = static_cast<std::uint32_t>(m.vertices.size() - 1);
    for (int j = 0; j < segments; ++j) m.faces.push_back({0, at(1, j + 1), at(1, j)});
    for (int i = 1; i + 1 < rings; ++i)
        for (int j = 0; j < segments; ++j) {
            m.faces.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
            m.faces.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
        }
    for (int j = 0; j < segments; ++j) m.faces.push_back({at(rings - 1, j), at(rings - 1, j + 1), top});
    return m;
}

// A cylinder lying along x (radius r, `segments` sides, centre height zc), tilted about y by
// `tilt` degrees and turned about z by `turn` degrees: its underside needs support up to where the
// wall steepens past the critical angle, so the rims run through lattice cells the overhang only
// partly fills (a round hole or shaft in a printed part).
Mesh lying_cylinder(double r, double len, int segments, double zc, double tilt, double turn) {
    Mesh m;
    const double ct = std::cos(tilt * kDeg), st = std::sin(tilt * kDeg), cz = std::cos(turn * kDeg), sz = std::sin(turn * kDeg);
    auto place = [&](double x, double y, double z) {
        double x1 = ct * x + st * z, z1 = -st * x + ct * z;
        return Vec3{cz * x1 - sz * y, sz * x1 + cz * y, z1 + zc};
    };
    for (double x : {-0.5 * len, 0.5 * len})
        for (int j = 0; j < segments; ++j) {
            double a = 2 * M_PI * j / segments + 0.1;
            m.vertices.push_back(place(x, r * std::cos(a), r * std::sin(a)));
        }
    auto v = [&](int end, int j) { return static_cast<std::uint32_t>(end * segments + (j % segments)); };
    for (int j = 0; j < segments; ++j) {
        m.faces.push_back({v(0, j), v(1, j + 1), v(1, j)});
        m.faces.push_back({v(0, j), v(0, j + 1), v(1, j + 1)});
    }
    for (int j = 1; j + 1 < segments; ++j) {
        m.faces.push_back({v(0, 0), v(0, j + 1), v(0, j)});
        m.faces.push_back({v(1, 0), v(1, j), v(1, j + 1)});
    }
    return m;
}

}  // namespace

// ---------------------------------------------------------------- classification

TEST(NeedsSupport, Thresholds) {
    const double s50 = std::sin(50 * kDeg);
    EXPECT_TRUE(needs_support({0, 0, -1}, 50));
    EXPECT_FALSE(needs_support({0, 0, 1}, 50));
    EXPECT_FALSE(needs_support({1, 0, 0}, 50));  // a vertical wall
    // n_z = -sin(critical): the face deviates from vertical by exactly the critical angle: printable.
    EXPECT_FALSE(needs_support({std::cos(50 * kDeg), 0, -s50}, 50));
    // A face 1 degree flatter than that needs support, 1 degree steeper does not.
    EXPECT_TRUE(needs_support({std::cos(51 * kDeg), 0, -std::sin(51 * kDeg)}, 50));
    EXPECT_FALSE(needs_support({std::cos(49 * kDeg), 0, -std::sin(49 * kDeg)}, 50));
    // A 45 degree chamfer is fine at 50, not at 40.
    Vec3 chamfer = normalized(Vec3{1, 0, -1});
    EXPECT_FALSE(needs_support(chamfer, 50));
    EXPECT_TRUE(needs_support(chamfer, 40));
    EXPECT_FALSE(needs_support({0, 0, -1}, 90));  // nothing needs support at 90
    // Within kCriticalRounding of the critical angle (the float32 model.stl tilts a face drawn at it
    // by its corners' rounding) a face is still at it: printable; a little beyond, an overhang.
    auto steeper_by = [&](double dz) { return Vec3{std::sqrt(1 - (s50 + dz) * (s50 + dz)), 0, -(s50 + dz)}; };
    EXPECT_FALSE(needs_support(steeper_by(1e-8), 50));
    EXPECT_FALSE(needs_support(steeper_by(0.5 * kCriticalRounding), 50));
    EXPECT_TRUE(needs_support(steeper_by(2 * kCriticalRounding), 50));
}

TEST(ClassifyFaces, CubeOnBedHasNoOverhang) {
    Mesh cube = box({-5, -5, 0}, {5, 5, 10});
    auto cls = classify_faces(cube, default_options());
    for (char c : cls) EXPECT_EQ(c, 0);
    EXPECT_EQ(sample_overhangs(cube, default_options()).overhang_area, 0);
    auto s = sample_overhangs(cube, default_options());
    EXPECT_TRUE(s.samples.empty());
    EXPECT_EQ(s.overhang_faces, 0u);
    EXPECT_EQ(s.point_overhangs, 0u);
}

TEST(ClassifyFaces, FloatingCubeBottomIsOverhang) {
    Mesh cube = box({0, 0, 3}, {6, 3, 5});
    EXPECT_NEAR(sample_overhangs(cube, default_options()).overhang_area, 18, 1e-12);
    auto s = sample_overhangs(cube, default_options());
    EXPECT_EQ(s.overhang_faces, 2u);
    ASSERT_FALSE(s.samples.empty());
    for (const auto& x : s.samples) EXPECT_EQ(x.p.z, 3);
    // Lattice points of the bottom face (0..6 x 0..3, spacing 1.5): all but those on its top/right edges.
    std::set<std::pair<double, double>> face;
    for (const auto& x : s.samples)
        if (x.kind == SampleKind::Face) face.insert({x.p.x, x.p.y});
    EXPECT_EQ(face.size(), 8u);  // x in {0,1.5,3,4.5}, y in {0,1.5}
}

// ---------------------------------------------------------------- the T shape

TEST(SampleOverhangs, TShapeSamplesExactlyUnderThePlate) {
    Mesh t = cs::test::t_shape();
    auto o = default_options();
    auto res = sample_overhangs(t, o);
    EXPECT_NEAR(res.overhang_area, 20 * 10 - 4 * 4, 1e-9);
    EXPECT_EQ(res.point_overhangs, 0u);
    ASSERT_FALSE(res.samples.empty());
    std::map<std::pair<long, long>, int> face;
    for (const auto& s : res.samples) {
        // On the plate's underside, outside the stem: nowhere else.
        EXPECT_EQ(s.p.z, 10) << s.p.x << "," << s.p.y;
        EXPECT_GE(s.p.x, -10 - 1e-12);
        EXPECT_LE(s.p.x, 10 + 1e-12);
        EXPECT_GE(s.p.y, -5 - 1e-12);
        EXPECT_LE(s.p.y, 5 + 1e-12);
        EXPECT_FALSE(std::abs(s.p.x) < 2 - 1e-9 && std::abs(s.p.y) < 2 - 1e-9) << "sample over the stem at " << s.p.x << "," << s.p.y;
        if (s.kind == SampleKind::Face) ++face[lattice_index(s.p, 1.5)];
    }
    // Every lattice point of the overhanging underside, once: x = 1.5 i in [-10, 10], y = 1.5 j in
    // [-5, 5], not over the stem (no lattice point lies on any of these boundaries).
    std::map<std::pair<long, long>, int> want;
    for (long i = -6; i <= 6; ++i)
        for (long j = -3; j <= 3; ++j)
            if (!(std::abs(i) <= 1 && std::abs(j) <= 1)) want[{i, j}] = 1;
    EXPECT_EQ(face, want) << describe(face, want);
    EXPECT_TRUE(uncovered(t, res, o).empty());
}

TEST(SampleOverhangs, DownwardOctahedronTipIsAPointSample) {
    // An octahedron raised 5 mm: its lower faces slope at 54.7 degrees from horizontal (normal
    // n_z = -0.577, printable at 50), its lower edges at 45 degrees: only the tip needs support.
    Mesh m;
    m.vertices = {{0, 0, 5}, {5, 0, 10}, {0, 5, 10}, {-5, 0, 10}, {0, -5, 10}, {0, 0, 15}};
    m.faces = {{0, 2, 1}, {0, 3, 2}, {0, 4, 3}, {0, 1, 4}, {5, 1, 2}, {5, 2, 3}, {5, 3, 4}, {5, 4, 1}};
    ASSERT_GT(signed_volume(m), 0);
    auto res = sample_overhangs(m, default_options());
    EXPECT_EQ(res.overhang_faces, 0u);
    EXPECT_EQ(res.point_overhangs, 1u);
    ASSERT_EQ(res.samples.size(), 1u);
    EXPECT_EQ(res.samples[0].kind, SampleKind::Point);
    EXPECT_EQ(res.samples[0].p, (Vec3{0, 0, 5}));
}

TEST(SampleOverhangs, DownwardSquarePyramidApexIsAPointSample) {
    // A square pyramid standing on its apex, 2 mm above the bed (on nothing).
    Mesh m;
    m.vertices = {{0.3, 0.2, 2}, {-4.7, -4.8, 12}, {5.3, -4.8, 12}, {5.3, 5.2, 12}, {-4.7, 5.2, 12}};
    m.faces = {{0, 2, 1}, {0, 3, 2}, {0, 4, 3}, {0, 1, 4}, {1, 2, 3}, {1, 3, 4}};
    ASSERT_GT(signed_volume(m), 0);
    auto res = sample_overhangs(m, default_options());
    ASSERT_EQ(res.samples.size(), 1u);
    EXPECT_EQ(res.samples[0].kind, SampleKind::Point);
    EXPECT_EQ(res.samples[0].p, (Vec3{0.3, 0.2, 2}));
}

TEST(SampleOverhangs, FlatPyramidKeepsItsApexExactly) {
    // Lower faces flat enough to need support: the apex (no lattice point within half a spacing
    // of it) is still a sample, at its exact position, and the lowest one.
    Mesh m;
    m.vertices = {{0.75, 0.75, 4}, {-9.25, -9.25, 6}, {10.75, -9.25, 6}, {10.75, 10.75, 6}, {-9.25, 10.75, 6}};
    m.faces = {{0, 2, 1}, {0, 3, 2}, {0, 4, 3}, {0, 1, 4}, {1, 2, 3}, {1, 3, 4}};
    auto res = sample_overhangs(m, default_options());
    EXPECT_EQ(res.overhang_faces, 4u);
    bool apex = false;
    for (const auto& s : res.samples) apex |= s.kind == SampleKind::Point && s.p == Vec3{0.75, 0.75, 4};
    EXPECT_TRUE(apex);
    EXPECT_EQ(res.samples.back().p, (Vec3{0.75, 0.75, 4}));  // the lowest sample
}

TEST(SampleOverhangs, DownwardRidgeIsSampledAlongItsLength) {
    // An upside-down roof: faces at 45 degrees (printable), the ridge between them is not.
    Mesh m;
    m.vertices = {{0, 0, 5}, {9, 0, 5}, {0, -5, 10}, {9, -5, 10}, {0, 5, 10}, {9, 5, 10}};
    m.faces = {{0, 1, 3}, {0, 3, 2}, {0, 4, 5}, {0, 5, 1}, {2, 3, 5}, {2, 5, 4}, {0, 2, 4}, {1, 5, 3}};
    ASSERT_GT(signed_volume(m), 0);
    auto res = sample_overhangs(m, default_options());
    EXPECT_EQ(res.overhang_faces, 0u);
    EXPECT_EQ(res.ridge_edges, 1u);
    // Each sample covers the reach on both sides: 9 mm takes 5 (the old rule, a sample every
    // spacing, took 7), and every point of the ridge is within reach of one.
    EXPECT_LE(res.samples.size(), 5u);
    for (const auto& s : res.samples) {
        EXPECT_EQ(s.kind, SampleKind::Edge);
        EXPECT_EQ(s.p.y, 0);
        EXPECT_EQ(s.p.z, 5);
    }
    std::vector<Vec3> pts;
    for (const auto& s : res.samples) pts.push_back(s.p);
    for (double x = 0; x <= 9; x += 0.05) EXPECT_TRUE(covered_by(pts, {x, 0, 5}, default_options())) << "ridge at x " << x;
}

// A plate's underside (z = 5, facing down) whose edge y = 0 is split at its middle d, a T-junction
// a mesh closes with a zero-area face (a, b, d): d lies 1e-7 mm off the edge's line, so the sliver's
// normal, rounding, faces straight down and it is classed an overhang. Beside it along (a, b), a face
// that is no overhang. Found on molecule.stl at 1.5x (auto pose): such an edge counted as an inside
// corner, its anchors held the overhang around it, and `check` failed there (0.21 mm2 beyond reach).
TEST(SampleOverhangs, ASliverClassedAnOverhangAnchorsNothing) {
    Mesh m;
    const Vec3 a{0, 0, 5}, b{10, 0, 5}, d{5, -1e-7, 5}, p{0, -10, 5}, q{10, -10, 5}, c{5, -5, 4.9};
    m.vertices = {a, b, d, p, q, c};
    m.faces = {{0, 1, 2},               // the sliver (a, b, d), first: its normal decides convexity
               {0, 2, 3}, {2, 4, 3}, {2, 1, 4},  // the plate, facing down
               {1, 0, 5}};              // beside the sliver along (a, b): no overhang
    const OverhangOptions o = default_options();
    const auto cls = classify_faces(m, o);
    ASSERT_EQ(cls[0], 1) << "the sliver is classed an overhang, as on molecule.stl";
    ASSERT_EQ(cls[4], 0);
    const OverhangSamples s = sample_overhangs(m, o);
    EXPECT_TRUE(s.anchors.empty()) << s.anchors.size() << " anchors, the first at (" << s.anchors.front().x << ", "
                                   << s.anchors.front().y << ", " << s.anchors.front().z << ")";
    // The plate's points there are held by samples instead.
    EXPECT_TRUE(uncovered(m, s, o).empty());
}

// ---------------------------------------------------------------- lean sampling

TEST(LeanSampling, EveryOverhangPointIsCoveredWithinReach) {
    // Flat plates, a curved cap with a pole and a twisted rim, at two spacings.
    std::vector<Mesh> shapes{cs::test::t_shape(), cs::test::bridge_shape(), cs::test::cantilever_over_box(),
                             uv_sphere({0.3, -0.2, 12}, 8, 14, 22)};
    for (double s : {1.5, 2.5})
        for (size_t i = 0; i < shapes.size(); ++i) {
            SCOPED_TRACE("shape " + std::to_string(i) + " spacing " + std::to_string(s));
            OverhangOptions o{50, s, 0.2};
            auto res = sample_overhangs(shapes[i], o);
            auto holes = uncovered(shapes[i], res, o);
            EXPECT_TRUE(holes.empty()) << holes.size() << " uncovered, first at " << holes[0].x << ", " << holes[0].y
                                       << ", " << holes[0].z;
        }
}

TEST(LeanSampling, EveryExtraCoversAPointTheLatticeLeavesOpen) {
    // No extra stands where the lattice (and the inside corners) already cover everything around it.
    size_t total_extras = 0;
    for (const Mesh& m : {cs::test::t_shape(), uv_sphere({0.3, -0.2, 12}, 8, 14, 22)}) {
        auto o = default_options();
        auto res = sample_overhangs(m, o);
        std::vector<Vec3> lattice = res.anchors;
        for (const auto& s : res.samples)
            if (s.kind == SampleKind::Face) lattice.push_back(s.p);
        auto open = dense_overhang_points(m, o);
        std::erase_if(open, [&](const Vec3& x) { return covered_by(lattice, x, o); });
        size_t extras = 0;
        for (const auto& s : res.samples) {
            if (s.kind == SampleKind::Face) continue;
            ++extras;
            EXPECT_TRUE(covered_by({s.p}, s.p, o));
            bool needed = std::any_of(open.begin(), open.end(), [&](const Vec3& x) { return covered_by({s.p}, x, o); });
            EXPECT_TRUE(needed) << "extra at " << s.p.x << ", " << s.p.y << ", " << s.p.z;
        }
        total_extras += extras;
    }
    EXPECT_GT(total_extras, 0u);  // the T's rims need some
}

TEST(LeanSampling, TheLowestPointHasASampleAtItsHeight) {
    // The pole of a cap is where it starts printing: a sample within reach and at most half a
    // layer above it carries its first layer (a lattice point, or the pole itself).
    for (double s : {1.5, 2.5, 4.0}) {
        OverhangOptions o{50, s, 0.2};
        auto res = sample_overhangs(uv_sphere({0.3, -0.2, 12}, 8, 14, 22), o);
        ASSERT_FALSE(res.samples.empty());
        const Vec3 pole{0.3, -0.2, 4};
        const Sample& low = res.samples.back();
        EXPECT_LE(horizontal_distance(low.p, pole), coverage_reach(s));
        EXPECT_LE(low.p.z, pole.z + 0.5 * o.bed_height);
    }
}

TEST(LeanSampling, PointsRestingOnMaterialNeedNoExtras) {
    // A slab hovering 0.4 mm over a block (within touching space): every point of its underside
    // rests on the block. With the model index the sampler adds nothing beyond the lattice; without
    // it, it cannot know and samples the rims too.
    Mesh m = box({0.3, 0.3, 0}, {9.7, 9.7, 3});
    append(m, box({0.3, 0.3, 3.4}, {9.7, 9.7, 5}));
    ModelQuery q(m);
    auto o = default_options();
    auto with = sample_overhangs(m, o, &q), without = sample_overhangs(m, o);
    for (const auto& s : with.samples) EXPECT_EQ(s.kind, SampleKind::Face);
    EXPECT_GT(without.samples.size(), with.samples.size());
}

// An underside exactly touching space (2 gaps + 1 layer, 0.6 mm) over the bed does not rest: the
// model.stl a slicer and `check` read is float32, where 0.6 lies 0.6000000238 mm up (bearing_block
// at 0.6x: its flange's lowest line left 1 mm2 beyond reach). A hundredth lower, it rests.
TEST(LeanSampling, AnUndersideExactlyTouchingSpaceOverTheBedDoesNotRest) {
    const OverhangOptions o = default_options();
    ASSERT_NEAR(o.touching_space, 0.6, 1e-12);
    for (const double z : {0.6, 0.59}) {
        const Mesh slab = box({0, 0, z}, {10, 10, 3});
        const ModelQuery q(slab);
        EXPECT_EQ(rests_on_material(q, {5, 5, z}, o.touching_space), z < 0.6) << z;
    }
}

TEST(LeanSampling, PointsInTheAirAreCoveredBySamplesThatGetAContact) {
    // The T with a block under one wing, 0.4 mm below the plate (within touching space): the
    // points over the block rest on it. Every other point has within reach a sample that does not
    // rest (it gets a tip), an inside corner, or a lattice point over the block (the plate is
    // printed onto the block there and bridges from it); never only an off-lattice resting point.
    Mesh m = cs::test::t_shape();
    append(m, box({4.3, -5.3, 0}, {11.3, 5.3, 9.6}));
    ModelQuery q(m);
    OverhangOptions o = default_options();
    auto res = sample_overhangs(m, o, &q);
    std::vector<Vec3> carriers = res.anchors;
    for (const auto& s : res.samples)
        if (s.kind == SampleKind::Face || !rests_on_material(q, s.p, o.touching_space)) carriers.push_back(s.p);
    size_t in_air = 0;
    for (const auto& x : dense_overhang_points(m, o)) {
        if (rests_on_material(q, x, o.touching_space)) continue;
        ++in_air;
        EXPECT_TRUE(covered_by(carriers, x, o)) << "uncovered at " << x.x << ", " << x.y << ", " << x.z;
    }
    EXPECT_GT(in_air, 0u);
    // Extras never stand where they would rest (no tip is built there).
    for (const auto& s : res.samples)
        if (s.kind != SampleKind::Face) EXPECT_FALSE(rests_on_material(q, s.p, o.touching_space));
}

TEST(LeanSampling, CoverageRuleIsHorizontalReachOnTheSameSurface) {
    EXPECT_NEAR(coverage_reach(2.5), 2.5 * std::sqrt(0.5), 1e-12);
    const double reach = coverage_reach(2.0);
    EXPECT_TRUE(covers({0, 0, 5}, {reach, 0, 5}, reach, 50));
    EXPECT_FALSE(covers({0, 0, 5}, {reach + 1e-6, 0, 5}, reach, 50));
    // Up or down the steepest overhang over the reach: still the same surface; beyond: another one.
    const double rise = reach * std::tan(40 * kDeg);
    EXPECT_TRUE(covers({0, 0, 5}, {0, 0, 5 + 0.99 * rise}, reach, 50));
    EXPECT_FALSE(covers({0, 0, 5}, {0, 0, 5 - 1.01 * rise}, reach, 50));
}

TEST(SampleOverhangs, DeterministicAndSortedTopToBottom) {
    // Overhangs at several heights: the T's plate (z 10), a floating box (z 3), a tip (z 6).
    Mesh m = cs::test::t_shape();
    append(m, box({14, -3, 3}, {19, 3, 4}));
    Mesh tip;
    tip.vertices = {{-20, 0, 6}, {-15, 0, 11}, {-20, 5, 11}, {-25, 0, 11}, {-20, -5, 11}, {-20, 0, 16}};
    tip.faces = {{0, 2, 1}, {0, 3, 2}, {0, 4, 3}, {0, 1, 4}, {5, 1, 2}, {5, 2, 3}, {5, 3, 4}, {5, 4, 1}};
    append(m, tip);
    auto a = sample_overhangs(m, default_options());
    auto b = sample_overhangs(m, default_options());
    ASSERT_EQ(a.samples.size(), b.samples.size());
    for (size_t i = 0; i < a.samples.size(); ++i) {
        EXPECT_EQ(a.samples[i].p, b.samples[i].p);
        EXPECT_EQ(a.samples[i].kind, b.samples[i].kind);
    }
    std::set<double> heights;
    for (size_t i = 0; i < a.samples.size(); ++i) {
        heights.insert(a.samples[i].p.z);
        if (i == 0) continue;
        const Vec3 &p = a.samples[i - 1].p, &q = a.samples[i].p;
        bool ordered = p.z > q.z || (p.z == q.z && (p.x < q.x || (p.x == q.x && p.y < q.y)));
        EXPECT_TRUE(ordered) << "sample " << i;
    }
    EXPECT_EQ(heights, (std::set<double>{3, 6, 10}));
}

TEST(SampleOverhangs, ShuffledFaceOrderGivesTheSameSamples) {
    Mesh m = cs::test::t_shape();
    Mesh r = m;
    std::reverse(r.faces.begin(), r.faces.end());
    for (auto& f : r.faces) std::rotate(f.begin(), f.begin() + 1, f.end());
    auto a = sample_overhangs(m, default_options()), b = sample_overhangs(r, default_options());
    ASSERT_EQ(a.samples.size(), b.samples.size());
    for (size_t i = 0; i < a.samples.size(); ++i) EXPECT_EQ(a.samples[i].p, b.samples[i].p);
}

TEST(SampleOverhangs, NothingBelowTheFirstLayer) {
    // The underside of a plate 0.1 mm above the bed is printed on the bed: no samples.
    auto res = sample_overhangs(box({0, 0, 0.1}, {6, 6, 2}), default_options());
    EXPECT_TRUE(res.samples.empty());
}

// ---------------------------------------------------------------- the lattice

TEST(Rasterize, SquareSplitOnItsDiagonalEqualsTheWholeSquare) {
    const double s = 1.5;
    // Corners on lattice points; the diagonal passes through the lattice point (1.5, 1.5).
    Vec3 a{0, 0, 1}, b{3, 0, 1}, c{3, 3, 1}, d{0, 3, 1};
    auto want = half_open_rect(0, 2, 0, 2);
    auto one = coverage({{a, b, c}, {a, c, d}}, s);
    EXPECT_EQ(one, want) << describe(one, want);
    auto other = coverage({{a, b, d}, {b, c, d}}, s);  // the other diagonal
    EXPECT_EQ(other, want) << describe(other, want);
    auto cw = coverage({{a, c, b}, {a, d, c}}, s);  // clockwise input
    EXPECT_EQ(cw, want) << describe(cw, want);
}

TEST(Rasterize, TriangulatedRectangleHasNoGapsNoDoubles) {
    const double s = 1.5;
    // 4 x 3 cells of 2 x 2 lattice steps, diagonals alternating.
    auto got = coverage(split_cells(s, 4, 3, 2, true), s);
    auto want = half_open_rect(0, 8, 0, 6);
    EXPECT_EQ(got, want) << describe(got, want);
}

TEST(Rasterize, NonDyadicSpacingWithCornersOnTheLattice) {
    // Spacing 0.1 and 0.3 are not exact in binary: a cell corner at lattice point i*s must still
    // give that point to exactly one cell (e.g. 3*0.1 / 0.1 rounds to 3.0000000000000004).
    for (double s : {0.1, 0.3, 0.7}) {
        SCOPED_TRACE(s);
        auto got = coverage(split_cells(s, 10, 10, 3, true), s);
        auto want = half_open_rect(0, 30, 0, 30);
        EXPECT_EQ(got, want) << describe(got, want);
    }
}

TEST(Rasterize, FanAroundALatticePointGivesItOnce) {
    const double s = 1.5;
    const Vec3 centre{3, 4.5, 2};
    for (int n : {3, 5, 6, 8, 11}) {
        SCOPED_TRACE(n);
        std::vector<std::array<Vec3, 3>> tris;
        for (int k = 0; k < n; ++k) {
            double a0 = 2 * M_PI * k / n + 0.1, a1 = 2 * M_PI * (k + 1) / n + 0.1;
            double r0 = 2.2 + 0.3 * (k % 3), r1 = 2.2 + 0.3 * ((k + 1) % 3);
            tris.push_back({centre, centre + Vec3{r0 * std::cos(a0), r0 * std::sin(a0), 0.5},
                            centre + Vec3{r1 * std::cos(a1), r1 * std::sin(a1), 0.5}});
        }
        auto got = coverage(tris, s);
        EXPECT_EQ((got[{2, 3}]), 1) << "the centre";
        for (const auto& [k, c] : got) EXPECT_EQ(c, 1) << "at " << k.first << "," << k.second;
    }
}

TEST(Rasterize, FanWithSpokesAlongLatticeLines) {
    // Spokes to the 8 lattice neighbours: every edge runs through lattice points.
    const double s = 1.5;
    auto L = [&](long i, long j) { return Vec3{double(i) * s, double(j) * s, 1}; };
    const long ring[8][2] = {{1, 0}, {1, 1}, {0, 1}, {-1, 1}, {-1, 0}, {-1, -1}, {0, -1}, {1, -1}};
    std::vector<std::array<Vec3, 3>> tris;
    for (int k = 0; k < 8; ++k) {
        const long* p = ring[k];
        const long* q = ring[(k + 1) % 8];
        tris.push_back({L(0, 0), L(2 * p[0], 2 * p[1]), L(2 * q[0], 2 * q[1])});
    }
    auto got = coverage(tris, s);
    auto want = half_open_rect(-2, 2, -2, 2);
    EXPECT_EQ(got, want) << describe(got, want);
}

TEST(Rasterize, SharedEdgesThroughOddPointsAreConsistent) {
    // A strip of thin triangles whose shared edges pass through lattice points at odd slopes.
    const double s = 0.5;
    std::vector<std::array<Vec3, 3>> tris;
    for (int k = 0; k < 12; ++k) {
        Vec3 a{k * 1.0, 0, 1}, b{k * 1.0 + 1.0, 0, 1}, c{k * 1.0 + 3.0, 6, 2}, d{k * 1.0 + 2.0, 6, 2};
        tris.push_back({a, b, d});
        tris.push_back({b, c, d});
    }
    auto got = coverage(tris, s);
    for (const auto& [k, c] : got) EXPECT_EQ(c, 1) << "double at " << k.first << "," << k.second;
    // A parallelogram strip 12 wide at every height: 24 lattice columns per lattice row.
    std::map<long, int> per_row;
    for (const auto& [k, c] : got) ++per_row[k.second];
    for (long j = 0; j < 12; ++j) EXPECT_EQ(per_row[j], 24) << "row " << j;
}

TEST(Rasterize, ZIsTakenFromTheTrianglePlane) {
    std::vector<Vec3> pts;
    rasterize_triangle({0, 0, 1}, {6, 0, 4}, {0, 6, 7}, 1.5, pts);  // z = 1 + x/2 + y
    ASSERT_FALSE(pts.empty());
    for (const auto& p : pts) EXPECT_NEAR(p.z, 1 + p.x / 2 + p.y, 1e-12);
}

TEST(Rasterize, VerticalTriangleHasNoFootprint) {
    std::vector<Vec3> pts;
    rasterize_triangle({0, 0, 0}, {3, 0, 0}, {0, 0, 3}, 1.5, pts);
    EXPECT_TRUE(pts.empty());
}

// ---------------------------------------------------------------- top-up after placement
namespace {

// The samples of a flat 20 x 20 plate hanging 10 mm up, and where their tips stand: on the samples.
struct Plate {
    Mesh mesh = box({0, 0, 10}, {20, 20, 12});
    OverhangOptions o = default_options();
    OverhangSamples sampled = sample_overhangs(mesh, o);
    std::vector<Vec3> tips;
    Plate() {
        for (const auto& s : sampled.samples) tips.push_back(s.p);
    }
};

}  // namespace

TEST(TopUp, SamplesAndTheirTopUpLeaveNoPointBeyondReach) {
    // Judged between the sampler's own points too. The lean pass lets the lattice cover at the
    // full reach, which a cell the overhang only partly fills (the rims of a tilted shaft) can
    // miss by a hair; the top-up, given tips standing on their samples, closes every such gap.
    std::vector<Mesh> shapes{cs::test::t_shape(), cs::test::bridge_shape(), uv_sphere({0.3, -0.2, 12}, 8, 14, 22),
                             lying_cylinder(6, 30, 40, 10, 8, 17)};
    size_t lean_gaps = 0;
    for (double s : {1.5, 2.5})
        for (size_t i = 0; i < shapes.size(); ++i) {
            SCOPED_TRACE("shape " + std::to_string(i) + " spacing " + std::to_string(s));
            OverhangOptions o{50, s, 0.2};
            auto res = sample_overhangs(shapes[i], o);
            lean_gaps += uncovered(shapes[i], res, o, true).size();
            std::vector<Vec3> tips;
            for (const auto& x : res.samples) tips.push_back(x.p);
            for (const auto& x : top_up_samples(shapes[i], o, nullptr, res, tips)) res.samples.push_back(x);
            auto holes = uncovered(shapes[i], res, o, true);
            EXPECT_TRUE(holes.empty()) << holes.size() << " uncovered, first at " << holes[0].x << ", " << holes[0].y
                                       << ", " << holes[0].z;
        }
    EXPECT_GT(lean_gaps, 0u) << "the shapes no longer show what the top-up is for";
}

TEST(TopUp, NothingToAddWhereEveryTipStandsOnItsSample) {
    Plate plate;
    ASSERT_GT(plate.tips.size(), 10u);
    EXPECT_TRUE(top_up_samples(plate.mesh, plate.o, nullptr, plate.sampled, plate.tips).empty());
}

TEST(TopUp, ATipMovedAsideGetsTheGapItLeavesFilled) {
    // Placement moved one tip in the middle of the plate 0.6 mm aside (under a curved overhang it
    // may): the points on its far side are now beyond reach of every tip.
    Plate plate;
    auto moved = std::find_if(plate.tips.begin(), plate.tips.end(), [](const Vec3& t) {
        return std::abs(t.x - 9) < 0.8 && std::abs(t.y - 9) < 0.8;
    });
    ASSERT_NE(moved, plate.tips.end());
    const Vec3 was = *moved;
    moved->x += 0.6;
    auto extra = top_up_samples(plate.mesh, plate.o, nullptr, plate.sampled, plate.tips);
    ASSERT_FALSE(extra.empty());
    // What was added covers every point the move left open, and lies near where the tip was.
    std::vector<Vec3> all = plate.tips;
    for (const auto& s : extra) {
        all.push_back(s.p);
        EXPECT_LT(horizontal_distance(s.p, was), 2 * coverage_reach(plate.o.sampling_distance));
    }
    for (const auto& x : dense_overhang_points(plate.mesh, plate.o, true))
        EXPECT_TRUE(covered_by(all, x, plate.o)) << "uncovered at " << x.x << ", " << x.y;
}

TEST(TopUp, ASampleWhoseSupportDoesNotFitMovesWithinReachToWhereOneDoes) {
    // A tip in the middle of the plate given up (its sample held nothing up): the points around
    // it are beyond the full reach of every other tip. No support fits within 0.5 mm of where the
    // plain top-up puts its samples (a knife edge there, as on the propeller's blade at 80 mm,
    // where the sample on the uncovered point took no tip). Each sample moves to the nearest point
    // of the overhang whose support fits and still covers the point it was for; every point is
    // covered again.
    Plate plate;
    auto gone = std::find_if(plate.tips.begin(), plate.tips.end(), [](const Vec3& t) {
        return std::abs(t.x - 9) < 0.8 && std::abs(t.y - 9) < 0.8;
    });
    ASSERT_NE(gone, plate.tips.end());
    plate.tips.erase(gone);
    const auto first = top_up_samples(plate.mesh, plate.o, nullptr, plate.sampled, plate.tips);
    ASSERT_FALSE(first.empty());
    auto refused = [&](const Vec3& x) {
        return std::any_of(first.begin(), first.end(), [&](const Sample& s) { return horizontal_distance(s.p, x) < 0.5; });
    };
    int asked = 0;
    const SupportAt support_at = [&](const Vec3& x) -> std::optional<Vec3> {
        ++asked;
        if (refused(x)) return std::nullopt;
        return x;  // the tip's top straight under the sample
    };
    const auto extra = top_up_samples(plate.mesh, plate.o, nullptr, plate.sampled, plate.tips, support_at);
    ASSERT_FALSE(extra.empty());
    EXPECT_GT(asked, static_cast<int>(extra.size())) << "the samples' own places were asked first";
    // What holds the plate up: the tips, and the samples whose support fits (a sample left bare
    // where one fits near covers only what the others hold at the full reach).
    std::vector<Vec3> held = plate.tips;
    for (const auto& s : extra)
        if (!refused(s.p)) held.push_back(s.p);
    EXPECT_GT(held.size(), plate.tips.size()) << "no sample moved to where its support fits";
    for (const auto& x : dense_overhang_points(plate.mesh, plate.o))
        EXPECT_TRUE(covered_by(held, x, plate.o)) << "beyond reach at " << x.x << ", " << x.y;
    // Where every support fits, the samples are the plain top-up's.
    const SupportAt fits_everywhere = [](const Vec3& x) -> std::optional<Vec3> { return x; };
    const auto same = top_up_samples(plate.mesh, plate.o, nullptr, plate.sampled, plate.tips, fits_everywhere);
    ASSERT_EQ(same.size(), first.size());
    for (size_t i = 0; i < same.size(); ++i) EXPECT_EQ(same[i].p, first[i].p);
}

// The air below a rim where a wall rises from it, the wall's lowest corner a hair below the rim
// (float STL: the bearing block's counterbore at 60 mm, 1e-4 mm): a ray started just under the
// rim would run inside the wall's plane and meet it at once, as if the rim rested on material.
TEST(AirBelow, AWallRisingFromTheRimIsNotTheFloor) {
    Mesh m;
    m.vertices = {{-1, 0, 20}, {1, 0, 20}, {0, 0, 10 - 5e-4},  // the wall, in the plane y = 0
                  {-5, -5, 2}, {5, -5, 2}, {0, 5, 2}};        // the floor, facing up
    m.faces = {{0, 1, 2}, {3, 4, 5}};
    ModelQuery q(m);
    const Vec3 rim{0, 0, 10};
    EXPECT_NEAR(air_below(q, rim), 8, 1e-9);
    EXPECT_FALSE(rests_on_material(q, rim, 0.6));
}

// Cover takes the rise once; its answer is covers', and within_reach is hypot's <= (points on and
// around the reach's circle and the rise's bounds, where the squares alone would not decide).
TEST(Covers, CoverAndWithinReachAnswerAsCoversAndHypot) {
    const double reach = coverage_reach(2.5);
    for (double angle : {30.0, 45.0, 55.0}) {
        const Cover cover(reach, angle);
        const double rise = surface_rise(reach, angle);
        const Vec3 s{1.1, -2.3, 7.7};
        for (int k = 0; k < 4000; ++k) {
            const double a = 0.0017 * k, r = reach * (0.999 + 0.0000005 * (k % 4001)) * (k % 3 == 0 ? 1.0 : 0.5 + 0.001 * k);
            const double dz = rise * (k % 5 == 0 ? 1.0 : (k % 5 == 1 ? -1.0 : 0.0007 * (k % 2000) - 0.7));
            const Vec3 x{s.x + r * std::cos(a), s.y + r * std::sin(a), s.z + dz};
            EXPECT_EQ(cover(s, x), covers(s, x, reach, angle)) << k;
            EXPECT_EQ(within_reach(s, x, r), horizontal_distance(s, x) <= r) << k;
            EXPECT_EQ(within_reach(s, x, reach), horizontal_distance(s, x) <= reach) << k;
        }
    }
}

namespace {

// The orientation search sorts the model's edges once (edge_uses) and hands them to every pose's
// sampling: the samples must be those the sampling finds sorting them itself, in every pose.
TEST(EdgeUses, SortedOnceTheySampleEachPoseAsSortedThere) {
    const Mesh m = test::keel_shape();
    const EdgeUses edges = edge_uses(m);
    EdgeUses sorted;
    for (std::uint32_t f = 0; f < m.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) sorted.emplace_back(edge_key(m.faces[f][k], m.faces[f][(k + 1) % 3]), f);
    std::sort(sorted.begin(), sorted.end());
    EXPECT_EQ(edges, sorted);
    OverhangOptions o;
    o.sampling_distance = 1.0;
    std::size_t total = 0;
    for (const Vec3& axis : {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{1, 1, 0}}) {
        Mesh turned = m;  // the same faces, the vertices turned 90 degrees about `axis`
        const Vec3 a = normalized(axis);
        for (Vec3& v : turned.vertices) v = a * dot(a, v) + cross(a, v);
        const double floor = bounding_box(turned).min.z;
        for (Vec3& v : turned.vertices) v.z -= floor;  // standing on the bed
        const OverhangSamples own = sample_overhangs(turned, o), given = sample_overhangs(turned, o, nullptr, &edges);
        ASSERT_EQ(own.samples.size(), given.samples.size());
        total += own.samples.size();
        for (std::size_t i = 0; i < own.samples.size(); ++i) {
            EXPECT_TRUE(own.samples[i].p == given.samples[i].p) << i;
            EXPECT_EQ(own.samples[i].kind, given.samples[i].kind) << i;
        }
        EXPECT_EQ(own.ridge_edges, given.ridge_edges);
        EXPECT_EQ(own.edges.size(), given.edges.size());
    }
    EXPECT_GT(total, 20u);  // the poses have overhangs to sample
}

}  // namespace

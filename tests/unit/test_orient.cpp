// Orientation: obvious least-support poses, rigid rotations, `keep`, determinism.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <tbb/global_control.h>

#include "core/errors.hpp"
#include "mesh/repair.hpp"
#include "orient/orient.hpp"
#include "orient/symmetry.hpp"
#include "overhang/overhang.hpp"
#include "pipeline/pipeline.hpp"
#include "support.hpp"

namespace cs::test {
namespace {

Mesh join(std::initializer_list<Mesh> parts) {
    Mesh m;
    for (const auto& p : parts) append(m, p);
    return m;
}

// A closed solid: the counter-clockwise polygon (x, z) swept along y from y0 to y1. Caps are
// triangulated by ear clipping, so the solid has no internal faces (unlike a union of boxes).
Mesh extrude_xz(const std::vector<std::array<double, 2>>& poly, double y0, double y1) {
    const auto n = static_cast<std::uint32_t>(poly.size());
    Mesh m;
    for (double y : {y0, y1})
        for (const auto& q : poly) m.vertices.push_back({q[0], y, q[1]});
    auto cross2 = [&](std::uint32_t a, std::uint32_t b, std::uint32_t c) {
        return (poly[b][0] - poly[a][0]) * (poly[c][1] - poly[a][1]) - (poly[b][1] - poly[a][1]) * (poly[c][0] - poly[a][0]);
    };
    std::vector<std::uint32_t> idx(n);
    for (std::uint32_t i = 0; i < n; ++i) idx[i] = i;
    std::vector<Triangle> cap;
    while (idx.size() > 3) {
        for (size_t i = 0; i < idx.size(); ++i) {
            auto a = idx[(i + idx.size() - 1) % idx.size()], b = idx[i], c = idx[(i + 1) % idx.size()];
            if (cross2(a, b, c) <= 0) continue;
            bool empty = true;
            for (auto q : idx)
                if (q != a && q != b && q != c && cross2(a, b, q) >= 0 && cross2(b, c, q) >= 0 && cross2(c, a, q) >= 0)
                    empty = false;
            if (!empty) continue;
            cap.push_back({a, b, c});
            idx.erase(idx.begin() + static_cast<long>(i));
            break;
        }
    }
    cap.push_back({idx[0], idx[1], idx[2]});
    // The polygon is counter-clockwise in (x, z) seen from -y: the y0 cap faces -y as listed.
    for (auto t : cap) m.faces.push_back({t[0], t[1], t[2]}), m.faces.push_back({n + t[0], n + t[2], n + t[1]});
    for (std::uint32_t i = 0; i < n; ++i) {
        std::uint32_t j = (i + 1) % n;
        m.faces.push_back({i, n + i, n + j});
        m.faces.push_back({i, n + j, j});
    }
    if (signed_volume(m) < 0)
        for (auto& f : m.faces) std::swap(f[1], f[2]);
    return m;
}

Mesh tee() { return extrude_xz({{-3, 0}, {3, 0}, {3, 20}, {15, 20}, {15, 24}, {-15, 24}, {-15, 20}, {-3, 20}}, -5, 5); }

// Runs the real orientation search (overhang area, then support volume of real trees). With
// `answer` the judge answers the search's question as the pipeline does: a pose asked its height
// only grows no tree when it has overhang samples; without, every pose asked grows its tree.
// `trees` (if given) counts the trees grown.
Orientation orient(const Mesh& m, const std::string& mode = "auto", bool answer = false, int* trees = nullptr) {
    Params p;
    std::atomic<int> grown{0};
    Orientation o = choose_orientation(m, p, mode, [&](const Mesh& rotated, const Rotation&, PoseQuestion question) {
        Placement pl;
        Rotation id;
        Mesh placed = place_on_bed(rotated, 1.0, id.m, pl);
        const auto samples = sample_overhangs(placed, overhang_options(p)).samples;
        const double height = bounding_box(placed).size().z;
        if (answer && !samples.empty() && question == PoseQuestion::height_if_it_needs_support)
            return PoseSupport{.grown = false, .height = height};
        ++grown;
        auto s = build_supports(placed, samples, p);
        return PoseSupport{true, s.volume, s.sized.tree.stats.model_contacts, height};
    });
    if (trees) *trees = grown;
    return o;
}

Mesh rotated(const Mesh& m, const Rotation& r) {
    Mesh out = m;
    for (auto& v : out.vertices) v = r.apply(v);
    return out;
}

double placed_overhang_area(const Mesh& m, const Rotation& r) {
    Placement pl;
    Rotation id;
    Mesh placed = place_on_bed(rotated(m, r), 1.0, id.m, pl);
    return sample_overhangs(placed, {50, 1.5, 0.2}).overhang_area;
}

// Upright, a T's wings overhang. Plate down or lying on its flat side it needs nothing; of
// those, the flat side is lower (the tie-break), so that is where it ends.
TEST(Orient, TGoesWhereItNeedsNoSupport) {
    Mesh t = tee();
    ASSERT_GT(placed_overhang_area(t, Rotation{}), 100.0);
    auto o = orient(t);
    EXPECT_LT(placed_overhang_area(t, o.rotation), 1.0);
    EXPECT_NEAR(std::abs(o.rotation.apply({0, 1, 0}).z), 1, 1e-9) << "lying on its flat side";
    EXPECT_EQ(o.decided_by, "height");
}

// Once a pose with an empty tree is found, only poses as low grow their trees (the others' trees
// are most of the search's time on a small part), and the choice is the one growing them all makes.
TEST(Orient, PosesTallerThanOneThatNeedsNothingGrowNoTree) {
    // A trough (a U swept along y) needs nothing opening up (25 mm tall) or standing on either end
    // (40 mm); the fourth pose judged, on its side (40 mm), holds a wall over its other wall. Given
    // upside down, and as is.
    const Mesh trough = extrude_xz({{-20, 0}, {20, 0}, {20, 25}, {17, 25}, {17, 3}, {-17, 3}, {-17, 25}, {-20, 25}}, -20, 20);
    Rotation flip;
    flip.m[1][1] = -1, flip.m[2][2] = -1;
    for (const Mesh& m : {trough, rotated(trough, flip)}) {
        int trees = 0;
        const Orientation answered = orient(m, "auto", true, &trees);
        const Orientation grown = orient(m);
        std::size_t asked = 0, not_grown = 0;
        double lowest_empty = INFINITY;
        for (const auto& c : answered.candidates)
            if (c.evaluated && c.support.grown && c.support.volume == 0) lowest_empty = std::min(lowest_empty, c.support.height);
        for (const auto& c : answered.candidates) {
            asked += c.evaluated;
            if (c.evaluated && !c.support.grown) {
                ++not_grown;
                EXPECT_GT(c.overhang_area, 0) << "a pose with no overhang area is always grown";
                EXPECT_GT(c.support.height, lowest_empty + 1e-6) << "a pose as low as the lowest empty one is grown";
            }
        }
        EXPECT_GT(not_grown, 0u) << "every pose's tree was grown";
        EXPECT_EQ(trees, static_cast<int>(asked - not_grown));
        EXPECT_EQ(answered.chosen, grown.chosen);
        EXPECT_EQ(answered.decided_by, grown.decided_by);
        for (int r = 0; r < 3; ++r)
            for (int c = 0; c < 3; ++c) EXPECT_EQ(answered.rotation.m[r][c], grown.rotation.m[r][c]);
    }
}

// An L lying on its long arm needs nothing; standing on its short arm its long arm overhangs.
TEST(Orient, LLiesOnItsLongArm) {
    Mesh l = extrude_xz({{0, 0}, {20, 0}, {20, 5}, {5, 5}, {5, 40}, {0, 40}}, 0, 10);  // long arm vertical
    auto o = orient(l);
    EXPECT_LT(placed_overhang_area(l, o.rotation), 1.0);
    Placement pl;
    Rotation id;
    Box3 b = bounding_box(place_on_bed(rotated(l, o.rotation), 1.0, id.m, pl));
    EXPECT_LT(b.size().z, 20.5) << "lying down, the L is at most as tall as its short arm";
}

// A bowl (here a trough: a U swept along y) upside down must be turned over, opening up.
TEST(Orient, BowlIsTurnedRightSideUp) {
    Mesh bowl = extrude_xz({{-20, 0}, {20, 0}, {20, 25}, {17, 25}, {17, 3}, {-17, 3}, {-17, 25}, {-20, 25}}, -20, 20);
    Rotation flip;  // upside down: half a turn about X
    flip.m[1][1] = -1, flip.m[2][2] = -1;
    Mesh upside_down = rotated(bowl, flip);
    ASSERT_GT(placed_overhang_area(upside_down, Rotation{}), 1000.0);
    auto o = orient(upside_down);
    EXPECT_LT(placed_overhang_area(upside_down, o.rotation), 1.0);
}

TEST(Orient, RotationIsRigid) {
    Mesh m = tee();
    auto o = orient(m);
    Mesh r = rotated(m, o.rotation);
    EXPECT_NEAR(signed_volume(r), signed_volume(m), 1e-6 * signed_volume(m));
    for (const auto& f : m.faces)
        for (int k = 0; k < 3; ++k) {
            double before = distance(m.vertices[f[k]], m.vertices[f[(k + 1) % 3]]);
            double after = distance(r.vertices[f[k]], r.vertices[f[(k + 1) % 3]]);
            EXPECT_NEAR(before, after, 1e-9);
        }
}

TEST(Orient, KeepChangesNothing) {
    Mesh m = tee();
    auto o = orient(m, "keep");
    EXPECT_EQ(o.decided_by, "kept");
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_EQ(o.rotation.m[i][j], i == j ? 1.0 : 0.0);
}

TEST(Orient, EulerAnglesAreApplied) {
    Mesh m = box({0, 0, 0}, {1, 1, 1});
    auto o = orient(m, "90,0,0");
    EXPECT_EQ(o.decided_by, "given");
    Vec3 y = o.rotation.apply({0, 1, 0});
    EXPECT_NEAR(y.z, 1, 1e-12);  // rotate([90,0,0]) takes +Y to +Z, as in OpenSCAD
    EXPECT_THROW(orient(m, "90,0"), ParameterError);
    EXPECT_THROW(orient(m, "sideways"), ParameterError);
}

TEST(Orient, Deterministic) {
    Mesh m = join({box({0, 0, 0}, {5, 10, 40}), box({5, 0, 0}, {20, 10, 5}), box({-10, 0, 30}, {0, 10, 34})});
    auto a = orient(m), b = orient(m);
    ASSERT_EQ(a.candidates.size(), b.candidates.size());
    EXPECT_EQ(a.chosen, b.chosen);
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) EXPECT_EQ(a.rotation.m[i][j], b.rotation.m[i][j]);
    for (size_t i = 0; i < a.candidates.size(); ++i) EXPECT_EQ(a.candidates[i].overhang_area, b.candidates[i].overhang_area);
}

// Candidates are scored and their trees grown on worker threads: one thread or all, and which
// model comes first in a process, must not change the answer.
TEST(Orient, SameAnswerForAnyThreadCountAndRunOrder) {
    Mesh m = join({box({0, 0, 0}, {5, 10, 40}), box({5, 0, 0}, {20, 10, 5}), box({-10, 0, 30}, {0, 10, 34})});
    Mesh t = tee();
    Orientation many_m = orient(m), many_t = orient(t);
    Orientation one_t, one_m;
    {
        tbb::global_control single(tbb::global_control::max_allowed_parallelism, 1);
        one_t = orient(t);  // the other order
        one_m = orient(m);
    }
    for (auto [a, b] : {std::pair{&many_m, &one_m}, std::pair{&many_t, &one_t}}) {
        ASSERT_EQ(a->candidates.size(), b->candidates.size());
        EXPECT_EQ(a->chosen, b->chosen);
        EXPECT_EQ(a->decided_by, b->decided_by);
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) EXPECT_EQ(a->rotation.m[i][j], b->rotation.m[i][j]);
        for (size_t i = 0; i < a->candidates.size(); ++i) {
            EXPECT_EQ(a->candidates[i].overhang_area, b->candidates[i].overhang_area);
            EXPECT_EQ(a->candidates[i].support.volume, b->candidates[i].support.volume);
        }
    }
}

// CGAL's hull draws from a per-thread random generator that moves on with every call: the
// facets must not show it (this once changed the candidates between one thread and two).
TEST(Orient, HullFacetsDoNotDependOnWhatRanBefore) {
    Mesh m = join({box({0, 0, 0}, {5, 10, 40}), box({5, 0, 0}, {20, 10, 5}), box({-10, 0, 30}, {0, 10, 34})});
    auto first = hull_facets(m.vertices);
    for (int i = 0; i < 3; ++i) hull_facets(tee().vertices);
    auto again = hull_facets(m.vertices);
    ASSERT_EQ(first.size(), again.size());
    for (size_t i = 0; i < first.size(); ++i) {
        EXPECT_EQ(first[i].normal.x, again[i].normal.x);
        EXPECT_EQ(first[i].normal.y, again[i].normal.y);
        EXPECT_EQ(first[i].normal.z, again[i].normal.z);
        EXPECT_EQ(first[i].area, again[i].area);
    }
    // Coplanar hull triangles are one facet: a box's hull has six, whatever its triangulation.
    EXPECT_EQ(hull_facets(box({0, 0, 0}, {3, 4, 5}).vertices).size(), 6u);
    double total = 0;
    for (const auto& f : hull_facets(box({0, 0, 0}, {3, 4, 5}).vertices)) total += f.area;
    EXPECT_NEAR(total, 2 * (12 + 15 + 20), 1e-6);
}

TEST(Orient, RotationToDownTakesTheDirectionToMinusZ) {
    for (Vec3 d : {Vec3{0, 0, -1}, Vec3{0, 0, 1}, Vec3{1, 0, 0}, normalized(Vec3{1, 2, -3}), normalized(Vec3{-0.3, 0.1, 0.9})}) {
        Vec3 r = rotation_to_down(d).apply(d);
        EXPECT_NEAR(r.x, 0, 1e-12);
        EXPECT_NEAR(r.y, 0, 1e-12);
        EXPECT_NEAR(r.z, -1, 1e-12);
    }
}

// A box with a closed cavity: a ceiling to support inside in every pose.
Mesh hollow_box(Vec3 lo, Vec3 hi, Vec3 cavity_lo, Vec3 cavity_hi) {
    Mesh m = box(lo, hi), cavity = box(cavity_lo, cavity_hi);
    for (auto& f : cavity.faces) std::swap(f[1], f[2]);  // facing into the cavity
    append(m, cavity);
    return m;
}

// A 10 mm square prism 10 mm tall whose top is its bottom turned 20 degrees: each side is a bent
// quad, split along the diagonal from its bottom's first corner, or (`one_other`) the last side
// along the other diagonal.
Mesh twisted_prism(bool one_other) {
    Mesh m;
    const Rotation twist = turn_about_z(20);
    const Vec3 corners[4] = {{5, 5, 0}, {-5, 5, 0}, {-5, -5, 0}, {5, -5, 0}};  // counter-clockwise from above
    for (const Vec3& c : corners) m.vertices.push_back(c);
    for (const Vec3& c : corners) m.vertices.push_back(twist.apply(c) + Vec3{0, 0, 10});
    m.faces = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}};
    for (std::uint32_t i = 0; i < 4; ++i) {
        const std::uint32_t b = i, b1 = (i + 1) % 4, t = 4 + i, t1 = 4 + (i + 1) % 4;
        if (one_other && i == 3) m.faces.insert(m.faces.end(), {{b, b1, t}, {b1, t1, t}});
        else m.faces.insert(m.faces.end(), {{b, b1, t1}, {b, t1, t}});
    }
    return m;
}

// Does `r` map the mesh onto itself, within 1e-4 mm?
bool symmetric(const Mesh& m, const Rotation& r) { return SurfaceSymmetry(m, 1e-4).maps_onto_itself(r); }

TEST(Symmetry, QuarterTurnsMapACubeOntoItselfButNotABrickOnItsSide) {
    Rotation about_x;  // a quarter turn about x: y -> z, z -> -y
    about_x.m[1][1] = 0, about_x.m[1][2] = -1, about_x.m[2][1] = 1, about_x.m[2][2] = 0;
    const Mesh cube = box({1000, 1000, 0}, {1010, 1010, 10});  // far from the origin: turned about its own middle
    const Mesh brick = box({0, 0, 0}, {10, 10, 20});
    EXPECT_TRUE(symmetric(cube, turn_about_z(90))) << "its square faces split along other diagonals";
    EXPECT_TRUE(symmetric(cube, about_x));
    EXPECT_TRUE(symmetric(brick, turn_about_z(90)));
    EXPECT_TRUE(symmetric(brick, compose(about_x, about_x))) << "a half turn";
    EXPECT_FALSE(symmetric(brick, about_x));
    EXPECT_FALSE(symmetric(brick, turn_about_z(60)));
    EXPECT_FALSE(symmetric(tee(), turn_about_z(90)));
    EXPECT_TRUE(symmetric(tee(), turn_about_z(180)));
    // The same vertices, the surface between them another: a square prism whose top is twisted
    // 20 degrees, so its sides are not flat; each side splits along one diagonal or the other.
    EXPECT_TRUE(symmetric(twisted_prism(false), turn_about_z(90)));
    EXPECT_FALSE(symmetric(twisted_prism(true), turn_about_z(90))) << "one side bends the other way";
    EXPECT_FALSE(symmetric(box({0, 0, 0}, {10, 10, 10.001}), about_x)) << "a micrometre taller";
    // A cube with one face split in four about an extra vertex at its middle (CSG exports add
    // vertices on one side only): the same surface, so still symmetric.
    Mesh split = box({0, 0, 0}, {10, 10, 10});
    split.vertices.push_back({5, 5, 10});
    std::erase_if(split.faces, [](const Triangle& f) { return f == Triangle{4, 5, 6} || f == Triangle{5, 7, 6}; });
    split.faces.insert(split.faces.end(), {{4, 5, 8}, {5, 7, 8}, {7, 6, 8}, {6, 4, 8}});
    EXPECT_TRUE(symmetric(split, about_x));
}

// A hollow cube needs the same support on any face: its best poses are all one print turned about
// the vertical, and the search grows no tree for them (the Menger sponge's cost two seconds of its
// ten).
TEST(Orient, BestPosesThatAreAllOnePrintGrowNoTree) {
    const Mesh cube = hollow_box({0, 0, 0}, {20, 20, 20}, {5, 5, 5}, {15, 15, 15});
    int trees = 0;
    const Orientation o = orient(cube, "auto", false, &trees);
    EXPECT_EQ(trees, 0);
    EXPECT_EQ(o.chosen, 0u);
    EXPECT_EQ(o.decided_by, "overhang area");
    ASSERT_GE(o.candidates.size(), 4u);
    for (size_t i = 1; i < 4; ++i) EXPECT_EQ(o.candidates[i].same_pose_as, 0) << i;
    for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) EXPECT_EQ(o.rotation.m[r][c], r == c ? 1 : 0) << "the input pose, first of its kind";
}

// A flat hollow box has two prints among its axis poses: on a broad face and on an edge. Then every
// pose is judged, the turned copies too: each is one more placement of the sampling lattice.
TEST(Orient, PosesOfMoreThanOnePrintAreAllJudged) {
    const Mesh flat = hollow_box({0, 0, 0}, {30, 30, 10}, {5, 5, 3}, {25, 25, 7});
    Params p;
    std::atomic<int> trees{0};
    const Orientation o = choose_orientation(
        flat, p, "auto",
        [&](const Mesh& rotated, const Rotation&, PoseQuestion) {
            ++trees;
            Placement pl;
            Rotation id;
            Mesh placed = place_on_bed(rotated, 1.0, id.m, pl);
            auto s = build_supports(placed, sample_overhangs(placed, overhang_options(p)).samples, p);
            return PoseSupport{true, s.volume, s.sized.tree.stats.model_contacts, bounding_box(placed).size().z};
        },
        6);
    EXPECT_EQ(trees, 6);
    ASSERT_EQ(o.candidates.size(), 6u);
    for (const auto& c : o.candidates) {
        EXPECT_TRUE(c.evaluated);
        EXPECT_EQ(c.same_pose_as, -1);
    }
    EXPECT_NEAR(o.rotation.apply({0, 0, 1}).z, 0, 1e-9) << "on an edge: its cavity's roof is 4 mm across, not 20";
}

}  // namespace
}  // namespace cs::test

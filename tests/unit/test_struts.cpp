// struts/ and the sizing rules in core/params: Eqn (1), Murray's rule, the strength rule,
// size_struts' invariants, and body meshes (closed, outward, the right volume and profile).
#include <gtest/gtest.h>

#include <cmath>

#include "check/check.hpp"
#include "core/params.hpp"
#include "core/rules.hpp"
#include "overhang/overhang.hpp"
#include "query/model_query.hpp"
#include "shapes.hpp"
#include "struts/solid_volume.hpp"
#include "struts/struts.hpp"
#include "support.hpp"
#include "tree/tree.hpp"

using namespace cs;

namespace {

// A tree grown by the real sweep on a test shape (the model outlives its query).
struct Grown {
    Mesh model;
    std::unique_ptr<ModelQuery> query;
    SupportTree tree;
};
std::unique_ptr<Grown> grow(const Mesh& model, const Params& p) {
    auto g = std::make_unique<Grown>();
    g->model = model;
    g->query = std::make_unique<ModelQuery>(g->model);
    auto samples = sample_overhangs(g->model, overhang_options(p));
    g->tree = grow_tree(*g->query, samples.samples, p);
    return g;
}

// A hand-made tree: a chain of nodes from `points[0]` (a leaf) down to the last (on the bed).
SupportTree chain(const std::vector<Vec3>& points) {
    SupportTree t;
    for (size_t i = 0; i < points.size(); ++i) {
        Node n;
        n.p = points[i];
        n.kind = i == 0 ? NodeKind::Leaf : i + 1 == points.size() ? NodeKind::Bed : NodeKind::Bend;
        if (i == 0) n.contact = points[0] + Vec3{0, 0, 1.2}, n.tip = points[0] + Vec3{0, 0, 1.0};
        t.nodes.push_back(n);
        if (i > 0) t.struts.push_back({static_cast<int>(i - 1), static_cast<int>(i)});
    }
    return t;
}

// Sizing invariants (struts.hpp): widths never shrink going down, merges carry what comes in, and
// each strut is at least as wide as the strength rule asks for its run.
void expect_sizing_invariants(const SizedTree& s, const Params& p) {
    const auto& t = s.tree;
    ASSERT_EQ(s.struts.size(), t.struts.size());
    ASSERT_EQ(s.node_width.size(), t.nodes.size());
    std::vector<std::vector<size_t>> in(t.nodes.size());
    std::vector<int> out(t.nodes.size(), -1);
    for (size_t e = 0; e < t.struts.size(); ++e) {
        in[t.struts[e].bottom].push_back(e);
        out[t.struts[e].top] = static_cast<int>(e);
    }
    for (size_t e = 0; e < t.struts.size(); ++e) {
        const StrutSize& z = s.struts[e];
        SCOPED_TRACE("strut " + std::to_string(e));
        EXPECT_GE(z.top_width, p.d_min - 1e-12);
        EXPECT_LE(z.top_width, p.d_max + 1e-12);
        EXPECT_LE(z.bottom_width, p.d_max + 1e-12);
        EXPECT_GE(z.bottom_width, z.top_width) << "lower end narrower than the upper";
        EXPECT_GE(z.top_width, std::min(strength_width(p, z.run_length, z.run_angle), p.d_max) - 1e-12)
            << "run " << z.run_length << " mm at " << z.run_angle << " deg";
        EXPECT_GE(z.run_length, z.length - 1e-9);
        EXPECT_GE(z.run_angle, z.angle - 1e-9);
        EXPECT_NEAR(z.length, distance(t.nodes[t.struts[e].top].p, t.nodes[t.struts[e].bottom].p), 1e-9);
        EXPECT_GE(z.bottom_width, eqn1_width(p, z.length, z.angle) - 1e-12);
    }
    for (size_t v = 0; v < t.nodes.size(); ++v) {
        SCOPED_TRACE("node " + std::to_string(v));
        for (size_t e : in[v]) {
            EXPECT_GE(s.node_width[v], s.struts[e].bottom_width - 1e-12) << "a node narrower than what comes in";
            if (out[v] >= 0) EXPECT_GE(s.struts[out[v]].top_width, s.struts[e].bottom_width - 1e-12) << "width shrinks going down";
        }
        if (in[v].size() > 1) {
            std::vector<double> w;
            for (size_t e : in[v]) w.push_back(s.struts[e].bottom_width);
            EXPECT_NEAR(s.node_width[v], merged_width(p, w), 1e-12);
        }
    }
}

double shoelace_n_area(double d, double t) { return t * (2 * d + std::sqrt(2.0) * (d - 2 * t)); }

}  // namespace

// ---------------------------------------------------------------- width rules

TEST(Widths, Eqn1ValuesAndClamping) {
    Params p;  // k 0.0015, d 1..4
    EXPECT_NEAR(eqn1_width(p, 50, 20), 0.0015 * 50 * 20, 1e-12);  // 1.5, inside the clamp
    EXPECT_NEAR(eqn1_width(p, 40, 50), 3.0, 1e-12);
    EXPECT_EQ(eqn1_width(p, 10, 20), p.d_min);  // 0.3 -> d_min
    EXPECT_EQ(eqn1_width(p, 100, 0), p.d_min);  // vertical: d_min
    EXPECT_EQ(eqn1_width(p, 100, 30), p.d_max);  // 4.5 -> d_max
    p.k = 0.003;
    EXPECT_NEAR(eqn1_width(p, 50, 20), 3.0, 1e-12);
    // Monotone in length and angle.
    Params q;
    for (double l = 0; l < 200; l += 7)
        for (double a = 0; a < 50; a += 5) {
            EXPECT_LE(eqn1_width(q, l, a), eqn1_width(q, l + 7, a));
            EXPECT_LE(eqn1_width(q, l, a), eqn1_width(q, l, a + 5));
        }
}

TEST(Widths, MergedWidthValuesAndClamping) {
    Params p;
    EXPECT_NEAR(merged_width(p, {1, 1}), std::cbrt(2.0), 1e-12);
    EXPECT_NEAR(merged_width(p, {1.5, 1.2}), std::cbrt(1.5 * 1.5 * 1.5 + 1.2 * 1.2 * 1.2), 1e-12);
    EXPECT_NEAR(merged_width(p, {2}), 2, 1e-12);
    EXPECT_EQ(merged_width(p, {0.2, 0.3}), p.d_min);
    EXPECT_EQ(merged_width(p, {3, 3, 3}), p.d_max);  // cbrt(81) = 4.33 -> 4
    for (auto w : std::vector<std::vector<double>>{{1, 3}, {2, 2, 1}, {1.1, 1.2, 1.3, 1.4}}) {
        double m = merged_width(p, w);
        for (double x : w) EXPECT_GE(m, x);
    }
}

TEST(Widths, StrengthRuleMatchesThePapersTable) {
    Params p;  // strength_length 30
    // A 1 mm strut is safe to 30 mm at 30 degrees; 1.5 mm to 57 mm at 50 degrees.
    EXPECT_GE(safe_length(p, 1.0, 30), 30 - 1e-12);
    EXPECT_GE(safe_length(p, 1.5, 50), 57);
    EXPECT_LE(strength_width(p, 30, 30), 1.0 + 1e-12);
    EXPECT_LE(strength_width(p, 57, 50), 1.5);
    // Longer or steeper needs wider.
    EXPECT_GT(strength_width(p, 40, 30), 1.0);
    EXPECT_GT(strength_width(p, 30, 60), strength_width(p, 30, 30));
    EXPECT_EQ(strength_width(p, 0, 0), 0);
    // Inverse of each other.
    for (double a : {0.0, 20.0, 30.0, 40.0, 50.0, 70.0}) {
        for (double d : {0.5, 1.0, 1.5, 2.7, 4.0}) EXPECT_NEAR(strength_width(p, safe_length(p, d, a), a), d, 1e-12);
        for (double l : {1.0, 10.0, 30.0, 57.0, 120.0}) EXPECT_NEAR(safe_length(p, strength_width(p, l, a), a), l, 1e-9);
    }
}

// ---------------------------------------------------------------- size_struts

TEST(SizeStruts, TallColumnIsWideEnoughForItsLength) {
    Params p;
    SizedTree s = size_struts(chain({{0, 0, 60}, {0, 0, 0}}), p);
    ASSERT_EQ(s.struts.size(), 1u);
    EXPECT_NEAR(s.struts[0].top_width, std::sqrt(2.0), 1e-12);  // 60 mm vertical: sqrt(60 / 30)
    EXPECT_EQ(s.strength_violations, 0u);
    expect_sizing_invariants(s, p);
}

TEST(SizeStruts, BendsBelongToOneRun) {
    // A 60 mm column with a bend half-way is sized for 60 mm, not for two 30 mm struts.
    Params p;
    SizedTree s = size_struts(chain({{0, 0, 60}, {0, 0, 30}, {5, 0, 0}}), p);
    ASSERT_EQ(s.struts.size(), 2u);
    double run = 30 + std::hypot(5.0, 30.0);
    for (const auto& z : s.struts) {
        EXPECT_NEAR(z.run_length, run, 1e-9);
        EXPECT_GE(z.top_width, strength_width(p, run, z.run_angle) - 1e-12);
    }
    expect_sizing_invariants(s, p);
}

TEST(SizeStruts, TooLongEvenAtDMaxIsCounted) {
    Params p;
    SizedTree s = size_struts(chain({{0, 0, 1000}, {0, 0, 0}}), p);
    EXPECT_EQ(s.strength_violations, 1u);
    EXPECT_EQ(s.struts[0].top_width, p.d_max);
}

TEST(SizeStruts, GrownTreesKeepTheSizingInvariants) {
    Params p;
    for (const Mesh& m : {cs::test::t_shape(), cs::test::bridge_shape(), cs::test::cantilever_over_box()}) {
        auto g = grow(m, p);
        ASSERT_FALSE(g->tree.struts.empty());
        SizedTree s = size_struts(g->tree, p);
        expect_sizing_invariants(s, p);
    }
    // And with a strong Eqn (1) so the lower ends really grow.
    Params k = p;
    k.k = 0.05;
    auto g = grow(cs::test::t_shape(), k);
    SizedTree s = size_struts(g->tree, k);
    expect_sizing_invariants(s, k);
    bool grew = false;
    for (const auto& z : s.struts) grew |= z.bottom_width > z.top_width + 1e-9;
    EXPECT_TRUE(grew);
}

// ---------------------------------------------------------------- bodies

TEST(Bodies, NProfilePrismIsClosedOutwardAndHasTheNArea) {
    const double wall = 0.5;
    for (double d : {1.5, 2.0, 3.0, 4.0}) {
        SCOPED_TRACE(d);
        Body b{BodyKind::Strut, Profile::N, {1, 2, 3}, {1, 2, 13}, d, d};
        Mesh m = body_mesh(b, wall);
        EXPECT_TRUE(is_closed_and_consistent(m));
        // Walls: two bars and the diagonal, less the diagonal's overlap with the bars.
        double want = 10 * shoelace_n_area(d, wall);
        EXPECT_NEAR(signed_volume(m), want, 1e-9 * want);
        EXPECT_NEAR(signed_volume(m), 10 * wall * (2 * d + d * std::sqrt(2.0)), 10 * 2 * std::sqrt(2.0) * wall * wall + 1e-9);
        EXPECT_LT(signed_volume(m), 10 * d * d);  // open gaps between the walls
        Box3 box = bounding_box(m);
        EXPECT_NEAR(box.size().x, d, 1e-12);
        EXPECT_NEAR(box.size().y, d, 1e-12);
        EXPECT_NEAR(box.size().z, 10, 1e-12);
    }
}

TEST(Bodies, SlantedNPrismIsShearedNotRotated) {
    const double wall = 0.5, d = 2.5;
    Body b{BodyKind::Strut, Profile::N, {0, 0, 0}, {4, 3, 8}, d, d};
    Mesh m = body_mesh(b, wall);
    EXPECT_TRUE(is_closed_and_consistent(m));
    EXPECT_NEAR(signed_volume(m), 8 * shoelace_n_area(d, wall), 1e-9);
    // Every vertex is on the bottom or the top plane (horizontal cross-sections).
    for (const auto& v : m.vertices) EXPECT_TRUE(v.z == 0 || v.z == 8);
}

TEST(Bodies, TaperedNPrismIsClosedAndBetweenItsEnds) {
    const double wall = 0.5;
    Body b{BodyKind::Strut, Profile::N, {0, 0, 0}, {2, -1, 12}, 4.0, 1.6};
    Mesh m = body_mesh(b, wall);
    EXPECT_TRUE(is_closed_and_consistent(m));
    double v = signed_volume(m);
    EXPECT_GT(v, 12 * shoelace_n_area(1.6, wall));
    EXPECT_LT(v, 12 * shoelace_n_area(4.0, wall));
}

TEST(Bodies, SquareFrustaAndTipsAreExact) {
    struct Case {
        Vec3 bottom, top;
        double wb, wt;
    };
    const Case cases[] = {{{0, 0, 0}, {0, 0, 10}, 1.0, 1.0},    // column
                          {{0, 0, 5}, {0, 0, 6}, 2.0, 0.8},     // tip: narrow at the top
                          {{0, 0, 5}, {0, 0, 6}, 0.8, 2.0},     // contact tip: narrow at the bottom
                          {{1, 1, 0}, {6, -2, 7}, 1.4, 1.0},    // slanted, tapered
                          {{0, 0, 0}, {0.5, 0, 1}, 4.0, 1.0}};  // a foot
    for (const auto& c : cases) {
        Body b{BodyKind::Tip, Profile::Square, c.bottom, c.top, c.wb, c.wt};
        Mesh m = body_mesh(b, 0.5);
        EXPECT_TRUE(is_closed_and_consistent(m));
        double h = c.top.z - c.bottom.z, A = c.wb * c.wb, B = c.wt * c.wt;
        EXPECT_NEAR(signed_volume(m), h / 3 * (A + B + std::sqrt(A * B)), 1e-9);
    }
}

TEST(Bodies, ProfileIsNOnlyWhenWideEnough) {
    Params p;
    EXPECT_NEAR(min_n_width(p), 3 * p.wall_thickness, 1e-12);
    for (double d_min : {1.0, 1.5, 2.0}) {
        SCOPED_TRACE(d_min);
        Params q = p;
        q.d_min = d_min;
        SizedTree s = size_struts(chain({{0, 0, 20}, {0, 0, 10}, {3, 0, 0}}), q);
        auto bodies = build_bodies(s, q);
        size_t struts = 0;
        for (const auto& b : bodies) {
            if (b.kind != BodyKind::Strut) {
                EXPECT_EQ(b.profile, Profile::Square);
                continue;
            }
            ++struts;
            bool wide = std::min(b.top_width, b.bottom_width) >= min_n_width(q);
            EXPECT_EQ(b.profile, wide ? Profile::N : Profile::Square) << b.top_width << " / " << b.bottom_width;
        }
        EXPECT_EQ(struts, 2u);
    }
}

TEST(Bodies, GrownTreeBodiesAreClosedOutwardSolids) {
    Params p;
    p.d_min = 1.6;  // so both profiles occur
    auto g = grow(cs::test::t_shape(), p);
    SizedTree s = size_struts(g->tree, p);
    auto bodies = build_bodies(s, p);
    size_t tips = 0, strut_bodies = 0, leaves = 0;
    for (const auto& n : s.tree.nodes) leaves += n.kind == NodeKind::Leaf;
    for (const auto& b : bodies) {
        Mesh m = body_mesh(b, p.wall_thickness);
        EXPECT_TRUE(is_closed_and_consistent(m));
        EXPECT_GT(signed_volume(m), 0);
        EXPECT_GE(b.top.z, b.bottom.z);
        tips += b.kind == BodyKind::Tip;
        strut_bodies += b.kind == BodyKind::Strut;
        if (b.kind == BodyKind::Tip) EXPECT_NEAR(b.top_width, p.tip_diameter, 1e-12);
    }
    EXPECT_EQ(tips, leaves);
    EXPECT_EQ(strut_bodies, s.tree.struts.size());
    // All of them in one mesh: separate closed shells whose volumes add.
    Mesh all = bodies_mesh(bodies, p.wall_thickness);
    double sum = 0;
    for (const auto& b : bodies) sum += signed_volume(body_mesh(b, p.wall_thickness));
    EXPECT_NEAR(signed_volume(all), sum, 1e-6 * sum);
    EXPECT_EQ(split_shells(all).size(), bodies.size());
}

TEST(Bodies, FootExtraKeepsClearanceOrIsDropped) {
    Params p;  // foot_extra 1.5, clearance 0.3
    EXPECT_EQ(foot_extra(p, 1.0, INFINITY), p.foot_extra);
    EXPECT_EQ(foot_extra(p, 1.0, 0.5), 0);  // no room: no foot
    double room = 3.0, extra = foot_extra(p, 1.0, room);
    EXPECT_GT(extra, 0);
    EXPECT_LE((0.5 * 1.0 + extra) * std::sqrt(2.0) + p.model_clearance, room + 1e-12);
}

// ---------------------------------------------------------------- solid_volume

namespace {
// Whether p is inside the closed mesh m: parity of a +x ray's crossings (a check that shares
// nothing with solid_volume's slices and rows).
bool inside_mesh(const Mesh& m, const Vec3& p) {
    int crossings = 0;
    for (const auto& f : m.faces) {
        const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &c = m.vertices[f[2]];
        // Barycentric test in the y-z plane, then the hit must lie at x > p.x.
        double d = (b.y - a.y) * (c.z - a.z) - (c.y - a.y) * (b.z - a.z);
        if (d == 0) continue;
        double u = ((p.y - a.y) * (c.z - a.z) - (c.y - a.y) * (p.z - a.z)) / d;
        double v = ((b.y - a.y) * (p.z - a.z) - (p.y - a.y) * (b.z - a.z)) / d;
        if (u < 0 || v < 0 || u + v > 1) continue;
        if (a.x + u * (b.x - a.x) + v * (c.x - a.x) > p.x) ++crossings;
    }
    return crossings % 2 == 1;
}
// The union's volume by counting lattice points (cell centres, spacing h) inside any body.
double lattice_union_volume(const std::vector<Body>& bodies, double wall, double h) {
    std::vector<Mesh> meshes;
    Box3 box;
    for (const auto& b : bodies) {
        meshes.push_back(body_mesh(b, wall));
        for (const auto& v : meshes.back().vertices) box.add(v);
    }
    long count = 0;
    // Odd offsets keep the lattice off the bodies' corners and axis-aligned walls.
    for (double z = box.min.z + 0.37 * h; z < box.max.z; z += h)
        for (double y = box.min.y + 0.41 * h; y < box.max.y; y += h)
            for (double x = box.min.x + 0.53 * h; x < box.max.x; x += h)
                for (const auto& m : meshes)
                    if (inside_mesh(m, {x, y, z})) {
                        ++count;
                        break;
                    }
    return count * h * h * h;
}
double bodies_sum(const std::vector<Body>& bodies, double wall) {
    double v = 0;
    for (const auto& b : bodies) v += signed_volume(body_mesh(b, wall));
    return v;
}
}  // namespace

TEST(SolidVolume, OverlappingCubesCountTheOverlapOnce) {
    std::vector<Body> cubes = {{BodyKind::Strut, Profile::Square, {0, 0, 0}, {0, 0, 1}, 1, 1},
                               {BodyKind::Strut, Profile::Square, {0.5, 0, 0}, {0.5, 0, 1}, 1, 1}};
    EXPECT_NEAR(bodies_sum(cubes, 0.5), 2.0, 1e-12);
    EXPECT_NEAR(solid_volume(cubes, 0.5), 1.5, 1e-9);
    // Shifted half-way up as well: a quarter of a cube in common.
    cubes[1].bottom.z = 0.5;
    cubes[1].top.z = 1.5;
    EXPECT_NEAR(solid_volume(cubes, 0.5), 1.75, 1e-9);
}

TEST(SolidVolume, ApartBodiesAddUpExactly) {
    std::vector<Body> apart = {{BodyKind::Strut, Profile::N, {0, 0, 0}, {2, 1, 6}, 2.0, 2.0},
                               {BodyKind::Tip, Profile::Square, {10, 0, 3}, {10, 0, 4}, 0.8, 1.0},
                               {BodyKind::Strut, Profile::Square, {0, 10, 0}, {0, 10, 0.05}, 1.0, 1.0}};  // thinner than a slice
    EXPECT_NEAR(solid_volume(apart, 0.5), bodies_sum(apart, 0.5), 1e-9 * bodies_sum(apart, 0.5));
    EXPECT_EQ(solid_volume({}, 0.5), 0.0);
}

TEST(SolidVolume, AJointMatchesAnIndependentLatticeCount) {
    // Two slanted N struts merging into a wider square strut, each reaching into the joint, a tip
    // on one leaf: the overlaps of a real merge.
    const double wall = 0.5;
    std::vector<Body> joint = {{BodyKind::Strut, Profile::N, {0, 0, 4.3}, {-3, 0.5, 9}, 1.6, 1.6},
                               {BodyKind::Strut, Profile::N, {0, 0, 4.3}, {2.5, -1, 8}, 1.8, 1.6},
                               {BodyKind::Strut, Profile::Square, {0, 0, 0}, {0, 0, 5}, 2.2, 2.0},
                               {BodyKind::Tip, Profile::Square, {-3, 0.5, 8.8}, {-3, 0.5, 10}, 1.6, 0.8}};
    const double sum = bodies_sum(joint, wall), solid = solid_volume(joint, wall);
    const double lattice = lattice_union_volume(joint, wall, 0.04);
    EXPECT_LT(solid, sum * 0.97) << "the overlaps are several percent of this joint";
    EXPECT_NEAR(solid, lattice, 0.01 * lattice);
}

TEST(SolidVolume, GrownTreeSolidIsAtMostTheSumAndDeterministic) {
    Params p;
    auto g = grow(test::table_shape(), p);
    auto bodies = build_bodies(size_struts(g->tree, p), p);
    ASSERT_GT(bodies.size(), 10u);
    const double solid = solid_volume(bodies, p.wall_thickness), sum = bodies_sum(bodies, p.wall_thickness);
    EXPECT_LE(solid, sum * (1 + 1e-12));
    EXPECT_GT(solid, 0.8 * sum);
    EXPECT_EQ(solid, solid_volume(bodies, p.wall_thickness));
}

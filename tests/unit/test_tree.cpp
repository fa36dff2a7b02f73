// tree/: cone merging (algorithm.md section 3) and the grown support tree's invariants.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include "overhang/overhang.hpp"
#include "pipeline/pipeline.hpp"
#include "struts/struts.hpp"
#include "query/model_query.hpp"
#include "shapes.hpp"
#include "support.hpp"
#include "tree/clearance.hpp"
#include "tree/slicer_cost.hpp"
#include "core/slicer_time.hpp"
#include "tree/tree.hpp"

using namespace cs;

namespace {

constexpr double kDeg = M_PI / 180.0;

// Height of the highest point of the intersection of the downward cones at a and b above (x, y).
double cones_top_at(const Vec3& a, const Vec3& b, double tan_c, double x, double y) {
    Vec3 q{x, y, 0};
    return std::min(a.z - horizontal_distance(a, q) / tan_c, b.z - horizontal_distance(b, q) / tan_c);
}

void expect_on_cone(const Vec3& apex, const Vec3& s, double tan_c) {
    EXPECT_LE(s.z, apex.z);
    EXPECT_NEAR(horizontal_distance(apex, s), (apex.z - s.z) * tan_c, 1e-9);
}

struct Grown {
    Mesh model;
    std::unique_ptr<ModelQuery> query;
    OverhangSamples samples;
    SupportTree tree;
};

// The placed model must outlive its ModelQuery: both live in the returned object.
std::unique_ptr<Grown> grow(const Mesh& model, const Params& p) {
    auto g = std::make_unique<Grown>();
    g->model = model;
    g->query = std::make_unique<ModelQuery>(g->model);
    g->samples = sample_overhangs(g->model, overhang_options(p));
    g->tree = grow_tree(*g->query, g->samples.samples, p);
    return g;
}

// Invariants every grown tree keeps (algorithm.md section 3 (a), (b)).
void expect_valid_tree(const Grown& g, const Params& p) {
    const auto& t = g.tree;
    ASSERT_FALSE(t.struts.empty());
    std::vector<int> out(t.nodes.size(), 0), in(t.nodes.size(), 0);
    for (size_t e = 0; e < t.struts.size(); ++e) {
        const auto& s = t.struts[e];
        ASSERT_GE(s.top, 0);
        ASSERT_GE(s.bottom, 0);
        ASSERT_LT(static_cast<size_t>(s.top), t.nodes.size());
        ASSERT_LT(static_cast<size_t>(s.bottom), t.nodes.size());
        const Vec3 &a = t.nodes[s.top].p, &b = t.nodes[s.bottom].p;
        SCOPED_TRACE("strut " + std::to_string(e) + " from (" + std::to_string(a.x) + "," + std::to_string(a.y) + "," +
                     std::to_string(a.z) + ") to (" + std::to_string(b.x) + "," + std::to_string(b.y) + "," +
                     std::to_string(b.z) + ")");
        EXPECT_GT(a.z, b.z) << "strut does not go down";
        EXPECT_LE(angle_from_vertical_deg(a, b), p.critical_angle + 1e-6);
        EXPECT_FALSE(g.query->segment_hits(a, b)) << "strut axis passes through the model";
        EXPECT_GE(b.z, -1e-12);
        ++out[s.top];
        ++in[s.bottom];
    }
    std::set<std::tuple<double, double, double>> sample_points;
    for (const auto& s : g.samples.samples) sample_points.insert({s.p.x, s.p.y, s.p.z});
    std::set<std::tuple<double, double, double>> leaf_contacts;
    for (size_t v = 0; v < t.nodes.size(); ++v) {
        const Node& n = t.nodes[v];
        SCOPED_TRACE("node " + std::to_string(v));
        EXPECT_LE(out[v], 1) << "a node with two struts below it";
        switch (n.kind) {
            case NodeKind::Leaf:
                EXPECT_TRUE(sample_points.count({n.contact.x, n.contact.y, n.contact.z})) << "leaf without a sample";
                EXPECT_TRUE(leaf_contacts.insert({n.contact.x, n.contact.y, n.contact.z}).second) << "two leaves, one sample";
                EXPECT_EQ(out[v], 1);
                EXPECT_LT(n.p.z, n.contact.z);
                EXPECT_LT(n.tip.z, n.contact.z);
                EXPECT_GE(n.tip.z, n.p.z);
                break;
            case NodeKind::Merge:
                EXPECT_GE(in[v], 2);
                EXPECT_EQ(out[v], 1);
                break;
            case NodeKind::Bend:
                EXPECT_GE(in[v], 1);
                EXPECT_EQ(out[v], 1);
                break;
            case NodeKind::Bed:
                EXPECT_NEAR(n.p.z, 0, 1e-9);
                EXPECT_EQ(out[v], 0);
                EXPECT_GE(in[v], 1);
                break;
            case NodeKind::ModelContact:
                EXPECT_EQ(out[v], 0);
                EXPECT_GE(in[v], 1);
                EXPECT_GT(n.p.z, n.contact.z);
                EXPECT_NEAR(std::sqrt(g.query->squared_distance(n.contact)), 0, 1e-6) << "contact not on the model";
                break;
            case NodeKind::Dropped:  // given up: nothing is built from or into it
                EXPECT_EQ(out[v], 0);
                EXPECT_EQ(in[v], 0);
                break;
        }
    }
}

// Every path from a leaf ends on the bed or on the model.
void expect_every_leaf_reaches_ground(const SupportTree& t) {
    std::vector<int> down(t.nodes.size(), -1);
    for (const auto& s : t.struts) down[s.top] = s.bottom;
    for (size_t v = 0; v < t.nodes.size(); ++v) {
        if (t.nodes[v].kind != NodeKind::Leaf) continue;
        int x = static_cast<int>(v);
        for (size_t guard = 0; down[x] >= 0 && guard <= t.nodes.size(); ++guard) x = down[x];
        EXPECT_TRUE(t.nodes[x].kind == NodeKind::Bed || t.nodes[x].kind == NodeKind::ModelContact) << "leaf " << v;
    }
}

void expect_same_tree(const SupportTree& a, const SupportTree& b) {
    ASSERT_EQ(a.nodes.size(), b.nodes.size());
    ASSERT_EQ(a.struts.size(), b.struts.size());
    for (size_t i = 0; i < a.nodes.size(); ++i) {
        EXPECT_EQ(a.nodes[i].p, b.nodes[i].p);
        EXPECT_EQ(a.nodes[i].kind, b.nodes[i].kind);
        EXPECT_EQ(a.nodes[i].contact, b.nodes[i].contact);
    }
    for (size_t i = 0; i < a.struts.size(); ++i) {
        EXPECT_EQ(a.struts[i].top, b.struts[i].top);
        EXPECT_EQ(a.struts[i].bottom, b.struts[i].bottom);
    }
    EXPECT_EQ(a.pillars.size(), b.pillars.size());
}

size_t count_kind(const SupportTree& t, NodeKind k) {
    size_t n = 0;
    for (const auto& node : t.nodes) n += node.kind == k;
    return n;
}

}  // namespace

// ---------------------------------------------------------------- merge_point

TEST(MergePoint, BInsideAsConeReturnsB) {
    const double t = std::tan(50 * kDeg);
    Vec3 a{0, 0, 10}, b{1, 2, 5};
    EXPECT_EQ(merge_point(a, b, t), b);
    // Straight below, and exactly on the cone's boundary.
    EXPECT_EQ(merge_point(a, Vec3{0, 0, 3}, t), (Vec3{0, 0, 3}));
    Vec3 edge{5 * t, 0, 5};
    EXPECT_EQ(merge_point(a, edge, t), edge);
}

TEST(MergePoint, OutsideConeMeetsOnTheVerticalPlaneAtTheFormulaHeight) {
    // Exact numbers with tan = 1: z_s = (10 + 8 - 10) / 2 = 4, 6 mm from a towards b.
    Vec3 s = merge_point({0, 0, 10}, {10, 0, 8}, 1.0);
    EXPECT_NEAR(s.x, 6, 1e-12);
    EXPECT_NEAR(s.y, 0, 1e-12);
    EXPECT_NEAR(s.z, 4, 1e-12);
    // Equal heights: half-way between, D / (2 t) below.
    Vec3 m = merge_point({0, 0, 10}, {4, 0, 10}, 1.0);
    EXPECT_NEAR(m.x, 2, 1e-12);
    EXPECT_NEAR(m.z, 8, 1e-12);
}

TEST(MergePoint, GeneralCaseIsTheHighestPointOfBothCones) {
    const double t = std::tan(50 * kDeg);
    const Vec3 cases[][2] = {{{1, 2, 20}, {9, -4, 17}}, {{-3, 5, 8}, {4, 9, 8}}, {{0, 0, 30}, {-40, -10, 5}},
                             {{2.5, 2.5, 12}, {2.5, 9.5, 11.9}}};
    for (const auto& c : cases) {
        const Vec3 a = c[0], b = c[1];
        const double D = horizontal_distance(a, b);
        ASSERT_GT(D, (a.z - b.z) * t) << "case must be outside the cone";
        Vec3 s = merge_point(a, b, t);
        // Height from algorithm.md: z_s = (z1 + z2 - D/t) / 2.
        EXPECT_NEAR(s.z, (a.z + b.z - D / t) / 2, 1e-9);
        // On the vertical plane through both apexes, between them.
        Vec3 ab{b.x - a.x, b.y - a.y, 0}, as{s.x - a.x, s.y - a.y, 0};
        EXPECT_NEAR(cross(ab, as).z, 0, 1e-9);
        EXPECT_GE(dot(ab, as), 0);
        EXPECT_LE(horizontal_distance(a, s), D + 1e-9);
        // On the boundary of both cones.
        expect_on_cone(a, s, t);
        expect_on_cone(b, s, t);
        // No point in both cones is higher (brute force over a fine XY grid around the apexes).
        double best = -INFINITY;
        for (double x = std::min(a.x, b.x) - 2; x <= std::max(a.x, b.x) + 2; x += 0.05)
            for (double y = std::min(a.y, b.y) - 2; y <= std::max(a.y, b.y) + 2; y += 0.05)
                best = std::max(best, cones_top_at(a, b, t, x, y));
        EXPECT_LE(best, s.z + 1e-9);
        EXPECT_GE(best, s.z - 0.1);
    }
}

TEST(MergePoint, StrutsToTheMergePointAreWithinTheCriticalAngle) {
    const double angle = 50, t = std::tan(angle * kDeg);
    Vec3 a{0, 0, 10}, b{7, 3, 9};
    Vec3 s = merge_point(a, b, t);
    EXPECT_NEAR(angle_from_vertical_deg(a, s), angle, 1e-9);
    EXPECT_NEAR(angle_from_vertical_deg(b, s), angle, 1e-9);
}

// ---------------------------------------------------------------- helpers of the sweep

TEST(TreeHelpers, TouchingSpaceAndContactTolerance) {
    Params p;
    EXPECT_NEAR(touching_space(p), 2 * 0.2 + 0.2, 1e-12);
    EXPECT_GT(contact_tolerance(p), p.gap);
}

// The leaves judge what rests as the sampling does (core/rules.hpp rests_at): a slab exactly
// touching space over the bed is no touching overhang (the float32 file puts it a hair higher,
// where `check` finds nothing resting); a hundredth lower it is.
TEST(TreeHelpers, ASlabExactlyTouchingSpaceOverTheBedIsNotTouching) {
    Params p;
    for (const double z : {touching_space(p), touching_space(p) - 0.01}) {
        const auto g = grow(cs::test::box({0, 0, z}, {10, 10, 3}), p);
        ASSERT_FALSE(g->samples.samples.empty());
        EXPECT_EQ(g->tree.stats.touching == 0, z == touching_space(p)) << z << ": " << g->tree.stats.touching << " touching";
    }
}

TEST(TreeHelpers, StrutIsClearAwayFromTheModelNotThroughIt) {
    Mesh m = cs::test::box({0, 0, 0}, {10, 10, 10});
    ModelQuery q(m);
    EXPECT_TRUE(strut_is_clear(q, {20, 5, 15}, 1, {20, 5, 0}, 1, 0.3));
    EXPECT_FALSE(strut_is_clear(q, {5, 5, 15}, 1, {5, 5, 5}, 1, 0.3));       // axis into the box
    EXPECT_FALSE(strut_is_clear(q, {10.6, 5, 15}, 1, {10.6, 5, 0}, 1, 0.3));  // edges within the clearance
    EXPECT_TRUE(strut_is_clear(q, {11.5, 5, 15}, 1, {11.5, 5, 0}, 1, 0.3));
}

// A strut onto the model ends a tip's length above it; a thin ridge of the model rising between
// the strut's edges into its foot must still stop it.
TEST(TreeHelpers, StrutOntoTheModelKeepsARidgeOutOfItsFoot) {
    Mesh m = cs::test::box({0, 0, 0}, {20, 10, 5});
    // A ridge up to z = 5.95: just under the strut's end at z = 6, but above the bottom of the
    // built body, which reaches half a layer past its node.
    append(m, cs::test::box({10.4, 4.5, 4.9}, {10.6, 5.5, 5.95}));
    ModelQuery q(m);
    // Foot 2 mm wide at z = 6 over x = 10: the ridge at x = 10.5 is inside its square, between
    // its corner lines, and beside its axis.
    EXPECT_FALSE(strut_is_clear(q, {10, 5, 15}, 2, {10, 5, 6}, 2, 0.0, /*onto_model=*/true));
    // The same strut 3 mm away has the ridge outside its square.
    EXPECT_TRUE(strut_is_clear(q, {7, 5, 15}, 2, {7, 5, 6}, 2, 0.0, /*onto_model=*/true));
}

// ---------------------------------------------------------------- grow_tree

TEST(GrowTree, TShapeKeepsEveryInvariant) {
    Params p;
    p.sampling_distance = 1.5;  // dense enough that many cones meet: merges are what this pins down
    auto g = grow(cs::test::t_shape(), p);
    ASSERT_GT(g->samples.samples.size(), 50u);
    expect_valid_tree(*g, p);
    expect_every_leaf_reaches_ground(g->tree);
    EXPECT_GT(g->tree.stats.merges, 0u);
    // Under the plate there is only the bed: no model contacts.
    EXPECT_EQ(count_kind(g->tree, NodeKind::ModelContact), 0u);
    // Samples over the stem do not exist (the underside there is no surface); every sample is
    // either a leaf, a pillar, touching, internal or dropped.
    const auto& st = g->tree.stats;
    EXPECT_EQ(count_kind(g->tree, NodeKind::Leaf) + count_kind(g->tree, NodeKind::Dropped) + st.pillars + st.touching +
                  st.internal,
              g->samples.samples.size());
    EXPECT_EQ(st.dropped, 0u);
}

TEST(GrowTree, BridgeKeepsEveryInvariant) {
    Params p;
    auto g = grow(cs::test::bridge_shape(), p);
    ASSERT_GT(g->samples.samples.size(), 20u);
    expect_valid_tree(*g, p);
    expect_every_leaf_reaches_ground(g->tree);
    EXPECT_EQ(g->tree.stats.dropped, 0u);
}

TEST(GrowTree, CantileverKeepsEveryInvariant) {
    Params p;
    auto g = grow(cs::test::cantilever_over_box(), p);
    expect_valid_tree(*g, p);
    expect_every_leaf_reaches_ground(g->tree);
}

TEST(GrowTree, OtherCriticalAnglesKeepTheirAngle) {
    for (double angle : {30.0, 60.0}) {
        SCOPED_TRACE(angle);
        Params p;
        p.critical_angle = angle;
        auto g = grow(cs::test::bridge_shape(), p);
        expect_valid_tree(*g, p);
    }
}

TEST(GrowTree, IsDeterministic) {
    Params p;
    for (const Mesh& m : {cs::test::t_shape(), cs::test::cantilever_over_box()}) {
        auto a = grow(m, p), b = grow(m, p);
        expect_same_tree(a->tree, b->tree);
        EXPECT_EQ(a->tree.total_length(), b->tree.total_length());
    }
}

TEST(GrowTree, TreeIsShorterThanColumns) {
    Params tree, columns;
    columns.strategy = Strategy::columns;
    for (const Mesh& m : {cs::test::t_shape(), cs::test::bridge_shape()}) {
        auto t = grow(m, tree), c = grow(m, columns);
        EXPECT_GT(c->tree.total_length(), 0);
        EXPECT_LT(t->tree.total_length(), c->tree.total_length());
        // Columns: no merges, every strut vertical.
        EXPECT_EQ(c->tree.stats.merges, 0u);
        for (const auto& s : c->tree.struts)
            EXPECT_NEAR(angle_from_vertical_deg(c->tree.nodes[s.top].p, c->tree.nodes[s.bottom].p), 0, 1e-9);
    }
}

TEST(GrowTree, SupportsOnModelLandOnTheLowBox) {
    Params p;
    auto g = grow(cs::test::cantilever_over_box(), p);
    EXPECT_GT(count_kind(g->tree, NodeKind::ModelContact), 0u) << "the low box is right under the cantilever";
    EXPECT_EQ(g->tree.stats.model_contacts, count_kind(g->tree, NodeKind::ModelContact));
}

TEST(GrowTree, BuildplateOnlyNeverLandsOnTheModel) {
    Params p;
    p.supports_on_model = false;
    auto g = grow(cs::test::cantilever_over_box(), p);
    expect_valid_tree(*g, p);
    expect_every_leaf_reaches_ground(g->tree);
    EXPECT_EQ(count_kind(g->tree, NodeKind::ModelContact), 0u);
    EXPECT_EQ(g->tree.stats.model_contacts, 0u);
    EXPECT_EQ(g->tree.stats.dropped, 0u) << "samples given up although the bed is reachable around the box";
    EXPECT_EQ(g->tree.stats.dropped_branches, 0u);
    EXPECT_GT(count_kind(g->tree, NodeKind::Bed), 0u);
    for (const auto& pl : g->tree.pillars) EXPECT_FALSE(pl.on_model);
}

TEST(GrowTree, ALaterNodeOnAColumnToTheBedJoinsItInsteadOfSharingItsFoot) {
    // A sample 20 mm up whose leaf goes straight down through a 5 mm slot between two slabs, and
    // one under each slab, 3.5 mm either side of it: the upper leaf cannot reach them past the slabs,
    // and the two meet under the slot, on its column. That merge went straight down to the same
    // foot: two struts whose end caps are the same faces, one torn solid (menger_sponge3 with
    // --buildplate-only). It joins the column instead: one foot, carrying all three.
    Mesh m = cs::test::box({-10, -5, 12}, {-2.5, 5, 13});
    append(m, cs::test::box({2.5, -5, 12}, {10, 5, 13}));
    append(m, cs::test::box({-1, -1, 20}, {1, 1, 21}));
    Params p;
    p.supports_on_model = false;  // as there: else the upper leaf stands on a slab
    ModelQuery q(m);
    const std::vector<Sample> samples{{{0, 0, 20}, SampleKind::Face}, {{-3.5, 0, 12}, SampleKind::Face}, {{3.5, 0, 12}, SampleKind::Face}};
    const SupportTree t = grow_tree(q, samples, p);
    EXPECT_EQ(count_kind(t, NodeKind::Leaf), 3u);
    EXPECT_EQ(t.stats.dropped, 0u);
    ASSERT_EQ(count_kind(t, NodeKind::Bed), 1u) << "a foot of its own beside the column's";
    std::vector<int> struts_into(t.nodes.size(), 0);
    for (const Strut& s : t.struts) ++struts_into[s.bottom];
    for (std::size_t v = 0; v < t.nodes.size(); ++v)
        if (t.nodes[v].kind == NodeKind::Bed) EXPECT_EQ(struts_into[v], 1) << "two struts end on one foot";
}

TEST(GrowTree, ADeadEndLosesOnlyTheLeavesThatCannotGetDownAlone) {
    // A U on its side, open at the front and both ends: a 27 x 30 ceiling 30 mm up, anchored on
    // the back wall, with the U's bottom arm right under it. Buildplate-only, every branch has to
    // leave sideways. A trunk merged under the middle of the ceiling is too wide to get out; its
    // leaves then go down again alone, and each one finds a way (earlier the whole branch, over a
    // hundred samples, was given up).
    Params p;
    p.supports_on_model = false;
    Mesh m = cs::test::box({0, 0, 0}, {30, 30, 3});
    append(m, cs::test::box({0, 0, 3}, {30, 3, 30}));
    append(m, cs::test::box({0, 0, 30}, {30, 30, 33}));
    auto g = grow(m, p);
    expect_valid_tree(*g, p);
    expect_every_leaf_reaches_ground(g->tree);
    EXPECT_EQ(count_kind(g->tree, NodeKind::ModelContact), 0u);
    EXPECT_EQ(g->tree.stats.dropped, 0u);
    EXPECT_EQ(g->tree.stats.dropped_branches, 0u);
    const auto& st = g->tree.stats;
    EXPECT_EQ(count_kind(g->tree, NodeKind::Leaf), g->samples.samples.size() - st.touching - st.internal - st.bridged - g->tree.pillars.size())
        << st.touching << " " << st.internal << " " << st.bridged << " " << g->tree.pillars.size();
}

TEST(GrowTree, ALeafWhoseOnlyLandingIsJustSteeperThanATipStandsOnStandsOnIt) {
    // bench/validation/wall_rack in the pose --orient auto chose (its rotation, as the report gave
    // it), without the keyholes and hooks: the back plate leans back, its front a 45 deg underside
    // over the shelf, whose top and the lip's inner face are both 0.1-0.2 deg steeper than the
    // slope a tip stands on by choice (kTreeTuning.stand_on_slope_deg), and the lip bars the way
    // out. The leaf of a sample on the plate 3.3 mm above the shelf (where a keyhole's rim is) has
    // no other landing; a tip fits on those faces all the same. It was lost, and `check` found the
    // keyhole's rim beyond reach.
    cs::test::CellGrid g({-35, 35}, {-4, 0, 22, 24}, {0, 38, 40.5, 45.5, 55});
    g.fill({-35, -4, 0}, {35, 0, 55});        // the plate
    g.fill({-35, 0, 38}, {35, 24, 40.5});     // the shelf
    g.fill({-35, 22, 40.5}, {35, 24, 45.5});  // its lip
    Mesh m = g.mesh();
    const double R[3][3] = {{0.9971693787713378, 0.028738299285209587, -0.06947906299726585},
                            {0.028738299285209587, 0.7082301802009033, 0.705396428972241},
                            {0.06947906299726585, -0.705396428972241, 0.705399558972241}};
    auto turn = [&](const Vec3& v) {
        return Vec3{R[0][0] * v.x + R[0][1] * v.y + R[0][2] * v.z, R[1][0] * v.x + R[1][1] * v.y + R[1][2] * v.z,
                    R[2][0] * v.x + R[2][1] * v.y + R[2][2] * v.z};
    };
    for (auto& v : m.vertices) v = turn(v);
    double low = INFINITY;
    for (const auto& v : m.vertices) low = std::min(low, v.z);
    for (auto& v : m.vertices) v.z -= low;
    const Vec3 lift{0, 0, low};
    const Vec3 sample = turn({-26.16, 0, 43.83}) - lift;  // on the plate's front, 3.3 mm above the shelf
    const Params p;
    ModelQuery q(m);
    const SupportTree t = grow_tree(q, std::vector<Sample>{{sample, SampleKind::Edge}}, p);
    EXPECT_EQ(t.stats.dropped, 0u) << "the leaf was lost";
    EXPECT_EQ(count_kind(t, NodeKind::Leaf), 1u);
    ASSERT_EQ(count_kind(t, NodeKind::ModelContact), 1u);
    for (const Node& n : t.nodes)
        if (n.kind == NodeKind::ModelContact) {
            // In the trough: on the shelf's top or the lip's inner face (a tip's foot stands a
            // little above where its axis meets a slope).
            const double height = dot(n.contact + lift, turn({0, 0, 1})), out = dot(n.contact + lift, turn({0, 1, 0}));
            EXPECT_GT(height, 40.5 - 1e-6);
            EXPECT_LT(height, 45.5);
            EXPECT_GT(out, 0);
            EXPECT_LT(out, 22 + 0.5);
        }
}

// The coverage top-up judges where tips stand from hang_leaves, before the tree grows: that is
// only sound if the grown tree's leaves and pillars are exactly the hung ones.
TEST(HangLeaves, AreTheLeavesAndPillarsTheTreeGrowsFrom) {
    Params bed_only;
    bed_only.supports_on_model = false;
    Mesh low_plate = cs::test::box({-10, -2, 0}, {-8, 2, 3});
    append(low_plate, cs::test::box({-8, -2, 1.5}, {0, 2, 3}));
    const std::vector<std::pair<Mesh, Params>> cases = {
        {cs::test::t_shape(), Params{}}, {cs::test::cantilever_over_box(), Params{}}, {low_plate, Params{}},
        {cs::test::cantilever_over_box(), bed_only}};
    for (size_t i = 0; i < cases.size(); ++i) {
        SCOPED_TRACE(i);
        const auto& [mesh, p] = cases[i];
        auto g = grow(mesh, p);
        SupportTree hung = hang_leaves(*g->query, g->samples.samples, p);
        EXPECT_TRUE(hung.struts.empty());
        auto leaves = [](const SupportTree& t) {
            std::vector<std::array<double, 6>> out;
            for (const auto& n : t.nodes)
                if (n.kind == NodeKind::Leaf) out.push_back({n.contact.x, n.contact.y, n.contact.z, n.tip.x, n.tip.y, n.tip.z});
            std::sort(out.begin(), out.end());
            return out;
        };
        ASSERT_FALSE(leaves(hung).empty() && hung.pillars.empty());
        // A leaf lost in a dead end is no leaf of the grown tree; none is lost on these shapes.
        EXPECT_EQ(leaves(g->tree), leaves(hung));
        ASSERT_EQ(g->tree.pillars.size(), hung.pillars.size());
        for (size_t k = 0; k < hung.pillars.size(); ++k) {
            EXPECT_EQ(g->tree.pillars[k].top, hung.pillars[k].top);
            EXPECT_EQ(g->tree.pillars[k].bottom, hung.pillars[k].bottom);
        }
        EXPECT_EQ(g->tree.stats.touching, hung.stats.touching);
        EXPECT_EQ(g->tree.stats.bridged, hung.stats.bridged);
        EXPECT_EQ(g->tree.stats.internal, hung.stats.internal);
    }
}

// A sample too low for a tree in a slot narrower than a pillar's foot: no pillar fits, and the hung
// tree lists it (the coverage top-up then counts it as holding nothing up, as a leaf given up, so
// the overhang it leaves beyond reach gets samples of its own: the tree example in its auto pose,
// a sample 2.1 mm over a slope where no pillar fits, 0.18 mm2 left beyond reach). Hanging more
// leaves into the tree keeps the list.
TEST(HangLeaves, ASampleUnderWhichNoPillarFitsIsListed) {
    Params p;
    Mesh m = cs::test::box({-5, -5, 1.5}, {5, 5, 3});
    append(m, cs::test::box({-5, -5, 0}, {-0.3, 5, 1.5}));
    append(m, cs::test::box({0.3, -5, 0}, {5, 5, 1.5}));
    ModelQuery q(m);
    const Vec3 in_slot{0, 0, 1.5};
    const SupportTree hung = hang_leaves(q, {{in_slot, SampleKind::Face}}, p);
    EXPECT_TRUE(hung.pillars.empty());
    EXPECT_EQ(hung.stats.dropped, 1u);
    ASSERT_EQ(hung.no_pillar.size(), 1u);
    EXPECT_EQ(hung.no_pillar[0], in_slot);
    const SupportTree more = hang_more_leaves(q, hung, {{{-4, 0, 3}, SampleKind::Face}}, p);
    EXPECT_EQ(more.no_pillar, hung.no_pillar);
}

// A sample in a slot too low for a pillar between its gaps is bridged (FitPillar's groove): it
// holds nothing up either (`check` lets the print bridge only where the overhang hangs no more
// than touching_space above what is below; here 1 mm), so the hung tree lists it with the samples
// no pillar fits under (propeller at 80 mm in its auto pose: a bridged sample on a blade counted
// as holding its neighbours, 1.89 mm gap).
TEST(HangLeaves, ASampleInASlotTooLowForAPillarIsListed) {
    Params p;
    Mesh m = cs::test::box({-5, -5, 0}, {-0.05, 5, 0.45});
    append(m, cs::test::box({0.05, -5, 0}, {5, 5, 0.45}));
    append(m, cs::test::box({-5, -5, 1.0}, {5, 5, 2}));
    ModelQuery q(m);
    const Vec3 in_slot{0, 0, 1.0};
    const SupportTree hung = hang_leaves(q, {{in_slot, SampleKind::Face}}, p);
    EXPECT_EQ(hung.stats.bridged, 1u);
    EXPECT_TRUE(hung.pillars.empty());
    ASSERT_EQ(hung.no_pillar.size(), 1u);
    EXPECT_EQ(hung.no_pillar[0], in_slot);
}

// The coverage top-up hangs only its new samples' leaves into the hung tree: node for node,
// pillar for pillar and count for count what hanging every sample again gives (the tree grown from
// it, and so every output, is the same). Every other sample is held back and added after.
TEST(HangLeaves, MoreLeavesHungIntoATreeAreTheLeavesOfAllSamples) {
    Mesh low_plate = cs::test::box({-10, -2, 0}, {-8, 2, 3});
    append(low_plate, cs::test::box({-8, -2, 1.5}, {0, 2, 3}));
    for (const Mesh& mesh : {cs::test::t_shape(), cs::test::cantilever_over_box(), low_plate, cs::test::table_shape()}) {
        Params p;
        auto g = grow(mesh, p);
        std::vector<Sample> first, more;
        for (size_t i = 0; i < g->samples.samples.size(); ++i) (i % 2 ? more : first).push_back(g->samples.samples[i]);
        const SupportTree all = hang_leaves(*g->query, g->samples.samples, p);
        const SupportTree merged = hang_more_leaves(*g->query, hang_leaves(*g->query, first, p), more, p);
        ASSERT_EQ(merged.nodes.size(), all.nodes.size());
        ASSERT_FALSE(all.nodes.empty() && all.pillars.empty());
        for (size_t k = 0; k < all.nodes.size(); ++k) {
            EXPECT_EQ(merged.nodes[k].p, all.nodes[k].p) << k;
            EXPECT_EQ(merged.nodes[k].kind, all.nodes[k].kind) << k;
            EXPECT_EQ(merged.nodes[k].contact, all.nodes[k].contact) << k;
            EXPECT_EQ(merged.nodes[k].tip, all.nodes[k].tip) << k;
        }
        ASSERT_EQ(merged.pillars.size(), all.pillars.size());
        for (size_t k = 0; k < all.pillars.size(); ++k) EXPECT_EQ(merged.pillars[k].top, all.pillars[k].top) << k;
        EXPECT_EQ(merged.stats.touching, all.stats.touching);
        EXPECT_EQ(merged.stats.bridged, all.stats.bridged);
        EXPECT_EQ(merged.stats.internal, all.stats.internal);
        EXPECT_EQ(merged.stats.dropped, all.stats.dropped);
        EXPECT_EQ(merged.stats.pillars, all.stats.pillars);
        EXPECT_EQ(grow_tree(*g->query, merged, p).total_length(), grow_tree(*g->query, all, p).total_length());
    }
}

TEST(GrowTree, NoSamplesNoTree) {
    Params p;
    Mesh m = cs::test::box({0, 0, 0}, {5, 5, 5});
    ModelQuery q(m);
    SupportTree t = grow_tree(q, std::vector<Sample>{}, p);
    EXPECT_TRUE(t.nodes.empty());
    EXPECT_TRUE(t.struts.empty());
    EXPECT_EQ(t.total_length(), 0);
}

TEST(GrowTree, LowOverhangsBecomePillarsOrRest) {
    // A plate 1.5 mm above the bed (less than two tips): pillars, not trees; 0.5 mm: printed on the bed.
    Params p;
    Mesh m = cs::test::box({-10, -2, 0}, {-8, 2, 3});  // a post, so the plate is one model
    append(m, cs::test::box({-8, -2, 1.5}, {0, 2, 3}));
    auto g = grow(m, p);
    EXPECT_GT(g->tree.pillars.size(), 0u);
    EXPECT_TRUE(g->tree.struts.empty());
    for (const auto& pl : g->tree.pillars) {
        EXPECT_NEAR(pl.top.z, 1.5 - p.gap, 1e-9);
        EXPECT_EQ(pl.bottom.z, 0);
    }
    Mesh low = cs::test::box({0, 0, 0.5}, {5, 5, 2});
    auto h = grow(low, p);
    EXPECT_TRUE(h->tree.pillars.empty());
    EXPECT_TRUE(h->tree.struts.empty());
    EXPECT_EQ(h->tree.stats.touching, h->samples.samples.size());
}

// ---------------------------------------------------------------- shaped for printing

namespace {

// The tree grown from these face samples beside this model.
std::unique_ptr<Grown> grow_from(const Mesh& model, const std::vector<Vec3>& at, const Params& p) {
    auto g = std::make_unique<Grown>();
    g->model = model;
    g->query = std::make_unique<ModelQuery>(g->model);
    for (const Vec3& s : at) g->samples.samples.push_back({s, SampleKind::Face});
    g->tree = grow_tree(*g->query, g->samples.samples, p);
    return g;
}

// Two samples `apart` mm apart at z = 12 over an empty bed (the model is a small box far away).
std::unique_ptr<Grown> two_samples(double apart, const Params& p) {
    return grow_from(cs::test::box({100, 100, 0}, {101, 101, 1}), {{0, 0, 12}, {apart, 0, 12}}, p);
}

std::vector<double> all_d_min(const SupportTree& t, const Params& p) { return std::vector<double>(t.struts.size(), p.d_min); }

}  // namespace

TEST(GrowTree, BranchesJoinWhenTheJoinLeavesFewerIslands) {
    // 20 mm apart, leaves 10.8 mm up: the cones meet 2.4 mm above the bed. The struts to the join
    // are longer (13 mm) than straight down, but each branch is an island of its own for 8.4 mm
    // instead of 10.8: the sweep joins them, and one trunk goes down.
    Params p;
    auto g = two_samples(20, p);
    expect_valid_tree(*g, p);
    expect_every_leaf_reaches_ground(g->tree);
    EXPECT_EQ(g->tree.stats.merges, 1u);
    EXPECT_EQ(g->tree.stats.bed_contacts, 1u);
    // 40 mm apart the cones would meet below the bed: two columns.
    auto far = two_samples(40, p);
    EXPECT_EQ(far->tree.stats.merges, 0u);
    EXPECT_EQ(far->tree.stats.bed_contacts, 2u);
}

TEST(GrowTree, BranchesBesideAWallStillJoin) {
    // The two samples 10 mm apart, 30 mm up, 1.5 mm in front of a wall that goes down to the bed:
    // the cone's slanted rays hit the wall 1.4 mm below each leaf. A tip cannot stand on a wall, so
    // that hit must not cut short the search for partners: the branches join 4.2 mm down and one
    // trunk goes to the bed, as they would in the open. (Before, each went down alone: the arches
    // example at 80 mm had 25 columns to the bed instead of 11.)
    Params p;
    auto g = grow_from(cs::test::box({-10, 1, 0}, {20, 5, 35}), {{0, -0.5, 30}, {10, -0.5, 30}}, p);
    expect_valid_tree(*g, p);
    expect_every_leaf_reaches_ground(g->tree);
    EXPECT_EQ(g->tree.stats.merges, 1u);
    EXPECT_EQ(g->tree.stats.bed_contacts, 1u);
    EXPECT_EQ(g->tree.stats.model_contacts, 0u);
}

TEST(GrowTree, APartnerBeyondTheNearestBlockedOnesStillJoins) {
    // A thin wall (y 1..3) with six samples close behind it and two 14 mm apart in front of it.
    // For the higher front leaf the six behind are the cheapest partners (about 2.5 mm of island
    // each) and the wall blocks all of them; the front partner (about 6 mm) comes next. It must
    // still be found: the front leaves join and one trunk carries them, instead of two columns.
    // (Before, the search kept only the six cheapest partners: the arches example at 80 mm had 11
    // trunks to the bed, 6 now.)
    Params p;
    std::vector<Vec3> at = {{0, -0.5, 30}, {14, -0.5, 29.5}};
    for (double x : {-2.5, -1.5, -0.5, 0.5, 1.5, 2.5}) at.push_back({x, 4.5, 29.5});
    auto g = grow_from(cs::test::box({-20, 1, 0}, {30, 3, 35}), at, p);
    expect_valid_tree(*g, p);
    expect_every_leaf_reaches_ground(g->tree);
    // Where each front leaf ends up: follow its struts down to the bed.
    auto ground_of = [&](const Vec3& sample) {
        int v = -1;
        for (int i = 0; i < static_cast<int>(g->tree.nodes.size()); ++i)
            if (g->tree.nodes[i].kind == NodeKind::Leaf && horizontal_distance(g->tree.nodes[i].contact, sample) < 1e-9) v = i;
        for (bool moved = v >= 0; moved;) {
            moved = false;
            for (const auto& s : g->tree.struts)
                if (s.top == v) v = s.bottom, moved = true;
        }
        return v;
    };
    const int a = ground_of({0, -0.5, 30}), c = ground_of({14, -0.5, 29.5});
    ASSERT_GE(a, 0);
    EXPECT_EQ(a, c) << "the front leaves share one trunk";
    EXPECT_EQ(g->tree.nodes[a].kind, NodeKind::Bed);
    EXPECT_LT(g->tree.nodes[a].p.y, 1) << "the trunk stays in front of the wall";
}

// The ways of growing that lean two leaves' tips towards each other (GrowOptions), by name.
std::vector<std::pair<GrowOptions, const char*>> leaning_ways() {
    return {{GrowOptions{}, "raised after the sweep"},
            {GrowOptions{.lean_merging_leaves = true}, "leaning during the sweep"},
            {GrowOptions{.pair_leaves_first = true}, "paired before the sweep"}};
}

TEST(GrowTree, TwoLeavesLeanTheirTipsAndMeetJustBelowThem) {
    // 2.5 mm apart (the sampling lattice) under a flat ceiling: standing straight, the leaves' cones
    // meet 2.5 / (2 tan 50) = 1.05 mm below them, five layers each leaf is an island of its own. Each
    // tip leans as far as a tip may (0.9 of the critical angle over its height) until the feet are
    // half a strut apart: the merge is then 0.5 / (2 tan 50) = 0.21 mm below, about one layer.
    // Every way of growing does it (GrowOptions: after the sweep, during it, or before it).
    for (const auto& [way, name] : leaning_ways()) {
        SCOPED_TRACE(name);
        Params p;
        auto g = std::make_unique<Grown>();
        g->model = cs::test::box({100, 100, 0}, {101, 101, 1});
        g->query = std::make_unique<ModelQuery>(g->model);
        g->samples.samples = {{{0, 0, 12}, SampleKind::Face}, {{2.5, 0, 12}, SampleKind::Face}};
        g->tree = grow_tree(*g->query, g->samples.samples, p, way);
        expect_valid_tree(*g, p);
        ASSERT_EQ(g->tree.stats.merges, 1u);
        const double tan_c = std::tan(p.critical_angle * kDeg);
        for (const Node& n : g->tree.nodes) {
            if (n.kind == NodeKind::Leaf) {
                EXPECT_NEAR(horizontal_distance(n.tip, n.contact), 0, 1e-9) << "the tip top stays under its sample";
                EXPECT_LE(horizontal_distance(n.p, n.tip), 0.9 * tan_c * (n.tip.z - n.p.z) + 1e-9);
            }
            if (n.kind == NodeKind::Merge) {
                const Node& leaf = g->tree.nodes[0];
                EXPECT_NEAR(leaf.p.z - n.p.z, 0.5 * p.d_min / (2 * tan_c), 1e-6);
            }
        }
    }
}

TEST(GrowTree, TwoLeavesBesideAWallLeanAsFarAsTheirSlantedTipsAllow) {
    // The two leaves of the test above, 0.6 mm in front of a wall that goes down to the bed: each
    // foot moves 0.46 mm away from the wall (leaf_position), so each tip already slants across the
    // pair. A tip may slant 0.9 of the critical angle over its height from under its top, all told
    // (1.07 mm): each foot still has 0.97 mm of that towards the other, and the pair meets 0.23 mm
    // below the feet instead of 2.5 / (2 tan 50) = 1.05 mm. (Before, each foot was to move the 1 mm
    // it moves in the open; with the slant it had, that was too far for its tip, and neither
    // leaned: five layers of two islands.) Every way of growing does it.
    for (const auto& [way, name] : leaning_ways()) {
        SCOPED_TRACE(name);
        Params p;
        auto g = grow_from(cs::test::box({-10, 0.6, 0}, {12, 3, 14}), {{0, 0, 12}, {2.5, 0, 12}}, p);
        g->tree = grow_tree(*g->query, g->samples.samples, p, way);
        expect_valid_tree(*g, p);
        ASSERT_EQ(g->tree.stats.merges, 1u);
        const double tan_c = std::tan(p.critical_angle * kDeg);
        std::vector<const Node*> leaves;
        const Node* merge = nullptr;
        for (const Node& n : g->tree.nodes) {
            if (n.kind == NodeKind::Leaf) leaves.push_back(&n);
            if (n.kind == NodeKind::Merge) merge = &n;
        }
        ASSERT_EQ(leaves.size(), 2u);
        ASSERT_NE(merge, nullptr);
        for (const Node* n : leaves) {
            EXPECT_GT(std::abs(n->p.y - n->tip.y), 0.1) << "the foot stands away from the wall";
            EXPECT_LE(horizontal_distance(n->p, n->tip), 0.9 * tan_c * (n->tip.z - n->p.z) + 1e-9) << "within its slant";
        }
        EXPECT_LT(horizontal_distance(leaves[0]->p, leaves[1]->p), 1.0) << "the feet lean together";
        EXPECT_LT(leaves[0]->p.z - merge->p.z, 0.4) << "and meet within two layers below them";
    }
}

TEST(GrowTree, FourLeavesPairedFirstLeanToTheirMiddleAndMeetSooner) {
    // A 2 x 2 block of the sampling lattice under a flat ceiling. Leaned in pairs, the two pairs'
    // merges sit 2.5 mm apart and meet 1.05 mm lower still: two islands for five more layers. Paired
    // first (GrowOptions::pair_leaves_first), the pairs then lean all four tips towards the block's
    // middle, as far as a tip may slant, feet at least half a strut apart: the feet stand within a
    // strut's width of each other (one island in a slicer) and the four meet layers sooner.
    Params p;
    auto grow_block = [&](GrowOptions way) {
        auto g = std::make_unique<Grown>();
        g->model = cs::test::box({100, 100, 0}, {101, 101, 1});
        g->query = std::make_unique<ModelQuery>(g->model);
        for (double x : {0.0, 2.5})
            for (double y : {0.0, 2.5}) g->samples.samples.push_back({{x, y, 12}, SampleKind::Face});
        g->tree = grow_tree(*g->query, g->samples.samples, p, way);
        expect_valid_tree(*g, p);
        expect_every_leaf_reaches_ground(g->tree);
        return g;
    };
    auto lowest_merge = [](const SupportTree& t) {
        double z = INFINITY;
        for (const Node& n : t.nodes)
            if (n.kind == NodeKind::Merge) z = std::min(z, n.p.z);
        return z;
    };
    const auto four = grow_block(GrowOptions{.pair_leaves_first = true, .lean_quads = true});
    const auto pairs = grow_block(GrowOptions{.pair_leaves_first = true});
    const double tan_c = std::tan(p.critical_angle * kDeg);
    const Vec3 middle{1.25, 1.25, 0};
    std::vector<Vec3> feet;
    for (const Node& n : four->tree.nodes) {
        if (n.kind != NodeKind::Leaf) continue;
        EXPECT_NEAR(horizontal_distance(n.tip, n.contact), 0, 1e-9) << "the tip top stays under its sample";
        EXPECT_LE(horizontal_distance(n.p, n.tip), 0.9 * tan_c * (n.tip.z - n.p.z) + 1e-9) << "as far as a tip may slant";
        EXPECT_LT(horizontal_distance(n.p, middle), horizontal_distance(n.tip, middle) - 0.5) << "leaned to the middle";
        feet.push_back(n.p);
    }
    ASSERT_EQ(feet.size(), 4u);
    for (std::size_t i = 0; i < 4; ++i)
        for (std::size_t j = i + 1; j < 4; ++j) EXPECT_GE(horizontal_distance(feet[i], feet[j]), 0.5 * p.d_min * (1 - 1e-6));
    for (const Vec3& f : feet) EXPECT_LE(horizontal_distance(f, middle), 0.5 * p.d_min * std::sqrt(2.0) + 1e-9);
    ASSERT_EQ(four->tree.stats.merges, 3u);
    ASSERT_EQ(pairs->tree.stats.merges, 3u);
    EXPECT_GT(lowest_merge(four->tree), lowest_merge(pairs->tree) + 2 * p.layer_height);
}

TEST(GrowCheaperTree, KeepsTheWayTheSlicerEstimatePrefersUnlessItDropsMore) {
    Params p;
    for (const Mesh& m : {cs::test::table_shape(), cs::test::bridge_shape(), cs::test::cantilever_over_box()}) {
        ModelQuery q(m);
        const auto samples = sample_overhangs(m, overhang_options(p)).samples;
        auto seconds = [&](const SupportTree& t) {
            const SizedTree sized = size_struts(t, p);
            return estimate_slicer_cost(sized.tree, mean_strut_widths(sized), p).prusa_seconds;
        };
        const SupportTree plain = grow_tree(q, samples, p);
        // The expected pick, by the rule: the cheapest that drops no more than the plain growth.
        SupportTree expected = plain;
        for (const GrowOptions way : {GrowOptions{.lean_merging_leaves = true}, GrowOptions{.pair_leaves_first = true},
                                      GrowOptions{.pair_leaves_first = true, .lean_quads = true}}) {
            SupportTree t = grow_tree(q, samples, p, way);
            if (t.stats.dropped <= plain.stats.dropped && t.stats.dropped_branches <= plain.stats.dropped_branches &&
                seconds(t) < seconds(expected))
                expected = t;
        }
        const SupportTree kept = grow_cheaper_tree(q, samples, p).tree;
        EXPECT_EQ(kept.grown_with.lean_merging_leaves, expected.grown_with.lean_merging_leaves);
        EXPECT_EQ(kept.grown_with.pair_leaves_first, expected.grown_with.pair_leaves_first);
        EXPECT_EQ(kept.grown_with.lean_quads, expected.grown_with.lean_quads);
        EXPECT_LE(kept.stats.dropped, plain.stats.dropped);
        EXPECT_LE(seconds(kept), seconds(plain));
        ASSERT_EQ(kept.nodes.size(), expected.nodes.size());
        for (size_t v = 0; v < kept.nodes.size(); ++v) EXPECT_EQ(kept.nodes[v].p, expected.nodes[v].p);
    }
    // The columns baseline has no merges to lean into: grown once, plainly.
    Params columns;
    columns.strategy = Strategy::columns;
    const Mesh m = cs::test::table_shape();
    ModelQuery q(m);
    const auto samples = sample_overhangs(m, overhang_options(columns)).samples;
    EXPECT_FALSE(grow_cheaper_tree(q, samples, columns).tree.grown_with.lean_merging_leaves);
}

TEST(GrowTree, TreeCostsTheSlicerLessThanColumns) {
    Params tree, columns;
    columns.strategy = Strategy::columns;
    for (const Mesh& m : {cs::test::t_shape(), cs::test::bridge_shape()}) {
        auto t = grow(m, tree), c = grow(m, columns);
        auto ct = estimate_slicer_cost(t->tree, all_d_min(t->tree, tree), tree);
        auto cc = estimate_slicer_cost(c->tree, all_d_min(c->tree, columns), columns);
        EXPECT_LT(ct.island_layers, cc.island_layers);
        EXPECT_LE(ct.most_islands, cc.most_islands);  // at the top every leaf is an island in both
        EXPECT_LT(ct.seconds, cc.seconds);
    }
}

// The plain O(n^2) nearest-next walk the grid walk must match, tie for tie.
double plain_nearest_next_path(std::vector<Vec3> pts) {
    double len = 0;
    auto d2 = [](const Vec3& a, const Vec3& b) { return (a.x - b.x) * (a.x - b.x) + (a.y - b.y) * (a.y - b.y); };
    for (size_t i = 0; i + 1 < pts.size(); ++i) {
        size_t best = i + 1;
        for (size_t j = i + 2; j < pts.size(); ++j)
            if (d2(pts[i], pts[j]) < d2(pts[i], pts[best])) best = j;
        std::swap(pts[i + 1], pts[best]);
        len += horizontal_distance(pts[i], pts[i + 1]);
    }
    return len;
}

TEST(SlicerCost, NearestNextPathIsThePlainWalksTieForTie) {
    EXPECT_EQ(nearest_next_path({}), 0);
    EXPECT_EQ(nearest_next_path({{1, 2, 3}}), 0);
    EXPECT_DOUBLE_EQ(nearest_next_path({{0, 0, 0}, {3, 0, 0}, {1, 0, 0}}), 3);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-40, 40);
    for (int n : {2, 5, 17, 60, 300, 1500}) {
        std::vector<Vec3> scattered, lattice, clusters;
        for (int i = 0; i < n; ++i) {
            scattered.push_back({u(rng), u(rng), 1});
            // tips on a 2.5 mm lattice, in shuffled order: equal distances everywhere
            lattice.push_back({2.5 * (i % 23), 2.5 * (i / 23), 1});
            // two far clusters and a few strays: the walk jumps, the grid refiles
            const double off = i % 2 ? 500 : 0;
            clusters.push_back({off + u(rng) / 8, u(rng) / 8 + (i % 97 == 0 ? 300 : 0), 1});
        }
        std::shuffle(lattice.begin(), lattice.end(), rng);
        for (const auto* pts : {&scattered, &lattice, &clusters})
            EXPECT_EQ(nearest_next_path(*pts), plain_nearest_next_path(*pts)) << n << " points";
    }
}

TEST(SlicerCost, CountsIslandsOutlineAndTravelPerLayer) {
    // Two 1 mm columns 10 mm apart, 10 mm tall: 50 layers of 0.2 mm, two islands in each.
    Params p;
    SupportTree t;
    t.nodes = {{{0, 0, 10}, NodeKind::Bend}, {{0, 0, 0}, NodeKind::Bed}, {{10, 0, 10}, NodeKind::Bend},
               {{10, 0, 0}, NodeKind::Bed}};
    t.struts = {{0, 1}, {2, 3}};
    auto c = estimate_slicer_cost(t, {1.0, 1.0}, p);
    EXPECT_DOUBLE_EQ(c.island_layers, 100);
    EXPECT_EQ(c.most_islands, 2u);
    EXPECT_NEAR(c.outline_mm, 100 * 4.0, 1e-9);  // a 1 mm square
    EXPECT_NEAR(c.travel_mm, 50 * 10.0, 1e-9);
    // Priced by the one price list (core/slicer_time.hpp) for both routes; ranked by their mean.
    EXPECT_DOUBLE_EQ(c.cura_seconds, tree_route_seconds(kCuraRoute, 100, 400, 500));
    EXPECT_DOUBLE_EQ(c.prusa_seconds, tree_route_seconds(kPrusaRoute, 100, 400, 500));
    EXPECT_DOUBLE_EQ(c.seconds, 0.5 * (c.cura_seconds + c.prusa_seconds));
    EXPECT_GT(c.seconds, 0);
    // Joined half-way into one trunk: fewer islands, less travel, less time.
    SupportTree j;
    j.nodes = {{{0, 0, 10}, NodeKind::Bend}, {{10, 0, 10}, NodeKind::Bend}, {{5, 0, 5}, NodeKind::Merge},
               {{5, 0, 0}, NodeKind::Bed}};
    j.struts = {{0, 2}, {1, 2}, {2, 3}};
    auto cj = estimate_slicer_cost(j, {1.0, 1.0, 1.26}, p);
    EXPECT_LT(cj.island_layers, c.island_layers);
    EXPECT_LT(cj.travel_mm, c.travel_mm);
    EXPECT_LT(cj.seconds, c.seconds);
    // A wide strut: the slicer walls its square only (it closes the N's narrow holes).
    SupportTree w;
    w.nodes = {{{0, 0, 1}, NodeKind::Bend}, {{0, 0, 0}, NodeKind::Bed}};
    w.struts = {{0, 1}};
    EXPECT_NEAR(estimate_slicer_cost(w, {3.0}, p).outline_mm, 5 * 4 * 3.0, 1e-9);
}

// A contact tip is a taper from tip_diameter at the contact up to the width of the strut ending
// on it. A ledge in front of a step (a seat's front lip under a roof, shelter_roof in
// bench/validation): a wide strut landing on the ledge right in front of the step clears the
// step, its contact keeps the gap, but the tip widening into the strut reaches into the step.
// The sweep asks contact_tip_is_clear of every strut onto the model (Sweep::clear).
TEST(TreeHelpers, AContactTipInFrontOfAStepMustClearIt) {
    Params p;
    Mesh m = cs::test::box({-10, -10, 0}, {10, 0, 9});  // the ledge
    append(m, cs::test::box({-10, 0, 0}, {10, 10, 10}));  // the step, 1 mm above it
    ModelQuery q(m);
    const double w = 3.4;  // a strut sized by the strength rule
    const Vec3 node{0, -1.2, 9 + p.gap + p.tip_length}, contact{0, -1.2, 9};
    EXPECT_TRUE(strut_is_clear(q, node + Vec3{0, 0, 20}, w, node, w, p.gap, /*onto_model=*/true, joint_overlap(p)));
    EXPECT_FALSE(contact_tip_is_clear(q, p, node, contact, w));
    // A thin strut's tip there, or the wide one 1 mm further out on the ledge, clears it.
    EXPECT_TRUE(contact_tip_is_clear(q, p, node, contact, p.d_min));
    EXPECT_TRUE(contact_tip_is_clear(q, p, node - Vec3{0, 1, 0}, contact - Vec3{0, 1, 0}, w));
}

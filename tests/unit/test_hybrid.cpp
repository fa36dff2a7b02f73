// ceilings/hybrid: short walls under a ceiling, standing on the tree (issue #32 part 2).
#include <gtest/gtest.h>

#include <cmath>

#include "ceilings/hybrid.hpp"
#include "check/check.hpp"
#include "mesh/mesh_io.hpp"
#include "overhang/overhang.hpp"
#include "pipeline/pipeline.hpp"
#include "query/model_query.hpp"
#include "shapes.hpp"
#include "support.hpp"
#include "tree/feet.hpp"

using namespace cs;

namespace {

// A tree priced out of reach (a thousand island-layers a sample, a foot counting as a sample):
// every region where the hybrid fits gets it, so the geometry tests do not hang on the time model.
TreeCount dear_tree(const std::vector<Sample>& samples, const std::vector<Vec3>& feet) {
    return {1000.0 * (samples.size() + feet.size()), 0, 0};
}

// A 30 x 12 x 2 deck (z 20..22) on one 4 x 4 post at its middle.
Mesh high_deck() {
    test::CellGrid g({-15, -2, 2, 15}, {-6, -2, 2, 6}, {0, 20, 22});
    g.fill({-2, -2, 0}, {2, 2, 20});
    g.fill({-15, -6, 20}, {15, 6, 22});
    return g.mesh();
}

struct Hybrid {
    Mesh model;
    Params p;
    OverhangSamples samples;
    Ceilings hybrid;
};

Hybrid hybrid(const Mesh& model, double height) {
    Hybrid h{model, {}, {}, {}};
    h.p.hybrid_height = height;
    ModelQuery q(h.model);
    h.samples = sample_overhangs(h.model, {h.p.critical_angle, h.p.sampling_distance, h.p.layer_height, touching_space(h.p)}, &q);
    h.hybrid = support_hybrid(q, h.samples.samples, h.p, dear_tree);
    return h;
}

}  // namespace

TEST(Hybrid, ShortWallsHangUnderTheCeilingEachOnOneFoot) {
    Hybrid h = hybrid(high_deck(), 3);
    ASSERT_FALSE(h.hybrid.walls.empty());
    EXPECT_GE(h.hybrid.regions, 1u);
    EXPECT_GT(h.hybrid.covered, h.samples.samples.size() / 2);
    EXPECT_EQ(h.hybrid.covered + h.hybrid.rest.size(), h.samples.samples.size());
    ASSERT_EQ(h.hybrid.feet.size(), h.hybrid.walls.size());
    const double reach = coverage_reach(h.p.sampling_distance);
    for (std::size_t i = 0; i < h.hybrid.walls.size(); ++i) {
        const CeilingWall& w = h.hybrid.walls[i];
        EXPECT_NEAR(w.top, 20 - h.p.gap, 1e-6);               // a gap under the deck
        EXPECT_NEAR(w.top - w.bottom, h.p.hybrid_height, 1e-6);  // as tall as asked, not down to the bed
        const Vec3& f = h.hybrid.feet[i];
        EXPECT_NEAR(f.z, w.bottom, 1e-9);  // the foot is the middle of the piece's bottom
        EXPECT_NEAR(f.x, 0.5 * (w.from.x + w.to.x), 1e-9);
        EXPECT_NEAR(f.y, 0.5 * (w.from.y + w.to.y), 1e-9);
        // A piece is either short (judged at its middle) or surely long (a contact along its top).
        const double length = horizontal_distance(w.from, w.to), long_top = std::max(2 * reach, 3 * w.thickness);
        EXPECT_TRUE(length < 1.02 * long_top || length >= 1.05 * long_top) << length;
        EXPECT_LT(length, 2 * 1.05 * long_top + 1e-9);  // the printer bridges its foot from tip to tip
    }
}

// The whole structure, grown as the pipeline grows it: the tree carries every foot, and `check`
// passes it judged by its own geometry (the pieces grounded on their tips, their tops the deck's
// contacts; without the pieces the deck is not covered).
TEST(Hybrid, TheTreeCarriesEveryFootAndCheckPassesIt) {
    Hybrid h = hybrid(high_deck(), 3);
    ASSERT_FALSE(h.hybrid.walls.empty());
    ModelQuery q(h.model);
    const SupportTree leaves = hang_feet(hang_leaves(q, h.hybrid.rest, h.p), h.hybrid.feet, h.p);
    SizedTree grown = grow_cheaper_tree(q, leaves, h.p);
    ASSERT_TRUE(feet_carried(grown.tree, h.hybrid.feet));
    const Supports s = finish_supports(std::move(grown), h.p, {}, h.hybrid.walls);
    const CheckResult r = check_supports(h.model, s.mesh, h.p, {});
    EXPECT_TRUE(r.ok()) << r.summary();
    Mesh tree_only = bodies_mesh(s.bodies, h.p.wall_thickness);
    EXPECT_FALSE(check_supports(h.model, tree_only, h.p, {}).ok());  // the pieces hold the deck
}

TEST(Hybrid, FeetCarriedOnlyWhereALeafHoldsEachWithAStrutBelow) {
    SupportTree t;
    t.nodes = {{{0, 0, 5}, NodeKind::Leaf, {0, 0, 6}, {0, 0, 6}}, {{0, 0, 0}, NodeKind::Bed}};
    EXPECT_FALSE(feet_carried(t, {{0, 0, 6}}));  // no strut below the leaf
    t.struts = {{0, 1}};
    EXPECT_TRUE(feet_carried(t, {{0, 0, 6}}));
    EXPECT_FALSE(feet_carried(t, {{0, 0, 6}, {1, 0, 6}}));  // a foot with no leaf
    EXPECT_TRUE(feet_carried(t, {}));
}

TEST(Hybrid, HangFeetAddsALeafATipBelowEachFootInTheLeavesOrder) {
    Params p;
    SupportTree hung;
    hung.nodes = {{{0, 0, 7}, NodeKind::Leaf, {0, 0, 9}, {0, 0, 8.8}}, {{0, 0, 3}, NodeKind::Leaf, {0, 0, 5}, {0, 0, 4.8}}};
    const SupportTree t = hang_feet(hung, {{1, 1, 6}}, p);
    ASSERT_EQ(t.nodes.size(), 3u);
    EXPECT_EQ(t.nodes[1].kind, NodeKind::Leaf);
    EXPECT_NEAR(distance(t.nodes[1].tip, {1, 1, 6}), 0, 1e-12);
    EXPECT_NEAR(distance(t.nodes[1].p, {1, 1, 6 - p.tip_length}), 0, 1e-12);
    EXPECT_EQ(t.nodes[2].contact.z, 5);
}

TEST(Hybrid, OffOrWithoutRoomForATipEverySampleStaysWithTheTree) {
    Hybrid off = hybrid(high_deck(), 0);
    EXPECT_TRUE(off.hybrid.walls.empty());
    EXPECT_EQ(off.hybrid.rest.size(), off.samples.samples.size());
    // The bridge's deck 8 mm up: a 6 mm tall hybrid leaves no room under its feet for a tip and a strut.
    Hybrid low = hybrid(test::bridge_shape(), 6);
    EXPECT_TRUE(low.hybrid.walls.empty());
    EXPECT_EQ(low.hybrid.rest.size(), low.samples.samples.size());
}

// Through the pipeline (the walls first, the time model choosing): whatever it builds, check passes.
TEST(Hybrid, ThePipelinesRunPassesCheck) {
    test::TempDir tmp;
    const std::string input = tmp / "deck.stl";
    write_stl(input, high_deck());
    Job job;
    job.input = input;
    job.orient = "keep";
    job.params.hybrid_height = 3;
    const Result r = run_job(job);
    const CheckResult c = check_supports(r.model, r.supports.mesh, job.params, {});
    EXPECT_TRUE(c.ok()) << c.summary();
}

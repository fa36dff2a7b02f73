// ceilings/slabs: neighbouring rows joined into slabs that CuraEngine prints as one outline.
#include <gtest/gtest.h>

#include <cmath>

#include "ceilings/ceilings.hpp"
#include "ceilings/slabs.hpp"
#include "check/check.hpp"
#include "core/rules.hpp"
#include "core/slicer_time.hpp"
#include "edit/scad_values.hpp"
#include "overhang/overhang.hpp"
#include "pipeline/pipeline.hpp"
#include "query/model_query.hpp"
#include "shapes.hpp"
#include "support.hpp"
#include "view/view_tree.hpp"

using namespace cs;

namespace {

// A lid: a 40 x 30 x 2 plate 3 mm over the bed (z 3..5) on four 2 x 2 corner posts; `post`: one
// more, 1 x 1 mm, from the bed to the plate, its corner at post_at.
Mesh low_lid(const Vec3* post_at = nullptr) {
    std::vector<double> xs{-20, -18, 18, 20}, ys{-15, -13, 13, 15};
    if (post_at) xs.push_back(post_at->x), xs.push_back(post_at->x + 1), ys.push_back(post_at->y), ys.push_back(post_at->y + 1);
    std::sort(xs.begin(), xs.end()), std::sort(ys.begin(), ys.end());
    test::CellGrid g(xs, ys, {0, 3, 5});
    for (double x : {-20.0, 18.0})
        for (double y : {-15.0, 13.0}) g.fill({x, y, 0}, {x + 2, y + 2, 3});
    if (post_at) g.fill({post_at->x, post_at->y, 0}, {post_at->x + 1, post_at->y + 1, 3});
    g.fill({-20, -15, 3}, {20, 15, 5});
    return g.mesh();
}

// Every region gets its walls (a tree priced out of reach), as in test_ceilings.cpp.
TreeCount dear_tree(const std::vector<Sample>& samples) { return {1000.0 * samples.size(), 0, 0}; }

std::vector<CeilingWall> lid_walls(const Mesh& model, const Params& p) {
    ModelQuery q(model);
    const OverhangSamples s = sample_overhangs(model, {p.critical_angle, p.sampling_distance, p.layer_height, touching_space(p)}, &q);
    return support_ceilings(q, s.samples, p, dear_tree, {}, 1.0).walls;
}

// The supports mesh as finish_supports builds it from walls: each piece a box.
Mesh walls_mesh(const std::vector<CeilingWall>& walls) {
    Mesh m;
    for (const auto& w : walls) append(m, wall_mesh(w));
    return m;
}

Vec3 middle(const CeilingWall& w) { return (w.from + w.to) * 0.5; }

// Does the point lie within w's footprint (grown by `margin`)?
bool in_footprint(const Vec3& x, const CeilingWall& w, double margin = 0) {
    const Vec3 d = normalized(Vec3{w.to.x - w.from.x, w.to.y - w.from.y, 0});
    const Vec3 m = middle(w);
    const double along = (x.x - m.x) * d.x + (x.y - m.y) * d.y, across = -(x.x - m.x) * d.y + (x.y - m.y) * d.x;
    return std::abs(along) <= 0.5 * horizontal_distance(w.from, w.to) + margin && std::abs(across) <= 0.5 * w.thickness + margin;
}

}  // namespace

// The lid's meander: pairs of neighbouring rows get a bridge filling the space between them (the
// same foot and top), reaching a hair into each, each row in one slab at most.
TEST(Slabs, ALowLidsNeighbouringRowsPairIntoSlabs) {
    const Params p;
    const Mesh model = low_lid();
    const std::vector<CeilingWall> before = lid_walls(model, p);
    ASSERT_GE(before.size(), 5u);
    ModelQuery q(model);
    const std::vector<CeilingWall> after = join_rows_into_slabs(q, before, p);
    ASSERT_GT(after.size(), before.size());
    // What was there stays, in its order and place.
    for (std::size_t i = 0; i < before.size(); ++i) {
        EXPECT_EQ(after[i].from, before[i].from);
        EXPECT_EQ(after[i].to, before[i].to);
        EXPECT_FALSE(after[i].bridge);
    }
    std::vector<int> slabs_of_row(before.size(), 0);
    for (std::size_t k = before.size(); k < after.size(); ++k) {
        const CeilingWall& b = after[k];
        ASSERT_TRUE(b.bridge);
        EXPECT_NEAR(b.thickness, p.ceiling_span - b.row_thickness, p.ceiling_span * 0.1);
        EXPECT_EQ(b.bottom, 0);  // the lid's walls stand on the bed
        // Its two rows: parallel, reached into (by a hair, at most 0.02 mm) on
        // either side, along its whole length.
        int sides = 0;
        for (std::size_t i = 0; i < before.size(); ++i) {
            const CeilingWall& r = before[i];
            if (r.join || r.bottom != b.bottom || r.top != b.top) continue;
            const Vec3 d = normalized(Vec3{b.to.x - b.from.x, b.to.y - b.from.y, 0}), n{-d.y, d.x, 0};
            const double off = (middle(r).x - middle(b).x) * n.x + (middle(r).y - middle(b).y) * n.y;
            const double into = 0.5 * (b.thickness + r.thickness) - std::abs(off);
            if (into <= 0 || into > 0.02) continue;
            if (!in_footprint(b.from + n * off, r, 1e-9) || !in_footprint(b.to + n * off, r, 1e-9)) continue;
            ++sides, ++slabs_of_row[i];
        }
        EXPECT_EQ(sides, 2) << "bridge " << k;
    }
    for (int n : slabs_of_row) EXPECT_LE(n, 1);
}

// Cura draws a wall one line wide as a loop and a slab as its outline: the slabs' walls cost it
// less; PrusaSlicer's file has no bridges and its price does not move.
TEST(Slabs, SlabsCostCuraLessAndPrusaSlicerTheSame) {
    const Params p;
    const Mesh model = low_lid();
    const std::vector<CeilingWall> before = lid_walls(model, p);
    ModelQuery q(model);
    const std::vector<CeilingWall> after = join_rows_into_slabs(q, before, p);
    ASSERT_GT(after.size(), before.size());
    EXPECT_LT(walls_seconds(kCuraRoute, after, p), 0.8 * walls_seconds(kCuraRoute, before, p));
    EXPECT_NEAR(walls_seconds(kPrusaRoute, after, p), walls_seconds(kPrusaRoute, before, p), 1e-9);
}

// Under a round or sloping ceiling a row is a staircase of pieces, and its slab a bridge under
// each step. On a layer, the steps' bridges that meet end to end are one slab: one outline, in
// place of the loops along its length. (Priced a bridge at a time, each step added two ends, and a
// staircase's slab cost Cura more than its loops: the choice then kept trees on propeller's blades
// that both slicers printed slower than walls.)
TEST(Slabs, AStaircasesBridgesOnALayerAreOneSlab) {
    const Params p;
    std::vector<CeilingWall> rows;
    for (double y : {0.0, 3.0})
        for (int i = 0; i < 10; ++i)  // 10 steps of 0.5 mm, tops 4.0 down to 3.1 mm
            rows.push_back({{0.5 * i, y, 0}, {0.5 * (i + 1), y, 0}, 0, 4.0 - 0.1 * i, false, 0.5});
    std::vector<CeilingWall> slab = rows;
    const double width = 2.5 + 0.02;  // between the rows' inner faces, a hair into each
    for (int i = 0; i < 10; ++i) {
        CeilingWall b{{0.5 * i, 1.5, 0}, {0.5 * (i + 1), 1.5, 0}, 0, 4.0 - 0.1 * i, false, width};
        b.bridge = true, b.row_thickness = 0.5;
        slab.push_back(b);
    }
    double outlines = 0;
    for (int k = 0; (k + 0.5) * p.layer_height < 4.0; ++k) {
        int steps = 0;  // the first `steps` pieces of each row reach layer k's middle
        for (int i = 0; i < 10; ++i) steps += (k + 0.5) * p.layer_height < 4.0 - 0.1 * i;
        const double length = 0.5 * steps;
        outlines += outline_route_seconds(kCuraRoute, length, width + 2 * 0.5) - 2 * line_route_seconds(kCuraRoute, length, 0.5);
    }
    EXPECT_NEAR(walls_printed(kCuraRoute, slab, p).line_seconds, walls_printed(kCuraRoute, rows, p).line_seconds + outlines, 1e-9);
    EXPECT_LT(walls_seconds(kCuraRoute, slab, p), walls_seconds(kCuraRoute, rows, p));
    EXPECT_NEAR(walls_seconds(kPrusaRoute, slab, p), walls_seconds(kPrusaRoute, rows, p), 1e-9);
}

// A post standing between two rows that would pair: no bridge comes within the side clearance of it.
TEST(Slabs, NoBridgeWhereThePostStandsBetweenTwoRows) {
    const Params p;
    const Mesh plain = low_lid();
    ModelQuery q0(plain);
    const std::vector<CeilingWall> paired = join_rows_into_slabs(q0, lid_walls(plain, p), p);
    const CeilingWall* first = nullptr;
    for (const CeilingWall& w : paired)
        if (w.bridge) first = first ? first : &w;
    ASSERT_NE(first, nullptr);
    // A 1 x 1 post in the bridge's middle (it falls between the two rows: the bridge is 2.9 wide).
    const Vec3 at = middle(*first) - Vec3{0.5, 0.5, 0};
    const Mesh with_post = low_lid(&at);
    const std::vector<CeilingWall> walls = lid_walls(with_post, p);
    ModelQuery q(with_post);
    const std::vector<CeilingWall> after = join_rows_into_slabs(q, walls, p);
    for (const CeilingWall& b : after)
        if (b.bridge)
            for (double dx : {0.0, 1.0})
                for (double dy : {0.0, 1.0})
                    EXPECT_FALSE(in_footprint(at + Vec3{dx, dy, 0}, b, tip_side_clearance(p) - 1e-6))
                        << "bridge at " << middle(b).x << ", " << middle(b).y;
}

// The slabs are closed solids, and `check` passes the lid's walls with them.
TEST(Slabs, TheSlabbedLidsWallsAreClosedAndPassCheck) {
    const Params p;
    const Mesh model = low_lid();
    ModelQuery q(model);
    const OverhangSamples s = sample_overhangs(model, {p.critical_angle, p.sampling_distance, p.layer_height, touching_space(p)}, &q);
    const Ceilings c = support_ceilings(q, s.samples, p, dear_tree, {}, 1.0);
    const std::vector<CeilingWall> walls = join_rows_into_slabs(q, c.walls, p);
    for (const CeilingWall& w : walls) EXPECT_TRUE(is_closed_and_consistent(wall_mesh(w)));
    Supports tree = build_supports(model, c.rest, p);
    Mesh all = tree.mesh;
    append(all, walls_mesh(walls));
    const CheckResult r = check_supports(model, all, p, {});
    EXPECT_TRUE(r.ok()) << r.summary();
}

// The .scad marks a bridge with a sixth element, 1, and reading it back (what `apply` builds the
// .prusa.3mf and the .supported.stl from) keeps the mark: those files leave bridges out.
TEST(Slabs, AScadsBridgeIsReadBackAsABridge) {
    const ScadValues values = parse_scad_values(
        "cs_walls = [\n"
        "  /* 0 row */ [[0, 0], [5, 0], 0, 2.8, 0.5],\n"
        "  /* 1 row */ [[0, 3.2], [5, 3.2], 0, 2.8, 0.5],\n"
        "  /* 2 bridge */ [[0, 1.6], [5, 1.6], 0, 2.8, 2.72, 1]\n"
        "];\n",
        "slab.scad");
    const std::vector<CeilingWall> walls = walls_from_scad(values);
    ASSERT_EQ(walls.size(), 3u);
    EXPECT_FALSE(walls[0].bridge);
    EXPECT_FALSE(walls[1].bridge);
    EXPECT_TRUE(walls[2].bridge);
    EXPECT_DOUBLE_EQ(walls[2].thickness, 2.72);
}

// A tapered blade's outer rows go on stepped in (tails, ceilings.cpp add_tails), between their
// neighbour and where they ended. The neighbour's slab goes on beside each tail, its bridges as
// wide as the tail stands from it; where two widths meet, the tail's bridge reaches a hair into
// the other, so no corner lies on a corner: each bridge stays a closed solid of its own (the first
// form of this left one solid open on propeller, which `check` failed), and `check` passes the lot.
TEST(Slabs, ATailsNeighbourIsSlabbedBesideItAndEverySolidIsClosed) {
    const Params p;
    const Mesh model = test::tapered_blade();
    ModelQuery q(model);
    const OverhangSamples s = sample_overhangs(model, {p.critical_angle, p.sampling_distance, p.layer_height, touching_space(p)}, &q);
    const Ceilings c = support_ceilings(q, s.samples, p, dear_tree, {}, 1.0);
    const std::vector<CeilingWall> walls = join_rows_into_slabs(q, c.walls, p);
    std::size_t beside_tails = 0;
    for (const CeilingWall& b : walls) {
        if (!b.bridge) continue;
        EXPECT_TRUE(is_closed_and_consistent(wall_mesh(b)));
        for (const CeilingWall& t : walls)
            if (t.tail && in_footprint(middle(b), t, 0.5 * b.thickness + 1e-6)) ++beside_tails;
    }
    EXPECT_GT(beside_tails, 0u);
    const Mesh slabs = walls_mesh(walls);
    for (const Mesh& shell : split_shells(slabs)) EXPECT_TRUE(is_closed_and_consistent(shell));
    Supports tree = build_supports(model, c.rest, p);
    Mesh all = tree.mesh;
    append(all, slabs);
    const CheckResult r = check_supports(model, all, p, {});
    EXPECT_TRUE(r.ok()) << r.summary();
}

// Laid out by hand: a row along x at y = 0 (x 0..20), an outer row at y = 3 that ends at x = 10 and
// its tail at y = 2.5 (x 9.5..20), all as tall. The slab goes on beside the tail, narrower; where
// the two bridges meet, the tail's reaches kIntoRows into the other, so no corner of one lies on a
// corner of the other (on propeller, bridges of two widths meeting corner on corner left `check` a
// solid it found open), and every piece is a closed solid of its own.
TEST(Slabs, ATailsBridgeReachesAHairIntoTheWiderOne) {
    const Params p;
    const Mesh far_away = test::box({100, 100, 0}, {101, 101, 1});
    ModelQuery q(far_away);
    std::vector<CeilingWall> walls{{{0, 0, 0}, {20, 0, 0}, 0, 5, false, 0.5},
                                   {{0, 3, 0}, {10, 3, 0}, 0, 5, false, 0.5},
                                   {{9.75, 3.25, 0}, {9.75, 2.25, 0}, 0, 5, true, 0.5},
                                   {{9.5, 2.5, 0}, {20, 2.5, 0}, 0, 5, false, 0.5}};
    walls.back().tail = true;
    walls = join_rows_into_slabs(q, walls, p);
    std::vector<CeilingWall> bridges;
    for (const CeilingWall& w : walls)
        if (w.bridge) bridges.push_back(w);
    ASSERT_EQ(bridges.size(), 2u);
    std::sort(bridges.begin(), bridges.end(), [](const CeilingWall& a, const CeilingWall& b) { return a.from.x < b.from.x; });
    EXPECT_NEAR(bridges[0].to.x, 10, 1e-9);                    // beside the outer row
    EXPECT_GT(bridges[0].thickness, bridges[1].thickness);     // the tail stands nearer
    EXPECT_NEAR(bridges[1].from.x, 10 - 0.01, 1e-9);           // a hair into the wider one
    EXPECT_NEAR(bridges[1].to.x, 20, 1e-9);
    const std::vector<Mesh> shells = split_shells(walls_mesh(walls));
    EXPECT_EQ(shells.size(), walls.size());
    for (const Mesh& shell : shells) EXPECT_TRUE(is_closed_and_consistent(shell));
}

// tree/placement: where pillars, tip tops and contact tips go (issue #12). Each is placed by its
// whole square: the properties asked are those of every corner (air above and below, nothing in
// the model), on small box models built to break a placement that looks at the axis alone.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "core/params.hpp"
#include "query/model_query.hpp"
#include "tree/placement.hpp"
#include "support.hpp"

using namespace cs;
using cs::test::box;

namespace {

std::array<Vec3, 4> corners(const Vec3& c, double w) {
    const double h = 0.5 * w;
    return {c + Vec3{h, h, 0}, c + Vec3{h, -h, 0}, c + Vec3{-h, h, 0}, c + Vec3{-h, -h, 0}};
}

// Nearest model straight up (or down) from each corner of the square; INFINITY where none.
double nearest_from_corners(const ModelQuery& q, const Vec3& c, double w, double dir) {
    double d = INFINITY;
    for (const auto& v : corners(c, w))
        if (auto hit = q.first_hit(v, {0, 0, dir})) d = std::min(d, hit->distance);
    return d;
}

// A slot 1.1 mm high under a ceiling at z 6.1 whose floor steps down from z 5 (x >= 5) to z 4
// (x < 5): the gearbox housing of issue #12. The step runs through a pillar's square when the
// sample lies 0.2 mm from it.
Mesh stepped_slot() {
    Mesh m = box({0, 0, 0}, {5, 10, 4});
    append(m, box({5, 0, 0}, {10, 10, 5}));
    append(m, box({0, 0, 6.1}, {10, 10, 8}));
    return m;
}

// A ceiling at z 10 over walls that go down from it at x <= left and x >= right: the ceiling of a
// slot between them (left = -INFINITY: one wall only).
Mesh ceiling_over_walls(double left, double right) {
    Mesh m = box({-5, -5, 10}, {5, 5, 12});
    if (std::isfinite(left)) append(m, box({-5, -5, 0}, {left, 5, 10}));
    append(m, box({right, -5, 0}, {5, 5, 10}));
    return m;
}

TEST(FitPillar, FootStandsAboveTheHighestFloorUnderItsSquare) {
    Params p;
    Mesh m = stepped_slot();
    ModelQuery q(m);
    const Vec3 sample{4.8, 5, 6.1};
    auto placed = fit_pillar(q, sample, p);
    ASSERT_EQ(placed.fit, PillarFit::Fits);
    const Pillar& pl = placed.pillar;
    EXPECT_TRUE(pl.on_model);
    EXPECT_LE(horizontal_distance(pl.top, sample), 0.5 + 1e-9) << "stays near its sample";
    // No corner of the foot in the model, and a gap of air under every one of them.
    for (const auto& v : corners(pl.bottom, p.d_min)) EXPECT_FALSE(q.inside(v));
    EXPECT_GE(nearest_from_corners(q, pl.bottom, p.d_min, -1), p.gap - 1e-9);
    EXPECT_GE(nearest_from_corners(q, pl.top, p.tip_diameter, 1), p.gap - 1e-9);
    EXPECT_NEAR(pl.top.z, 6.1 - p.gap, 1e-9);
    EXPECT_TRUE(prism_is_clear(q, pl.bottom, p.d_min, pl.top, p.tip_diameter));
}

TEST(FitPillar, SlotTooLowForAPillarIsBridged) {
    // A ceiling 1 mm over a floor at z 0.45 with a 0.1 mm groove down to z 0 under the sample:
    // the sample sees 1 mm of free space, but a pillar's square stands on the floor beside the
    // groove, leaving less than a layer between the two gaps anywhere near.
    Params p;
    Mesh m = box({-5, -5, 0}, {-0.05, 5, 0.45});
    append(m, box({0.05, -5, 0}, {5, 5, 0.45}));
    append(m, box({-5, -5, 1.0}, {5, 5, 2}));
    ModelQuery q(m);
    EXPECT_EQ(fit_pillar(q, {0, 0, 1.0}, p).fit, PillarFit::TooLow);
}

TEST(FitPillar, WallBesideTheSampleMovesThePillarOff) {
    // A ledge 1.5 mm above the bed meeting a wall: a sample 0.2 mm from the wall gets a pillar
    // moved away from it, not one cutting into it.
    Params p;
    Mesh m = box({-5, -5, 1.5}, {5, 5, 3});
    append(m, box({5, -5, 0}, {7, 5, 3}));
    ModelQuery q(m);
    auto placed = fit_pillar(q, {4.8, 0, 1.5}, p);
    ASSERT_EQ(placed.fit, PillarFit::Fits);
    EXPECT_FALSE(placed.pillar.on_model);
    EXPECT_EQ(placed.pillar.bottom.z, 0);
    EXPECT_LE(placed.pillar.bottom.x + 0.5 * p.d_min, 5.0);
    EXPECT_TRUE(prism_is_clear(q, placed.pillar.bottom, p.d_min, placed.pillar.top, p.tip_diameter));
}

TEST(FitPillar, KeepsTheSideClearanceFromAWallBesideIt) {
    // The ledge and wall above, the sample 0.6 mm from the wall: straight below it the pillar's
    // foot (d_min wide) would stand 0.1 mm from the wall and print fused to its outer line. It
    // moves off, on the same level bed, until the whole pillar keeps tip_side_clearance.
    Params p;
    Mesh m = box({-5, -5, 1.5}, {5, 5, 3});
    append(m, box({5, -5, 0}, {7, 5, 3}));
    ModelQuery q(m);
    const Vec3 sample{4.4, 0, 1.5};
    auto placed = fit_pillar(q, sample, p);
    ASSERT_EQ(placed.fit, PillarFit::Fits);
    const Pillar& pl = placed.pillar;
    EXPECT_EQ(pl.bottom.z, 0);
    EXPECT_LE(pl.bottom.x + 0.5 * p.d_min, 5.0 - tip_side_clearance(p) + 1e-9) << "foot keeps the clearance";
    EXPECT_LE(pl.top.x + 0.5 * p.tip_diameter, 5.0 - tip_side_clearance(p) + 1e-9) << "top keeps the clearance";
    EXPECT_LE(horizontal_distance(pl.top, sample), 0.5 + 1e-9) << "stays near its sample";
    EXPECT_NEAR(pl.top.z, 1.5 - p.gap, 1e-9);
}

TEST(FitPillar, InASlotTooNarrowForTheClearanceThePillarStillGoes) {
    // A slot 1.2 mm wide, 1.5 mm high: a pillar (1 mm foot) fits, but not with 0.2 mm on both
    // sides. It is placed anyway: a pillar fused to a wall beats an unsupported overhang.
    Params p;
    Mesh m = box({-5, -5, 1.5}, {5, 5, 3});
    append(m, box({-7, -5, 0}, {-0.6, 5, 1.5}));
    append(m, box({0.6, -5, 0}, {7, 5, 1.5}));
    ModelQuery q(m);
    auto placed = fit_pillar(q, {0, 0, 1.5}, p);
    ASSERT_EQ(placed.fit, PillarFit::Fits);
    EXPECT_TRUE(prism_is_clear(q, placed.pillar.bottom, p.d_min, placed.pillar.top, p.tip_diameter));
}

TEST(FitPillar, StaysUnderTheKeelItHoldsThoughTheFloorBesideIsLevel) {
    // A keel 2 mm over the floor: a prism along x whose bottom edge (z 2, y 0) is the overhang,
    // its sides 75 deg steep. The floor under it is a ramp rising gently (11 deg) towards -y
    // from that edge's foot: straight under the sample the pillar's foot stands on a slope, a
    // quarter millimetre towards +y on a level bed. But there the keel is 0.55 mm and more above
    // every point of the pillar's top: it holds nothing up (check finds no contact there, and
    // the keel's points beyond reach: the tree example at 80 mm in its auto pose). It stays
    // under the keel, on the slope.
    Params p;
    const double h = 3.73;
    Mesh m;
    m.vertices = {{-5, 0, 2}, {5, 0, 2}, {-5, -1, 2 + h}, {5, -1, 2 + h}, {-5, 1, 2 + h}, {5, 1, 2 + h},
                  {-5, 0, 0}, {5, 0, 0}, {-5, -5, 0}, {5, -5, 0}, {-5, -5, 1}, {5, -5, 1}};
    m.faces = {{0, 3, 2}, {0, 1, 3}, {0, 4, 5}, {0, 5, 1}, {2, 3, 5}, {2, 5, 4}, {0, 2, 4}, {1, 5, 3},
               {6, 9, 8}, {6, 7, 9}, {6, 10, 11}, {6, 11, 7}, {8, 9, 11}, {8, 11, 10}, {6, 8, 10}, {7, 11, 9}};
    ASSERT_GT(signed_volume(m), 0);
    ModelQuery q(m);
    auto placed = fit_pillar(q, {0, 0, 2}, p);
    ASSERT_EQ(placed.fit, PillarFit::Fits);
    const Pillar& pl = placed.pillar;
    EXPECT_NEAR(pl.top.y, 0, 1e-9) << "moved off the keel";
    const auto over_centre = q.first_hit(pl.top, {0, 0, 1});
    ASSERT_TRUE(over_centre.has_value());
    EXPECT_LE(std::min(over_centre->distance, nearest_from_corners(q, pl.top, p.tip_diameter, 1)), p.gap + 1e-9)
        << "the keel right above the top";
    EXPECT_TRUE(prism_is_clear(q, pl.bottom, p.d_min, pl.top, p.tip_diameter));
}

TEST(PlaceTipTop, EveryCornerKeepsTheGapUnderASteppedCeiling) {
    // The ceiling steps down by 0.5 mm 0.1 mm beside the sample: a square straight under the
    // sample would need to drop further than a contact allows; it moves to the flat side.
    Params p;
    Mesh m = box({-5, -5, 10}, {0.1, 5, 12});
    append(m, box({0.1, -5, 9.5}, {5, 5, 12}));
    ModelQuery q(m);
    const auto placed = place_tip_top(q, {0, 0, 10}, p);
    ASSERT_TRUE(placed);
    const Vec3 top = *placed;
    EXPECT_GE(nearest_from_corners(q, top, p.tip_diameter, 1), p.gap - 1e-9);
    EXPECT_LE(horizontal_distance(top, {0, 0, 10}), 0.5 + 1e-9);
    EXPECT_GE(top.z, 10 - contact_tolerance(p)) << "still a contact of its sample";
}

TEST(PlaceTipTop, NoneInASlotNarrowerThanATip) {
    // The ceiling of a 0.5 mm slot between two walls: every square a tip's width across, near the
    // sample, has a corner in a wall. No tip is placed rather than one built into the model.
    Params p;
    Mesh m = ceiling_over_walls(-0.25, 0.25);
    ModelQuery q(m);
    EXPECT_FALSE(place_tip_top(q, {0, 0, 10}, p));
    // A slot twice as wide as a tip takes one.
    Mesh wide = ceiling_over_walls(-p.tip_diameter, p.tip_diameter);
    ModelQuery qw(wide);
    EXPECT_TRUE(place_tip_top(qw, {0, 0, 10}, p));
}

TEST(PlaceTipTop, MovesOffAWallBesideItToKeepTheClearance) {
    // A ceiling at z 10 meeting a wall that goes down at x = 0.5: straight below a sample 0.5 mm
    // from the wall, a tip's top (0.8 mm square) would stand 0.1 mm from the wall in its own
    // layer, where it would print fused to the wall's outer line. It moves away, no
    // further than a top may, and keeps its gap under the ceiling.
    Params p;
    Mesh m = ceiling_over_walls(-INFINITY, 0.5);
    ModelQuery q(m);
    const auto placed = place_tip_top(q, {0, 0, 10}, p);
    ASSERT_TRUE(placed);
    const Vec3 top = *placed;
    EXPECT_LE(top.x + 0.5 * p.tip_diameter, 0.5 - tip_side_clearance(p) + 1e-9) << "keeps the clearance from the wall";
    EXPECT_LE(horizontal_distance(top, {0, 0, 10}), 0.5 + 1e-9) << "stays near its sample";
    EXPECT_NEAR(top.z, 10 - p.gap, 1e-9);
    EXPECT_GE(nearest_from_corners(q, top, p.tip_diameter, 1), p.gap - 1e-9);
}

TEST(PlaceTipTop, InASlotTooNarrowForTheClearanceTheTipStillGoes) {
    // A slot 0.9 mm wide: a tip's top fits, but nowhere with the clearance to both walls. The
    // sample keeps its tip, straight below it, rather than going unsupported.
    Params p;
    Mesh m = ceiling_over_walls(-0.45, 0.45);
    ModelQuery q(m);
    const auto placed = place_tip_top(q, {0, 0, 10}, p);
    ASSERT_TRUE(placed);
    EXPECT_NEAR(placed->x, 0, 1e-9);
    EXPECT_NEAR(placed->y, 0, 1e-9);
    EXPECT_TRUE(square_is_clear(q, *placed, p.tip_diameter));
}

TEST(PlaceTipTop, AtTheUpperEdgeOfADiagonalSlopeATipStillGoes) {
    // The upper edge of a blade's underside (the propeller in bench/validation, issue 32): a
    // 2 mm plate whose underside rises 35 degrees along x and y together (the worst case for a
    // square) and ends 0.05 mm uphill of the sample. Straight below, the tip's square dips its
    // downhill corner more than a slope along a side of the square would; uphill is past the
    // edge, with nothing above. The tip still goes there, every corner keeping the gap, rather
    // than leaving the sample unsupported.
    Params p;
    const double s = std::tan(35 * M_PI / 180) / std::sqrt(2.0);
    auto under = [&](double x, double y) { return Vec3{x, y, 8.5 + s * (x + y)}; };
    Mesh m;
    m.vertices = {under(-5, -5), under(5.05, -5), under(-5, 5.05)};
    for (int i = 0; i < 3; ++i) m.vertices.push_back(m.vertices[i] + Vec3{0, 0, 2});
    m.faces = {{0, 2, 1}, {3, 4, 5}, {0, 1, 4}, {0, 4, 3}, {1, 2, 5}, {1, 5, 4}, {2, 0, 3}, {2, 3, 5}};
    ModelQuery q(m);
    const Vec3 sample{0, 0, 8.5};
    ASSERT_FALSE(q.inside(sample - Vec3{0, 0, 0.1}));
    ASSERT_TRUE(q.inside(sample + Vec3{0, 0, 0.1}));
    const auto placed = place_tip_top(q, sample, p);
    ASSERT_TRUE(placed);
    EXPECT_NEAR(nearest_from_corners(q, *placed, p.tip_diameter, 1), p.gap, 1e-9) << "its nearest corner keeps the gap";
    EXPECT_TRUE(square_is_clear(q, *placed, p.tip_diameter));
    EXPECT_LE(horizontal_distance(*placed, sample), 0.5 + 1e-9) << "stays near its sample";
}

TEST(ContactUnderTip, FootClearsTheModelOnASlope) {
    // A 30-degree slope rising along x and y together (the worst case for a square): the tip's
    // foot keeps air under every corner.
    Params p;
    const double s = std::tan(30 * M_PI / 180) / std::sqrt(2.0);
    Mesh m;
    m.vertices = {{-5, -5, 5 - 10 * s}, {5, -5, 5}, {5, 5, 5 + 10 * s}, {-5, 5, 5}};
    m.faces = {{0, 1, 2}, {0, 2, 3}};
    ModelQuery q(m);
    const Vec3 c = contact_under_tip(q, {0, 0, 5}, 7, p);
    const Vec3 foot = c + Vec3{0, 0, p.gap};
    for (const auto& v : corners(foot, p.tip_diameter)) {
        auto hit = q.first_hit(v, {0, 0, -1});
        ASSERT_TRUE(hit.has_value());
        EXPECT_GT(hit->distance, 0.0) << "a corner of the foot lies in the slope";
    }
    EXPECT_GE(c.z, 5.0);
}

TEST(SquareIsClear, CornerInAWallIsCaught) {
    Mesh m = box({0, -5, 0}, {5, 5, 5});
    ModelQuery q(m);
    EXPECT_TRUE(square_is_clear(q, {-0.6, 0, 2}, 1.0));
    EXPECT_FALSE(square_is_clear(q, {-0.4, 0, 2}, 1.0));
}

}  // namespace

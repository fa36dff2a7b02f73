// ModelQuery on a moved model: one index of the model as given answers for the model turned and
// shifted (the orientation search judges every candidate pose from one index).
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "orient/orient.hpp"
#include "query/model_query.hpp"
#include "shapes.hpp"

namespace cs {
namespace {

Mesh moved(const Mesh& m, const Rotation& r, const Vec3& t) {
    Mesh out = m;
    for (auto& v : out.vertices) v = r.apply(v) + t;
    return out;
}

// Questions at random points and along random segments and rays in (a little beyond) the moved
// model's box: a moved index must answer them as an index built on the moved mesh does. Random
// points are never exactly on a face, so no answer hangs on rounding.
void expect_same_answers(const ModelQuery& own, const ModelQuery& shared) {
    const Box3 box = bounding_box(own.mesh());
    std::mt19937 rng(29);
    auto in_box = [&] {
        auto u = [&](double lo, double hi) { return std::uniform_real_distribution<double>(lo - 2, hi + 2)(rng); };
        return Vec3{u(box.min.x, box.max.x), u(box.min.y, box.max.y), u(box.min.z, box.max.z)};
    };
    int inside = 0, hits = 0, segments = 0;
    for (int i = 0; i < 400; ++i) {
        const Vec3 p = in_box(), q = in_box(), r = in_box();
        EXPECT_EQ(own.inside(p), shared.inside(p)) << "at " << p.x << ", " << p.y << ", " << p.z;
        inside += own.inside(p);
        EXPECT_NEAR(own.squared_distance(p), shared.squared_distance(p), 1e-9);
        EXPECT_NEAR(distance(own.closest_point(p), shared.closest_point(p)), 0, 1e-9);
        EXPECT_EQ(own.segment_hits(p, q), shared.segment_hits(p, q));
        segments += own.segment_hits(p, q);
        EXPECT_EQ(own.triangle_hits(p, q, r), shared.triangle_hits(p, q, r));
        const auto a = own.first_hit(p, q - p), b = shared.first_hit(p, q - p);
        ASSERT_EQ(a.has_value(), b.has_value());
        if (!a) continue;
        ++hits;
        EXPECT_EQ(a->face, b->face);
        EXPECT_NEAR(distance(a->point, b->point), 0, 1e-9);
        EXPECT_NEAR(a->distance, b->distance, 1e-9);
    }
    // The questions probe both answers (else the comparison proves nothing).
    EXPECT_GT(inside, 10);
    EXPECT_LT(inside, 380);
    EXPECT_GT(segments, 20);
    EXPECT_GT(hits, 20);
}

TEST(ModelQuery, MovedIndexAnswersLikeTheMovedMesh) {
    const Mesh t = test::t_shape();
    const ModelQuery as_given(t);
    const Rotation r = rotation_to_down({0.3, -0.5, 0.8});
    const Vec3 shift{4.5, -2.25, 7.0};
    const Mesh m = moved(t, r, shift);
    const ModelQuery own(m), shared(m, as_given, r.m, shift);
    EXPECT_EQ(&shared.mesh(), &m);
    expect_same_answers(own, shared);
}

// Moved twice (a moved index moved again): the two moves compose.
TEST(ModelQuery, MovedTwiceComposes) {
    const Mesh t = test::table_shape();
    const ModelQuery as_given(t);
    const Rotation r1 = rotation_to_down({1, 2, -0.5}), r2 = rotation_to_down({-0.2, 0.4, -1});
    const Vec3 s1{1, 2, 3}, s2{-3, 0.5, 10};
    const Mesh once = moved(t, r1, s1), twice = moved(once, r2, s2);
    const ModelQuery first(once, as_given, r1.m, s1), second(twice, first, r2.m, s2), own(twice);
    expect_same_answers(own, second);
}

// A CAD part's faces lie along its axes; turned off the axes, none does; a face is along an axis
// within kAlongAxis of its normal's length, no further.
TEST(ModelQuery, ShareOfFacesAlongTheAxes) {
    const Mesh t = test::t_shape();
    EXPECT_EQ(share_along_axes(t), 1.0);
    const Mesh turned = moved(t, rotation_to_down({0.3, -0.5, 0.8}), {4.5, -2.25, 7.0});
    EXPECT_EQ(share_along_axes(turned), 0.0);
    Mesh both = t;
    for (const Triangle& f : turned.faces) {
        const auto at = static_cast<std::uint32_t>(both.vertices.size());
        for (int k = 0; k < 3; ++k) both.vertices.push_back(turned.vertices[f[k]]);
        both.faces.push_back({at, at + 1, at + 2});
    }
    EXPECT_EQ(share_along_axes(both), 0.5);
    // A face whose normal is (lean, 1, 1) times -100: along the x axis where lean is 1e-12 of
    // it, not where it is 1e-6.
    for (const auto& [lean, along] : {std::pair{1e-12, 1.0}, std::pair{1e-6, 0.0}}) {
        const Mesh wall{{{0, 0, 0}, {0, 10, -10}, {10, -5 * lean, -5 * lean}}, {{0, 1, 2}}};
        EXPECT_EQ(share_along_axes(wall), along) << "lean " << lean;
    }
    EXPECT_EQ(share_along_axes(Mesh{}), 0.0);
}

// A query remembers its answers: asked again, or after other questions, it answers bit for bit as
// a fresh query asked once does.
TEST(ModelQuery, AnswersDoNotDependOnWhatWasAskedBefore) {
    const Mesh m = test::bridge_shape();
    const ModelQuery asked(m);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-14, 14);
    std::vector<Vec3> points;
    for (int i = 0; i < 200; ++i) points.push_back({u(rng), 0.5 * u(rng), 0.4 * u(rng) + 5});
    auto same = [](const Vec3& a, const Vec3& b) { return a.x == b.x && a.y == b.y && a.z == b.z; };
    for (int round = 0; round < 2; ++round)
        for (size_t i = 0; i + 1 < points.size(); ++i) {
            const Vec3 &p = points[i], &q = points[i + 1];
            const ModelQuery fresh(m);
            EXPECT_EQ(asked.inside(p), fresh.inside(p));
            EXPECT_EQ(asked.segment_hits(p, q), fresh.segment_hits(p, q));
            EXPECT_EQ(asked.squared_distance(p), fresh.squared_distance(p));
            EXPECT_TRUE(same(asked.closest_point(p), fresh.closest_point(p)));
            const auto a = asked.first_hit(p, q - p), b = fresh.first_hit(p, q - p);
            ASSERT_EQ(a.has_value(), b.has_value());
            if (a) EXPECT_TRUE(same(a->point, b->point) && a->face == b->face && a->distance == b->distance);
        }
}

// A caller's verdict is decided once per question (exact bits, kind included) and kept.
TEST(ModelQuery, RemembersAVerdictByItsQuestion) {
    const Mesh m = test::bridge_shape();
    const ModelQuery q(m);
    int decided = 0;
    auto decide = [&](bool answer) { return [&decided, answer] { return ++decided, answer; }; };
    const ModelQuery::Question a{1, 0.5, 2.0}, other_kind{2, 0.5, 2.0}, nearby{1, 0.5, std::nextafter(2.0, 3.0)};
    EXPECT_TRUE(q.verdict(a, decide(true)));
    EXPECT_TRUE(q.verdict(a, decide(false)));  // the first answer, not asked again
    EXPECT_EQ(decided, 1);
    EXPECT_FALSE(q.verdict(other_kind, decide(false)));
    EXPECT_FALSE(q.verdict(nearby, decide(false)));
    EXPECT_EQ(decided, 3);
    const ModelQuery fresh(m);  // each query (a job's pose) keeps its own
    EXPECT_FALSE(fresh.verdict(a, decide(false)));
    EXPECT_EQ(decided, 4);
}

}  // namespace
}  // namespace cs

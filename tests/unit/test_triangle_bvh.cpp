// ModelQuery answers through its own BVH (query/triangle_bvh.hpp) exactly as it did through CGAL's
// AABB tree alone: the tree is built here the way ModelQuery built it before, and asked the same
// questions. Exactly means bit for bit: the face, the point and the distance of a ray's first hit
// (where two faces tie or rounding decides, CGAL's answer is what the generator has always used),
// every segment's verdict, every inside verdict, every closest point and squared distance. The questions include the hard
// ones: points on the grid lines of an axis-aligned sponge, rays along its faces and edges.
#include <gtest/gtest.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Simple_cartesian.h>

#include <bit>
#include <random>

#include "query/model_query.hpp"
#include "query/triangle_bvh.hpp"
#include "shapes.hpp"

namespace cs {
namespace {

using K = CGAL::Simple_cartesian<double>;
using Point = K::Point_3;
using Triangle3 = K::Triangle_3;
using Primitive = CGAL::AABB_triangle_primitive<K, std::vector<Triangle3>::const_iterator>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<K, Primitive>>;

Point pt(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

// The index ModelQuery had before the BVH, with its answers computed as it computed them.
struct OldIndex {
    std::vector<Triangle3> triangles;
    Tree tree;
    explicit OldIndex(const Mesh& m) {
        for (const auto& f : m.faces)
            triangles.emplace_back(pt(m.vertices[f[0]]), pt(m.vertices[f[1]]), pt(m.vertices[f[2]]));
        tree.insert(triangles.begin(), triangles.end());
        tree.build();
        tree.accelerate_distance_queries();
    }
    std::optional<RayHit> first_hit(const Vec3& o, const Vec3& d) const {
        auto hit = tree.first_intersection(K::Ray_3(pt(o), K::Vector_3(d.x, d.y, d.z)));
        if (!hit) return std::nullopt;
        Vec3 q;
        if (const Point* p = boost::get<Point>(&hit->first)) {
            q = vec(*p);
        } else if (const auto* s = boost::get<K::Segment_3>(&hit->first)) {
            Vec3 a = vec(s->source()), b = vec(s->target());
            q = distance(a, o) < distance(b, o) ? a : b;
        } else {
            return std::nullopt;
        }
        return RayHit{q, distance(q, o), static_cast<std::size_t>(hit->second - triangles.begin())};
    }
    Vec3 closest_point(const Vec3& p) const { return vec(tree.closest_point(pt(p))); }
    double squared_distance(const Vec3& p) const { return tree.squared_distance(pt(p)); }
    bool segment_hits(const Vec3& a, const Vec3& b) const {
        return a != b && tree.do_intersect(K::Segment_3(pt(a), pt(b)));
    }
    bool inside(const Vec3& p) const {
        static const Vec3 dirs[3] = {{0.5773, 0.5781, -0.5767}, {-0.7071, 0.0123, -0.7070}, {0.0211, -0.9981, -0.0582}};
        int votes = 0;
        for (int r = 0; r < 3; ++r) {
            const K::Vector_3 d(dirs[r].x, dirs[r].y, dirs[r].z);
            std::vector<Tree::Primitive_id> hits;
            tree.all_intersected_primitives(K::Ray_3(pt(p), d), std::back_inserter(hits));
            int winding = 0;
            for (auto id : hits) {
                double s = CGAL::scalar_product(id->supporting_plane().orthogonal_vector(), d);
                winding += s > 0 ? 1 : (s < 0 ? -1 : 0);
            }
            votes += winding > 0;
            if (r == 1 && votes != 1) break;
        }
        return votes >= 2;
    }
};

bool same_bits(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }

// A level-2 Menger sponge of side `side` (9 x 9 x 9 cells, the holes carved through), its grid
// lines at multiples of side / 9 rounded as doubles are: the shape of the benchmark's slowest model.
Mesh sponge(double side) {
    std::vector<double> g;
    for (int i = 0; i <= 9; ++i) g.push_back(side * i / 9);
    test::CellGrid grid(g, g, g);
    for (int k = 0; k < 9; ++k)
        for (int j = 0; j < 9; ++j)
            for (int i = 0; i < 9; ++i) {
                // A cell is carved where two of its coordinates are in the middle third at some level.
                const bool a = i % 3 == 1, b = j % 3 == 1, c = k % 3 == 1;
                const bool A = (i / 3) % 3 == 1, B = (j / 3) % 3 == 1, C = (k / 3) % 3 == 1;
                if ((a + b + c) >= 2 || (A + B + C) >= 2) continue;
                grid.set(i, j, k);
            }
    return grid.mesh();
}

struct Counts {
    int hits = 0, segments = 0, inside = 0, on_edges = 0;
};

// `n` questions of each kind; on_grid: coordinates drawn from the sponge's grid lines (and the
// middles between them), directions along the axes and the diagonals, so rays run along faces and
// through edges, where ties and rounding decide.
Counts expect_same_as_old(const Mesh& m, int n, bool on_grid, double side, std::uint32_t seed) {
    const ModelQuery q(m);
    const OldIndex old(m);
    std::mt19937 rng(seed);
    const Box3 box = bounding_box(m);
    auto coordinate = [&](double lo, double hi) {
        if (!on_grid) return std::uniform_real_distribution<double>(lo - 2, hi + 2)(rng);
        const int i = std::uniform_int_distribution<int>(-1, 19)(rng);
        return side * i / 18;  // grid lines (even i) and cell middles (odd i)
    };
    auto point = [&] {
        return Vec3{coordinate(box.min.x, box.max.x), coordinate(box.min.y, box.max.y), coordinate(box.min.z, box.max.z)};
    };
    static const Vec3 axes[] = {{0, 0, -1}, {0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0},
                                {1, 1, 0},  {1, 0, -1}, {0.3, -0.2, -1}};
    Counts c;
    for (int i = 0; i < n; ++i) {
        const Vec3 p = point(), r = point();
        const Vec3 d = on_grid ? axes[std::uniform_int_distribution<int>(0, 8)(rng)] : r - p;
        const auto mine = q.first_hit(p, d), theirs = old.first_hit(p, d);
        EXPECT_EQ(mine.has_value(), theirs.has_value()) << i;
        if (mine && theirs) {
            ++c.hits;
            EXPECT_EQ(mine->face, theirs->face) << i;
            EXPECT_TRUE(same_bits(mine->point.x, theirs->point.x) && same_bits(mine->point.y, theirs->point.y) &&
                        same_bits(mine->point.z, theirs->point.z))
                << i;
            EXPECT_TRUE(same_bits(mine->distance, theirs->distance)) << i;
            c.on_edges += mine->distance == 0;
        }
        const bool seg = q.segment_hits(p, r);
        EXPECT_EQ(seg, old.segment_hits(p, r)) << i;
        c.segments += seg;
        const Vec3 near = q.closest_point(p), near_old = old.closest_point(p);
        EXPECT_TRUE(same_bits(near.x, near_old.x) && same_bits(near.y, near_old.y) && same_bits(near.z, near_old.z)) << i;
        EXPECT_TRUE(same_bits(q.squared_distance(p), old.squared_distance(p))) << i;
        const bool in = q.inside(p);
        EXPECT_EQ(in, old.inside(p)) << i;
        c.inside += in;
    }
    return c;
}

TEST(TriangleBvh, ModelQueryAnswersAsCgalsTreeOnRandomQuestions) {
    const Mesh t = test::t_shape();
    const Counts c = expect_same_as_old(t, 3000, false, 0, 7);
    EXPECT_GT(c.hits, 300);  // both answers probed
    EXPECT_GT(c.segments, 300);
    EXPECT_GT(c.inside, 30);
    const Mesh s = sponge(80);
    const Counts d = expect_same_as_old(s, 3000, false, 0, 8);
    EXPECT_GT(d.hits, 300);
    EXPECT_GT(d.segments, 300);
    EXPECT_GT(d.inside, 100);
}

TEST(TriangleBvh, ModelQueryAnswersAsCgalsTreeOnGridLines) {
    // Two sides whose ninths are not exact doubles (180,000 such questions passed when written).
    for (double side : {80.0, 27.7}) {
        const Mesh s = sponge(side);
        const Counts c = expect_same_as_old(s, 5000, true, side, 9);
        EXPECT_GT(c.hits, 1000);
        EXPECT_GT(c.segments, 1000);
        EXPECT_GT(c.inside, 300);
        EXPECT_GT(c.on_edges, 10);  // rays starting on a face: the ties and overlaps are probed
    }
}

TEST(TriangleBvh, OffersEveryFaceASegmentTouches) {
    // Conservative: a face the segment touches (by CGAL's predicate) is always offered.
    const Mesh s = sponge(10);
    const TriangleBvh bvh(s);
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1, 11);
    int touched = 0;
    for (int i = 0; i < 500; ++i) {
        const Vec3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
        std::vector<char> offered(s.faces.size(), 0);
        bvh.along_segment(a, b, [&](std::uint32_t f) { return offered[f] = 1, false; });
        for (std::size_t f = 0; f < s.faces.size(); ++f) {
            const auto& v = s.vertices;
            const Triangle3 tri(pt(v[s.faces[f][0]]), pt(v[s.faces[f][1]]), pt(v[s.faces[f][2]]));
            if (!CGAL::do_intersect(K::Segment_3(pt(a), pt(b)), tri)) continue;
            ++touched;
            EXPECT_TRUE(offered[f]) << "segment " << i << " face " << f;
        }
    }
    EXPECT_GT(touched, 500);
}

}  // namespace
}  // namespace cs

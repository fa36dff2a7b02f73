// count_self_intersections counts, on a closed manifold mesh, without the Surface_mesh CGAL's
// self_intersections walks (query/model_query.cpp): the count must be CGAL's own, pair for pair,
// on meshes whose faces cross, fold onto each other in a plane, pass the limit, come in any
// order, and on meshes a Surface_mesh cannot take whole (counted by CGAL itself there).
#include <gtest/gtest.h>

#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "query/model_query.hpp"

namespace cs {
namespace {

using K = CGAL::Simple_cartesian<double>;
using SM = CGAL::Surface_mesh<K::Point_3>;

// What the count was before: CGAL's self_intersections on a Surface_mesh of the faces, to `limit`.
std::size_t cgal_count(const Mesh& m, std::size_t limit) {
    SM sm;
    std::vector<SM::Vertex_index> vs;
    for (const Vec3& v : m.vertices) vs.push_back(sm.add_vertex({v.x, v.y, v.z}));
    for (const Triangle& f : m.faces) sm.add_face(vs[f[0]], vs[f[1]], vs[f[2]]);
    std::vector<std::pair<SM::Face_index, SM::Face_index>> pairs;
    CGAL::Polygon_mesh_processing::self_intersections(sm, std::back_inserter(pairs));
    return std::min(pairs.size(), limit);
}

void add(Mesh& into, const Mesh& part) {
    const auto base = static_cast<std::uint32_t>(into.vertices.size());
    into.vertices.insert(into.vertices.end(), part.vertices.begin(), part.vertices.end());
    for (Triangle f : part.faces) into.faces.push_back({f[0] + base, f[1] + base, f[2] + base});
}

// A closed UV sphere, outward, its seam turned by `turn` radians.
Mesh sphere(const Vec3& c, double r, int n, double turn = 0) {
    Mesh m;
    m.vertices.push_back(c + Vec3{0, 0, r});
    for (int i = 1; i < n; ++i)
        for (int j = 0; j < 2 * n; ++j) {
            const double th = M_PI * i / n, ph = M_PI * j / n + turn;
            m.vertices.push_back(c + Vec3{r * std::sin(th) * std::cos(ph), r * std::sin(th) * std::sin(ph), r * std::cos(th)});
        }
    m.vertices.push_back(c - Vec3{0, 0, r});
    const auto ring = [&](int i, int j) { return static_cast<std::uint32_t>(1 + (i - 1) * 2 * n + (j % (2 * n))); };
    const auto bottom = static_cast<std::uint32_t>(m.vertices.size() - 1);
    for (int j = 0; j < 2 * n; ++j) {
        m.faces.push_back({0, ring(1, j), ring(1, j + 1)});
        m.faces.push_back({bottom, ring(n - 1, j + 1), ring(n - 1, j)});
        for (int i = 1; i + 1 < n; ++i) {
            m.faces.push_back({ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)});
            m.faces.push_back({ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)});
        }
    }
    return m;
}

// An axis-aligned cube, outward.
Mesh cube(const Vec3& lo, double s) {
    Mesh m;
    for (int x = 0; x < 2; ++x)
        for (int y = 0; y < 2; ++y)
            for (int z = 0; z < 2; ++z) m.vertices.push_back(lo + Vec3{s * x, s * y, s * z});
    m.faces = {{0, 1, 3}, {0, 3, 2}, {4, 6, 7}, {4, 7, 5}, {0, 4, 5}, {0, 5, 1},
               {2, 3, 7}, {2, 7, 6}, {0, 2, 6}, {0, 6, 4}, {1, 5, 7}, {1, 7, 3}};
    return m;
}

TEST(SelfIntersections, OneClosedSurfaceCrossesNothing) {
    const Mesh m = sphere({0, 0, 0}, 10, 12);
    EXPECT_EQ(count_self_intersections(m, 1000), 0u);
    EXPECT_EQ(cgal_count(m, 1000), 0u);
}

// Ours counts `m` as CGAL does, where CGAL finds more than `at_least`: a mesh that crosses itself.
void expect_counted_as_cgal_counts(const Mesh& m, std::size_t at_least) {
    const std::size_t n = cgal_count(m, 1000);
    EXPECT_GT(n, at_least);
    EXPECT_EQ(count_self_intersections(m, 1000), n);
}

TEST(SelfIntersections, CrossingSpheresCountAsCgalCounts) {
    Mesh m = sphere({0, 0, 0}, 10, 10);
    add(m, sphere({12, 1, 0.5}, 9, 9, 0.1));
    expect_counted_as_cgal_counts(m, 10);
}

TEST(SelfIntersections, CoplanarOverlapsCountAsCgalCounts) {
    // Two cubes on one floor, overlapping in their bottom and top faces' planes.
    Mesh m = cube({0, 0, 0}, 10);
    add(m, cube({5, 5, 0}, 10));
    expect_counted_as_cgal_counts(m, 0);
}

TEST(SelfIntersections, StopsAtTheLimit) {
    Mesh m = sphere({0, 0, 0}, 10, 120);
    add(m, sphere({5, 0, 0}, 10, 120, 0.05));
    ASSERT_GT(cgal_count(m, 1000000), 1000u);
    EXPECT_EQ(count_self_intersections(m, 1000), 1000u);
    EXPECT_EQ(count_self_intersections(m, 50), 50u);
}

TEST(SelfIntersections, FacesInAnyOrderCountTheSame) {
    Mesh m = sphere({0, 0, 0}, 10, 10);
    add(m, sphere({8, 3, 2}, 8, 8, 0.3));
    std::shuffle(m.faces.begin(), m.faces.end(), std::mt19937(7));
    expect_counted_as_cgal_counts(m, 0);
}

TEST(SelfIntersections, MeshesNotClosedOrNotManifoldAreCgalsCount) {
    // Two cubes meeting at one corner (a vertex two fans share), a sphere with a face missing and
    // one with a face turned: a Surface_mesh leaves faces out of these, and CGAL counts what it has.
    Mesh pinched = cube({0, 0, 0}, 10);
    add(pinched, cube({10, 10, 10}, 10));
    Mesh open = sphere({0, 0, 0}, 10, 8);
    add(open, sphere({6, 0, 0}, 10, 8, 0.2));
    open.faces.erase(open.faces.begin() + 5);
    Mesh turned = open;
    std::swap(turned.faces[9][1], turned.faces[9][2]);
    for (const Mesh* m : {&pinched, &open, &turned}) EXPECT_EQ(count_self_intersections(*m, 1000), cgal_count(*m, 1000));
}

}  // namespace
}  // namespace cs

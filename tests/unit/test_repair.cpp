// mesh/repair: welding, dropping bad triangles, orientation, shells, placement on the bed.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "check/check.hpp"
#include "core/errors.hpp"
#include "mesh/repair.hpp"
#include "mesh/unfold_caps.hpp"
#include "mesh/weld.hpp"
#include "support.hpp"

using namespace cs;
using cs::test::box;

namespace {

// Three fresh vertices per triangle, as STL stores them.
Mesh to_soup(const Mesh& m) {
    Mesh s;
    for (const auto& f : m.faces) {
        auto n = static_cast<std::uint32_t>(s.vertices.size());
        for (auto i : f) s.vertices.push_back(m.vertices[i]);
        s.faces.push_back({n, n + 1, n + 2});
    }
    return s;
}

Mesh joined(const Mesh& a, const Mesh& b) {
    Mesh m = a;
    append(m, b);
    return m;
}

Mesh inverted(Mesh m) {
    for (auto& f : m.faces) std::swap(f[1], f[2]);
    return m;
}

Mesh repair(const Mesh& raw, RepairReport& r) { return repair_mesh(raw, "test.stl", r); }

bool has_warning(const RepairReport& r, const std::string& phrase) {
    for (const auto& w : r.warnings)
        if (w.find(phrase) != std::string::npos && w.find("test.stl") != std::string::npos) return true;
    return false;
}

// Every face's outward normal, as a multiset of rounded directions (orientation-sensitive).
std::multiset<std::array<long, 3>> normal_set(const Mesh& m) {
    std::multiset<std::array<long, 3>> s;
    for (const auto& f : m.faces) {
        Vec3 n = normalized(face_normal_unnormalized(m, f));
        s.insert({std::lround(n.x * 1000), std::lround(n.y * 1000), std::lround(n.z * 1000)});
    }
    return s;
}

std::vector<double> edge_lengths(const Mesh& m) {
    std::vector<double> l;
    for (const auto& f : m.faces)
        for (int k = 0; k < 3; ++k) l.push_back(distance(m.vertices[f[k]], m.vertices[f[(k + 1) % 3]]));
    return l;
}

// A 10 mm cube without its top, the corners of the top (counter-clockwise from above, from the
// origin's) and one new vertex `c` at `apex` in the top's plane: the caller closes the top.
struct OpenTopCube {
    Mesh mesh;
    std::uint32_t corner[4];
    std::uint32_t c;
};

OpenTopCube cube_without_top(Vec3 apex) {
    OpenTopCube o{box({0, 0, 0}, {10, 10, 10}), {}, 0};
    Mesh& m = o.mesh;
    std::erase_if(m.faces, [&](const Triangle& f) {
        return m.vertices[f[0]].z == 10 && m.vertices[f[1]].z == 10 && m.vertices[f[2]].z == 10;
    });
    const Vec3 corners[4] = {{0, 0, 10}, {10, 0, 10}, {10, 10, 10}, {0, 10, 10}};
    for (int k = 0; k < 4; ++k) {
        auto it = std::find(m.vertices.begin(), m.vertices.end(), corners[k]);
        EXPECT_NE(it, m.vertices.end()) << "no cube corner " << k;
        o.corner[k] = static_cast<std::uint32_t>(it - m.vertices.begin());
    }
    o.c = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.push_back(apex);
    return o;
}

// A 10 mm cube whose top is a, x, b, y (counter-clockwise from above) with a vertex c near the
// diagonal a-b: the top triangles are (a, x, b), (a, c, y), (c, b, y) and the cap (a, b, c). With
// c on x's side of the diagonal (`folded`), the cap faces down, folded back over (a, x, b): a
// scanner's fold. On y's side it is an ordinary sliver lying flat in the top.
Mesh cube_with_cap_on_top(bool folded) {
    OpenTopCube o = cube_without_top({5, folded ? 4.8 : 5.2, 10});
    const auto [a, x, b, y] = o.corner;
    const std::uint32_t c = o.c;
    o.mesh.faces.insert(o.mesh.faces.end(), {{a, x, b}, {a, b, c}, {a, c, y}, {c, b, y}});
    return o.mesh;
}

// A 10 mm cube whose top carries a sliver along its front edge a-b: the cap (a, b, c) with c
// 0.3 mm in from the edge (apex 173 degrees), facing up, at 90 degrees to the front face across.
Mesh cube_with_sliver_along_an_edge() {
    OpenTopCube o = cube_without_top({5, 0.3, 10});
    const auto [a, b, e, f] = o.corner;
    const std::uint32_t c = o.c;
    o.mesh.faces.insert(o.mesh.faces.end(), {{a, b, c}, {c, b, e}, {c, e, f}, {a, c, f}});
    return o.mesh;
}
}  // namespace

// mesh/weld: the one weld (repair, check's shells and the 3MF writer all use it).
TEST(Weld, AnStlCubeWeldsToItsEightCornersInOrderOfFirstAppearance) {
    const Mesh cube = box({0, 0, 0}, {1, 2, 3});
    const Mesh soup = to_soup(cube);
    const Welded w = weld_vertices(soup);
    ASSERT_EQ(w.mesh.vertices.size(), 8u);
    ASSERT_EQ(w.mesh.faces.size(), soup.faces.size());
    ASSERT_EQ(w.remap.size(), soup.vertices.size());
    std::uint32_t next = 0;  // a vertex seen for the first time gets the next number
    for (size_t i = 0; i < soup.vertices.size(); ++i) {
        EXPECT_TRUE(w.mesh.vertices[w.remap[i]] == soup.vertices[i]) << i;
        if (w.remap[i] == next) ++next;
        EXPECT_LT(w.remap[i], next) << "numbered out of order at " << i;
    }
    for (size_t f = 0; f < soup.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) EXPECT_EQ(w.mesh.faces[f][k], w.remap[soup.faces[f][k]]);
}

TEST(Weld, OnlyEqualCoordinatesWeldAndMinusZeroIsZero) {
    Mesh m;
    m.vertices = {{0, 0, 0}, {-0.0, 0, -0.0}, {1e-12, 0, 0}, {1, 1, 1}};
    m.faces = {{0, 2, 3}, {1, 2, 3}};
    const Welded w = weld_vertices(m);
    EXPECT_EQ(w.mesh.vertices.size(), 3u);  // -0 is 0; 1e-12 is not
    EXPECT_EQ(w.remap[0], w.remap[1]);
    EXPECT_NE(w.remap[0], w.remap[2]);
}

// The weld before it grouped by hash (speed5): coordinates sorted with their index, each vertex to
// the first of its run. The grouping by hash must give the same vertices, order and faces.
Welded weld_by_sorting(const Mesh& m) {
    const auto& mv = m.vertices;
    const auto n = static_cast<std::uint32_t>(mv.size());
    std::vector<std::uint32_t> by_coords(n);
    for (std::uint32_t i = 0; i < n; ++i) by_coords[i] = i;
    auto key = [&](std::uint32_t i) { return std::make_tuple(mv[i].x, mv[i].y, mv[i].z); };
    std::sort(by_coords.begin(), by_coords.end(), [&](std::uint32_t a, std::uint32_t b) {
        return key(a) != key(b) ? key(a) < key(b) : a < b;
    });
    std::vector<std::uint32_t> first(n);
    for (std::uint32_t i = 0; i < n; ++i)
        first[by_coords[i]] = i > 0 && key(by_coords[i]) == key(by_coords[i - 1]) ? first[by_coords[i - 1]] : by_coords[i];
    Welded w;
    w.remap.resize(n);
    for (std::uint32_t i = 0; i < n; ++i) {
        if (first[i] == i) w.remap[i] = static_cast<std::uint32_t>(w.mesh.vertices.size()), w.mesh.vertices.push_back(mv[i]);
        else w.remap[i] = w.remap[first[i]];
    }
    for (const auto& f : m.faces) w.mesh.faces.push_back({w.remap[f[0]], w.remap[f[1]], w.remap[f[2]]});
    return w;
}

TEST(Weld, GroupingByHashWeldsAsSortingTheCoordinates) {
    // Soups small (std::sort inside) and large (the radix passes), coordinates drawn from a few
    // values with signed zeros, so most vertices repeat some earlier one.
    std::uint64_t state = 12345;
    auto next = [&state] {
        state = state * 6364136223846793005ull + 1442695040888963407ull;
        return static_cast<std::uint32_t>(state >> 33);
    };
    const double values[] = {0.0, -0.0, 1.0, -1.0, 0.1, 0.1 + 1e-16, 2.5, 1e-300, -1e-300, 123456.789};
    for (std::uint32_t vertices : {3u, 30u, 1000u, 5000u, 60000u}) {
        Mesh m;
        for (std::uint32_t i = 0; i < vertices; ++i)
            m.vertices.push_back({values[next() % 10], values[next() % 10], values[next() % 4]});
        for (std::uint32_t i = 0; i + 2 < vertices; i += 3) m.faces.push_back({i, i + 1, i + 2});
        const Welded fast = weld_vertices(m), slow = weld_by_sorting(m);
        EXPECT_EQ(fast.remap, slow.remap) << vertices;
        EXPECT_EQ(fast.mesh.faces, slow.mesh.faces) << vertices;
        ASSERT_EQ(fast.mesh.vertices.size(), slow.mesh.vertices.size()) << vertices;
        for (std::size_t i = 0; i < fast.mesh.vertices.size(); ++i) {
            const Vec3 &a = fast.mesh.vertices[i], &b = slow.mesh.vertices[i];
            EXPECT_TRUE(std::signbit(a.x) == std::signbit(b.x) && a.x == b.x && a.y == b.y && a.z == b.z &&
                        std::signbit(a.z) == std::signbit(b.z))
                << vertices << " " << i;
        }
    }
    // A scan's soup: every vertex in six faces, repeated far apart.
    Mesh soup = to_soup(box({0, 0, 0}, {1, 2, 3}));
    for (int copy = 0; copy < 2000; ++copy) {
        Mesh b = to_soup(box({double(copy % 40), double(copy / 40), 0}, {double(copy % 40) + 1, double(copy / 40) + 1, 1}));
        append(soup, b);
    }
    const Welded fast = weld_vertices(soup), slow = weld_by_sorting(soup);
    EXPECT_EQ(fast.remap, slow.remap);
    EXPECT_EQ(fast.mesh.faces, slow.mesh.faces);
}

TEST(Repair, WeldsStlSoupBox) {
    Mesh soup = to_soup(box({0, 0, 0}, {10, 10, 10}));
    ASSERT_EQ(soup.vertices.size(), 36u);
    RepairReport r;
    Mesh m = repair(soup, r);
    EXPECT_EQ(r.input_triangles, 12u);
    EXPECT_EQ(r.welded_vertices, 28u);  // 36 corners onto 8 vertices
    EXPECT_EQ(m.vertices.size(), 8u);
    EXPECT_EQ(m.faces.size(), 12u);
    EXPECT_EQ(r.flipped, 0u);
    EXPECT_EQ(r.boundary_edges, 0u);
    EXPECT_EQ(r.nonmanifold_edges, 0u);
    EXPECT_EQ(r.shells, 1u);
    EXPECT_TRUE(r.warnings.empty());
    EXPECT_TRUE(is_closed_and_consistent(m));
    EXPECT_NEAR(signed_volume(m), 1000, 1e-9);
}

TEST(Repair, IndexedInputReportsNoWelding) {
    RepairReport r;
    repair(box({0, 0, 0}, {10, 10, 10}), r);
    EXPECT_EQ(r.welded_vertices, 0u);
}

TEST(Repair, DropsDegenerateAndDuplicateTriangles) {
    Mesh m = box({0, 0, 0}, {10, 10, 10});
    m.faces.push_back({0, 0, 5});                                      // repeated index
    m.vertices.push_back({5, 0, 0});                                   // midpoint of edge 0-1
    m.faces.push_back({0, 1, static_cast<std::uint32_t>(m.vertices.size() - 1)});  // collinear: zero area
    m.faces.push_back(m.faces[3]);                                     // the same triangle again
    m.faces.push_back({m.faces[6][1], m.faces[6][2], m.faces[6][0]});  // again, corners rotated
    m.faces.push_back({m.faces[8][0], m.faces[8][2], m.faces[8][1]});  // again, reversed
    RepairReport r;
    Mesh out = repair(m, r);
    EXPECT_EQ(r.degenerate_removed, 2u);
    EXPECT_EQ(r.duplicates_removed, 3u);
    EXPECT_EQ(out.faces.size(), 12u);
    EXPECT_EQ(out.vertices.size(), 8u);  // the unused midpoint is not carried along
    EXPECT_TRUE(is_closed_and_consistent(out));
    EXPECT_NEAR(signed_volume(out), 1000, 1e-9);
    EXPECT_TRUE(has_warning(r, "2 degenerate triangles removed"));
    EXPECT_TRUE(has_warning(r, "3 duplicate triangles removed"));
}

TEST(Repair, SomeFlippedFacesComeBackConsistentAndOutward) {
    Mesh m = box({0, 0, 0}, {10, 20, 30});
    for (int i : {1, 4, 7, 10}) std::swap(m.faces[i][1], m.faces[i][2]);
    RepairReport r;
    Mesh out = repair(m, r);
    EXPECT_EQ(r.flipped, 4u);
    EXPECT_TRUE(is_closed_and_consistent(out));
    EXPECT_NEAR(signed_volume(out), 6000, 1e-9);
    EXPECT_EQ(normal_set(out), normal_set(box({0, 0, 0}, {10, 20, 30})));
    EXPECT_TRUE(has_warning(r, "4 triangles flipped to face outward"));
}

TEST(Repair, MostFacesFlippedStillEndsOutward) {
    // The seed face of the orientation sweep is itself one of the wrong ones.
    Mesh m = box({0, 0, 0}, {10, 20, 30});
    for (int i = 0; i < 9; ++i) std::swap(m.faces[i][1], m.faces[i][2]);
    RepairReport r;
    Mesh out = repair(to_soup(m), r);
    EXPECT_EQ(r.flipped, 9u);
    EXPECT_TRUE(is_closed_and_consistent(out));
    EXPECT_NEAR(signed_volume(out), 6000, 1e-9);
}

TEST(Repair, FullyInvertedBoxIsFlipped) {
    Mesh m = inverted(box({-5, -5, 0}, {5, 5, 4}));
    ASSERT_LT(signed_volume(m), 0);
    RepairReport r;
    Mesh out = repair(to_soup(m), r);
    EXPECT_EQ(r.flipped, 12u);
    EXPECT_NEAR(signed_volume(out), 400, 1e-9);
    EXPECT_TRUE(is_closed_and_consistent(out));
    EXPECT_TRUE(has_warning(r, "12 triangles flipped to face outward"));
}

TEST(Repair, OpenBoxIsClosedWithAPatchAndAWarning) {
    Mesh m = box({0, 0, 0}, {10, 10, 10});
    m.faces.erase(m.faces.begin() + 2, m.faces.begin() + 4);  // the top (z = 10) face
    RepairReport r;
    Mesh out;
    ASSERT_NO_THROW(out = repair(to_soup(m), r));
    EXPECT_EQ(r.boundary_edges, 4u);
    EXPECT_EQ(r.holes_filled, 1u);
    EXPECT_EQ(r.boundary_edges_left, 0u);
    EXPECT_EQ(r.nonmanifold_edges, 0u);
    EXPECT_EQ(out.faces.size(), 12u);
    EXPECT_EQ(r.flipped, 0u);
    EXPECT_TRUE(is_closed_and_consistent(out));
    EXPECT_NEAR(signed_volume(out), 1000, 1e-9);
    for (const auto& f : out.faces)  // the patch is the top again, facing up
        if (out.vertices[f[0]].z == 10 && out.vertices[f[1]].z == 10 && out.vertices[f[2]].z == 10)
            EXPECT_GT(face_normal_unnormalized(out, f).z, 0);
    EXPECT_TRUE(has_warning(r, "1 hole closed with a patch (4 open edges)"));
}

TEST(Repair, ABentHoleIsClosedIntoAConsistentSolid) {
    // The top and one side missing: one loop of six edges that does not lie in a plane.
    Mesh m = box({0, 0, 0}, {10, 10, 10});
    std::vector<Triangle> kept;
    for (const auto& f : m.faces) {
        const Vec3 n = face_normal_unnormalized(m, f);
        if (n.z > 0 || n.x > 0) continue;
        kept.push_back(f);
    }
    ASSERT_EQ(kept.size(), 8u);
    m.faces = kept;
    RepairReport r;
    Mesh out = repair(to_soup(m), r);
    EXPECT_EQ(r.boundary_edges, 6u);
    EXPECT_EQ(r.holes_filled, 1u);
    EXPECT_EQ(r.boundary_edges_left, 0u);
    EXPECT_TRUE(is_closed_and_consistent(out));
    EXPECT_EQ(out.faces.size(), 12u);  // a six-edge loop takes four triangles
    EXPECT_GT(signed_volume(out), 0);
}

TEST(Repair, OpenInvertedBoxIsTurnedOutward) {
    Mesh m = inverted(box({0, 0, 0}, {10, 10, 10}));
    m.faces.erase(m.faces.begin() + 2, m.faces.begin() + 4);
    RepairReport r;
    Mesh out = repair(m, r);
    EXPECT_EQ(r.boundary_edges, 4u);
    EXPECT_EQ(r.flipped, 10u);
    // The bottom face points down again.
    for (const auto& f : out.faces) {
        Vec3 n = face_normal_unnormalized(out, f);
        bool bottom = out.vertices[f[0]].z == 0 && out.vertices[f[1]].z == 0 && out.vertices[f[2]].z == 0;
        if (bottom) EXPECT_LT(n.z, 0);
    }
}

TEST(Repair, FlatMeshThrowsInputError) {
    Mesh flat;
    flat.vertices = {{0, 0, 0}, {10, 0, 0}, {10, 10, 0}, {0, 10, 0}};
    flat.faces = {{0, 1, 2}, {0, 2, 3}};
    RepairReport r;
    try {
        repair_mesh(flat, "flat.stl", r);
        FAIL() << "no InputError";
    } catch (const InputError& e) {
        std::string msg = e.what();
        EXPECT_NE(msg.find("flat.stl"), std::string::npos) << msg;
        EXPECT_NE(msg.find("encloses no volume"), std::string::npos) << msg;
    }
}

TEST(Repair, FlatSquareAwayFromTheOriginThrowsInputError) {
    // The same single square, but not in a plane through the origin (as any real export is): the
    // signed volume of an OPEN mesh depends on where the origin is, so it cannot prove volume.
    Mesh flat;
    flat.vertices = {{10, 0, 5}, {20, 0, 5}, {20, 10, 5}, {10, 10, 5}};
    flat.faces = {{0, 1, 2}, {0, 2, 3}};
    RepairReport r;
    EXPECT_THROW(repair_mesh(flat, "flat5.stl", r), InputError);
    // Both sides of it (which repair reduces to one side, as duplicates).
    Mesh sheet = flat;
    sheet.faces.push_back({0, 2, 1});
    sheet.faces.push_back({0, 3, 2});
    EXPECT_THROW(repair_mesh(sheet, "sheet.stl", r), InputError);
}

TEST(Repair, AllDegenerateThrowsInputError) {
    Mesh m;
    m.vertices = {{0, 0, 0}, {1, 1, 1}, {2, 2, 2}, {0, 0, 0}};
    m.faces = {{0, 0, 1}, {0, 1, 2}, {0, 3, 1}};
    RepairReport r;
    try {
        repair_mesh(m, "degenerate.stl", r);
        FAIL() << "no InputError";
    } catch (const InputError& e) {
        std::string msg = e.what();
        EXPECT_NE(msg.find("degenerate.stl"), std::string::npos) << msg;
        EXPECT_NE(msg.find("degenerate"), std::string::npos) << msg;
    }
}

TEST(Repair, TwoDisjointBoxesAreTwoShells) {
    RepairReport r;
    Mesh out = repair(to_soup(joined(box({0, 0, 0}, {10, 10, 10}), box({20, 0, 0}, {25, 5, 5}))), r);
    EXPECT_EQ(r.shells, 2u);
    EXPECT_EQ(r.inner_shells_removed, 0u);
    EXPECT_EQ(out.faces.size(), 24u);
    EXPECT_NEAR(signed_volume(out), 1125, 1e-9);
    int count = 0;
    face_components(out, count);
    EXPECT_EQ(count, 2);
}

TEST(Repair, TwoDisjointBoxesOneInvertedBothEndOutward) {
    RepairReport r;
    Mesh out = repair(joined(box({0, 0, 0}, {10, 10, 10}), inverted(box({20, 0, 0}, {25, 5, 5}))), r);
    EXPECT_EQ(r.flipped, 12u);
    EXPECT_NEAR(signed_volume(out), 1125, 1e-9);
}

TEST(Repair, CavityKeepsFacingInward) {
    // A hollow box: the inner shell faces inward (a cavity, as authored).
    Mesh m = joined(box({0, 0, 0}, {10, 10, 10}), inverted(box({3, 3, 3}, {7, 7, 7})));
    RepairReport r;
    Mesh out = repair(to_soup(m), r);
    EXPECT_EQ(r.shells, 2u);
    EXPECT_EQ(r.inner_shells_removed, 0u);
    EXPECT_EQ(r.flipped, 0u);
    EXPECT_EQ(out.faces.size(), 24u);
    EXPECT_NEAR(signed_volume(out), 1000 - 64, 1e-9);
}

TEST(Repair, InsideOutHollowBoxKeepsItsCavity) {
    // The same hollow box exported inside out (every face reversed, a common export error): after
    // repair it must be the same hollow box, volume 1000 - 64, with the cavity still there.
    Mesh m = inverted(joined(box({0, 0, 0}, {10, 10, 10}), inverted(box({3, 3, 3}, {7, 7, 7}))));
    RepairReport r;
    Mesh out = repair(to_soup(m), r);
    EXPECT_EQ(r.inner_shells_removed, 0u);
    EXPECT_EQ(out.faces.size(), 24u);
    EXPECT_NEAR(signed_volume(out), 1000 - 64, 1e-9);
}

TEST(Repair, SolidWhollyInsideAnotherIsRemoved) {
    Mesh m = joined(box({0, 0, 0}, {10, 10, 10}), box({3, 3, 3}, {7, 7, 7}));
    RepairReport r;
    Mesh out = repair(to_soup(m), r);
    EXPECT_EQ(r.inner_shells_removed, 1u);
    EXPECT_EQ(r.shells, 1u);
    EXPECT_EQ(out.faces.size(), 12u);
    EXPECT_EQ(out.vertices.size(), 8u);
    EXPECT_NEAR(signed_volume(out), 1000, 1e-9);
    EXPECT_TRUE(has_warning(r, "wholly inside another solid removed"));
}

TEST(Repair, OverlappingSolidIsKeptEvenWhenItsFirstCornerIsInside) {
    // An arm pushed into a body (overlapping solids, which slicers unite): the arm's first corner
    // lies inside the body, most of the arm does not. It must be kept, not removed as "wholly inside".
    Mesh body = box({0, 0, 0}, {10, 10, 10});
    Mesh arm = box({5, 3, 4}, {25, 7, 8});  // corner (5,3,4) is inside the body; x 10..25 is outside
    RepairReport r;
    Mesh out = repair(to_soup(joined(body, arm)), r);
    EXPECT_EQ(r.inner_shells_removed, 0u);
    EXPECT_EQ(out.faces.size(), 24u);
    EXPECT_NEAR(bounding_box(out).max.x, 25, 1e-12);
}

TEST(Repair, OverlappingSolidWithCornerOutsideIsKept) {
    Mesh body = box({0, 0, 0}, {10, 10, 10});
    Mesh arm = box({5, -4, 3}, {18, 4, 7});  // no corner of either lies inside the other
    RepairReport r;
    Mesh out = repair(to_soup(joined(body, arm)), r);
    EXPECT_EQ(r.inner_shells_removed, 0u);
    EXPECT_EQ(out.faces.size(), 24u);
    EXPECT_EQ(r.shells, 2u);
}

TEST(Repair, NonManifoldEdgeIsCountedAndCarriedOn) {
    // Two boxes sharing one vertical edge, with shared vertex indices: that edge has 4 triangles.
    Mesh a = box({0, 0, 0}, {10, 10, 10});
    Mesh b = box({10, 10, 0}, {20, 20, 10});
    Mesh m = a;
    std::map<std::tuple<double, double, double>, std::uint32_t> index;
    for (std::uint32_t i = 0; i < m.vertices.size(); ++i) index[{m.vertices[i].x, m.vertices[i].y, m.vertices[i].z}] = i;
    std::vector<std::uint32_t> remap;
    for (const auto& v : b.vertices) {
        auto [it, fresh] = index.emplace(std::tuple{v.x, v.y, v.z}, static_cast<std::uint32_t>(m.vertices.size()));
        if (fresh) m.vertices.push_back(v);
        remap.push_back(it->second);
    }
    for (const auto& f : b.faces) m.faces.push_back({remap[f[0]], remap[f[1]], remap[f[2]]});
    RepairReport r;
    Mesh out;
    ASSERT_NO_THROW(out = repair(m, r));
    EXPECT_EQ(r.nonmanifold_edges, 1u);
    EXPECT_EQ(r.boundary_edges, 0u);
    EXPECT_NEAR(signed_volume(out), 2000, 1e-9);
    EXPECT_TRUE(has_warning(r, "non-manifold"));
}

TEST(Repair, AFoldedCapIsUnfoldedAndTheTopFacesUpAgain) {
    const Mesh m = cube_with_cap_on_top(true);
    ASSERT_TRUE(is_closed_and_consistent(m));
    ASSERT_NEAR(signed_volume(m), 1000, 1e-9);
    int down_on_top = 0;
    for (const auto& f : m.faces)
        if (m.vertices[f[0]].z == 10 && m.vertices[f[1]].z == 10 && m.vertices[f[2]].z == 10)
            down_on_top += face_normal_unnormalized(m, f).z < 0;
    ASSERT_EQ(down_on_top, 1);  // the fold is there to begin with

    Mesh u = m;
    EXPECT_EQ(unfold_caps(u), 1u);
    EXPECT_EQ(u.vertices, m.vertices);  // no vertex added or moved
    EXPECT_EQ(u.faces.size(), m.faces.size());
    EXPECT_TRUE(is_closed_and_consistent(u));
    EXPECT_NEAR(signed_volume(u), 1000, 1e-9);
    for (const auto& f : u.faces)
        if (u.vertices[f[0]].z == 10 && u.vertices[f[1]].z == 10 && u.vertices[f[2]].z == 10)
            EXPECT_GT(face_normal_unnormalized(u, f).z, 0);

    RepairReport r;
    const Mesh out = repair(m, r);
    EXPECT_EQ(r.caps_unfolded, 1u);
    EXPECT_TRUE(has_warning(r, "1 sliver triangle"));
    EXPECT_TRUE(is_closed_and_consistent(out));
}

TEST(Repair, ACapLyingFlatASliverAlongAnEdgeAndABoxAreLeftAlone) {
    Mesh flat = cube_with_cap_on_top(false);
    ASSERT_TRUE(is_closed_and_consistent(flat));
    const Mesh before = flat;
    EXPECT_EQ(unfold_caps(flat), 0u);
    EXPECT_EQ(flat.faces, before.faces);

    // A sharp edge of the shape is not a fold: flipping its sliver would chamfer the edge.
    Mesh edge = cube_with_sliver_along_an_edge();
    ASSERT_TRUE(is_closed_and_consistent(edge));
    const Mesh edge_before = edge;
    EXPECT_EQ(unfold_caps(edge), 0u);
    EXPECT_EQ(edge.faces, edge_before.faces);
    EXPECT_NEAR(signed_volume(edge), 1000, 1e-9);

    RepairReport r;
    repair(box({0, 0, 0}, {10, 10, 10}), r);
    EXPECT_EQ(r.caps_unfolded, 0u);
    EXPECT_FALSE(has_warning(r, "sliver"));
}

TEST(Repair, IsDeterministic) {
    Mesh m = to_soup(joined(inverted(box({0, 0, 0}, {10, 10, 10})), box({20, 0, 0}, {25, 5, 5})));
    RepairReport r1, r2;
    Mesh a = repair(m, r1), b = repair(m, r2);
    EXPECT_EQ(a.vertices, b.vertices);
    EXPECT_EQ(a.faces, b.faces);
    EXPECT_EQ(r1.warnings, r2.warnings);
}

// ---------------------------------------------------------------- placement

TEST(Placement, PlaceOnBedPutsMinZAtZeroAndCentresXY) {
    Mesh m = box({10, -30, 5}, {14, -20, 9});
    double id[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Placement pl;
    Mesh out = place_on_bed(m, 1.0, id, pl);
    Box3 b = bounding_box(out);
    EXPECT_DOUBLE_EQ(b.min.z, 0);
    EXPECT_NEAR(b.max.z, 4, 1e-12);
    EXPECT_NEAR(b.min.x + b.max.x, 0, 1e-12);
    EXPECT_NEAR(b.min.y + b.max.y, 0, 1e-12);
    EXPECT_NEAR(pl.translation.x, -12, 1e-12);
    EXPECT_NEAR(pl.translation.y, 25, 1e-12);
    EXPECT_NEAR(pl.translation.z, -5, 1e-12);
    EXPECT_EQ(out.faces, m.faces);
}

TEST(Placement, PlaceOnBedScalesFirst) {
    Mesh m = box({0, 0, 1}, {1, 2, 3});
    double id[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Placement pl;
    Mesh out = place_on_bed(m, 25.4, id, pl);
    Vec3 size = bounding_box(out).size();
    EXPECT_NEAR(size.x, 25.4, 1e-9);
    EXPECT_NEAR(size.y, 50.8, 1e-9);
    EXPECT_NEAR(size.z, 50.8, 1e-9);
    EXPECT_DOUBLE_EQ(bounding_box(out).min.z, 0);
    EXPECT_EQ(pl.scale, 25.4);
    EXPECT_NEAR(signed_volume(out), 4 * 25.4 * 25.4 * 25.4, 1e-6);
}

TEST(Placement, MirroringScaleKeepsTheMeshOutward) {
    Mesh m = box({0, 0, 0}, {1, 2, 3});
    double id[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Placement pl;
    Mesh out = place_on_bed(m, -2.0, id, pl);
    EXPECT_NEAR(signed_volume(out), 48, 1e-9);
    EXPECT_DOUBLE_EQ(bounding_box(out).min.z, 0);
}

TEST(Placement, RotationFromEulerIsRigid) {
    double R[3][3];
    rotation_from_euler_deg(30, 45, 60, R);
    // Orthonormal with determinant +1.
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            double d = 0;
            for (int k = 0; k < 3; ++k) d += R[k][i] * R[k][j];
            EXPECT_NEAR(d, i == j ? 1 : 0, 1e-12);
        }
    double det = R[0][0] * (R[1][1] * R[2][2] - R[1][2] * R[2][1]) - R[0][1] * (R[1][0] * R[2][2] - R[1][2] * R[2][0]) +
                 R[0][2] * (R[1][0] * R[2][1] - R[1][1] * R[2][0]);
    EXPECT_NEAR(det, 1, 1e-12);

    Mesh m = box({0, 0, 0}, {3, 5, 7});
    Placement pl;
    Mesh out = place_on_bed(m, 1.0, R, pl);
    auto a = edge_lengths(m), b = edge_lengths(out);
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) EXPECT_NEAR(a[i], b[i], 1e-9);
    EXPECT_NEAR(signed_volume(out), 105, 1e-9);
    EXPECT_NEAR(bounding_box(out).min.z, 0, 1e-12);
}

TEST(Placement, EulerAnglesFollowOpenScadRotate) {
    // OpenSCAD's rotate([x, y, z]) turns about X first, then Y, then Z.
    auto apply = [](const double R[3][3], Vec3 v) {
        return Vec3{R[0][0] * v.x + R[0][1] * v.y + R[0][2] * v.z, R[1][0] * v.x + R[1][1] * v.y + R[1][2] * v.z,
                    R[2][0] * v.x + R[2][1] * v.y + R[2][2] * v.z};
    };
    auto near = [](Vec3 a, Vec3 b) { return distance(a, b) < 1e-12; };
    double R[3][3];
    rotation_from_euler_deg(90, 0, 0, R);
    EXPECT_TRUE(near(apply(R, {0, 1, 0}), {0, 0, 1}));
    rotation_from_euler_deg(0, 90, 0, R);
    EXPECT_TRUE(near(apply(R, {0, 0, 1}), {1, 0, 0}));
    rotation_from_euler_deg(0, 0, 90, R);
    EXPECT_TRUE(near(apply(R, {1, 0, 0}), {0, 1, 0}));
    rotation_from_euler_deg(90, 90, 0, R);  // y -> z (about X), then z -> x (about Y)
    EXPECT_TRUE(near(apply(R, {0, 1, 0}), {1, 0, 0}));
    rotation_from_euler_deg(90, 0, 90, R);  // y -> z, then z stays (about Z)
    EXPECT_TRUE(near(apply(R, {0, 1, 0}), {0, 0, 1}));
    rotation_from_euler_deg(0, 90, 90, R);  // z -> x (about Y), then x -> y (about Z)
    EXPECT_TRUE(near(apply(R, {0, 0, 1}), {0, 1, 0}));
}

// sort_edge_uses (core/geometry.hpp) orders (edge key, index) pairs as std::sort does: a mesh's
// face-edges, repeated pairs, and keys too sparse to count.
TEST(SortEdgeUses, OrdersAsStdSort) {
    std::uint64_t state = 12345;
    auto next = [&state] { return state = state * 6364136223846793005ULL + 1442695040888963407ULL, state >> 33; };
    for (const std::uint32_t vertices : {3u, 50u, 5000u, 4000000000u}) {
        std::vector<std::pair<std::uint64_t, std::uint32_t>> uses;
        for (std::uint32_t f = 0; f < 3000; ++f) {
            const auto a = static_cast<std::uint32_t>(next() % vertices), b = static_cast<std::uint32_t>(next() % vertices);
            uses.push_back({edge_key(a, b), f});
            if (f % 7 == 0) uses.push_back({edge_key(a, b), f});  // the same pair twice
        }
        auto expected = uses;
        std::sort(expected.begin(), expected.end());
        sort_edge_uses(uses);
        EXPECT_EQ(uses, expected) << vertices;
    }
    const Mesh cube = box({0, 0, 0}, {1, 1, 1});
    std::vector<std::pair<std::uint64_t, std::uint32_t>> uses;
    for (std::uint32_t f = 0; f < cube.faces.size(); ++f)
        for (int k = 0; k < 3; ++k) uses.push_back({edge_key(cube.faces[f][k], cube.faces[f][(k + 1) % 3]), f});
    auto expected = uses;
    std::sort(expected.begin(), expected.end());
    sort_edge_uses(uses);
    EXPECT_EQ(uses, expected);
}

// The convex hull, in its own translation unit: CGAL headers compile slowly.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

#include "orient/orient.hpp"

namespace cs {

std::vector<HullFacet> hull_facets(const std::vector<Vec3>& points) {
    using K = CGAL::Exact_predicates_inexact_constructions_kernel;
    using Point = K::Point_3;
    std::vector<Point> pts;
    pts.reserve(points.size());
    for (const auto& v : points) pts.emplace_back(v.x, v.y, v.z);
    CGAL::Surface_mesh<Point> hull;
    // convex_hull_3 draws from CGAL's per-thread default random generator, so the order of its
    // faces and how it triangulates coplanar points depend on what ran before on the thread.
    // A fixed seed helps; the canonical form below makes the result a function of the points.
    CGAL::get_default_random() = CGAL::Random(20140707);
    CGAL::convex_hull_3(pts.begin(), pts.end(), hull);

    // Coplanar triangles are one facet: group them by their normal rounded to 1e-9, which any
    // triangulation of the facet agrees on, and add up their areas.
    std::map<std::tuple<long long, long long, long long>, HullFacet> facets;
    for (auto f : hull.faces()) {
        std::vector<Vec3> c;
        for (auto v : hull.vertices_around_face(hull.halfedge(f))) {
            const auto& p = hull.point(v);
            c.push_back({p.x(), p.y(), p.z()});
        }
        if (c.size() < 3) continue;
        Vec3 n = cross(c[1] - c[0], c[2] - c[0]);
        double len = norm(n);
        if (!(len > 0)) continue;
        Vec3 u = n / len;
        auto q = [](double x) { return std::llround(x * 1e9); };
        auto& facet = facets[{q(u.x), q(u.y), q(u.z)}];
        facet.normal = Vec3{double(q(u.x)), double(q(u.y)), double(q(u.z))} * 1e-9;
        facet.area += 0.5 * len;
    }
    std::vector<HullFacet> out;
    out.reserve(facets.size());
    for (auto& [key, facet] : facets) {
        facet.normal = normalized(facet.normal);
        facet.area = std::round(facet.area * 1e6) * 1e-6;  // the sum's order is CGAL's: round it away
        out.push_back(facet);
    }
    return out;
}

}  // namespace cs

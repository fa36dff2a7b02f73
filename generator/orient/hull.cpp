// The convex hull, in its own translation unit: CGAL headers compile slowly.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include "orient/orient.hpp"

namespace cs {

std::vector<Vec3> hull_face_normals(const std::vector<Vec3>& points) {
    using K = CGAL::Exact_predicates_inexact_constructions_kernel;
    using Point = K::Point_3;
    std::vector<Point> pts;
    pts.reserve(points.size());
    for (const auto& v : points) pts.emplace_back(v.x, v.y, v.z);
    CGAL::Surface_mesh<Point> hull;
    CGAL::convex_hull_3(pts.begin(), pts.end(), hull);
    std::vector<Vec3> normals;
    for (auto f : hull.faces()) {
        std::vector<Vec3> c;
        for (auto v : hull.vertices_around_face(hull.halfedge(f))) {
            const auto& p = hull.point(v);
            c.push_back({p.x(), p.y(), p.z()});
        }
        if (c.size() < 3) continue;
        Vec3 n = cross(c[1] - c[0], c[2] - c[0]);
        if (norm(n) > 0) normals.push_back(normalized(n));
    }
    return normals;
}

}  // namespace cs

#include "query/model_query.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <boost/iterator/function_output_iterator.hpp>
#include <vector>

namespace cs {
namespace {

using K = CGAL::Simple_cartesian<double>;
using Point = K::Point_3;
using Triangle3 = K::Triangle_3;
using Iterator = std::vector<Triangle3>::const_iterator;
using Primitive = CGAL::AABB_triangle_primitive<K, Iterator>;
using Traits = CGAL::AABB_traits<K, Primitive>;
using Tree = CGAL::AABB_tree<Traits>;

Point pt(const Vec3& v) { return {v.x, v.y, v.z}; }
Vec3 vec(const Point& p) { return {p.x(), p.y(), p.z()}; }

}  // namespace

struct ModelQuery::Impl {
    std::vector<Triangle3> triangles;
    Tree tree;
};

ModelQuery::ModelQuery(const Mesh& model) : model_(model), impl_(std::make_unique<Impl>()) {
    impl_->triangles.reserve(model.faces.size());
    for (const auto& f : model.faces)
        impl_->triangles.emplace_back(pt(model.vertices[f[0]]), pt(model.vertices[f[1]]), pt(model.vertices[f[2]]));
    impl_->tree.insert(impl_->triangles.begin(), impl_->triangles.end());
    impl_->tree.build();
    impl_->tree.accelerate_distance_queries();
}

ModelQuery::~ModelQuery() = default;

std::optional<RayHit> ModelQuery::first_hit(const Vec3& origin, const Vec3& dir) const {
    K::Ray_3 ray(pt(origin), K::Vector_3(dir.x, dir.y, dir.z));
    auto hit = impl_->tree.first_intersection(ray);
    if (!hit) return std::nullopt;
    const Point* p = boost::get<Point>(&hit->first);
    Vec3 q;
    if (p) {
        q = vec(*p);
    } else if (const auto* s = boost::get<K::Segment_3>(&hit->first)) {
        // Ray runs along a triangle: the nearer end of the overlap is the hit.
        Vec3 a = vec(s->source()), b = vec(s->target());
        q = distance(a, origin) < distance(b, origin) ? a : b;
    } else {
        return std::nullopt;
    }
    auto face = static_cast<std::size_t>(hit->second - impl_->triangles.begin());
    return RayHit{q, distance(q, origin), face};
}

bool ModelQuery::segment_hits(const Vec3& a, const Vec3& b) const {
    if (a == b) return false;
    return impl_->tree.do_intersect(K::Segment_3(pt(a), pt(b)));
}

bool ModelQuery::triangle_hits(const Vec3& a, const Vec3& b, const Vec3& c) const {
    Triangle3 t(pt(a), pt(b), pt(c));
    if (t.is_degenerate()) return a == b ? segment_hits(a, c) : segment_hits(a, b);
    return impl_->tree.do_intersect(t);
}

double ModelQuery::squared_distance(const Vec3& p) const { return impl_->tree.squared_distance(pt(p)); }

Vec3 ModelQuery::closest_point(const Vec3& p) const { return vec(impl_->tree.closest_point(pt(p))); }

bool ModelQuery::inside(const Vec3& p) const {
    // Irrational-looking directions avoid rays that graze edges of axis-aligned CAD meshes. None
    // points up: the usual question is about a point just below an overhang, whose face right
    // above would otherwise be crossed at a hair's distance, where rounding decides.
    static const K::Vector_3 dirs[3] = {{0.5773, 0.5781, -0.5767}, {-0.7071, 0.0123, -0.7070}, {0.0211, -0.9981, -0.0582}};
    // Winding number along each ray (exits minus entries), not parity: overlapping solids, which
    // slicers unite, count as inside.
    // Two rays that agree decide the majority: the third is cast only when they differ (a third
    // of the work on most points; the answer is the same).
    int votes = 0;
    std::vector<Tree::Primitive_id> hits;
    for (int r = 0; r < 3; ++r) {
        const auto& d = dirs[r];
        hits.clear();
        impl_->tree.all_intersected_primitives(K::Ray_3(pt(p), d), std::back_inserter(hits));
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

std::size_t count_self_intersections(const Mesh& mesh, std::size_t limit) {
    using SM = CGAL::Surface_mesh<Point>;
    SM sm;
    std::vector<SM::Vertex_index> vs;
    vs.reserve(mesh.vertices.size());
    for (const auto& v : mesh.vertices) vs.push_back(sm.add_vertex(pt(v)));
    for (const auto& f : mesh.faces) {
        // Non-manifold input cannot become a Surface_mesh face; such faces are skipped here.
        sm.add_face(vs[f[0]], vs[f[1]], vs[f[2]]);
    }
    struct Full {};
    std::size_t count = 0;
    auto counter = boost::make_function_output_iterator([&](const auto&) {
        if (++count >= limit) throw Full{};  // enough to warn: stop the search early
    });
    try {
        CGAL::Polygon_mesh_processing::self_intersections(sm, counter);
    } catch (const Full&) {
    }
    return count;
}

}  // namespace cs

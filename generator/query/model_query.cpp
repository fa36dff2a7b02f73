#include "query/model_query.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <boost/iterator/function_output_iterator.hpp>
#include <array>
#include <bit>
#include <mutex>
#include <unordered_map>
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

namespace {

// A question's exact bits (points and directions, as doubles): equal keys are the same question.
template <std::size_t N>
using Key = std::array<double, N>;

struct KeyHash {
    template <std::size_t N>
    std::size_t operator()(const Key<N>& k) const {
        std::uint64_t h = 0x9e3779b97f4a7c15ull;
        for (double d : k) {  // splitmix64 over each coordinate's bits
            std::uint64_t z = h ^ std::bit_cast<std::uint64_t>(d);
            z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
            z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
            h = z ^ (z >> 31);
        }
        return static_cast<std::size_t>(h);
    }
};

struct BitsEqual {
    template <std::size_t N>
    bool operator()(const Key<N>& a, const Key<N>& b) const {
        for (std::size_t i = 0; i < N; ++i)
            if (std::bit_cast<std::uint64_t>(a[i]) != std::bit_cast<std::uint64_t>(b[i])) return false;
        return true;
    }
};

template <std::size_t N, typename V>
using Answers = std::unordered_map<Key<N>, V, KeyHash, BitsEqual>;

Key<3> key(const Vec3& a) { return {a.x, a.y, a.z}; }
Key<6> key(const Vec3& a, const Vec3& b) { return {a.x, a.y, a.z, b.x, b.y, b.z}; }

// The answer to `k` from `answers`, else computed by `f` (outside the lock) and kept.
template <std::size_t N, typename V, typename F>
V remembered(std::mutex& m, Answers<N, V>& answers, const Key<N>& k, F f) {
    {
        std::lock_guard lock(m);
        if (auto it = answers.find(k); it != answers.end()) return it->second;
    }
    V v = f();
    std::lock_guard lock(m);
    answers.emplace(k, v);
    return v;
}

}  // namespace

struct ModelQuery::Memo {
    std::mutex mutex;
    Answers<6, bool> segments;
    Answers<6, std::optional<RayHit>> rays;
    Answers<3, bool> inside;
    Answers<3, double> distances;
    Answers<3, Vec3> closest;
};

ModelQuery::ModelQuery(const Mesh& model) : model_(model), memo_(std::make_unique<Memo>()) {
    auto impl = std::make_shared<Impl>();
    impl->triangles.reserve(model.faces.size());
    for (const auto& f : model.faces)
        impl->triangles.emplace_back(pt(model.vertices[f[0]]), pt(model.vertices[f[1]]), pt(model.vertices[f[2]]));
    impl->tree.insert(impl->triangles.begin(), impl->triangles.end());
    impl->tree.build();
    impl->tree.accelerate_distance_queries();
    impl_ = std::move(impl);
}

ModelQuery::ModelQuery(const Mesh& moved, const ModelQuery& indexed, const double rotation[3][3], const Vec3& translation)
    : model_(moved), impl_(indexed.impl_), memo_(std::make_unique<Memo>()) {
    Frame f;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) f.r[i][j] = rotation[i][j];
    f.t = translation;
    if (indexed.frame_) {  // moved twice: compose, so every question goes straight to the index
        const Frame& g = *indexed.frame_;
        Frame c;
        for (int i = 0; i < 3; ++i)
            for (int j = 0; j < 3; ++j) c.r[i][j] = f.r[i][0] * g.r[0][j] + f.r[i][1] * g.r[1][j] + f.r[i][2] * g.r[2][j];
        const Vec3 rt{dot({f.r[0][0], f.r[0][1], f.r[0][2]}, g.t), dot({f.r[1][0], f.r[1][1], f.r[1][2]}, g.t),
                      dot({f.r[2][0], f.r[2][1], f.r[2][2]}, g.t)};
        c.t = rt + f.t;
        f = c;
    }
    frame_ = f;
}

Vec3 ModelQuery::Frame::to_index(const Vec3& p) const { return dir_to_index(p - t); }

Vec3 ModelQuery::Frame::from_index(const Vec3& q) const {
    return Vec3{r[0][0] * q.x + r[0][1] * q.y + r[0][2] * q.z, r[1][0] * q.x + r[1][1] * q.y + r[1][2] * q.z,
                r[2][0] * q.x + r[2][1] * q.y + r[2][2] * q.z} +
           t;
}

Vec3 ModelQuery::Frame::dir_to_index(const Vec3& d) const {
    return {r[0][0] * d.x + r[1][0] * d.y + r[2][0] * d.z, r[0][1] * d.x + r[1][1] * d.y + r[2][1] * d.z,
            r[0][2] * d.x + r[1][2] * d.y + r[2][2] * d.z};
}

ModelQuery::~ModelQuery() = default;

std::optional<RayHit> ModelQuery::first_hit(const Vec3& origin, const Vec3& dir) const {
    return remembered(memo_->mutex, memo_->rays, key(origin, dir), [&] { return first_hit_uncached(origin, dir); });
}

std::optional<RayHit> ModelQuery::first_hit_uncached(const Vec3& origin, const Vec3& dir) const {
    if (!frame_) return first_hit_in_index(origin, dir);
    // The hit's point back in this model's frame; its face is the same face.
    auto hit = first_hit_in_index(frame_->to_index(origin), frame_->dir_to_index(dir));
    if (hit) hit->point = frame_->from_index(hit->point), hit->distance = distance(hit->point, origin);
    return hit;
}

std::optional<RayHit> ModelQuery::first_hit_in_index(const Vec3& origin, const Vec3& dir) const {
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
    return remembered(memo_->mutex, memo_->segments, key(a, b), [&] {
        return impl_->tree.do_intersect(K::Segment_3(pt(in_index(a)), pt(in_index(b))));
    });
}

bool ModelQuery::triangle_hits(const Vec3& a, const Vec3& b, const Vec3& c) const {
    if (Triangle3(pt(a), pt(b), pt(c)).is_degenerate()) return a == b ? segment_hits(a, c) : segment_hits(a, b);
    return impl_->tree.do_intersect(Triangle3(pt(in_index(a)), pt(in_index(b)), pt(in_index(c))));
}

double ModelQuery::squared_distance(const Vec3& p) const {
    return remembered(memo_->mutex, memo_->distances, key(p), [&] { return impl_->tree.squared_distance(pt(in_index(p))); });
}

Vec3 ModelQuery::closest_point(const Vec3& p) const {
    return remembered(memo_->mutex, memo_->closest, key(p),
                      [&] { return out_of_index(vec(impl_->tree.closest_point(pt(in_index(p))))); });
}

bool ModelQuery::inside(const Vec3& p) const {
    return remembered(memo_->mutex, memo_->inside, key(p), [&] { return inside_uncached(p); });
}

bool ModelQuery::inside_uncached(const Vec3& p) const {
    // Irrational-looking directions avoid rays that graze edges of axis-aligned CAD meshes. None
    // points up: the usual question is about a point just below an overhang, whose face right
    // above would otherwise be crossed at a hair's distance, where rounding decides.
    static const Vec3 placed_dirs[3] = {{0.5773, 0.5781, -0.5767}, {-0.7071, 0.0123, -0.7070}, {0.0211, -0.9981, -0.0582}};
    K::Vector_3 dirs[3];
    for (int r = 0; r < 3; ++r) {
        const Vec3 d = frame_ ? frame_->dir_to_index(placed_dirs[r]) : placed_dirs[r];
        dirs[r] = {d.x, d.y, d.z};
    }
    const Point from = pt(in_index(p));
    // Winding number along each ray (exits minus entries), not parity: overlapping solids, which
    // slicers unite, count as inside.
    // Two rays that agree decide the majority: the third is cast only when they differ (a third
    // of the work on most points; the answer is the same).
    int votes = 0;
    std::vector<Tree::Primitive_id> hits;
    for (int r = 0; r < 3; ++r) {
        const auto& d = dirs[r];
        hits.clear();
        impl_->tree.all_intersected_primitives(K::Ray_3(from, d), std::back_inserter(hits));
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

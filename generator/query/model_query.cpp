#include "query/model_query.hpp"
#include "query/triangle_bvh.hpp"

#include "core/flat_index.hpp"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <boost/iterator/function_output_iterator.hpp>
#include <array>
#include <bit>
#include <cmath>
#include <cfloat>
#include <atomic>
#include <memory>
#include <mutex>
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

namespace {

using RayIntersection = std::pair<decltype(CGAL::intersection(std::declval<K::Ray_3>(), std::declval<Triangle3>()))::value_type,
                                  std::size_t>;

// The ray's parameter at a hit as CGAL's first_intersection measures it (along the ray vector's
// largest coordinate; a segment's nearer end).
struct RayParameter {
    const K::Ray_3& ray;
    int axis = 0;
    explicit RayParameter(const K::Ray_3& r) : ray(r) {
        const K::Vector_3 v = r.to_vector();
        for (int i = 1; i < 3; ++i)
            if (std::abs(v[i]) > std::abs(v[axis])) axis = i;
    }
    double operator()(const Point& p) const { return K::Vector_3(ray.source(), p)[axis] / ray.to_vector()[axis]; }
    double operator()(const K::Segment_3& s) const { return std::min((*this)(s[0]), (*this)(s[1])); }
};

}  // namespace

// Two indexes of the same triangles: the BVH narrows segment and ray questions down to a few
// triangles, which CGAL's own predicates and constructions then decide, so the answers are those of
// CGAL's AABB tree (which still answers distance questions, and rays where two faces tie).
// The BVH is built only once the model has been asked about a quarter as many segment and ray
// questions as it has triangles (building costs about as much as that many questions save; a big
// scan is asked few). Until then CGAL's tree answers them: the answers are the same either way.
// A small model's is built at its first question (kBuildAtOnce).
struct ModelQuery::Impl {
    const Mesh& mesh;  // the indexed mesh, which outlives every query sharing this index
    std::vector<Triangle3> triangles;
    Tree tree;
    explicit Impl(const Mesh& m) : mesh(m) {}
    // The BVH, or null while too few questions were asked.
    const TriangleBvh* bvh() const;
    // A vertical ray's faces come from `memo`'s columns (defined with Memo).
    std::optional<RayIntersection> first_intersection(const K::Ray_3& ray, Memo& memo) const;
    // CGAL's answer from the faces `offer(visit)` offers: every face whose box the ray's line may
    // touch (first_intersection says why all of them).
    template <typename Offer>
    std::optional<RayIntersection> nearest_offered(const K::Ray_3& ray, Offer&& offer) const;
    std::optional<RayIntersection> fallback(const K::Ray_3& ray) const;  // CGAL's tree's answer
    bool segment_hits(const K::Segment_3& segment) const;
    std::vector<const Triangle3*> crossed_faces(const K::Ray_3& ray) const;
    Point closest_point(const Point& q) const;

private:
    mutable std::atomic<std::size_t> asked_{0};
    mutable std::once_flag built_;
    mutable std::unique_ptr<const TriangleBvh> bvh_;
    mutable std::atomic<const TriangleBvh*> ready_{nullptr};
};

// Below this many triangles the BVH is built at the first question: it builds in a few
// milliseconds, and a small part is asked many times its triangles (extruder_idler's 3,558 faces
// one to six times over on each pose the orientation search judges), where waiting for a
// quarter of them cost every pose about 13 M instructions of CGAL's slower answers (extruder_idler
// 1.079 -> 1.017 G). A big scan keeps the wait: igea's final pose asks a quarter of its 268,686
// faces less a few thousand, and building its BVH at an eighth cost it 7 % more instructions.
constexpr std::size_t kBuildAtOnce = 16384;

const TriangleBvh* ModelQuery::Impl::bvh() const {
    if (const TriangleBvh* b = ready_.load(std::memory_order_acquire)) return b;
    if (triangles.size() >= kBuildAtOnce && asked_.fetch_add(1, std::memory_order_relaxed) < triangles.size() / 4) return nullptr;
    std::call_once(built_, [&] {
        bvh_ = std::make_unique<const TriangleBvh>(mesh);
        ready_.store(bvh_.get(), std::memory_order_release);
    });
    return ready_.load(std::memory_order_acquire);
}

// CGAL's first_intersection(ray), found from the BVH's few candidates where the answer is certain.
// CGAL's answer is not always the nearest hit: it walks its boxes nearest first and stops at a
// box whose rounded entry is not below the best hit so far (so of two hits within rounding either
// may win), and on a ray lying in a face's plane its intersection may report an overlap behind
// the ray's start, which it meets only where its tree pairs that face with one the ray crosses.
// Every face whose box the ray's whole line touches is intersected here as CGAL does it (but
// those whose intersection is surely empty: first_intersection's vertical rays); the nearest is
// CGAL's answer when it is strictly nearer than any other and its own box lets CGAL's walk reach
// it before any other hit (CGAL's box entries only shrink up the tree, so every box above it is
// reached too). Otherwise, and where nothing is certain, CGAL's tree is asked.
template <typename Offer>
std::optional<RayIntersection> ModelQuery::Impl::nearest_offered(const K::Ray_3& ray, Offer&& offer) const {
    const RayParameter param(ray);
    std::optional<RayIntersection> nearest;
    double best = DBL_MAX, second = DBL_MAX;
    offer([&](std::uint32_t f) {
        auto x = K().intersect_3_object()(ray, triangles[f]);
        if (!x) return false;
        const double t = boost::apply_visitor([&](const auto& g) { return param(g); }, *x);
        if (t < best) {
            second = best, best = t;
            nearest.emplace(*x, f);
        } else if (t < second) {
            second = t;
        }
        return false;
    });
    if (!nearest) return std::nullopt;
    // CGAL first checks the root box, then walks boxes by their entry along the ray.
    if (!K().do_intersect_3_object()(ray, tree.bbox())) return std::nullopt;
    if (!(best < second)) return fallback(ray);
    const auto entry = tree.traits().intersection_distance_object()(ray, triangles[nearest->second].bbox());
    if (!entry || !(*entry < second)) return fallback(ray);
    return nearest;
}

// CGAL's tree.do_intersect(segment): the tree tests do_intersect(segment, triangle) on the faces
// whose boxes it lets through, so a face the BVH offers that touches is its answer too when CGAL's
// own test lets the face's box through (it then lets through every box above it: its test only
// passes more often on a bigger box). A touching face CGAL's box test turns away (a segment along
// a box's side, where rounding decides) leaves the answer to CGAL's tree; no touching face: false.
bool ModelQuery::Impl::segment_hits(const K::Segment_3& segment) const {
    const TriangleBvh* bvh = this->bvh();
    if (!bvh) return tree.do_intersect(segment);
    bool unsure = false;
    const bool hit = bvh->along_segment(vec(segment.source()), vec(segment.target()), [&](std::uint32_t f) {
        if (!K().do_intersect_3_object()(segment, triangles[f])) return false;
        if (K().do_intersect_3_object()(segment, triangles[f].bbox())) return true;
        unsure = true;
        return false;
    });
    return hit || (unsure && tree.do_intersect(segment));
}

// CGAL's tree.closest_point(q). CGAL starts from its search tree's nearest first corner of a face
// (each face's reference point) and walks the boxes a sphere through its current point reaches,
// taking each face's projection of q unless it is farther than the current point (so of two at
// one distance, the later). Here the faces and first corners near q are all measured as CGAL
// measures them: a point X strictly nearer than every other point among them is CGAL's answer
// when a face projecting to X has a box that CGAL's sphere test reaches from the second nearest
// point (it then reaches every box above it, from any current point, which is never nearer than
// that). Otherwise (ties, and rounding at the box) CGAL's tree is asked.
Point ModelQuery::Impl::closest_point(const Point& q) const {
    const TriangleBvh* bvh = this->bvh();
    if (!bvh || triangles.size() < 2) return tree.closest_point(q);
    const auto distance2 = K().compute_squared_distance_3_object();
    std::optional<Point> best, second;
    double d_best = DBL_MAX, d_second = DBL_MAX;
    std::size_t face = triangles.size();  // a face projecting to best, if any
    auto offer = [&](const Point& c, std::size_t f) {
        if (best && c == *best) {
            if (face == triangles.size()) face = f;
            return;
        }
        const double d = distance2(q, c);
        if (!best || d < d_best) {
            if (best) second = best, d_second = d_best;
            best = c, d_best = d, face = f;
        } else if (d < d_second) {
            second = c, d_second = d;
        }
    };
    bvh->near_point(
        vec(q),
        [&](std::uint32_t f) {
            offer(K().construct_projected_point_3_object()(triangles[f], q), f);
            offer(triangles[f].vertex(0), triangles.size());  // a possible starting point
        },
        [&] { return d_second; });
    if (!best || face == triangles.size() || (second && !(d_best < d_second))) return tree.closest_point(q);
    if (second && tree.traits().compare_distance_object()(q, triangles[face].bbox(), *second) != CGAL::SMALLER)
        return tree.closest_point(q);
    return *best;
}

// CGAL's tree.all_intersected_primitives(ray), in no particular order, by the same argument.
std::vector<const Triangle3*> ModelQuery::Impl::crossed_faces(const K::Ray_3& ray) const {
    std::vector<const Triangle3*> crossed;
    const TriangleBvh* bvh = this->bvh();
    bool unsure = !bvh;
    const K::Vector_3 v = ray.to_vector();
    if (bvh) bvh->along_ray(vec(ray.source()), Vec3{v.x(), v.y(), v.z()}, [&](std::uint32_t f) {
        if (!K().do_intersect_3_object()(ray, triangles[f])) return false;
        unsure = unsure || !K().do_intersect_3_object()(ray, triangles[f].bbox());
        crossed.push_back(&triangles[f]);
        return false;
    });
    if (unsure) {
        std::vector<Tree::Primitive_id> ids;
        tree.all_intersected_primitives(ray, std::back_inserter(ids));
        crossed.clear();
        for (auto id : ids) crossed.push_back(&*id);
    }
    return crossed;
}

std::optional<RayIntersection> ModelQuery::Impl::fallback(const K::Ray_3& ray) const {
    auto hit = tree.first_intersection(ray);
    if (!hit) return std::nullopt;
    return RayIntersection{hit->first, static_cast<std::size_t>(hit->second - triangles.begin())};
}


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

// Answers by their question, in the order given, found through a FlatIndex: a question not asked
// before costs one cache miss, where a node-based map's bucket and chain cost two or three (the
// growth of a tree asks hundreds of thousands of questions, most of them once).
template <std::size_t N, typename V>
class Answers {
public:
    const V* find(const Key<N>& k) const {
        const std::size_t at = index_.find(KeyHash{}(k), [&](std::size_t i) { return BitsEqual{}(entries_[i].key, k); });
        return at == FlatIndex::npos ? nullptr : &entries_[at].value;
    }
    // Keeps the first answer to a question (as std::unordered_map::emplace) and gives it back: `v`,
    // or the one kept before it when two threads raced to answer the same question.
    V emplace(const Key<N>& k, const V& v) {
        const auto [at, fresh] = index_.insert(
            KeyHash{}(k), entries_.size(), [&](std::size_t i) { return BitsEqual{}(entries_[i].key, k); },
            [&](std::size_t i) { return std::uint64_t(KeyHash{}(entries_[i].key)); });
        if (fresh) entries_.push_back({k, v});
        return entries_[at].value;
    }

private:
    struct Entry {
        Key<N> key;
        V value;
    };
    std::vector<Entry> entries_;
    FlatIndex index_;
};

Key<3> key(const Vec3& a) { return {a.x, a.y, a.z}; }
Key<6> key(const Vec3& a, const Vec3& b) { return {a.x, a.y, a.z, b.x, b.y, b.z}; }

// The answer to `k` from `answers`, else computed by `f` (outside the lock) and kept.
template <std::size_t N, typename V, typename F>
V remembered(std::mutex& m, Answers<N, V>& answers, const Key<N>& k, F f) {
    {
        std::lock_guard lock(m);
        if (const V* known = answers.find(k)) return *known;
    }
    V v = f();
    std::lock_guard lock(m);
    return answers.emplace(k, v);
}

}  // namespace

struct ModelQuery::Memo {
    std::mutex mutex;
    Answers<6, bool> segments;
    Answers<6, std::optional<RayHit>> rays;
    Answers<3, bool> inside;
    Answers<3, double> distances;
    Answers<3, Vec3> closest;
    Answers<12, bool> verdicts;
    // The faces a ray straight up or down may meet, by its column's exact x and y (in the index's
    // frame): those whose boxes the vertical line there touches, as TriangleBvh::along_line offers
    // them for such a ray from any height, less those it surely misses (surely_beside). Most rays
    // are vertical, and a column is asked again at other heights (the ceilings' stations ask up,
    // then down from what they find; regions and layouts ask again): on menger_sponge3 (kept
    // pose) 231,564 of 420,701 new vertical rays were in a column asked before. Walking the BVH
    // along the whole line cost more than deciding the faces it offers. Shared, not copied.
    Answers<2, std::shared_ptr<const std::vector<std::uint32_t>>> columns;
};

namespace {

// A vertical ray's step (its vector's z, as CGAL's ray holds it: its second point's z less its
// source's) at least this long: added to any coordinate under kMostCoordinate it changes it, with
// its own sign (surely_beside).
constexpr double kLeastVerticalStep = 1e-6;
constexpr double kMostCoordinate = 1e6;

// Is CGAL's intersection of `t` with every ray straight up or down through (x, y) (vector
// (0, 0, s), |s| >= kLeastVerticalStep) surely empty: the point lies clearly outside the triangle
// seen from above, which is clearly not edge-on? CGAL (Ray_3_Triangle_3_intersection.h) reports
// nothing unless the three orientations of the ray's line (source p, second point q = p + s z)
// against the edges, orientation(p,q,a,b), (p,q,b,c), (p,q,c,a) (or with q,p: their negations,
// bit for bit), are none positive, or unless the ray lies in the triangle's plane, where its
// orientation(a,b,c,a + s z) is zero. For such a ray, with exact zeros in x and y, CGAL's
// determinant for (p,q,a,b) works out to s times the 2D cross product (a - p) x (b - p) within a
// rounding under 6 units in the last place of s (|ax - px| |by - py| + |ay - py| |bx - px|), and
// that for (a,b,c,a + s z) to a nonzero step times (b - a) x (c - a) within as little. So where
// one edge's cross product is clearly positive, another's clearly negative (beyond 1e-12 of its
// bound, some 4,500 units in the last place) and the triangle's clearly not zero, CGAL's signs are
// the exact ones: one test comes out positive whichever way the ray points, and the plane is not
// the ray's. Coordinates are kept under kMostCoordinate (a step then moves a z) and products
// clear of underflow.
bool surely_beside(const Triangle3& t, double x, double y) {
    constexpr double kClearly = 1e-12, kTiny = 1e-200;
    const Point &a = t.vertex(0), &b = t.vertex(1), &c = t.vertex(2);
    for (const Point* v : {&a, &b, &c})
        if (!(std::abs(v->x()) < kMostCoordinate && std::abs(v->y()) < kMostCoordinate && std::abs(v->z()) < kMostCoordinate))
            return false;
    if (!(std::abs(x) < kMostCoordinate && std::abs(y) < kMostCoordinate)) return false;
    // The sign of u x w where it is clear: +1, -1, or 0 (not clear).
    auto clear_sign = [&](double ux, double uy, double wx, double wy) {
        const double cross = ux * wy - uy * wx, bound = std::abs(ux * wy) + std::abs(uy * wx);
        if (!(bound > kTiny)) return 0;
        return cross > kClearly * bound ? 1 : cross < -kClearly * bound ? -1 : 0;
    };
    if (clear_sign(b.x() - a.x(), b.y() - a.y(), c.x() - a.x(), c.y() - a.y()) == 0) return false;
    bool positive = false, negative = false;
    for (const auto& [u, w] : {std::pair{&a, &b}, std::pair{&b, &c}, std::pair{&c, &a}}) {
        const int s = clear_sign(u->x() - x, u->y() - y, w->x() - x, w->y() - y);
        positive = positive || s > 0, negative = negative || s < 0;
    }
    return positive && negative;
}

}  // namespace

// CGAL's first_intersection(ray), found from the BVH's few candidates where the answer is certain
// (nearest_offered).
std::optional<RayIntersection> ModelQuery::Impl::first_intersection(const K::Ray_3& ray, Memo& memo) const {
    const TriangleBvh* bvh = this->bvh();
    // Too few questions yet, or a one-face tree (CGAL's skips its box tests): CGAL's tree answers.
    if (!bvh || triangles.size() < 2) return fallback(ray);
    const K::Vector_3 v = ray.to_vector();
    const Point& o = ray.source();
    if (v.x() == 0 && v.y() == 0 && std::abs(v.z()) >= kLeastVerticalStep) {
        // Straight up or down: the line, so the faces along it, are the column's whatever the
        // height (along_vertical offers what along_line would, in the same order), less those
        // whose intersection with such a ray is surely empty.
        const auto faces = remembered(memo.mutex, memo.columns, Key<2>{o.x(), o.y()}, [&] {
            std::vector<std::uint32_t> along;
            bvh->along_vertical(o.x(), o.y(), [&](std::uint32_t f) {
                if (!surely_beside(triangles[f], o.x(), o.y())) along.push_back(f);
                return false;
            });
            return std::make_shared<const std::vector<std::uint32_t>>(std::move(along));
        });
        return nearest_offered(ray, [&](auto&& visit) {
            for (const std::uint32_t f : *faces) visit(f);
        });
    }
    return nearest_offered(ray, [&](auto&& visit) { bvh->along_line(vec(o), Vec3{v.x(), v.y(), v.z()}, visit); });
}

namespace {

// tree.build() for the tree of `triangles` (inserted in their order), faster, and the same tree.
// CGAL's build gives each node the union of its faces' boxes, then splits its faces at the median
// of their reference points (a face's first corner) along the box's longest side with
// std::nth_element, over the primitives, each comparison reaching through a primitive to its
// triangle (a cache miss: most of building an index of a big mesh). Here each face's box is made
// once, and nth_element runs over compact copies of the reference points kept in the primitives'
// order: the same comparisons give the same order, which is then written back to the primitives.
// Each node's box is the same union, taken in the same order. (Test: TriangleBvh's tests, which
// ask ModelQuery and a tree built by tree.build() the same questions, bit for bit.)
struct TreeBuild {
    struct Ref {
        double p[3];
        std::uint32_t face;
    };
    const std::vector<Triangle3>& triangles;
    std::vector<Ref> refs;            // in the primitives' order
    std::vector<CGAL::Bbox_3> boxes;  // by face
    const Primitive* first = nullptr;  // the primitives' start (the root's range is all of them)
    std::size_t at(const Primitive& p) const { return static_cast<std::size_t>(&p - first); }

    // CGAL's Compute_bbox: the union of the range's boxes, in its order.
    struct Box {
        TreeBuild* s;
        template <typename It>
        CGAL::Bbox_3 operator()(It first, It beyond) const {
            if (!s->first) s->first = &*first;  // the root comes first
            const std::size_t o = s->at(*first), n = static_cast<std::size_t>(beyond - first);
            CGAL::Bbox_3 box = s->boxes[s->refs[o].face];
            for (std::size_t k = 1; k < n; ++k) box = box + s->boxes[s->refs[o + k].face];
            return box;
        }
    };
    // CGAL's Split_primitives: nth_element at the middle by the reference points' coordinate
    // along the box's longest side.
    struct Split {
        TreeBuild* s;
        template <typename It>
        void operator()(It first, It beyond, const CGAL::Bbox_3& box) const {
            const std::size_t o = s->at(*first), n = static_cast<std::size_t>(beyond - first);
            const int axis = Traits::longest_axis(box);
            const auto refs = s->refs.begin() + static_cast<std::ptrdiff_t>(o);
            std::nth_element(refs, refs + static_cast<std::ptrdiff_t>(n / 2), refs + static_cast<std::ptrdiff_t>(n),
                             [axis](const Ref& a, const Ref& b) { return a.p[axis] < b.p[axis]; });
            for (std::size_t k = 0; k < n; ++k) first[k] = Primitive(s->triangles.begin() + refs[k].face);
        }
    };
};

void build_tree(Tree& tree, const std::vector<Triangle3>& triangles) {
    TreeBuild state{triangles, std::vector<TreeBuild::Ref>(triangles.size()), std::vector<CGAL::Bbox_3>(triangles.size())};
    for (std::size_t f = 0; f < triangles.size(); ++f) {
        const Point& c = triangles[f].vertex(0);  // the primitive's reference point
        state.refs[f] = {{c.x(), c.y(), c.z()}, static_cast<std::uint32_t>(f)};
        state.boxes[f] = triangles[f].bbox();  // what CGAL's traits take as the primitive's box
    }
    tree.insert(triangles.begin(), triangles.end());
    tree.custom_build(TreeBuild::Box{&state}, TreeBuild::Split{&state});
}

}  // namespace

ModelQuery::ModelQuery(const Mesh& model) : model_(model), memo_(std::make_unique<Memo>()) {
    auto impl = std::make_shared<Impl>(model);
    impl->triangles.reserve(model.faces.size());
    for (const auto& f : model.faces)
        impl->triangles.emplace_back(pt(model.vertices[f[0]]), pt(model.vertices[f[1]]), pt(model.vertices[f[2]]));
    build_tree(impl->tree, impl->triangles);
    // CGAL builds its distance search tree (a kd-tree of the faces' first corners) at its first
    // closest-point question, under its own lock: an index whose closest points the BVH decides
    // builds none (fandisk: 2 of its 5 indexes, -4 % CPU). The same tree either way, so the same
    // answers.
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
    const K::Ray_3 ray(pt(origin), K::Vector_3(dir.x, dir.y, dir.z));
    const auto where = impl_->first_intersection(ray, *memo_);
    if (!where) return std::nullopt;
    Vec3 q;
    if (const Point* p = boost::get<Point>(&where->first)) {
        q = vec(*p);
    } else if (const auto* s = boost::get<K::Segment_3>(&where->first)) {
        // Ray runs along a triangle: the nearer end of the overlap is the hit.
        Vec3 a = vec(s->source()), b = vec(s->target());
        q = distance(a, origin) < distance(b, origin) ? a : b;
    } else {
        return std::nullopt;
    }
    return RayHit{q, distance(q, origin), where->second};
}

bool ModelQuery::segment_hits(const Vec3& a, const Vec3& b) const {
    if (a == b) return false;
    const Vec3 from = in_index(a), to = in_index(b);
    return impl_->segment_hits(K::Segment_3(pt(from), pt(to)));
}

bool ModelQuery::triangle_hits(const Vec3& a, const Vec3& b, const Vec3& c) const {
    if (Triangle3(pt(a), pt(b), pt(c)).is_degenerate()) return a == b ? segment_hits(a, c) : segment_hits(a, b);
    return impl_->tree.do_intersect(Triangle3(pt(in_index(a)), pt(in_index(b)), pt(in_index(c))));
}

double ModelQuery::squared_distance(const Vec3& p) const {
    return remembered(memo_->mutex, memo_->distances, key(p), [&] {
        const Point q = pt(in_index(p));
        // As CGAL's tree.squared_distance: the squared distance to its closest point.
        return K().compute_squared_distance_3_object()(q, impl_->closest_point(q));
    });
}

Vec3 ModelQuery::closest_point(const Vec3& p) const {
    return remembered(memo_->mutex, memo_->closest, key(p), [&] { return out_of_index(vec(impl_->closest_point(pt(in_index(p))))); });
}

std::optional<bool> ModelQuery::known_verdict(const Question& question) const {
    std::lock_guard lock(memo_->mutex);
    const bool* known = memo_->verdicts.find(question);
    return known ? std::optional<bool>{*known} : std::nullopt;
}

bool ModelQuery::keep_verdict(const Question& question, bool answer) const {
    std::lock_guard lock(memo_->mutex);
    return memo_->verdicts.emplace(question, answer);
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
    for (int r = 0; r < 3; ++r) {
        const auto& d = dirs[r];
        const K::Ray_3 ray(from, d);
        int winding = 0;
        for (const Triangle3* t : impl_->crossed_faces(ray)) {
            double s = CGAL::scalar_product(t->supporting_plane().orthogonal_vector(), d);
            winding += s > 0 ? 1 : (s < 0 ? -1 : 0);
        }
        votes += winding > 0;
        if (r == 1 && votes != 1) break;
    }
    return votes >= 2;
}

double share_along_axes(const Mesh& mesh) {
    std::size_t along = 0;
    for (const Triangle& f : mesh.faces) {
        const Vec3 n = face_normal_unnormalized(mesh, f);
        const double at_most = kAlongAxis * std::sqrt(dot(n, n));
        along += at_most > 0 && (std::abs(n.x) <= at_most || std::abs(n.y) <= at_most || std::abs(n.z) <= at_most);
    }
    return mesh.faces.empty() ? 0.0 : double(along) / double(mesh.faces.size());
}

namespace {

// Thrown by a count that reached its limit: enough to warn, the search stops early.
struct CountFull {};

// CGAL's own count, over a Surface_mesh of the faces it can take (a non-manifold face is skipped).
std::size_t count_in_surface_mesh(const Mesh& mesh, std::size_t limit) {
    using SM = CGAL::Surface_mesh<Point>;
    SM sm;
    // Room for a closed mesh's elements at once (an edge to two faces): no array is copied as it
    // grows. Capacity only: the mesh built is the same.
    sm.reserve(mesh.vertices.size(), 3 * mesh.faces.size() / 2 + 1, mesh.faces.size());
    std::vector<SM::Vertex_index> vs;
    vs.reserve(mesh.vertices.size());
    for (const auto& v : mesh.vertices) vs.push_back(sm.add_vertex(pt(v)));
    for (const auto& f : mesh.faces) {
        // Non-manifold input cannot become a Surface_mesh face; such faces are skipped here.
        sm.add_face(vs[f[0]], vs[f[1]], vs[f[2]]);
    }
    std::size_t count = 0;
    auto counter = boost::make_function_output_iterator([&](const auto&) {
        if (++count >= limit) throw CountFull{};
    });
    try {
        CGAL::Polygon_mesh_processing::self_intersections(sm, counter);
    } catch (const CountFull&) {
    }
    return count;
}

// Does a Surface_mesh built face by face in order take every face of `mesh`, each as given? So it
// does when the mesh is closed, oriented and manifold: around every vertex its faces form one
// closed fan, each edge leaving the vertex once and coming in once (Euler::add_face refuses a
// face only at an edge or vertex that is already closed, or at a repeated corner).
bool surface_mesh_takes_every_face(const Mesh& mesh) {
    const std::size_t nv = mesh.vertices.size();
    // Each vertex's corners, grouped by vertex: the corner's edge leaving the vertex (to `out`) and
    // its edge coming in (from `in`).
    std::vector<std::uint32_t> first(nv + 1, 0);
    for (const auto& f : mesh.faces) {
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) return false;
        for (int k = 0; k < 3; ++k) ++first[f[k] + 1];
    }
    for (std::size_t v = 0; v < nv; ++v) first[v + 1] += first[v];
    std::vector<std::uint32_t> out(3 * mesh.faces.size()), in(out.size()), at(first.begin(), first.end() - 1);
    for (const auto& f : mesh.faces)
        for (int k = 0; k < 3; ++k) {
            const std::uint32_t c = at[f[k]]++;
            out[c] = f[(k + 1) % 3], in[c] = f[(k + 2) % 3];
        }
    // Around vertex v, the corner whose edge leaves to w is leaving[w] while seen[w] == v (marks
    // that need no clearing between vertices); the fan's next corner follows that edge back in.
    constexpr std::uint32_t kNone = UINT32_MAX;
    std::vector<std::uint32_t> seen(nv, kNone), leaving(nv), next;
    for (std::uint32_t v = 0; v < nv; ++v) {
        const std::uint32_t begin = first[v], n = first[v + 1] - begin;
        for (std::uint32_t i = 0; i < n; ++i) {
            const std::uint32_t w = out[begin + i];
            if (seen[w] == v) return false;  // an edge leaving twice
            seen[w] = v, leaving[w] = i;
        }
        next.assign(n, kNone);
        for (std::uint32_t j = 0; j < n; ++j) {
            const std::uint32_t w = in[begin + j];
            if (seen[w] != v) return false;  // an edge coming in with no edge going back: open
            std::uint32_t& after = next[leaving[w]];
            if (after != kNone) return false;  // an edge coming in twice
            after = j;
        }
        // One fan: following the corners from the first visits all of them before coming back.
        std::uint32_t steps = 0;
        for (std::uint32_t i = 0; steps < n;) {
            i = next[i], ++steps;
            if (i == 0) break;
        }
        if (steps != n) return false;
    }
    return true;
}

// CGAL's do_faces_intersect (Polygon_mesh_processing/self_intersections.h) for faces f and g of a
// mesh a Surface_mesh takes whole (surface_mesh_takes_every_face): there a face's halfedge runs
// from its corner 2 to its corner 0 (Euler::add_face), so the same predicates are asked of the
// same points in the same order, and the face across an edge is the one with the edge reversed.
bool faces_cross(const Mesh& mesh, const Triangle& f, const Triangle& g) {
    auto at = [&](std::uint32_t v) { return pt(mesh.vertices[v]); };
    // The edges in CGAL's order from the face's halfedge: corner (i + 2) % 3 to corner i.
    for (int i = 0; i < 3; ++i) {
        const std::uint32_t from = f[(i + 2) % 3], to = f[i];
        for (int j = 0; j < 3; ++j) {
            if (g[j] != to || g[(j + 1) % 3] != from) continue;
            // A shared edge: an overlap only where the two lie in one plane and fold onto each other.
            const Point across = at(g[(j + 2) % 3]);
            return CGAL::coplanar(at(f[i]), at(f[(i + 1) % 3]), at(f[(i + 2) % 3]), across) &&
                   CGAL::coplanar_orientation(at(f[(i + 2) % 3]), at(f[i]), at(f[(i + 1) % 3]), across) == CGAL::POSITIVE;
        }
    }
    const Triangle3 tf(at(f[0]), at(f[1]), at(f[2])), tg(at(g[0]), at(g[1]), at(g[2]));
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) {
            if (f[i] != g[j]) continue;
            // A shared corner: does either face's opposite side pass through the other?
            const K::Segment_3 sf(at(f[(i + 1) % 3]), at(f[(i + 2) % 3])), sg(at(g[(j + 1) % 3]), at(g[(j + 2) % 3]));
            return K().do_intersect_3_object()(tf, sg) || K().do_intersect_3_object()(tg, sf);
        }
    return K().do_intersect_3_object()(tf, tg);
}

}  // namespace

// CGAL's self_intersections on a Surface_mesh of the model asks, of every pair of faces whose
// boxes meet (box_self_intersection_d over boxes in face order), whether they truly cross. Where
// that mesh would take every face as given (a closed manifold, as repair leaves most models), the
// same boxes are searched the same way here and the same question asked of the faces themselves:
// the same pairs, in the same order, with the same answers, without building the Surface_mesh
// and walking its halfedges (most of the count's time on a big scan).
std::size_t count_self_intersections(const Mesh& mesh, std::size_t limit) {
    if (!surface_mesh_takes_every_face(mesh)) return count_in_surface_mesh(mesh, limit);
    using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::uint32_t, CGAL::Box_intersection_d::ID_FROM_BOX_ADDRESS>;
    std::size_t count = 0;
    auto found = [&] {
        if (++count >= limit) throw CountFull{};
    };
    try {
        // A degenerate face is a pair of its own (as CGAL reports it) and gets no box.
        std::vector<Box> boxes;
        boxes.reserve(mesh.faces.size());
        for (std::uint32_t fi = 0; fi < mesh.faces.size(); ++fi) {
            const Triangle& f = mesh.faces[fi];
            const Point p = pt(mesh.vertices[f[0]]), q = pt(mesh.vertices[f[1]]), r = pt(mesh.vertices[f[2]]);
            if (CGAL::collinear(p, q, r)) found();
            else boxes.push_back(Box(p.bbox() + q.bbox() + r.bbox(), fi));
        }
        std::vector<const Box*> box_ptr;
        box_ptr.reserve(boxes.size());
        for (const Box& b : boxes) box_ptr.push_back(&b);
        const std::ptrdiff_t cutoff = 2000;  // CGAL's own
        CGAL::box_self_intersection_d<CGAL::Sequential_tag>(
            box_ptr.begin(), box_ptr.end(),
            [&](const Box* b, const Box* c) {
                if (faces_cross(mesh, mesh.faces[b->info()], mesh.faces[c->info()])) found();
            },
            cutoff);
    } catch (const CountFull&) {
    }
    return count;
}

}  // namespace cs

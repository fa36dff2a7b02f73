// Plain geometry types shared by every stage: a 3-vector and an indexed triangle mesh.
// Units are millimetres; +Z is the build direction; the bed is z = 0.
#pragma once

#include <algorithm>
#include <array>
#include <utility>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <vector>

namespace cs {

struct Vec3 {
    double x = 0, y = 0, z = 0;

    Vec3 operator+(const Vec3& o) const { return {x + o.x, y + o.y, z + o.z}; }
    Vec3 operator-(const Vec3& o) const { return {x - o.x, y - o.y, z - o.z}; }
    Vec3 operator*(double s) const { return {x * s, y * s, z * s}; }
    Vec3 operator/(double s) const { return {x / s, y / s, z / s}; }
    Vec3 operator-() const { return {-x, -y, -z}; }
    Vec3& operator+=(const Vec3& o) { x += o.x; y += o.y; z += o.z; return *this; }
    bool operator==(const Vec3& o) const = default;
};

inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
    return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline Vec3 normalized(const Vec3& a) {
    double n = norm(a);
    return n > 0 ? a / n : Vec3{};
}
inline double distance(const Vec3& a, const Vec3& b) { return norm(a - b); }
inline double horizontal_distance(const Vec3& a, const Vec3& b) { return std::hypot(a.x - b.x, a.y - b.y); }
// Reach(reach)(a, b): horizontal_distance(a, b) <= reach, decided from the squares where they are
// clear (a relative 1e-9 either side, far beyond their rounding) and by the same hypot otherwise:
// the same answer, without a hypot for most points asked about. The squares' bounds are taken once
// for the many pairs asked at one reach (a Cover's); within_reach asks one pair.
struct Reach {
    explicit Reach(double r) : reach(r), most2(r * r * (1 + 1e-9)), least2(r * r * (1 - 1e-9)) {}
    bool operator()(const Vec3& a, const Vec3& b) const {
        if (!(reach >= 0)) return false;  // as hypot's answer: never <= a negative (or NaN) reach
        const double dx = a.x - b.x, dy = a.y - b.y, d2 = dx * dx + dy * dy;
        if (!(d2 <= most2)) return false;  // also NaN, which hypot would not call near
        return d2 < least2 || horizontal_distance(a, b) <= reach;
    }
    double reach, most2, least2;
};
inline bool within_reach(const Vec3& a, const Vec3& b, double reach) { return Reach(reach)(a, b); }
// Distance from p to the segment a-b.
inline double point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
    const Vec3 ab = b - a;
    const double len2 = dot(ab, ab);
    const double t = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    return distance(p, a + ab * t);
}

// The same in plan: the horizontal distance from p to segment ab, heights ignored.
inline double horizontal_point_segment_distance(const Vec3& p, const Vec3& a, const Vec3& b) {
    const double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
    const double t = l2 > 0 ? std::clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / l2, 0.0, 1.0) : 0.0;
    return std::hypot(p.x - a.x - t * dx, p.y - a.y - t * dy);
}

// Degrees to radians and back: parameters and reports speak degrees, <cmath> radians. Written
// as `deg * pi / 180` (not `deg * (pi / 180)`): the two differ in the last bit for some angles,
// and every stage converts the same way so a threshold means the same everywhere.
inline double deg_to_rad(double deg) { return deg * std::numbers::pi / 180.0; }
inline double rad_to_deg(double rad) { return rad * 180.0 / std::numbers::pi; }

// Angle of the segment a-b from vertical, in degrees (0 = vertical).
inline double angle_from_vertical_deg(const Vec3& a, const Vec3& b) {
    double h = horizontal_distance(a, b), v = std::abs(a.z - b.z);
    return rad_to_deg(std::atan2(h, v));
}

using Triangle = std::array<std::uint32_t, 3>;

struct Mesh {
    std::vector<Vec3> vertices;
    std::vector<Triangle> faces;

    bool empty() const { return faces.empty(); }
};

// One key for the undirected edge between vertices a and b (either order): the smaller index in
// the high word.
inline std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
    return a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a;
}

// Sorts (edge_key, index) pairs as std::sort sorts pairs (by key, then index), in about linear
// time: counted by the edge's lower vertex (the key's high word), then each vertex's few pairs
// sorted (a mesh's face-edges: a million on a scan, a handful per vertex). Keys whose high words
// are sparse (far more vertices than pairs) go to std::sort.
inline void sort_edge_uses(std::vector<std::pair<std::uint64_t, std::uint32_t>>& uses) {
    std::uint64_t top = 0;
    for (const auto& u : uses) top = std::max(top, u.first >> 32);
    if (uses.size() < 64 || top > 4 * uses.size()) {
        std::sort(uses.begin(), uses.end());
        return;
    }
    std::vector<std::size_t> end(static_cast<std::size_t>(top) + 2, 0);
    for (const auto& u : uses) ++end[static_cast<std::size_t>(u.first >> 32) + 1];
    for (std::size_t v = 1; v < end.size(); ++v) end[v] += end[v - 1];
    std::vector<std::pair<std::uint64_t, std::uint32_t>> out(uses.size());
    for (const auto& u : uses) out[end[static_cast<std::size_t>(u.first >> 32)]++] = u;
    for (std::size_t v = 0, begin = 0; v <= top; begin = end[v++])
        if (end[v] - begin > 1)
            std::sort(out.begin() + static_cast<std::ptrdiff_t>(begin), out.begin() + static_cast<std::ptrdiff_t>(end[v]));
    uses = std::move(out);
}

struct Box3 {
    Vec3 min{INFINITY, INFINITY, INFINITY};
    Vec3 max{-INFINITY, -INFINITY, -INFINITY};

    void add(const Vec3& p) {
        min = {std::fmin(min.x, p.x), std::fmin(min.y, p.y), std::fmin(min.z, p.z)};
        max = {std::fmax(max.x, p.x), std::fmax(max.y, p.y), std::fmax(max.z, p.z)};
    }
    Vec3 size() const { return max - min; }
    Vec3 center() const { return (min + max) * 0.5; }
};

inline bool contains(const Box3& b, const Vec3& p) {
    return p.x >= b.min.x && p.x <= b.max.x && p.y >= b.min.y && p.y <= b.max.y && p.z >= b.min.z && p.z <= b.max.z;
}

// Do the boxes share a point (touching counts)?
inline bool overlaps(const Box3& a, const Box3& b) {
    return a.min.x <= b.max.x && b.min.x <= a.max.x && a.min.y <= b.max.y && b.min.y <= a.max.y && a.min.z <= b.max.z &&
           b.min.z <= a.max.z;
}

// The box grown by r on each side horizontally and by rz vertically.
inline Box3 grown(const Box3& b, double r, double rz) {
    return {b.min - Vec3{r, r, rz}, b.max + Vec3{r, r, rz}};
}

// Does the segment a-b meet the (closed) box? Slab test: clip the segment's parameter range to
// each axis' slab in turn.
inline bool segment_meets_box(const Vec3& a, const Vec3& b, const Box3& box) {
    double t0 = 0, t1 = 1;
    const double from[3] = {a.x, a.y, a.z}, to[3] = {b.x, b.y, b.z};
    const double lo[3] = {box.min.x, box.min.y, box.min.z}, hi[3] = {box.max.x, box.max.y, box.max.z};
    for (int i = 0; i < 3; ++i) {
        double d = to[i] - from[i];
        if (std::abs(d) < 1e-12) {
            if (from[i] < lo[i] || from[i] > hi[i]) return false;
            continue;
        }
        double ta = (lo[i] - from[i]) / d, tb = (hi[i] - from[i]) / d;
        if (ta > tb) std::swap(ta, tb);
        t0 = std::max(t0, ta);
        t1 = std::min(t1, tb);
        if (t0 > t1) return false;
    }
    return true;
}

// Does a solid swept along a-b with a horizontal square cross-section (side up to `width`) meet
// any of the boxes? Exact for the square swept at its widest: the segment against each box grown
// by half the width horizontally (and by `rz` vertically, for what reaches past the ends).
inline bool sweep_meets_boxes(const Vec3& a, const Vec3& b, double width, double rz, const std::vector<Box3>& boxes) {
    for (const auto& box : boxes)
        if (segment_meets_box(a, b, grown(box, 0.5 * width, rz))) return true;
    return false;
}

inline Box3 bounding_box(const Mesh& m) {
    Box3 b;
    for (const auto& v : m.vertices) b.add(v);
    return b;
}

inline Vec3 face_normal_unnormalized(const Mesh& m, const Triangle& f) {
    const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &c = m.vertices[f[2]];
    return cross(b - a, c - a);
}

// Signed volume by the divergence theorem: positive for a closed, outward-facing mesh.
inline double signed_volume(const Mesh& m) {
    double v = 0;
    for (const auto& f : m.faces)
        v += dot(m.vertices[f[0]], cross(m.vertices[f[1]], m.vertices[f[2]]));
    return v / 6.0;
}

// Appends `b` to `a` (vertex indices of b are shifted).
inline void append(Mesh& a, const Mesh& b) {
    auto offset = static_cast<std::uint32_t>(a.vertices.size());
    a.vertices.insert(a.vertices.end(), b.vertices.begin(), b.vertices.end());
    for (auto f : b.faces) a.faces.push_back({f[0] + offset, f[1] + offset, f[2] + offset});
}

}  // namespace cs

#include "mesh/unfold_caps.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace cs {
namespace {

// A cap's apex angle is at least this: its apex lies within tan(10 deg) / 2 of its long edge's
// length from that edge.
constexpr double kCapApexDeg = 160;
// The cap folds back over the triangle across: their normals more than 120 degrees apart, the two
// faces within 60 degrees of lying flat on each other (nefertiti's fold behind the headdress: 153
// degrees). A sharp edge of the shape is not a fold: CAD meshes carry slivers along their
// 90-degree edges (bracket, slots, extruder_idler) and along a thread's crest (normals 93-105
// degrees apart); flipping those would chamfer the edge by up to the sliver's height (2 mm on the
// bracket).
constexpr double kFoldedCos = -0.5;
// Both new triangles must face within 60 degrees of the triangle across.
constexpr double kAgreeCos = 0.5;
// Flips that open other folds are retried; a few passes find every cap that can be unfolded.
constexpr int kPasses = 4;

Vec3 unit_normal(const Mesh& m, const Triangle& t) {
    const Vec3 n = face_normal_unnormalized(m, t);
    const double len = norm(n);
    return len > 0 ? n / len : Vec3{};
}

// Is c's corner of the triangle (a, b, c) a cap's apex, c almost on the edge a-b? Every corner of
// every face is asked at every repair: the angle is compared as a cosine, without acos.
bool is_apex(const Mesh& m, std::uint32_t a, std::uint32_t b, std::uint32_t c) {
    static const double max_cos = std::cos(deg_to_rad(kCapApexDeg));
    const Vec3 u = m.vertices[a] - m.vertices[c], v = m.vertices[b] - m.vertices[c];
    const double cosine_times_lengths = dot(u, v);
    // An angle under 90 degrees is no apex, whatever the lengths (max_cos * lengths is not
    // positive): two corners of most triangles, answered without the two square roots.
    if (cosine_times_lengths > 0) return false;
    const double lengths = norm(u) * norm(v);
    return lengths > 0 && cosine_times_lengths <= max_cos * lengths;
}

bool has_cap(const Mesh& m, const Triangle& t) {
    for (int k = 0; k < 3; ++k)
        if (is_apex(m, t[k], t[(k + 1) % 3], t[(k + 2) % 3])) return true;
    return false;
}

// The faces on each edge: as the pass found them (the face-edges sorted by edge, one run per
// edge, faces in the order met), and the few edges its flips changed since. A hash map of a
// vector per edge cost seconds and gigabytes on a 5M-triangle scan; one sorted array does not.
class EdgeFaces {
public:
    explicit EdgeFaces(const Mesh& m) {
        uses_.reserve(3 * m.faces.size());
        for (std::uint32_t f = 0; f < m.faces.size(); ++f)
            for (int k = 0; k < 3; ++k) uses_.push_back({edge_key(m.faces[f][k], m.faces[f][(k + 1) % 3]), f});
        sort_edge_uses(uses_);  // by edge, then face: each face-edge pushed in face order
    }
    // The faces on the edge, in the order they were met (none: no such edge).
    std::vector<std::uint32_t> faces(std::uint64_t edge) const {
        if (auto it = changed_.find(edge); it != changed_.end()) return it->second;
        auto lo = std::lower_bound(uses_.begin(), uses_.end(), edge, [](const auto& u, std::uint64_t e) { return u.first < e; });
        std::vector<std::uint32_t> out;
        for (; lo != uses_.end() && lo->first == edge; ++lo) out.push_back(lo->second);
        return out;
    }
    void set(std::uint64_t edge, std::vector<std::uint32_t> faces) { changed_[edge] = std::move(faces); }
    void replace(std::uint64_t edge, std::uint32_t from, std::uint32_t to) {
        std::vector<std::uint32_t> v = faces(edge);
        std::replace(v.begin(), v.end(), from, to);
        set(edge, std::move(v));
    }

private:
    std::vector<std::pair<std::uint64_t, std::uint32_t>> uses_;
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> changed_;  // empty: the edge is gone
};

}  // namespace

size_t unfold_caps(Mesh& m) {
    // Most meshes have no cap at all: then no edge map is built.
    if (std::none_of(m.faces.begin(), m.faces.end(), [&](const Triangle& t) { return has_cap(m, t); })) return 0;
    size_t unfolded = 0;
    for (int pass = 0; pass < kPasses; ++pass) {
        EdgeFaces faces_of_edge(m);
        std::vector<char> touched(m.faces.size(), 0);
        size_t this_pass = 0;
        for (std::uint32_t f = 0; f < m.faces.size(); ++f) {
            if (touched[f]) continue;
            const Triangle t = m.faces[f];
            for (int k = 0; k < 3; ++k) {
                // The cap (a, b, c): apex c opposite the edge a -> b.
                const std::uint32_t a = t[k], b = t[(k + 1) % 3], c = t[(k + 2) % 3];
                if (!is_apex(m, a, b, c)) continue;
                const auto across = faces_of_edge.faces(edge_key(a, b));
                if (across.size() != 2) break;  // an open or non-manifold edge: leave it
                const std::uint32_t g = across[0] == f ? across[1] : across[0];
                if (touched[g]) break;
                const Triangle& u = m.faces[g];
                const std::uint32_t d = u[0] != a && u[0] != b ? u[0] : u[1] != a && u[1] != b ? u[1] : u[2];
                if (d == c || !faces_of_edge.faces(edge_key(c, d)).empty()) break;
                const Vec3 n_across = unit_normal(m, u);
                if (dot(unit_normal(m, t), n_across) > kFoldedCos) break;  // not folded
                const Triangle t2{c, a, d}, u2{d, b, c};
                if (dot(unit_normal(m, t2), n_across) < kAgreeCos || dot(unit_normal(m, u2), n_across) < kAgreeCos) break;
                m.faces[f] = t2;
                m.faces[g] = u2;
                // The edges' faces as they are now: a-b is gone, c-d is new, a-d is f's, b-c is g's.
                faces_of_edge.set(edge_key(a, b), {});
                faces_of_edge.set(edge_key(c, d), {f, g});
                faces_of_edge.replace(edge_key(a, d), g, f);
                faces_of_edge.replace(edge_key(b, c), f, g);
                touched[f] = touched[g] = 1;
                ++this_pass;
                break;
            }
        }
        unfolded += this_pass;
        if (this_pass == 0) break;
    }
    return unfolded;
}

}  // namespace cs

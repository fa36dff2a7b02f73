#include "overhang/overhang.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace cs {
namespace {

// Edge function of p against the directed edge u->v. Computed from the lexicographically smaller
// endpoint so both triangles sharing an edge get bit-identical values of opposite sign: the
// top-left tie rule then gives a lattice point on the edge to exactly one of them.
double edge_function(const Vec3& u, const Vec3& v, double px, double py) {
    bool swapped = (v.x < u.x) || (v.x == u.x && v.y < u.y);
    const Vec3& a = swapped ? v : u;
    const Vec3& b = swapped ? u : v;
    double e = (b.x - a.x) * (py - a.y) - (b.y - a.y) * (px - a.x);
    return swapped ? -e : e;
}

// For a counter-clockwise triangle, an edge owns the lattice points lying exactly on it when it
// runs downward, or rightward when horizontal. Reversing the edge flips the answer.
bool owns_edge_points(const Vec3& u, const Vec3& v) {
    double dx = v.x - u.x, dy = v.y - u.y;
    return dy < 0 || (dy == 0 && dx > 0);
}

// Hash grid of accepted samples, to drop extras that land near an existing sample.
struct SampleGrid {
    double cell;
    std::unordered_map<std::uint64_t, std::vector<Vec3>> cells;

    std::uint64_t key(long i, long j, long k) const {
        return (std::uint64_t(i & 0x1fffff) << 42) | (std::uint64_t(j & 0x1fffff) << 21) | std::uint64_t(k & 0x1fffff);
    }
    long idx(double v) const { return static_cast<long>(std::floor(v / cell)); }
    void add(const Vec3& p) { cells[key(idx(p.x), idx(p.y), idx(p.z))].push_back(p); }
    bool near(const Vec3& p, double r) const {
        long i = idx(p.x), j = idx(p.y), k = idx(p.z);
        for (long a = i - 1; a <= i + 1; ++a)
            for (long b = j - 1; b <= j + 1; ++b)
                for (long c = k - 1; c <= k + 1; ++c) {
                    auto it = cells.find(key(a, b, c));
                    if (it == cells.end()) continue;
                    for (const auto& q : it->second)
                        if (dot(q - p, q - p) < r * r) return true;
                }
        return false;
    }
};

std::uint64_t edge_key(std::uint32_t a, std::uint32_t b) {
    return a < b ? (std::uint64_t(a) << 32) | b : (std::uint64_t(b) << 32) | a;
}

void sample_segment(const Vec3& a, const Vec3& b, double spacing, std::vector<Vec3>& out) {
    int n = std::max(1, static_cast<int>(std::ceil(distance(a, b) / spacing)));
    for (int i = 0; i <= n; ++i) out.push_back(a + (b - a) * (double(i) / n));
}

}  // namespace

bool needs_support(const Vec3& n, double critical_angle_deg) {
    return n.z < -std::sin(critical_angle_deg * M_PI / 180.0);
}

std::vector<char> classify_faces(const Mesh& m, const OverhangOptions& o) {
    std::vector<char> out(m.faces.size(), 0);
    const double on_bed = o.bed_height * 0.5;
    for (size_t i = 0; i < m.faces.size(); ++i) {
        const auto& f = m.faces[i];
        double zmax = std::max({m.vertices[f[0]].z, m.vertices[f[1]].z, m.vertices[f[2]].z});
        if (zmax <= on_bed) continue;
        out[i] = needs_support(normalized(face_normal_unnormalized(m, f)), o.critical_angle);
    }
    return out;
}

double overhang_area(const Mesh& m, const OverhangOptions& o) {
    auto cls = classify_faces(m, o);
    double a = 0;
    for (size_t i = 0; i < m.faces.size(); ++i)
        if (cls[i]) a += 0.5 * norm(face_normal_unnormalized(m, m.faces[i]));
    return a;
}

void rasterize_triangle(const Vec3& a0, const Vec3& b0, const Vec3& c0, double s, std::vector<Vec3>& out) {
    Vec3 a = a0, b = b0, c = c0;
    double area2 = edge_function(a, b, c.x, c.y);
    if (area2 == 0) return;  // vertical face: no XY footprint
    if (area2 < 0) std::swap(b, c);
    Vec3 n = cross(b - a, c - a);  // n.z > 0 after the swap
    double x0 = std::min({a.x, b.x, c.x}), x1 = std::max({a.x, b.x, c.x});
    double y0 = std::min({a.y, b.y, c.y}), y1 = std::max({a.y, b.y, c.y});
    const Vec3* e[3][2] = {{&a, &b}, {&b, &c}, {&c, &a}};
    // Loop bounds from floor/ceil with a cell to spare: x0 / s may round past a lattice point
    // lying exactly on the triangle (0.3 / 0.1 > 3); the edge functions decide exactly.
    const long i1 = static_cast<long>(std::ceil(x1 / s)) + 1, j1 = static_cast<long>(std::ceil(y1 / s)) + 1;
    for (long i = static_cast<long>(std::floor(x0 / s)) - 1; i <= i1; ++i) {
        for (long j = static_cast<long>(std::floor(y0 / s)) - 1; j <= j1; ++j) {
            double px = i * s, py = j * s;
            bool inside = true;
            for (auto& edge : e) {
                double w = edge_function(*edge[0], *edge[1], px, py);
                if (w < 0 || (w == 0 && !owns_edge_points(*edge[0], *edge[1]))) {
                    inside = false;
                    break;
                }
            }
            if (!inside) continue;
            // z on the triangle's plane: n . (p - a) = 0
            double z = a.z - (n.x * (px - a.x) + n.y * (py - a.y)) / n.z;
            out.push_back({px, py, z});
        }
    }
}

// A keel: two downward-facing faces that both rise away from their shared edge (the edge is the
// lowest line of its cross-section), the edge itself flatter than the critical angle. Such a line
// hangs whatever the faces' own slopes: nothing below it grows up to it.
static bool hanging_keel(const Mesh& m, std::uint32_t f0, std::uint32_t f1, std::uint32_t a, std::uint32_t b,
                         const Vec3& n0, const Vec3& n1, double sin_c) {
    if (!(n0.z < 0 && n1.z < 0)) return false;
    const Vec3 e = m.vertices[b] - m.vertices[a];
    const double cos_c = std::sqrt(std::max(0.0, 1 - sin_c * sin_c));
    if (norm(e) == 0 || std::abs(e.z) / norm(e) >= cos_c) return false;
    auto rises = [&](std::uint32_t fi) {
        const auto& f = m.faces[fi];
        std::uint32_t far = f[0] != a && f[0] != b ? f[0] : (f[1] != a && f[1] != b ? f[1] : f[2]);
        const Vec3 w = m.vertices[far] - m.vertices[a];
        return (w - e * (dot(w, e) / dot(e, e))).z > 0;
    };
    return rises(f0) && rises(f1);
}

OverhangSamples sample_overhangs(const Mesh& m, const OverhangOptions& o) {
    OverhangSamples res;
    const double s = o.sampling_distance;
    auto cls = classify_faces(m, o);
    std::vector<Vec3> lattice, extra;
    std::vector<SampleKind> extra_kind;
    std::vector<char> face_caught(m.faces.size(), 0);

    for (size_t i = 0; i < m.faces.size(); ++i) {
        if (!cls[i]) continue;
        const auto& f = m.faces[i];
        ++res.overhang_faces;
        res.overhang_area += 0.5 * norm(face_normal_unnormalized(m, f));
        size_t before = lattice.size();
        rasterize_triangle(m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]], s, lattice);
        face_caught[i] = lattice.size() > before;
    }

    // Edges: region borders (one side needs support) and downward convex ridges.
    std::unordered_map<std::uint64_t, std::vector<std::uint32_t>> edge_faces;
    edge_faces.reserve(m.faces.size() * 2);
    for (std::uint32_t fi = 0; fi < m.faces.size(); ++fi)
        for (int k = 0; k < 3; ++k) edge_faces[edge_key(m.faces[fi][k], m.faces[fi][(k + 1) % 3])].push_back(fi);
    std::vector<std::uint64_t> keys;
    keys.reserve(edge_faces.size());
    for (const auto& kv : edge_faces) keys.push_back(kv.first);
    std::sort(keys.begin(), keys.end());  // deterministic order
    const double sin_c = std::sin(o.critical_angle * M_PI / 180.0);
    for (auto key : keys) {
        const auto& fs = edge_faces[key];
        auto a = static_cast<std::uint32_t>(key >> 32), b = static_cast<std::uint32_t>(key & 0xffffffffu);
        const Vec3 &pa = m.vertices[a], &pb = m.vertices[b];
        if (std::max(pa.z, pb.z) <= o.bed_height * 0.5) continue;
        int over = 0;
        for (auto f : fs) over += cls[f];
        // Convex edge: the far corner of the second face lies behind the first face's plane.
        auto convex = [&] {
            const auto& g = m.faces[fs[1]];
            std::uint32_t far = g[0] != a && g[0] != b ? g[0] : (g[1] != a && g[1] != b ? g[1] : g[2]);
            return dot(normalized(face_normal_unnormalized(m, m.faces[fs[0]])), m.vertices[far] - pa) < 0;
        };
        // A border where the overhang meets a wall going down from it (an inside corner) rests
        // on that wall; only convex borders (lips) need their own samples.
        bool any_border = over > 0 && over < static_cast<int>(fs.size());
        bool border = any_border && (fs.size() != 2 || convex());
        if (any_border && !border) sample_segment(pa, pb, s, res.anchors);
        bool open_border = fs.size() == 1 && over == 1;
        bool ridge = false;
        if (fs.size() == 2 && over == 0) {
            Vec3 n1 = normalized(face_normal_unnormalized(m, m.faces[fs[0]]));
            Vec3 n2 = normalized(face_normal_unnormalized(m, m.faces[fs[1]]));
            ridge = (normalized(n1 + n2).z < -sin_c && convex()) || hanging_keel(m, fs[0], fs[1], a, b, n1, n2, sin_c);
        }
        if (!(border || open_border || ridge)) continue;
        res.ridge_edges += ridge;
        size_t before = extra.size();
        sample_segment(pa, pb, s, extra);
        extra_kind.resize(extra.size(), SampleKind::Edge);
        (void)before;
    }

    // Points: vertices lower than all their neighbours.
    std::vector<double> min_neighbour_z(m.vertices.size(), INFINITY);
    for (const auto& f : m.faces)
        for (int k = 0; k < 3; ++k) {
            auto v = f[k];
            min_neighbour_z[v] = std::min({min_neighbour_z[v], m.vertices[f[(k + 1) % 3]].z, m.vertices[f[(k + 2) % 3]].z});
        }
    for (size_t v = 0; v < m.vertices.size(); ++v) {
        if (m.vertices[v].z < min_neighbour_z[v] && m.vertices[v].z > o.bed_height * 0.5) {
            extra.push_back(m.vertices[v]);
            extra_kind.push_back(SampleKind::Point);
            ++res.point_overhangs;
        }
    }

    // Centroids of overhang faces that caught no lattice point.
    for (size_t i = 0; i < m.faces.size(); ++i) {
        if (!cls[i] || face_caught[i]) continue;
        const auto& f = m.faces[i];
        extra.push_back((m.vertices[f[0]] + m.vertices[f[1]] + m.vertices[f[2]]) / 3.0);
        extra_kind.push_back(SampleKind::Centroid);
    }

    SampleGrid grid{s};
    for (const auto& p : lattice) {
        if (p.z < o.bed_height) continue;
        grid.add(p);
        res.samples.push_back({p, SampleKind::Face});
    }
    // Points first (a local minimum must keep its exact position), then edges, then centroids.
    for (SampleKind kind : {SampleKind::Point, SampleKind::Edge, SampleKind::Centroid}) {
        for (size_t i = 0; i < extra.size(); ++i) {
            if (extra_kind[i] != kind || extra[i].z < o.bed_height) continue;
            if (grid.near(extra[i], 0.5 * s)) continue;
            grid.add(extra[i]);
            res.samples.push_back({extra[i], kind});
        }
    }
    std::sort(res.samples.begin(), res.samples.end(), [](const Sample& a, const Sample& b) {
        if (a.p.z != b.p.z) return a.p.z > b.p.z;
        if (a.p.x != b.p.x) return a.p.x < b.p.x;
        return a.p.y < b.p.y;
    });
    return res;
}

}  // namespace cs

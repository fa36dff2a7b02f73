#include "check/judge_overhangs.hpp"

#include <algorithm>
#include <cmath>
#include <map>

namespace cs {
namespace {


// A face (or a line) at the critical angle itself is printable: it needs support only beyond it.
// The judge reads the model as written, in float32, so a face drawn at exactly the critical angle
// (a 45 degree chamfer under a 45 degree preset, or a face the pose turned there) comes back
// tilted by the rounding of its corners, to either side: by 1e-8 in n_z on wedge_ledge turned a
// quarter at 0.8x, by 1e-16 on shelter_roof at 1.3x, whose supports `check` then failed over 33
// and 200 mm2. Within this much of the critical angle, in n_z (or in a line's slope), a face is
// taken to lie at it. Rounding a corner of up to 150 mm from the origin moves it by 1e-5 mm at
// most, which tilts a face a millimetre across by about that; in angle, under 0.001 degree.
constexpr double kCriticalRounding = 1e-5;

using EdgeKey = std::pair<std::uint32_t, std::uint32_t>;

std::map<EdgeKey, std::vector<std::uint32_t>> faces_by_edge(const Mesh& m) {
    std::map<EdgeKey, std::vector<std::uint32_t>> by_edge;
    for (std::uint32_t fi = 0; fi < m.faces.size(); ++fi)
        for (int k = 0; k < 3; ++k) by_edge[std::minmax(m.faces[fi][k], m.faces[fi][(k + 1) % 3])].push_back(fi);
    return by_edge;
}

Vec3 unit_normal(const Mesh& m, std::uint32_t fi) {
    Vec3 n = face_normal_unnormalized(m, m.faces[fi]);
    double l = norm(n);
    return l > 0 ? n / l : Vec3{};
}

// The corner of face fi that is not on the edge (u, v).
const Vec3& third_corner(const Mesh& m, std::uint32_t fi, std::uint32_t u, std::uint32_t v) {
    for (auto c : m.faces[fi])
        if (c != u && c != v) return m.vertices[c];
    return m.vertices[m.faces[fi][0]];
}

// Points from a to b, both ends included, no further apart than `spacing`.
void sample_segment(const Vec3& a, const Vec3& b, double spacing, std::vector<Vec3>& out) {
    int n = std::max(1, static_cast<int>(std::ceil(distance(a, b) / spacing)));
    for (int i = 0; i <= n; ++i) out.push_back(a + (b - a) * (double(i) / n));
}

// Face overhangs: a barycentric grid per face; shared corners once.
void sample_overhang_faces(const Mesh& m, const std::vector<char>& overhang, double bed_z, double spacing,
                           JudgeOverhangs& out) {
    std::vector<char> corner_done(m.vertices.size(), 0);
    for (std::uint32_t fi = 0; fi < m.faces.size(); ++fi) {
        if (!overhang[fi]) continue;
        const auto& f = m.faces[fi];
        const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &c = m.vertices[f[2]];
        const double area = 0.5 * norm(face_normal_unnormalized(m, f));
        const double longest = std::max({distance(a, b), distance(b, c), distance(c, a)});
        const int n = std::max(1, static_cast<int>(std::ceil(longest / spacing)));
        std::vector<Vec3> pts;
        for (int i = 0; i <= n; ++i)
            for (int j = 0; i + j <= n; ++j) {
                const int k = n - i - j;
                const bool corner = (i == n) || (j == n) || (k == n);
                if (corner) {
                    const std::uint32_t v = i == n ? f[1] : j == n ? f[2] : f[0];
                    if (corner_done[v]) continue;
                    corner_done[v] = 1;
                }
                pts.push_back(a + (b - a) * (double(i) / n) + (c - a) * (double(j) / n));
            }
        if (n == 1) pts.push_back((a + b + c) / 3.0);  // a small face is judged at its middle too
        for (const auto& p : pts)
            if (p.z >= bed_z) out.points.push_back({p, area / static_cast<double>(pts.size()), JudgeKind::Face});
    }
}

}  // namespace

JudgeOverhangs judge_overhangs(const Mesh& m, double critical_angle_deg, double bed_z, double spacing) {
    JudgeOverhangs out;
    // Beyond the critical angle by more than the file's rounding (kCriticalRounding).
    const double overhang_nz = -std::sin(deg_to_rad(critical_angle_deg)) - kCriticalRounding;
    const double line_ez = std::cos(deg_to_rad(critical_angle_deg)) - kCriticalRounding;  // a line flatter than this hangs

    std::vector<char> overhang(m.faces.size(), 0);
    std::vector<Vec3> normal(m.faces.size());
    for (std::uint32_t fi = 0; fi < m.faces.size(); ++fi) {
        normal[fi] = unit_normal(m, fi);
        const auto& f = m.faces[fi];
        const bool on_bed = std::max({m.vertices[f[0]].z, m.vertices[f[1]].z, m.vertices[f[2]].z}) < bed_z;
        overhang[fi] = normal[fi].z < overhang_nz && !on_bed;
    }
    sample_overhang_faces(m, overhang, bed_z, spacing, out);

    for (const auto& [edge, fs] : faces_by_edge(m)) {
        if (fs.size() != 2) continue;
        const auto [u, v] = edge;
        const Vec3 &pu = m.vertices[u], &pv = m.vertices[v];
        const Vec3 e = pv - pu;
        if (norm(e) == 0) continue;
        // In a face's plane, away from the edge.
        auto away = [&](std::uint32_t f) {
            const Vec3 w = third_corner(m, f, u, v) - pu;
            return w - e * (dot(w, e) / dot(e, e));
        };
        // Corner anchor: an overhang face beside a printable face that goes down from the edge.
        for (int side = 0; side < 2; ++side) {
            const auto fo = fs[side], fw = fs[1 - side];
            if (!overhang[fo] || overhang[fw]) continue;
            const Vec3 a = away(fw);
            if (a.z < -1e-9 * norm(a)) sample_segment(pu, pv, 0.5 * spacing, out.corner_anchors);
        }
        // Ridge: a hanging keel. Two downward-facing faces that both rise away from the edge (the
        // edge is the lowest line of its cross-section), the edge itself flatter than the angle.
        const Vec3 &n0 = normal[fs[0]], &n1 = normal[fs[1]];
        if (overhang[fs[0]] && overhang[fs[1]]) continue;  // face points already cover it
        if (!(n0.z < 0 && n1.z < 0)) continue;
        if (std::abs(e.z) / norm(e) >= line_ez) continue;
        // Lowest along its cross-section: both faces rise away from the edge.
        if (!(away(fs[0]).z > 0 && away(fs[1]).z > 0)) continue;
        std::vector<Vec3> along;
        sample_segment(pu, pv, spacing, along);
        for (const auto& p : along)
            if (p.z >= bed_z) out.points.push_back({p, 0, JudgeKind::Ridge});
    }

    // Lowest points: every neighbour higher.
    std::vector<char> lowest(m.vertices.size(), 1), used(m.vertices.size(), 0);
    for (const auto& f : m.faces)
        for (int k = 0; k < 3; ++k) {
            used[f[k]] = 1;
            for (int j = 1; j < 3; ++j)
                if (m.vertices[f[(k + j) % 3]].z <= m.vertices[f[k]].z) lowest[f[k]] = 0;
        }
    for (std::uint32_t vi = 0; vi < m.vertices.size(); ++vi)
        if (used[vi] && lowest[vi] && m.vertices[vi].z >= bed_z) out.points.push_back({m.vertices[vi], 0, JudgeKind::Lowest});
    return out;
}

}  // namespace cs

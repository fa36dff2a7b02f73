#include "orient/orient.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/rules.hpp"
#include "mesh/repair.hpp"
#include "orient/symmetry.hpp"
#include "overhang/overhang.hpp"

namespace cs {
namespace {

// Each face's normal (unnormalized) and its length, as rotated_overhang_area measures them: the
// same in every pose, so worked out once for all the candidates.
struct FaceNormal {
    Vec3 n;
    double len;
};

std::vector<FaceNormal> face_normals(const Mesh& m) {
    std::vector<FaceNormal> out(m.faces.size());
    for (size_t i = 0; i < m.faces.size(); ++i) {
        const Vec3 n = face_normal_unnormalized(m, m.faces[i]);
        out[i] = {n, norm(n)};
    }
    return out;
}

// Overhang area of the mesh after rotation, without building the rotated mesh. `normals`:
// face_normals(m).
double rotated_overhang_area(const Mesh& m, const std::vector<FaceNormal>& normals, const Rotation& r,
                             double critical_angle, double bed_height) {
    // Each written before it is read: not zeroed first (54 candidates on a big scan, a megabyte each).
    const auto z = std::make_unique_for_overwrite<double[]>(m.vertices.size());
    double zmin = INFINITY;
    for (size_t i = 0; i < m.vertices.size(); ++i) {
        z[i] = r.m[2][0] * m.vertices[i].x + r.m[2][1] * m.vertices[i].y + r.m[2][2] * m.vertices[i].z;
        zmin = std::min(zmin, z[i]);
    }
    const double nz_limit = overhang_normal_z_limit(critical_angle);
    double area = 0;
    for (size_t i = 0; i < m.faces.size(); ++i) {
        const auto& f = m.faces[i];
        const auto& [n, len] = normals[i];
        if (len == 0) continue;
        double nz = r.m[2][0] * n.x + r.m[2][1] * n.y + r.m[2][2] * n.z;
        // (Most faces are no overhang: their corners' heights are not looked up.)
        if (nz / len < nz_limit && std::max({z[f[0]], z[f[1]], z[f[2]]}) - zmin > 0.5 * bed_height) area += 0.5 * len;
    }
    return area;
}

// Greedy clustering of unit directions within `max_angle` degrees, heaviest first.
std::vector<Vec3> merge_directions(std::vector<std::pair<double, Vec3>> weighted, double max_angle, size_t keep) {
    std::stable_sort(weighted.begin(), weighted.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    const double cos_max = std::cos(deg_to_rad(max_angle));
    std::vector<Vec3> out;
    for (const auto& entry : weighted) {
        const Vec3& d = entry.second;  // a plain reference: lambdas may not capture structured bindings before C++20 in clang 14
        bool near = std::any_of(out.begin(), out.end(), [&](const Vec3& o) { return dot(o, d) > cos_max; });
        if (!near) out.push_back(d);
        if (out.size() >= keep) break;
    }
    return out;
}

}  // namespace

Rotation rotation_to_down(const Vec3& down) {
    Rotation r;
    Vec3 d = normalized(down), target{0, 0, -1};
    double c = dot(d, target);
    if (c > 1 - 1e-12) return r;
    if (c < -1 + 1e-12) {  // upside down: half turn about X
        r.m[1][1] = -1, r.m[2][2] = -1;
        return r;
    }
    Vec3 axis = normalized(cross(d, target));
    double s = std::sqrt(std::max(0.0, 1 - c * c));
    double x = axis.x, y = axis.y, z = axis.z, t = 1 - c;
    double m[3][3] = {{t * x * x + c, t * x * y - s * z, t * x * z + s * y},
                      {t * x * y + s * z, t * y * y + c, t * y * z - s * x},
                      {t * x * z - s * y, t * y * z + s * x, t * z * z + c}};
    std::copy(&m[0][0], &m[0][0] + 9, &r.m[0][0]);
    return r;
}

namespace {

// Candidate "down" directions with their source: the input pose first (wins ties), the six axes,
// then hull rest positions; none repeating an earlier one.
std::vector<std::pair<Vec3, std::string>> candidate_directions(const Mesh& mesh) {
    std::vector<std::pair<Vec3, std::string>> dirs{{{0, 0, -1}, "input"}};
    for (Vec3 d : {Vec3{0, 0, 1}, Vec3{1, 0, 0}, Vec3{-1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, -1, 0}})
        dirs.push_back({d, "axis"});
    {
        // Near-parallel hull facets merge; the hull area within 10 degrees of a direction says how
        // broad and stable a rest position it is, so merging keeps the broadest first.
        auto facets = hull_facets(mesh.vertices);
        if (facets.size() > 4000) {  // bounded work on huge scans: the largest facets
            std::stable_sort(facets.begin(), facets.end(), [](const auto& a, const auto& b) { return a.area > b.area; });
            facets.resize(4000);
        }
        const double cos_near = std::cos(deg_to_rad(10));
        std::vector<std::pair<double, Vec3>> counted;
        for (const auto& f : facets) {
            // Only the near facets are added (few of them): adding 0 for the others would keep
            // the same sum (areas are not negative) at the cost of an addition each, one after
            // the other.
            double w = 0;
            for (const auto& g : facets)
                if (dot(f.normal, g.normal) > cos_near) w += g.area;
            counted.push_back({w, f.normal});
        }
        for (auto& d : merge_directions(counted, 10.0, 48)) dirs.push_back({d, "hull"});
    }
    // Drop hull directions that repeat an earlier candidate.
    std::vector<std::pair<Vec3, std::string>> unique;
    for (const auto& d : dirs) {
        bool dup = std::any_of(unique.begin(), unique.end(), [&](const auto& u) { return dot(u.first, d.first) > std::cos(deg_to_rad(2)); });
        if (!dup) unique.push_back(d);
    }
    return unique;
}

// How close (a share of the model's bounding-box diagonal) a turned copy must lie to the surface
// for the turn to count as a symmetry: float32 STL coordinates carry about 1e-7 of their size, and
// a part asymmetric by less than a hundred-thousandth of its size prints the same either way.
constexpr double kSymmetryTolerance = 1e-5;

// The turns about the vertical tried between two poses: quarter turns (boxes, a cube's faces) and
// sixths (hexagonal parts).
constexpr int kTurnsTried[] = {0, 90, 180, 270, 60, 120, 240, 300};

// Whether the first n candidates are all one print: each the first turned about the vertical (see
// orient/symmetry.hpp). Then there is nothing to judge between them but where the sampling lattice
// falls, and each of the others is marked a repeat of the first. Where some are other prints,
// every pose is judged: a pose turned about the vertical is then one more placement of the
// lattice, and the search keeps what it finds (the wheel example's two turned poses: coarse trees
// 4 % apart). A symmetry keeps the overhang area, so a part whose best poses differ in area pays
// nothing.
bool all_one_print(const Mesh& mesh, std::vector<OrientCandidate>& cands, size_t n) {
    const double area = cands[0].overhang_area;
    for (size_t i = 1; i < n; ++i)
        if (std::abs(cands[i].overhang_area - area) > 1e-6 * std::max(area, cands[i].overhang_area) + 1e-9) return false;
    const SurfaceSymmetry symmetry(mesh, kSymmetryTolerance * norm(bounding_box(mesh).size()));
    for (size_t i = 1; i < n; ++i) {
        const bool repeat = std::any_of(std::begin(kTurnsTried), std::end(kTurnsTried), [&](int degrees) {
            return symmetry.maps_onto_itself(compose(transposed(cands[0].rotation), compose(turn_about_z(degrees), cands[i].rotation)));
        });
        if (!repeat) return false;
    }
    for (size_t i = 1; i < n; ++i) cands[i].same_pose_as = 0;
    return true;
}

}  // namespace

Orientation choose_orientation(const Mesh& mesh, const Params& p, const std::string& mode, const PoseJudge& support,
                               size_t evaluate_best) {
    Orientation o;
    const OrientRequest request = parse_orient(mode);
    o.mode = request.mode;
    if (request.mode == OrientMode::keep) {
        o.decided_by = "kept";
        return o;
    }
    if (request.mode == OrientMode::euler) {
        o.decided_by = "given";
        const auto& a = request.degrees;
        rotation_from_euler_deg(a[0], a[1], a[2], o.rotation.m);
        return o;
    }

    const auto unique = candidate_directions(mesh);

    o.candidates.resize(unique.size());
    {  // let go before the poses are judged (a 5M-triangle scan's take 170 MB)
        const std::vector<FaceNormal> normals = face_normals(mesh);
        tbb::parallel_for(size_t(0), unique.size(), [&](size_t i) {
            auto& c = o.candidates[i];
            c.down = unique[i].first;
            c.source = unique[i].second;
            c.rotation = rotation_to_down(c.down);
            c.overhang_area = rotated_overhang_area(mesh, normals, c.rotation, p.critical_angle, p.layer_height);
        });
    }
    std::stable_sort(o.candidates.begin(), o.candidates.end(),
                     [](const auto& a, const auto& b) { return a.overhang_area < b.overhang_area - 1e-9; });

    size_t n_eval = std::min(evaluate_best, o.candidates.size());
    if (!support || n_eval <= 1 || all_one_print(mesh, o.candidates, n_eval)) {
        o.rotation = o.candidates[0].rotation;
        o.decided_by = "overhang area";
        return o;
    }
    // Each candidate's tree is independent: build them side by side. Each holds two copies of the
    // model (turned, then placed: about 50 bytes a triangle; the caller shares one index between
    // poses on scans and big models), so past 8 million triangles they take turns: memory stays
    // bounded on huge scans, and the answer is the same either way.
    auto judge = [&](const std::vector<size_t>& which, PoseQuestion question) {
        auto evaluate = [&](size_t k) {
            auto& c = o.candidates[which[k]];
            Mesh rotated = mesh;
            for (auto& v : rotated.vertices) v = c.rotation.apply(v);
            c.support = support(rotated, c.rotation, question);
            c.evaluated = true;
        };
        if (mesh.faces.size() > 8'000'000)
            for (size_t k = 0; k < which.size(); ++k) evaluate(k);
        else
            tbb::parallel_for(size_t(0), which.size(), evaluate);
    };
    // A pose whose tree is empty (volume 0, no contact: a CAD part on a face that leaves no ceiling)
    // is beaten only by another empty one that is lower: any other tree has a volume above 0, and
    // two poses tie within 1 % of the larger volume. Such poses have no overhang area, so those
    // are judged first. Once one is found, the others are asked their height only, and only those
    // as low as it grow their trees. The trees not grown (most of the search's time on small parts)
    // could not have changed the choice, in whatever order the comparisons below meet them: a
    // volume above 0 never wins over an empty tree, and a taller empty one that had led would have
    // lost to the lowest one.
    std::vector<size_t> flat, rest;
    for (size_t i = 0; i < n_eval; ++i) (o.candidates[i].overhang_area <= 1e-9 ? flat : rest).push_back(i);
    judge(flat, PoseQuestion::tree);
    auto lowest_empty = [&] {
        double h = INFINITY;
        for (size_t i = 0; i < n_eval; ++i) {
            const auto& c = o.candidates[i];
            if (c.evaluated && c.support.grown && c.support.volume == 0 && c.support.model_contacts == 0)
                h = std::min(h, c.support.height);
        }
        return h;
    };
    if (std::isfinite(lowest_empty())) {
        judge(rest, PoseQuestion::height_if_it_needs_support);
        const double low = lowest_empty();
        std::vector<size_t> as_low;
        for (size_t i : rest)
            if (!o.candidates[i].support.grown && o.candidates[i].support.height <= low + 1e-6) as_low.push_back(i);
        judge(as_low, PoseQuestion::tree);
    } else {
        judge(rest, PoseQuestion::tree);
    }

    size_t best = 0;
    while (!o.candidates[best].support.grown) ++best;  // the flat ones are grown; without an empty tree, all are
    std::string why = "overhang area";
    for (size_t i = best + 1; i < n_eval; ++i) {
        const auto &a = o.candidates[i].support, &b = o.candidates[best].support;
        if (!a.grown) continue;
        double tol = 0.01 * std::max(a.volume, b.volume);
        if (a.volume < b.volume - tol) best = i, why = "support volume";
        else if (std::abs(a.volume - b.volume) <= tol) {
            if (a.model_contacts < b.model_contacts) best = i, why = "model contacts";
            else if (a.model_contacts == b.model_contacts && a.height < b.height - 1e-6) best = i, why = "height";
        }
    }
    if (best != 0 && why == "overhang area") why = "support volume";
    o.chosen = best;
    o.rotation = o.candidates[best].rotation;
    o.decided_by = why;
    return o;
}

}  // namespace cs

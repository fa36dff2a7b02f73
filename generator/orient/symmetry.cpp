#include "orient/symmetry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_set>
#include <vector>

#include "core/xy_grid.hpp"
#include "query/model_query.hpp"

namespace cs {
namespace {

// The one vertex within `tolerance` of p, or -1 (none, or more than one). `grid` files the vertices
// by their tolerance-sized cell seen from above: p's match lies in its cell or a neighbour.
std::int64_t vertex_at(const XyGrid<std::uint32_t>& grid, const std::vector<Vec3>& vertices, const Vec3& p, double tolerance) {
    std::int64_t found = -1;
    bool ambiguous = false;
    grid.visit_near(p, 1, [&](std::uint32_t j) {
        const Vec3 d = vertices[j] - p;
        if (dot(d, d) > tolerance * tolerance) return false;
        ambiguous = found >= 0;
        found = j;
        return ambiguous;
    });
    return ambiguous ? -1 : found;
}

// A face as its corners in increasing order, whatever the winding.
Triangle sorted_corners(Triangle t) {
    std::sort(t.begin(), t.end());
    return t;
}

struct CornersHash {
    std::size_t operator()(const Triangle& t) const {
        return static_cast<std::size_t>((std::uint64_t(t[0]) * 0x9E3779B97F4A7C15ULL) ^
                                        (std::uint64_t(t[1]) * 0xC2B2AE3D27D4EB4FULL) ^ (std::uint64_t(t[2]) * 0x165667B19E3779F9ULL));
    }
};

}  // namespace

Rotation compose(const Rotation& a, const Rotation& b) {
    Rotation r;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) r.m[i][j] = a.m[i][0] * b.m[0][j] + a.m[i][1] * b.m[1][j] + a.m[i][2] * b.m[2][j];
    return r;
}

Rotation transposed(const Rotation& r) {
    Rotation t;
    for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) t.m[i][j] = r.m[j][i];
    return t;
}

Rotation turn_about_z(int degrees) {
    const int d = ((degrees % 360) + 360) % 360;
    double c, s;
    switch (d) {  // exact where it can be: a cube's poses then differ by signed permutations only
        case 0: c = 1, s = 0; break;
        case 90: c = 0, s = 1; break;
        case 180: c = -1, s = 0; break;
        case 270: c = 0, s = -1; break;
        default: c = std::cos(deg_to_rad(d)), s = std::sin(deg_to_rad(d));
    }
    Rotation r;
    r.m[0][0] = c, r.m[0][1] = -s, r.m[1][0] = s, r.m[1][1] = c;
    return r;
}

namespace {

Vec3 surface_centroid(const Mesh& mesh) {
    Vec3 sum{0, 0, 0};
    double area = 0;
    for (const auto& f : mesh.faces) {
        const double a = norm(face_normal_unnormalized(mesh, f));
        sum = sum + (mesh.vertices[f[0]] + mesh.vertices[f[1]] + mesh.vertices[f[2]]) * (a / 3);
        area += a;
    }
    return area > 0 ? sum / area : sum;
}

}  // namespace

struct SurfaceSymmetry::Index {
    Index(const Mesh& m, double tol) : mesh(m), surface(m), centroid(surface_centroid(m)), tolerance(tol), grid(tol) {
        for (std::uint32_t i = 0; i < m.vertices.size(); ++i) grid.insert(m.vertices[i], i);
        faces.reserve(m.faces.size());
        for (const auto& f : m.faces) faces.insert(sorted_corners(f));
    }
    const Mesh& mesh;
    const ModelQuery surface;
    const Vec3 centroid;
    const double tolerance;
    // Most turned vertices land on a vertex, most turned faces on a face (a symmetric part is
    // mostly triangulated symmetrically): those are on the surface without asking `surface`.
    XyGrid<std::uint32_t> grid;
    std::unordered_set<Triangle, CornersHash> faces;
};

SurfaceSymmetry::SurfaceSymmetry(const Mesh& mesh, double tolerance) : index_(std::make_unique<const Index>(mesh, tolerance)) {}

SurfaceSymmetry::~SurfaceSymmetry() = default;

bool SurfaceSymmetry::maps_onto_itself(const Rotation& q) const {
    const Index& x = *index_;
    const Mesh& mesh = x.mesh;
    if (mesh.faces.empty() || !(x.tolerance > 0)) return false;
    const double tol2 = x.tolerance * x.tolerance;
    auto turned = [&](const Vec3& p) { return q.apply(p - x.centroid) + x.centroid; };
    std::vector<std::int64_t> lands_on(mesh.vertices.size());
    // The vertices first: on a part without the symmetry the first few fail.
    for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
        const Vec3 p = turned(mesh.vertices[i]);
        lands_on[i] = vertex_at(x.grid, mesh.vertices, p, x.tolerance);
        if (lands_on[i] < 0 && x.surface.squared_distance(p) > tol2) return false;
    }
    for (const auto& f : mesh.faces) {
        const std::int64_t a = lands_on[f[0]], b = lands_on[f[1]], c = lands_on[f[2]];
        // A face whose corners land on a face's corners is that face.
        if (a >= 0 && b >= 0 && c >= 0 &&
            x.faces.contains(sorted_corners({static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(c)})))
            continue;
        if (x.surface.squared_distance(turned((mesh.vertices[f[0]] + mesh.vertices[f[1]] + mesh.vertices[f[2]]) / 3)) > tol2)
            return false;
    }
    return true;
}

}  // namespace cs

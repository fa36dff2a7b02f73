#include "mesh/repair.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <cstring>
#include <numeric>
#include <utility>

#include "core/errors.hpp"
#include "mesh/fill_holes.hpp"
#include "mesh/unfold_caps.hpp"
#include "mesh/weld.hpp"

namespace cs {
namespace {

struct DisjointSets {
    std::vector<int> parent;
    explicit DisjointSets(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
    int find(int x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    }
    void unite(int a, int b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);  // deterministic roots
    }
};

// Does a ray from p along +x (slightly tilted to avoid edges) cross the faces `fs` an odd number of times?
bool inside_by_parity(const Mesh& m, const std::vector<size_t>& fs, const Vec3& p) {
    const Vec3 dir = normalized(Vec3{1, 0.000123457, 0.000345679});
    int hits = 0;
    for (size_t fi : fs) {
        const auto& f = m.faces[fi];
        const Vec3 &a = m.vertices[f[0]], &b = m.vertices[f[1]], &c = m.vertices[f[2]];
        Vec3 e1 = b - a, e2 = c - a, h = cross(dir, e2);
        double det = dot(e1, h);
        if (std::abs(det) < 1e-300) continue;
        Vec3 s = p - a;
        double u = dot(s, h) / det;
        if (u < 0 || u > 1) continue;
        Vec3 q = cross(s, e1);
        double v = dot(dir, q) / det;
        if (v < 0 || u + v > 1) continue;
        if (dot(e2, q) / det > 0) ++hits;
    }
    return hits % 2 == 1;
}

}  // namespace

std::vector<int> face_components(const Mesh& m, int& count) {
    DisjointSets ds(m.vertices.size());
    for (const auto& f : m.faces) ds.unite(f[0], f[1]), ds.unite(f[0], f[2]);
    // Components numbered in order of their first face; a root is a vertex, so its number is kept
    // by vertex (no hashing of every face's root).
    std::vector<int> id_of_root(m.vertices.size(), -1);
    std::vector<int> comp(m.faces.size());
    count = 0;
    for (size_t i = 0; i < m.faces.size(); ++i) {
        int& id = id_of_root[ds.find(m.faces[i][0])];
        if (id < 0) id = count++;
        comp[i] = id;
    }
    return comp;
}

namespace {

constexpr std::uint32_t kNone = UINT32_MAX;

// 1. Weld identical vertices (mesh/weld.hpp): `remap` takes each input vertex to its welded one.
Mesh weld_identical(const Mesh& raw, std::vector<std::uint32_t>& remap, RepairReport& r) {
    Welded w = weld_vertices(raw);
    Mesh m;
    m.vertices = std::move(w.mesh.vertices);
    remap = std::move(w.remap);
    // Count only vertices that were genuinely shared by separate triangle corners in indexed input.
    std::vector<char> used(raw.vertices.size(), 0);
    for (const auto& f : raw.faces) used[f[0]] = used[f[1]] = used[f[2]] = 1;
    const auto used_raw = static_cast<size_t>(std::count(used.begin(), used.end(), 1));
    r.welded_vertices = used_raw > m.vertices.size() ? used_raw - m.vertices.size() : 0;
    return m;
}

// 2. Drop degenerate and duplicate triangles (the first of identical corner sets stays).
//    Duplicates are found by sorting, not hashing: on multi-million-triangle scans a hash map
//    of buckets costs several times the memory and time.
void keep_proper_triangles(const Mesh& raw, const std::vector<std::uint32_t>& remap, double extent, Mesh& m,
                           RepairReport& r) {
    const double min_area2 = std::pow(extent * 1e-9, 4);
    std::vector<Triangle> kept;
    kept.reserve(raw.faces.size());
    for (const auto& f0 : raw.faces) {
        Triangle f{remap[f0[0]], remap[f0[1]], remap[f0[2]]};
        if (f[0] == f[1] || f[1] == f[2] || f[0] == f[2]) {
            ++r.degenerate_removed;
            continue;
        }
        Vec3 n = face_normal_unnormalized(m, f);
        if (dot(n, n) <= min_area2) {
            ++r.degenerate_removed;
            continue;
        }
        kept.push_back(f);
    }
    // Each triangle's corners in ascending order, with its index: sorted, equal corners are
    // neighbours and the first of them (the lowest index) is the one kept.
    // Grouped by their smallest corner in one counting pass, then each group sorted: the order of
    // one sort of them all (by corners, then index), with a few triangles per comparison sort.
    std::vector<std::uint32_t> end(m.vertices.size() + 1, 0);
    for (const Triangle& f : kept) ++end[std::min({f[0], f[1], f[2]}) + 1];
    for (size_t v = 1; v < end.size(); ++v) end[v] += end[v - 1];
    std::vector<std::pair<Triangle, std::uint32_t>> by_corners(kept.size());
    for (std::uint32_t i = 0; i < kept.size(); ++i) {
        Triangle c = kept[i];
        std::sort(c.begin(), c.end());
        by_corners[end[c[0]]++] = {c, i};
    }
    for (size_t v = 0, begin = 0; v + 1 < end.size(); begin = end[v++])
        if (end[v] - begin > 1) std::sort(by_corners.begin() + begin, by_corners.begin() + end[v]);
    std::vector<char> duplicate(kept.size(), 0);
    for (size_t i = 1; i < by_corners.size(); ++i)
        if (by_corners[i].first == by_corners[i - 1].first) duplicate[by_corners[i].second] = 1;
    m.faces.reserve(kept.size());
    for (size_t i = 0; i < kept.size(); ++i) {
        if (duplicate[i]) ++r.duplicates_removed;
        else m.faces.push_back(kept[i]);
    }
}

// 3. Edge use: holes and non-manifold edges. The face-edges sorted by edge give each edge's
//    faces as one run; a manifold edge (exactly two faces) links the faces across it. Returns,
//    per face-edge (3 * face + k), the face across it, or kNone.
std::vector<std::uint32_t> faces_across(const Mesh& m, RepairReport& r) {
    const size_t nf = m.faces.size();
    std::vector<std::uint32_t> across(3 * nf, kNone);
    std::vector<std::pair<std::uint64_t, std::uint32_t>> uses(3 * nf);  // (edge, face-edge)
    for (std::uint32_t fi = 0; fi < nf; ++fi)
        for (int k = 0; k < 3; ++k) uses[3 * fi + k] = {edge_key(m.faces[fi][k], m.faces[fi][(k + 1) % 3]), 3 * fi + k};
    sort_edge_uses(uses);
    for (size_t i = 0, j; i < uses.size(); i = j) {
        for (j = i + 1; j < uses.size() && uses[j].first == uses[i].first;) ++j;
        if (j - i == 1) ++r.boundary_edges;
        if (j - i > 2) ++r.nonmanifold_edges;
        if (j - i == 2) {
            across[uses[i].second] = uses[i + 1].second / 3;
            across[uses[i + 1].second] = uses[i].second / 3;
        }
    }
    return across;
}

// Edge-connected patches of consistently oriented faces.
struct Patches {
    int count = 0;
    std::vector<int> of_face;  // patch of each face
    std::vector<char> flip;    // faces turned so far (for the report)
};

// 4. Orient each edge-connected patch consistently (breadth first across manifold edges).
Patches orient_patches(Mesh& m, const std::vector<std::uint32_t>& across) {
    const size_t nf = m.faces.size();
    Patches p{0, std::vector<int>(nf, -1), std::vector<char>(nf, 0)};
    auto directed = [&](std::uint32_t fi, std::uint32_t a, std::uint32_t b) {
        // +1 if face fi (with its current flip) traverses a->b, -1 if b->a.
        const auto& f = m.faces[fi];
        for (int k = 0; k < 3; ++k)
            if (f[k] == a && f[(k + 1) % 3] == b) return p.flip[fi] ? -1 : 1;
        return p.flip[fi] ? 1 : -1;
    };
    std::vector<std::uint32_t> queue;
    for (std::uint32_t seed = 0; seed < nf; ++seed) {
        if (p.of_face[seed] >= 0) continue;
        queue.assign(1, seed);
        p.of_face[seed] = p.count;
        for (size_t qi = 0; qi < queue.size(); ++qi) {
            std::uint32_t fi = queue[qi];
            for (int k = 0; k < 3; ++k) {
                std::uint32_t g = across[3 * fi + k];
                if (g == kNone || p.of_face[g] >= 0) continue;
                std::uint32_t a = m.faces[fi][k], b = m.faces[fi][(k + 1) % 3];
                p.of_face[g] = p.count;
                if (directed(fi, a, b) == directed(g, a, b)) p.flip[g] = !p.flip[g];
                queue.push_back(g);
            }
        }
        ++p.count;
    }
    for (size_t i = 0; i < nf; ++i)
        if (p.flip[i]) std::swap(m.faces[i][1], m.faces[i][2]);
    return p;
}

// Nesting: q contains p when every probe of p (corners spread over its faces) lies inside q.
// A patch only partly inside another (intersecting shells) is not nested in it. Fills each
// patch's innermost container (-1: none) and how many contain it.
void nesting(const Mesh& m, const std::vector<std::vector<size_t>>& patch_faces, const std::vector<double>& volume,
             std::vector<int>& parent, std::vector<int>& depth) {
    const int patches = static_cast<int>(patch_faces.size());
    parent.assign(patches, -1), depth.assign(patches, 0);
    if (patches <= 1 || patches > 64) return;
    std::vector<std::vector<char>> contains(patches, std::vector<char>(patches, 0));
    for (int p = 0; p < patches; ++p) {
        std::vector<Vec3> probes;
        size_t n = patch_faces[p].size(), step = std::max<size_t>(1, n / 8);
        for (size_t k = 0; k < n && probes.size() < 8; k += step) probes.push_back(m.vertices[m.faces[patch_faces[p][k]][0]]);
        for (int q = 0; q < patches; ++q) {
            if (q == p || std::abs(volume[q]) == 0) continue;
            contains[q][p] = std::all_of(probes.begin(), probes.end(),
                                         [&](const Vec3& x) { return inside_by_parity(m, patch_faces[q], x); });
            depth[p] += contains[q][p];
        }
    }
    for (int p = 0; p < patches; ++p)
        for (int q = 0; q < patches; ++q)
            if (contains[q][p] && (parent[p] < 0 || depth[q] > depth[parent[p]])) parent[p] = q;
}

// Volume of a set of faces about `centre`.
double volume_about(const Mesh& m, const std::vector<size_t>& faces, const Vec3& centre) {
    double v = 0;
    for (size_t fi : faces) {
        const auto& f = m.faces[fi];
        v += dot(m.vertices[f[0]] - centre, cross(m.vertices[f[1]] - centre, m.vertices[f[2]] - centre)) / 6.0;
    }
    return v;
}

// 5. Turn each patch outward. Volumes are taken about the bounding box centre so an open
//    patch's volume does not depend on where the origin is. Solids nested in a solid are
//    dropped (marked in `dropped`), cavities kept.
std::vector<char> turn_patches_outward(Mesh& m, Patches& pt, const Vec3& centre, RepairReport& r) {
    std::vector<std::vector<size_t>> patch_faces(pt.count);
    for (size_t i = 0; i < m.faces.size(); ++i) patch_faces[pt.of_face[i]].push_back(i);
    std::vector<double> volume(pt.count, 0);
    for (int p = 0; p < pt.count; ++p) volume[p] = volume_about(m, patch_faces[p], centre);
    std::vector<int> parent, depth;
    nesting(m, patch_faces, volume, parent, depth);
    std::vector<int> order(pt.count);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return depth[a] < depth[b]; });
    std::vector<char> dropped(m.faces.size(), 0), patch_flipped(pt.count, 0), patch_dropped(pt.count, 0);
    auto turn = [&](int p) {
        for (size_t fi : patch_faces[p]) {
            std::swap(m.faces[fi][1], m.faces[fi][2]);
            pt.flip[fi] = !pt.flip[fi];
        }
        volume[p] = -volume[p];
        patch_flipped[p] = 1;
    };
    for (int p : order) {
        int q = parent[p];
        if (q < 0 || patch_dropped[q]) {
            if (volume[p] < 0) turn(p);  // free-standing and facing in: turn it out
            continue;
        }
        // Nested: a file turned inside out as a whole is turned back as a whole, so a shell
        // follows its container; then facing like the container it is a solid within a solid
        // (nothing to print, and its faces are no surfaces of the print: dropped), facing
        // against it a cavity (kept).
        if (patch_flipped[q]) turn(p);
        if ((volume[p] > 0) == (volume[q] > 0)) {
            if (volume[q] > 0) {
                for (size_t fi : patch_faces[p]) dropped[fi] = 1;
                patch_dropped[p] = 1;
                ++r.inner_shells_removed;
            } else {
                turn(p);  // a cavity within a cavity: an island, facing out
            }
        }
    }
    return dropped;
}

// The mesh without unused vertices, so outputs carry no strays.
Mesh without_unused_vertices(const Mesh& m) {
    std::vector<std::uint32_t> keep(m.vertices.size(), kNone);
    Mesh out;
    for (const auto& f : m.faces) {
        Triangle g;
        for (int k = 0; k < 3; ++k) {
            if (keep[f[k]] == kNone) {
                keep[f[k]] = static_cast<std::uint32_t>(out.vertices.size());
                out.vertices.push_back(m.vertices[f[k]]);
            }
            g[k] = keep[f[k]];
        }
        out.faces.push_back(g);
    }
    return out;
}

void add_warnings(const std::string& name, RepairReport& r) {
    auto warn = [&](size_t n, const std::string& what) {
        if (n) r.warnings.push_back(name + ": " + std::to_string(n) + " " + what);
    };
    warn(r.degenerate_removed, "degenerate triangles removed");
    warn(r.duplicates_removed, "duplicate triangles removed");
    warn(r.flipped, "triangles flipped to face outward");
    warn(r.inner_shells_removed, "shells lying wholly inside another solid removed (they are not surfaces of the print)");
    if (r.holes_filled)
        r.warnings.push_back(name + ": " + std::to_string(r.holes_filled) + " hole" + (r.holes_filled > 1 ? "s" : "") +
                             " closed with a patch (" + std::to_string(r.boundary_edges - r.boundary_edges_left) +
                             " open edges); the slicers close them the same way. Look over the patched surfaces in "
                             "the .model.stl");
    warn(r.caps_unfolded,
         "sliver triangles folded back over their neighbour flipped flat (a scanner's fold: it would read as a "
         "hanging edge needing support)");
    warn(r.boundary_edges_left,
         "open (boundary) edges left: holes that could not be closed; overhangs near them are still supported");
    warn(r.nonmanifold_edges, "non-manifold edges (shared by more than two triangles); carried on");
}

}  // namespace

Mesh repair_mesh(const Mesh& raw, const std::string& name, RepairReport& r) {
    r = {};
    r.input_triangles = raw.faces.size();
    const Box3 box = bounding_box(raw);
    const double extent = std::max({box.size().x, box.size().y, box.size().z});

    std::vector<std::uint32_t> remap;
    Mesh m = weld_identical(raw, remap, r);
    keep_proper_triangles(raw, remap, extent, m, r);
    if (m.faces.empty())
        throw InputError(name + ": every triangle is degenerate (zero area); nothing to print. Re-export the model.");
    Patches patches = orient_patches(m, faces_across(m, r));
    const Vec3 centre = box.center();
    std::vector<char> dropped = turn_patches_outward(m, patches, centre, r);
    r.flipped = 0;
    for (size_t i = 0; i < m.faces.size(); ++i) r.flipped += patches.flip[i] && !dropped[i];
    if (r.inner_shells_removed) {
        std::vector<Triangle> kept;
        for (size_t i = 0; i < m.faces.size(); ++i)
            if (!dropped[i]) kept.push_back(m.faces[i]);
        m.faces = std::move(kept);
    }
    if (r.boundary_edges) {
        // A slicer closes every open outline and prints the inside; closing the holes makes our
        // generator see the same solid (it grew struts inside stanford_bunny's open base).
        HoleFilling h = fill_holes(m);
        r.holes_filled = h.filled;
        r.boundary_edges_left = h.edges_left_open;
    }
    r.caps_unfolded = unfold_caps(m);

    int shells = 0;
    face_components(m, shells);
    r.shells = static_cast<size_t>(shells);
    std::vector<size_t> all(m.faces.size());
    std::iota(all.begin(), all.end(), size_t{0});
    if (!(std::abs(volume_about(m, all, centre)) > std::pow(extent, 3) * 1e-9))
        throw InputError(name + ": the mesh encloses no volume (it is flat or a single sheet); there is no solid to "
                                "support. Export the solid body, not a surface.");
    add_warnings(name, r);
    return without_unused_vertices(m);
}

void rotation_from_euler_deg(double rx, double ry, double rz, double out[3][3]) {
    double cx = std::cos(deg_to_rad(rx)), sx = std::sin(deg_to_rad(rx));
    double cy = std::cos(deg_to_rad(ry)), sy = std::sin(deg_to_rad(ry));
    double cz = std::cos(deg_to_rad(rz)), sz = std::sin(deg_to_rad(rz));
    // R = Rz * Ry * Rx
    double R[3][3] = {{cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx},
                      {sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx},
                      {-sy, cy * sx, cy * cx}};
    std::memcpy(out, R, sizeof(R));
}

Vec3 euler_deg_from_rotation(const double r[3][3]) {
    auto deg = [](double rad) { return rad * 180.0 / std::numbers::pi; };
    const double sy = std::clamp(-r[2][0], -1.0, 1.0);
    if (std::abs(sy) > 1 - 1e-9)  // y at +-90: x and z turn about the same axis; x taken as 0
        return {0, deg(std::asin(sy)), deg(std::atan2(-r[0][1], r[1][1]))};
    return {deg(std::atan2(r[2][1], r[2][2])), deg(std::asin(sy)), deg(std::atan2(r[1][0], r[0][0]))};
}

Mesh place_on_bed(const Mesh& m, double scale, const double rotation[3][3], Placement& pl) {
    Mesh out = m;
    pl.scale = scale;
    std::memcpy(pl.rotation, rotation, sizeof(pl.rotation));
    for (auto& v : out.vertices) {
        Vec3 s = v * scale;
        v = {rotation[0][0] * s.x + rotation[0][1] * s.y + rotation[0][2] * s.z,
             rotation[1][0] * s.x + rotation[1][1] * s.y + rotation[1][2] * s.z,
             rotation[2][0] * s.x + rotation[2][1] * s.y + rotation[2][2] * s.z};
    }
    Box3 b = bounding_box(out);
    pl.translation = {-(b.min.x + b.max.x) / 2, -(b.min.y + b.max.y) / 2, -b.min.z};
    for (auto& v : out.vertices) v += pl.translation;
    if (scale < 0)  // a mirror turns the mesh inside out
        for (auto& f : out.faces) std::swap(f[1], f[2]);
    return out;
}

}  // namespace cs

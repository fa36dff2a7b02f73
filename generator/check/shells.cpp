// Support solids from a support mesh: weld, split into closed shells, judge closedness.
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>
#include <unordered_map>

#include "check/check.hpp"
#include "mesh/weld.hpp"

namespace cs {
namespace {

// How often each directed edge (a -> b) is a side of a face, in its face's winding.
std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed_edges(const Mesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& f : m.faces)
        for (int k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
    return directed;
}

}  // namespace

bool is_closed_and_consistent(const Mesh& m) {
    const auto directed = directed_edges(m);
    for (const auto& [e, n] : directed) {
        if (n != 1) return false;
        auto it = directed.find({e.second, e.first});
        if (it == directed.end() || it->second != 1) return false;
    }
    return true;
}

bool is_watertight(const Mesh& m) {
    const auto directed = directed_edges(m);
    for (const auto& [e, n] : directed) {
        auto it = directed.find({e.second, e.first});
        if (it == directed.end() || it->second != n) return false;
    }
    return true;
}

namespace {

using Edge = std::pair<std::uint32_t, std::uint32_t>;  // vertex indices, smaller first

// Faces joined into solids: a union-find over face indices.
class FaceSets {
public:
    explicit FaceSets(size_t n) : parent_(n) {
        for (size_t i = 0; i < n; ++i) parent_[i] = static_cast<int>(i);
    }
    int find(int x) {
        while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
        return x;
    }
    void unite(int a, int b) {
        a = find(a), b = find(b);
        if (a != b) parent_[std::max(a, b)] = std::min(a, b);
    }

private:
    std::vector<int> parent_;
};

// A face about an edge: its angle around the edge, and whether it runs a -> b.
struct Around {
    double angle;
    bool forward;
    std::uint32_t face;
};

// The faces on edge (a, b), sorted by their angle about it, grouped where they lie on each other.
std::vector<std::vector<const Around*>> faces_around(const Mesh& m, const Edge& edge, const std::vector<std::uint32_t>& fs,
                                                     std::vector<Around>& around) {
    const Vec3 &a = m.vertices[edge.first], &b = m.vertices[edge.second];
    const Vec3 e = normalized(b - a);
    Vec3 ref{};
    for (auto fi : fs) {
        const auto& f = m.faces[fi];
        int k = 0;
        while (Edge(std::minmax(f[k], f[(k + 1) % 3])) != edge) ++k;
        const bool forward = f[k] == edge.first;
        Vec3 c = m.vertices[f[(k + 2) % 3]] - a;
        Vec3 v = c - e * dot(c, e);  // from the edge towards the face's third corner
        if (norm(v) == 0) continue;
        v = normalized(v);
        if (around.empty()) ref = v;
        around.push_back({std::atan2(dot(cross(ref, v), e), dot(ref, v)), forward, fi});
    }
    std::sort(around.begin(), around.end(), [](const Around& x, const Around& y) {
        return x.angle != y.angle ? x.angle < y.angle : x.face < y.face;
    });
    std::vector<std::vector<const Around*>> groups;
    for (size_t i = 0; i < around.size(); ++i) {
        if (i == 0 || around[i].angle - around[i - 1].angle > 1e-9) groups.emplace_back();
        groups.back().push_back(&around[i]);
    }
    if (groups.size() > 1 && around.back().angle - around.front().angle > 2 * std::numbers::pi - 1e-9) {
        // The first and last groups are the same angle across +-pi.
        for (auto* x : groups.back()) groups.front().push_back(x);
        groups.pop_back();
    }
    return groups;
}

// Where solids touch, an edge has more than two faces (two struts ending at one bed point, bodies
// meeting end to end); each face joins its neighbour on its solid's inner side. Faces at one angle
// lie on each other. A face running a -> b has its outside towards increasing angle about the
// edge, so its solid lies at decreasing angle: its partner runs b -> a in the nearest group of
// faces below its angle. Within tied groups, faces pair in order of their numbers (the k-th with
// the k-th): a solid's faces come together in the file.
void join_across_shared_edge(const Mesh& m, const Edge& edge, const std::vector<std::uint32_t>& fs, FaceSets& sets) {
    std::vector<Around> around;
    const auto groups = faces_around(m, edge, fs, around);
    const size_t ng = groups.size();
    for (size_t gi = 0; gi < ng; ++gi) {
        std::vector<std::uint32_t> fwd;
        for (const Around* f : groups[gi])
            if (f->forward) fwd.push_back(f->face);
        if (fwd.empty()) continue;
        for (size_t step = 1; step <= ng; ++step) {
            std::vector<std::uint32_t> back;
            for (const Around* b : groups[(gi + ng - step % ng) % ng])
                if (!b->forward) back.push_back(b->face);
            if (back.empty()) continue;
            for (size_t k = 0; k < std::min(fwd.size(), back.size()); ++k)
                sets.unite(static_cast<int>(fwd[k]), static_cast<int>(back[k]));
            break;
        }
    }
}

// One mesh per set of faces, numbered in the order their first face appears.
std::vector<Mesh> meshes_of(const Mesh& m, FaceSets& sets) {
    std::vector<int> comp(m.faces.size(), -1);
    std::map<int, int> root_id;
    int count = 0;
    for (size_t fi = 0; fi < m.faces.size(); ++fi) {
        auto [it, fresh] = root_id.emplace(sets.find(static_cast<int>(fi)), count);
        if (fresh) ++count;
        comp[fi] = it->second;
    }
    std::vector<Mesh> shells(count);
    std::vector<std::unordered_map<std::uint32_t, std::uint32_t>> local(count);
    for (size_t fi = 0; fi < m.faces.size(); ++fi) {
        auto& s = shells[comp[fi]];
        auto& l = local[comp[fi]];
        Triangle t;
        for (int k = 0; k < 3; ++k) {
            auto [it, fresh] = l.emplace(m.faces[fi][k], static_cast<std::uint32_t>(s.vertices.size()));
            if (fresh) s.vertices.push_back(m.vertices[m.faces[fi][k]]);
            t[k] = it->second;
        }
        s.faces.push_back(t);
    }
    return shells;
}

}  // namespace

std::vector<Mesh> split_shells(const Mesh& raw) {
    Mesh m = weld_vertices(raw).mesh;
    // Faces join across their edges: an edge that exactly two faces share joins them; an edge
    // with more (solids touching) joins each face to its own solid's next face.
    std::map<Edge, std::vector<std::uint32_t>> edge_faces;
    for (std::uint32_t fi = 0; fi < m.faces.size(); ++fi)
        for (int k = 0; k < 3; ++k) edge_faces[std::minmax(m.faces[fi][k], m.faces[fi][(k + 1) % 3])].push_back(fi);
    FaceSets sets(m.faces.size());
    for (const auto& [edge, fs] : edge_faces) {
        if (fs.size() == 2) sets.unite(fs[0], fs[1]);
        if (fs.size() > 2) join_across_shared_edge(m, edge, fs, sets);
    }
    return meshes_of(m, sets);
}

}  // namespace cs

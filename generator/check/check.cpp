#include "check/check.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <unordered_map>

#include "mesh/repair.hpp"
#include "overhang/overhang.hpp"
#include "query/model_query.hpp"
#include "tree/tree.hpp"

namespace cs {
namespace {

struct Shell {
    Mesh mesh;
    Vec3 bottom, top;  // centroids of the lowest and highest vertex rings
    double bottom_width = 0, top_width = 0;
    double zmin = 0, zmax = 0;
};

void ring(const Mesh& m, bool highest, Vec3& centre, double& width, double& z) {
    z = highest ? -INFINITY : INFINITY;
    for (const auto& v : m.vertices) z = highest ? std::max(z, v.z) : std::min(z, v.z);
    const double tol = 1e-5;
    Vec3 sum;
    int n = 0;
    double x0 = INFINITY, x1 = -INFINITY;
    for (const auto& v : m.vertices)
        if (std::abs(v.z - z) <= tol) sum += v, ++n, x0 = std::min(x0, v.x), x1 = std::max(x1, v.x);
    centre = sum / std::max(n, 1);
    width = x1 - x0;
}

// Where does a shell's axis pass at height z, and how wide is it there?
bool contains(const Shell& s, const Vec3& p, double tol) {
    if (p.z < s.zmin - tol || p.z > s.zmax + tol) return false;
    double t = s.zmax > s.zmin ? std::clamp((p.z - s.zmin) / (s.zmax - s.zmin), 0.0, 1.0) : 0.0;
    Vec3 c = s.bottom + (s.top - s.bottom) * t;
    double half = 0.5 * (s.bottom_width + (s.top_width - s.bottom_width) * t) + tol;
    return std::abs(p.x - c.x) <= half && std::abs(p.y - c.y) <= half;
}

struct PointGrid {
    double cell;
    std::unordered_map<std::uint64_t, std::vector<Vec3>> cells;
    static std::uint64_t pack(long i, long j) { return (std::uint64_t(i) << 32) ^ std::uint64_t(j & 0xffffffff); }
    long idx(double v) const { return static_cast<long>(std::floor(v / cell)); }
    void add(const Vec3& p) { cells[pack(idx(p.x), idx(p.y))].push_back(p); }
    template <typename F>
    bool any_near(const Vec3& p, double r, F pred) const {
        long r_cells = static_cast<long>(std::ceil(r / cell));
        for (long i = idx(p.x) - r_cells; i <= idx(p.x) + r_cells; ++i)
            for (long j = idx(p.y) - r_cells; j <= idx(p.y) + r_cells; ++j) {
                auto it = cells.find(pack(i, j));
                if (it == cells.end()) continue;
                for (const auto& q : it->second)
                    if (pred(q)) return true;
            }
        return false;
    }
};

}  // namespace

bool is_closed_and_consistent(const Mesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& f : m.faces)
        for (int k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
    for (const auto& [e, n] : directed) {
        if (n != 1) return false;
        auto it = directed.find({e.second, e.first});
        if (it == directed.end() || it->second != 1) return false;
    }
    return true;
}

bool is_watertight(const Mesh& m) {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto& f : m.faces)
        for (int k = 0; k < 3; ++k) ++directed[{f[k], f[(k + 1) % 3]}];
    for (const auto& [e, n] : directed) {
        auto it = directed.find({e.second, e.first});
        if (it == directed.end() || it->second != n) return false;
    }
    return true;
}

Mesh weld(const Mesh& raw) {
    std::map<std::tuple<double, double, double>, std::uint32_t> index;
    Mesh m;
    std::vector<std::uint32_t> remap(raw.vertices.size());
    for (size_t i = 0; i < raw.vertices.size(); ++i) {
        auto key = std::make_tuple(raw.vertices[i].x, raw.vertices[i].y, raw.vertices[i].z);
        auto [it, fresh] = index.emplace(key, static_cast<std::uint32_t>(m.vertices.size()));
        if (fresh) m.vertices.push_back(raw.vertices[i]);
        remap[i] = it->second;
    }
    for (const auto& f : raw.faces) m.faces.push_back({remap[f[0]], remap[f[1]], remap[f[2]]});
    return m;
}

std::vector<Mesh> split_shells(const Mesh& raw) {
    Mesh m = weld(raw);
    // Faces join across their edges. An edge that exactly two faces share joins them. Where
    // solids touch (two struts ending at one bed point, bodies meeting end to end) an edge has
    // more faces; there each face joins its neighbour on its solid's inner side: turning about the
    // edge from a face into the material behind it, the first face met bounds the same solid.
    std::map<std::pair<std::uint32_t, std::uint32_t>, std::vector<std::uint32_t>> edge_faces;
    for (std::uint32_t fi = 0; fi < m.faces.size(); ++fi)
        for (int k = 0; k < 3; ++k) edge_faces[std::minmax(m.faces[fi][k], m.faces[fi][(k + 1) % 3])].push_back(fi);
    std::vector<int> parent(m.faces.size());
    for (size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
    auto find = [&](int x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    auto unite = [&](int a, int b) {
        a = find(a), b = find(b);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);
    };
    for (const auto& [edge, fs] : edge_faces) {
        if (fs.size() == 2) {
            unite(fs[0], fs[1]);
            continue;
        }
        if (fs.size() < 2) continue;
        const Vec3 &a = m.vertices[edge.first], &b = m.vertices[edge.second];
        const Vec3 e = normalized(b - a);
        struct Around {
            double angle;
            bool forward;  // the face runs a -> b
            std::uint32_t face;
        };
        std::vector<Around> around;
        Vec3 ref{};
        for (auto fi : fs) {
            const auto& f = m.faces[fi];
            int k = 0;
            while (std::pair<std::uint32_t, std::uint32_t>(std::minmax(f[k], f[(k + 1) % 3])) != edge) ++k;
            bool forward = f[k] == edge.first;
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
        // Faces at one angle lie on each other (two struts ending on one bed point share their
        // bottom ring and sides). A face running a -> b has its outside towards increasing angle
        // about e, so its solid lies at decreasing angle: its partner runs b -> a in the nearest
        // group of faces below its angle. Within tied groups, faces pair in order of their numbers:
        // a solid's faces come together in the file.
        std::vector<std::vector<const Around*>> groups;
        for (size_t i = 0; i < around.size(); ++i) {
            if (i == 0 || around[i].angle - around[i - 1].angle > 1e-9) groups.emplace_back();
            groups.back().push_back(&around[i]);
        }
        if (groups.size() > 1 && around.back().angle - around.front().angle > 2 * M_PI - 1e-9) {
            // The first and last groups are the same angle across +-pi.
            for (auto* x : groups.back()) groups.front().push_back(x);
            groups.pop_back();
        }
        // Each group's faces running a -> b pair with the faces running b -> a of the nearest
        // group below that has any, in order of face number (the k-th with the k-th).
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
                    unite(static_cast<int>(fwd[k]), static_cast<int>(back[k]));
                break;
            }
        }
    }
    std::vector<int> comp(m.faces.size(), -1);
    std::map<int, int> root_id;
    int count = 0;
    for (size_t fi = 0; fi < m.faces.size(); ++fi) {
        auto [it, fresh] = root_id.emplace(find(static_cast<int>(fi)), count);
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

// Does the solid's foot stand on the model, within `gap` below it? Its centre and four points of
// its footprint are asked: a tip on the very rim of a hole stands on the rim though the ray down
// from its centre falls into the hole (or grazes the rim's edge).
static bool rests_on_model(const ModelQuery& q, const Shell& s, double gap) {
    const double h = 0.45 * s.bottom_width;
    for (Vec3 d : {Vec3{0, 0, 0}, Vec3{h, 0, 0}, Vec3{-h, 0, 0}, Vec3{0, h, 0}, Vec3{0, -h, 0}}) {
        auto hit = q.first_hit(s.bottom + d + Vec3{0, 0, 1e-4}, {0, 0, -1});
        if (hit && hit->distance <= gap) return true;
    }
    return false;
}

CheckResult check_supports(const Mesh& model_in, const Mesh& supports, const Params& p, const CheckOptions& o) {
    CheckResult r;
    // Welded (neighbours, closedness) and cleaned exactly as the generator saw it.
    RepairReport ignored;
    const Mesh model = repair_mesh(model_in, "model", ignored);
    ModelQuery q(model);
    r.model_closed = is_watertight(model);
    const double reach = o.reach > 0 ? o.reach : p.sampling_distance;

    // Shells and their shape.
    std::vector<Shell> shells;
    for (auto& m : split_shells(supports)) {
        Shell s;
        s.mesh = std::move(m);
        ring(s.mesh, false, s.bottom, s.bottom_width, s.zmin);
        ring(s.mesh, true, s.top, s.top_width, s.zmax);
        shells.push_back(std::move(s));
    }
    r.bodies = shells.size();

    std::vector<Vec3> contacts;
    std::vector<char> is_tip(shells.size(), 0);
    for (size_t si = 0; si < shells.size(); ++si) {
        const Shell& s = shells[si];
        if (!is_closed_and_consistent(s.mesh)) {
            ++r.open_bodies;
            if (r.flagged.size() < 10) r.flagged.push_back({s.bottom, s.top});
        }
        else if (signed_volume(s.mesh) <= 0) ++r.inward_bodies;
        double angle = angle_from_vertical_deg(s.top, s.bottom);
        r.max_angle = std::max(r.max_angle, angle);
        if (angle > p.critical_angle + o.angle_tolerance) ++r.steep_bodies;
        double w = std::min(s.top_width, s.bottom_width);
        if (w > 0) r.worst_length_to_width = std::max(r.worst_length_to_width, distance(s.top, s.bottom) / w);
        // A contact: the centre of a solid's top with the model just above it (about one z gap).
        // (Nearest point rather than a ray up: a tip under the very rim of an overhang has the model
        // beside its centre, not above it.)
        Vec3 above = q.closest_point(s.top);
        auto up = q.first_hit(s.top, {0, 0, 1});
        if ((up && up->distance <= contact_tolerance(p)) ||
            (above.z >= s.top.z - 1e-3 && distance(above, s.top) <= contact_tolerance(p))) {
            contacts.push_back(s.top);
            is_tip[si] = 1;
        }
        // A tip standing on the model: its bottom is about a gap above the model.
        if (s.zmin > 0.05 && rests_on_model(q, s, contact_tolerance(p))) is_tip[si] = 1;
    }

    // Penetration: edges that cross the model surface, or shells lying wholly inside it.
    // Tips touch the model by design: only what lies beyond them is judged.
    if (r.model_closed) {
        for (size_t si = 0; si < shells.size(); ++si) {
            const Shell& s = shells[si];
            if (is_tip[si]) continue;
            double depth = 0;
            std::map<std::pair<std::uint32_t, std::uint32_t>, bool> seen;
            for (const auto& f : s.mesh.faces)
                for (int k = 0; k < 3; ++k) {
                    auto a = f[k], b = f[(k + 1) % 3];
                    if (!seen.emplace(std::minmax(a, b), true).second) continue;
                    const Vec3 &pa = s.mesh.vertices[a], &pb = s.mesh.vertices[b];
                    if (!q.segment_hits(pa, pb)) continue;
                    int steps = std::max(1, static_cast<int>(std::ceil(distance(pa, pb) / 0.1)));
                    for (int i = 0; i <= steps; ++i) {
                        Vec3 x = pa + (pb - pa) * (double(i) / steps);
                        if (q.inside(x)) depth = std::max(depth, std::sqrt(q.squared_distance(x)));
                    }
                }
            if (depth == 0 && q.inside(s.mesh.vertices[0])) depth = std::sqrt(q.squared_distance(s.mesh.vertices[0]));
            r.max_penetration = std::max(r.max_penetration, depth);
            if (depth > o.penetration_tolerance) {
                ++r.penetrating_bodies;
                if (r.flagged.size() < 10) r.flagged.push_back({s.bottom, s.top});
            }
        }
    }

    // Grounding, lowest shells first: each rests on the bed, the model, or a grounded shell.
    std::vector<size_t> order(shells.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return shells[a].zmin < shells[b].zmin; });
    std::vector<char> grounded(shells.size(), 0);
    double cell = 4.0;
    std::unordered_map<std::uint64_t, std::vector<size_t>> by_cell;
    auto pack = [](long i, long j) { return (std::uint64_t(i) << 32) ^ std::uint64_t(j & 0xffffffff); };
    for (size_t i : order) {
        const Shell& s = shells[i];
        bool ok = s.zmin <= 0.05 || rests_on_model(q, s, p.gap + 0.05);
        if (!ok) {
            long ci = static_cast<long>(std::floor(s.bottom.x / cell)), cj = static_cast<long>(std::floor(s.bottom.y / cell));
            for (long a = ci - 1; a <= ci + 1 && !ok; ++a)
                for (long b = cj - 1; b <= cj + 1 && !ok; ++b) {
                    auto it = by_cell.find(pack(a, b));
                    if (it == by_cell.end()) continue;
                    for (size_t j : it->second)
                        if (grounded[j] && contains(shells[j], s.bottom, 0.05)) { ok = true; break; }
                }
        }
        grounded[i] = ok;
        if (!ok) {
            ++r.ungrounded_bodies;
            if (r.flagged.size() < 10) r.flagged.push_back({s.bottom, s.top});
        }
        // Index the shell by every cell its axis crosses, so shells above can find it.
        Box3 b = bounding_box(s.mesh);
        for (long a = static_cast<long>(std::floor(b.min.x / cell)); a <= static_cast<long>(std::floor(b.max.x / cell)); ++a)
            for (long c = static_cast<long>(std::floor(b.min.y / cell)); c <= static_cast<long>(std::floor(b.max.y / cell)); ++c)
                by_cell[pack(a, c)].push_back(i);
    }

    // Coverage.
    OverhangOptions oo{p.critical_angle, p.sampling_distance, p.layer_height};
    auto cls = classify_faces(model, oo);
    std::vector<Vec3> points;
    for (size_t i = 0; i < model.faces.size(); ++i) {
        if (!cls[i]) continue;
        const auto& f = model.faces[i];
        size_t before = points.size();
        rasterize_triangle(model.vertices[f[0]], model.vertices[f[1]], model.vertices[f[2]], 0.5 * p.sampling_distance, points);
        if (points.size() == before)
            points.push_back((model.vertices[f[0]] + model.vertices[f[1]] + model.vertices[f[2]]) / 3.0);
    }
    auto generator_view = sample_overhangs(model, oo);
    for (const auto& s : generator_view.samples)
        if (s.kind == SampleKind::Point) points.push_back(s.p);
    // Points resting on what is below (or with material right below), and inside corners where an
    // overhang meets a wall under it, anchor the overhang around them as a contact does: the
    // printer bridges from them.
    const double touch = touching_space(p);
    const Vec3 just_below{0, 0, 0.01};
    PointGrid contact_grid{std::max(reach, 0.5)}, anchor_grid{std::max(reach, 0.5)};
    for (const auto& c : contacts) contact_grid.add(c);
    for (const auto& a : generator_view.anchors) anchor_grid.add(a);
    std::vector<Vec3> need;
    for (const auto& x : points) {
        if (x.z < p.layer_height) continue;
        // Material right below (overlapping shells): not a surface of the print.
        if (q.inside(x - just_below)) {
            anchor_grid.add(x);
            continue;
        }
        ++r.overhang_points;
        auto hit = q.first_hit(x - just_below, {0, 0, -1});
        double free = x.z - (hit ? hit->point.z : 0.0);
        if (free <= touch) {
            ++r.exempt;
            anchor_grid.add(x);
            continue;
        }
        need.push_back(x);
    }
    // Within reach horizontally, and on the same surface: no further up or down than the steepest
    // overhang rises over that reach (plus a contact's gap).
    const double rise = reach * std::tan((90 - p.critical_angle) * M_PI / 180) + contact_tolerance(p);
    for (const auto& x : need) {
        auto near = [&](const Vec3& c) { return horizontal_distance(c, x) <= reach && std::abs(c.z - x.z) <= rise; };
        bool ok = contact_grid.any_near(x, reach, near) || anchor_grid.any_near(x, reach, near);
        if (ok) ++r.covered;
        else if (r.uncovered.size() < 10) r.uncovered.push_back(x);
    }
    return r;
}

std::string CheckResult::summary() const {
    std::ostringstream s;
    auto mark = [](bool ok) { return ok ? "ok  " : "FAIL"; };
    s << mark(coverage_ok()) << " coverage     " << covered << " of " << (overhang_points - exempt)
      << " overhang points have a contact within reach (" << exempt << " rest on what is below)\n";
    for (const auto& u : uncovered) s << "       uncovered at (" << u.x << ", " << u.y << ", " << u.z << ")\n";
    s << mark(penetrating_bodies == 0) << " penetration  " << penetrating_bodies << " solids reach into the model (deepest "
      << max_penetration << " mm)" << (model_closed ? "" : " [model not closed: not judged]") << "\n";
    s << mark(ungrounded_bodies == 0) << " grounding    " << ungrounded_bodies << " of " << bodies
      << " solids rest on nothing\n";
    s << mark(open_bodies + inward_bodies == 0) << " closed       " << open_bodies << " open, " << inward_bodies
      << " inward-facing solids\n";
    s << mark(steep_bodies == 0) << " angles       " << steep_bodies << " solids steeper than the critical angle (max "
      << max_angle << " deg)\n";
    for (const auto& [b, t] : flagged)
        s << "       failing solid from (" << b.x << ", " << b.y << ", " << b.z << ") to (" << t.x << ", " << t.y << ", "
          << t.z << ")\n";
    s << "     strength     worst length-to-width ratio " << worst_length_to_width << "\n";
    return s.str();
}

std::string CheckResult::json() const {
    nlohmann::ordered_json j;
    j["ok"] = ok();
    j["coverage"] = {{"ok", coverage_ok()}, {"points", overhang_points}, {"covered", covered}, {"exempt", exempt}};
    j["penetration"] = {{"bodies", penetrating_bodies}, {"max_mm", max_penetration}, {"judged", model_closed}};
    j["grounding"] = {{"ungrounded", ungrounded_bodies}};
    j["closed"] = {{"open", open_bodies}, {"inward", inward_bodies}};
    j["angles"] = {{"steep", steep_bodies}, {"max_deg", max_angle}};
    j["bodies"] = bodies;
    j["worst_length_to_width"] = worst_length_to_width;
    return j.dump(2);
}

}  // namespace cs

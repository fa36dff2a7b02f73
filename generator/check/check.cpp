#include "check/check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "check/judge_overhangs.hpp"
#include "core/xy_grid.hpp"
#include "mesh/weld.hpp"
#include "query/model_query.hpp"

namespace cs {
namespace {

constexpr std::size_t kMaxFlags = 12;
// Below this height a solid stands on the bed (slicers start at z = 0; half a tenth of a layer).
constexpr double kOnBed = 0.05;
// A face of a solid is probed down to pieces this small (mm): finer than any tolerance judged.
constexpr double kProbeResolution = 0.05;
// A point this close to the model's surface lies on it (rounding in meshes written as float STL).
constexpr double kOnSurface = 1e-3;

// The exemptions, each from the judge's own geometry (no generator rule is copied here):
//
//  free fall    A support under a point is at least one printed layer of material with an air
//               gap above it (under the point) and one below it (over the model it stands on).
//               Where the model below is no more than 2 gaps + 1 layer under the point, nothing
//               printable fits: the printer bridges the point onto what is below. The judge finds
//               the model below with its own ray down (check_coverage).
//  material     A ray down from just under a point whose first face faces down leaves the solid
//               there: the point has the print's own material right below it (shells overlapping
//               inside the print), so it is no surface of the print and nothing to support.
//  corners      Where an overhang face meets a face going down from their shared edge (a wall
//               below, judge_overhangs.hpp), the wall carries that edge as it is printed: the
//               edge anchors the overhang within reach of it, as a contact does.
//
// Every tolerance the judge uses, from the user's settings, each with its reason.
struct Tolerances {
    double reach;          // coverage radius
    double spacing;        // between the judge's overhang points
    double rise;           // same surface: how far up or down a contact may be over `reach`
    double bridge_height;  // free fall under which nothing printable fits: 2 gaps and a layer (above)
    double gap_min;        // smallest acceptable air gap above a contact
    double contact_slack;  // a top more than a layer beyond the gap does not hold the model up
    double penetration;    // anywhere but a contact end
    double tip_diameter;   // caps the depth a contact end may reach (half its width: a 45 degree slope)
    double gap;
};

Tolerances tolerances(const Params& p, const CheckOptions& o) {
    Tolerances t{};
    t.reach = o.reach > 0 ? o.reach : CheckOptions::kLatticeReach * p.sampling_distance;
    t.spacing = o.spacing > 0 ? o.spacing : std::min(0.5, t.reach / 3);
    t.rise = t.reach * std::tan(deg_to_rad(90 - p.critical_angle)) + p.layer_height;
    t.bridge_height = 2 * p.gap + p.layer_height;
    t.gap_min = p.gap - o.gap_tolerance;
    t.contact_slack = p.layer_height;
    t.penetration = o.penetration_tolerance >= 0 ? o.penetration_tolerance : 0.5 * p.gap;
    t.tip_diameter = p.tip_diameter;
    t.gap = p.gap;
    return t;
}

// The strength rule, in the judge's own words, from the paper's Table 1 alone: a 1 mm column is
// safe up to `strength_length` (30 mm) at <= 30 deg from vertical, a 1.5 mm one up to 60 mm at
// <= 50 deg. A thin column's stiffness against the nozzle's push grows with its width squared, so
// safe length = strength_length * (w / 1 mm)^2 * slant(a); the second row then gives
// slant(50 deg) = 60 / (30 * 1.5^2) = 0.89, taken as a straight line from 1 at 30 deg (and never
// below 0.3, where the line would reach 0 past 100 deg). As a ratio: a solid of width w may be at
// most strength_length * w * slant(a) times as long as it is wide.
double slant(double angle_deg) {
    const double at_50 = 60.0 / (30.0 * 1.5 * 1.5);
    return std::max(0.3, 1.0 - (1.0 - at_50) * std::max(0.0, angle_deg - 30.0) / 20.0);
}
double allowed_length_to_width(const Params& p, double width, double angle_deg) {
    return p.strength_length * width * slant(angle_deg);
}

// The model as the user's slicer gets it (`<name>.model.stl` as written), with identical vertices
// welded so faces find their neighbours, and the triangles welding collapsed (two corners the
// same point, no area, no edge of their own) left out. Nothing else: holes stay open and folds
// stay folded, since the slicer prints them so; the generator's repair is not the judge's.
Mesh as_written(const Mesh& m) {
    Mesh w = weld_vertices(m).mesh;
    std::erase_if(w.faces, [](const Triangle& f) { return f[0] == f[1] || f[1] == f[2] || f[2] == f[0]; });
    return w;
}

struct Shell {
    Mesh mesh;
    Vec3 bottom, top;  // centroids of the lowest and highest vertex rings
    double bottom_width = 0, top_width = 0;    // the rings' extent along x
    double bottom_narrow = 0, top_narrow = 0;  // the rings' narrowest extent, across any direction
    double zmin = 0, zmax = 0;
    bool top_contact = false;      // the model is right above its top
    double top_gap = INFINITY;     // smallest vertical distance from its top to the model
    Vec3 contact;                  // the model point above a top contact
    Vec3 gap_at;                   // the point of its top closest to the model above
    bool bottom_on_model = false;  // stands on the model, a gap above it
    // A long top (a wall's, README "check"): every point of it with the model right above is a
    // contact, not its centre alone (find_long_top).
    bool long_top = false;
    std::vector<Vec3> contacts;  // the model points above a long top's contact points
};

// The narrowest horizontal extent of some points: their width across the direction that makes it
// least, which is across a side of their convex hull. A wall's ring, at any angle, is as narrow as
// the wall is thick (or as short, if shorter).
double narrowest(std::vector<Vec3> pts) {
    std::sort(pts.begin(), pts.end(), [](const Vec3& a, const Vec3& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
    auto turn = [](const Vec3& o, const Vec3& a, const Vec3& b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); };
    std::vector<Vec3> hull;  // Andrew's monotone chain
    for (int pass = 0; pass < 2; ++pass) {
        const std::size_t base = hull.size();
        for (const Vec3& q : pts) {
            while (hull.size() >= base + 2 && turn(hull[hull.size() - 2], hull.back(), q) <= 0) hull.pop_back();
            hull.push_back(q);
        }
        hull.pop_back();
        std::reverse(pts.begin(), pts.end());
    }
    double best = INFINITY;
    for (std::size_t i = 0; i < hull.size(); ++i) {
        const Vec3 &a = hull[i], &b = hull[(i + 1) % hull.size()];
        const double l = std::hypot(b.x - a.x, b.y - a.y);
        if (!(l > 0)) continue;
        double far = 0;
        for (const Vec3& q : hull) far = std::max(far, std::abs(turn(a, b, q)) / l);
        best = std::min(best, far);
    }
    return std::isfinite(best) ? best : 0.0;
}

void ring(const Mesh& m, bool highest, Vec3& centre, double& width, double& narrow, double& z) {
    z = highest ? -INFINITY : INFINITY;
    for (const auto& v : m.vertices) z = highest ? std::max(z, v.z) : std::min(z, v.z);
    const double tol = 1e-5;
    Vec3 sum;
    std::vector<Vec3> at;
    double x0 = INFINITY, x1 = -INFINITY;
    for (const auto& v : m.vertices)
        if (std::abs(v.z - z) <= tol) sum += v, at.push_back(v), x0 = std::min(x0, v.x), x1 = std::max(x1, v.x);
    centre = sum / std::max<double>(static_cast<double>(at.size()), 1);
    width = x1 - x0;
    narrow = narrowest(std::move(at));
}

std::vector<Shell> shells_of(const Mesh& supports) {
    std::vector<Shell> shells;
    for (auto& m : split_shells(supports)) {
        Shell s;
        s.mesh = std::move(m);
        ring(s.mesh, false, s.bottom, s.bottom_width, s.bottom_narrow, s.zmin);
        ring(s.mesh, true, s.top, s.top_width, s.top_narrow, s.zmax);
        shells.push_back(std::move(s));
    }
    return shells;
}

// Is p within a shell's body at its height (its axis and width interpolated)?
bool contains(const Shell& s, const Vec3& p, double tol) {
    if (p.z < s.zmin - tol || p.z > s.zmax + tol) return false;
    double t = s.zmax > s.zmin ? std::clamp((p.z - s.zmin) / (s.zmax - s.zmin), 0.0, 1.0) : 0.0;
    Vec3 c = s.bottom + (s.top - s.bottom) * t;
    double half = 0.5 * (s.bottom_width + (s.top_width - s.bottom_width) * t) + tol;
    return std::abs(p.x - c.x) <= half && std::abs(p.y - c.y) <= half;
}

// Vertical distance from p up to the model; negative (minus the depth) when p is inside it.
// A vertical face is never above a point: a ray that runs along one (a tip exactly under a rim)
// goes on past it. A point on the surface (a corner touching a wall beside it) is judged by the
// model above it; how far a solid reaches sideways into the model is the penetration check's.
// Inside or not is read off the face the ray meets: leaving the solid, it faces up.
double gap_up(const ModelQuery& q, const Vec3& p) {
    Vec3 from = p;
    for (int grazes = 0; grazes < 8; ++grazes) {
        auto hit = q.first_hit(from, {0, 0, 1});
        if (!hit) return INFINITY;
        const Vec3 n = face_normal_unnormalized(q.mesh(), q.mesh().faces[hit->face]);
        if (std::abs(n.z) <= 1e-9 * norm(n)) {
            from = hit->point + Vec3{0, 0, 1e-6};
            continue;
        }
        if (n.z < 0) return hit->point.z - p.z;  // entering the model from below: outside
        const double d = std::sqrt(q.squared_distance(p));
        return d > kOnSurface && q.inside(p) ? -d : hit->point.z - p.z;
    }
    return INFINITY;
}

// The model above a solid's top: the smallest gap over its top's corners and centre. A tip under
// the very rim of an overhang may see the rim beside its centre rather than above: there the
// nearest model point counts when it is above the top by about a gap (not beside it).
void find_top_contact(const ModelQuery& q, Shell& s, const Tolerances& t) {
    Vec3 where = s.top;
    double gap = gap_up(q, s.top);
    for (const auto& v : s.mesh.vertices) {
        if (v.z < s.zmax - 1e-5) continue;
        double g = gap_up(q, v);
        if (g < gap) gap = g, where = v;
    }
    if (gap > t.gap + t.contact_slack) {
        Vec3 c = q.closest_point(s.top);
        if (c.z - s.top.z >= t.gap_min && distance(c, s.top) <= t.gap + t.contact_slack) gap = c.z - s.top.z, where = s.top;
    }
    s.top_gap = gap;
    s.gap_at = where;
    s.top_contact = gap <= t.gap + t.contact_slack;
    s.contact = {s.top.x, s.top.y, where.z + gap};
}

// A long top (a wall's): the solid's highest ring reaches at least 2 x reach along its longest
// direction and is at least three times longer than it is wide across it (a strut's or tip's top
// is a square). Every point of it with the model right above is a contact, not its centre alone;
// the smallest of their gaps is the solid's air gap.
void find_long_top(const ModelQuery& q, Shell& s, const Tolerances& t) {
    std::vector<std::uint32_t> ring;
    for (std::uint32_t v = 0; v < s.mesh.vertices.size(); ++v)
        if (std::abs(s.mesh.vertices[v].z - s.zmax) <= 1e-5) ring.push_back(v);
    Vec3 a, b;
    double length = 0;
    for (auto i : ring)
        for (auto j : ring)
            if (double d = horizontal_distance(s.mesh.vertices[i], s.mesh.vertices[j]); d > length)
                length = d, a = s.mesh.vertices[i], b = s.mesh.vertices[j];
    if (length < 2 * t.reach) return;
    const Vec3 dir{(b.x - a.x) / length, (b.y - a.y) / length, 0};
    double across = 0;
    for (auto i : ring) {
        const Vec3 d = s.mesh.vertices[i] - a;
        across = std::max(across, std::abs(d.x * dir.y - d.y * dir.x));
    }
    if (length < 3 * across) return;
    s.long_top = true;
    s.top_contact = false;
    s.top_gap = INFINITY;
    for (const auto& f : s.mesh.faces) {
        const Vec3 &p0 = s.mesh.vertices[f[0]], &p1 = s.mesh.vertices[f[1]], &p2 = s.mesh.vertices[f[2]];
        if (std::max({std::abs(p0.z - s.zmax), std::abs(p1.z - s.zmax), std::abs(p2.z - s.zmax)}) > 1e-5) continue;
        const double longest = std::max({distance(p0, p1), distance(p1, p2), distance(p2, p0)});
        const int n = std::max(1, static_cast<int>(std::ceil(longest / (0.5 * t.spacing))));
        for (int i = 0; i <= n; ++i)
            for (int j = 0; i + j <= n; ++j) {
                const Vec3 x = p0 + (p1 - p0) * (double(i) / n) + (p2 - p0) * (double(j) / n);
                const double gap = gap_up(q, x);
                if (gap > t.gap + t.contact_slack) continue;
                s.top_contact = true;
                s.contacts.push_back({x.x, x.y, x.z + gap});
                if (gap < s.top_gap) s.top_gap = gap, s.gap_at = x;
            }
    }
    if (s.top_contact) s.contact = s.contacts.front();
}

// Does the solid's foot stand on the model, within a gap below it? Its centre and four points of
// its footprint are asked: a tip on the very rim of a hole stands on the rim though the ray down
// from its centre falls into the hole.
bool rests_on_model(const ModelQuery& q, const Shell& s, double within) {
    const double h = 0.45 * s.bottom_width;
    for (Vec3 d : {Vec3{0, 0, 0}, Vec3{h, 0, 0}, Vec3{-h, 0, 0}, Vec3{0, h, 0}, Vec3{0, -h, 0}}) {
        auto hit = q.first_hit(s.bottom + d + Vec3{0, 0, 1e-4}, {0, 0, -1});
        if (hit && hit->distance <= within + 1e-4) return true;
    }
    return false;
}

void flag(CheckResult& r, std::string what, const Vec3& at) {
    if (r.flagged.size() < kMaxFlags) r.flagged.push_back({std::move(what), at});
}

std::string solid_name(const Shell& s) { return "solid from " + format_place(s.bottom) + " to " + format_place(s.top); }

void check_shape(const Shell& s, const Params& p, const CheckOptions& o, CheckResult& r) {
    if (!is_closed_and_consistent(s.mesh)) {
        ++r.open_bodies;
        flag(r, solid_name(s) + " is not closed", s.bottom);
    } else if (signed_volume(s.mesh) <= 0) {
        ++r.inward_bodies;
        flag(r, solid_name(s) + " faces inward", s.bottom);
    }
    double angle = angle_from_vertical_deg(s.top, s.bottom);
    r.max_angle = std::max(r.max_angle, angle);
    if (angle > p.critical_angle + o.angle_tolerance) {
        ++r.steep_bodies;
        flag(r, solid_name(s) + " leans " + std::to_string(angle) + " deg from vertical", s.bottom);
    }
    // Width: the narrower end's narrowest extent (a wall is judged by its thickness, at any angle).
    const double w = std::min(s.top_narrow, s.bottom_narrow), length = distance(s.top, s.bottom);
    if (w <= 0) return;
    r.worst_length_to_width = std::max(r.worst_length_to_width, length / w);
    // The slicer prints whole layers: the part-layer at each end of a solid prints fused into the
    // joint, foot or tip it meets, so its free length is known to a layer, and the judge gives it
    // that layer (a strut sized to the rule's very limit is not failed for its end caps).
    const double free_length = std::max(0.0, length - p.layer_height);
    const double allowed = allowed_length_to_width(p, w, angle);
    if (free_length / w > allowed) {
        ++r.weak_bodies;
        char b[160];
        std::snprintf(b, sizeof b,
                      " is %.1f mm long and %.2f mm wide (%.1f times its width, a layer less; the strength rule allows %.1f)",
                      length, w, free_length / w, allowed);
        flag(r, solid_name(s) + b, s.bottom);
    }
}

// Inside the (repaired, closed) model: the first face a ray meets faces away from the point. One
// ray that stops at its first hit, where the winding test lists every face along three.
bool inside_by_first_face(const ModelQuery& q, const Vec3& p) {
    const Vec3 dir{0.5773, 0.5781, -0.5767};  // irrational-looking: no grazing of axis-aligned faces
    auto hit = q.first_hit(p, dir);
    return hit && dot(face_normal_unnormalized(q.mesh(), q.mesh().faces[hit->face]), dir) > 0;
}

// The deepest point of a solid's surface inside the model, beyond what its contact ends may
// reach. A face that does not touch the model's surface lies wholly on one side of it: one inside
// test decides for all of it. A face that does is probed by halving; a piece whose bounding ball
// holds no model surface lies wholly on one side, and no point of a piece lies deeper than its
// centre's depth plus its radius, so pieces are refined only while that could exceed the allowance.
struct DepthProbe {
    const ModelQuery& q;
    double end_depth_top, end_depth_bottom;  // 0 where that end is not a contact
    double zmin, zmax, tolerance;
    double worst_excess = 0, worst_depth = 0;
    Vec3 worst_at;

    double allowed(double z) const {
        if (end_depth_top > 0 && z >= zmax - end_depth_top) return std::max(tolerance, end_depth_top);
        if (end_depth_bottom > 0 && z <= zmin + end_depth_bottom) return std::max(tolerance, end_depth_bottom);
        return tolerance;
    }
    void record(const Vec3& p, double depth) {
        if (allowed(p.z) == tolerance) worst_depth = std::max(worst_depth, depth);
        double excess = depth - allowed(p.z);
        if (excess > worst_excess) worst_excess = excess, worst_at = p;
    }
    void probe(const Vec3& a, const Vec3& b, const Vec3& c, int level) {
        const Vec3 g = (a + b + c) / 3.0;
        const double r = std::max({distance(g, a), distance(g, b), distance(g, c)});
        const double d = std::sqrt(q.squared_distance(g));
        const bool in = inside_by_first_face(q, g);
        if (!in && (d > r || r <= tolerance)) return;  // outside, or nowhere deeper than r
        if (in && d + r <= tolerance) return;
        if (in && d > r && d - r > std::max({tolerance, end_depth_top, end_depth_bottom})) return record(g, d);
        if (r <= kProbeResolution || level >= 14) {
            if (in) record(g, d);
            return;
        }
        const Vec3 ab = (a + b) * 0.5, bc = (b + c) * 0.5, ca = (c + a) * 0.5;
        probe(a, ab, ca, level + 1);
        probe(ab, b, bc, level + 1);
        probe(ca, bc, c, level + 1);
        probe(ab, bc, ca, level + 1);
    }
};

void check_penetration(const ModelQuery& q, const Shell& s, const Tolerances& t, CheckResult& r) {
    auto end_depth = [&](bool contact, double width) { return contact ? 0.5 * std::min(width, t.tip_diameter) : 0.0; };
    DepthProbe probe{q, end_depth(s.top_contact, s.top_width), end_depth(s.bottom_on_model, s.bottom_width),
                     s.zmin, s.zmax, t.penetration, 0, 0, {}};
    std::vector<const Triangle*> apart;  // faces that do not touch the model's surface
    for (const auto& f : s.mesh.faces) {
        const Vec3 &a = s.mesh.vertices[f[0]], &b = s.mesh.vertices[f[1]], &c = s.mesh.vertices[f[2]];
        const Vec3 g = (a + b + c) / 3.0;
        const double reach = std::max({distance(g, a), distance(g, b), distance(g, c)});
        const bool far = q.squared_distance(g) > reach * reach;  // no surface within its ball
        if (!far && q.triangle_hits(a, b, c)) probe.probe(a, b, c, 0);
        else apart.push_back(&f);
    }
    // Faces apart from the surface: all outside when the solid crosses no surface and one vertex
    // is outside; else each face by its own corner (each corner asked once).
    const bool crosses = apart.size() < s.mesh.faces.size();
    if (!crosses && !apart.empty() && !q.inside(s.mesh.vertices[(*apart[0])[0]])) apart.clear();
    std::vector<signed char> inside(s.mesh.vertices.size(), -1);
    for (const Triangle* f : apart) {
        auto v = (*f)[0];
        if (inside[v] < 0) inside[v] = inside_by_first_face(q, s.mesh.vertices[v]);
        if (inside[v]) probe.probe(s.mesh.vertices[(*f)[0]], s.mesh.vertices[(*f)[1]], s.mesh.vertices[(*f)[2]], 0);
    }
    if (probe.worst_depth > r.max_penetration) r.max_penetration = probe.worst_depth, r.max_penetration_at = probe.worst_at;
    if (probe.worst_excess > 0) {
        ++r.penetrating_bodies;
        char b[64];
        std::snprintf(b, sizeof b, " reaches %.2f mm too deep into the model at ", probe.worst_excess);
        flag(r, solid_name(s) + b + format_place(probe.worst_at), probe.worst_at);
    }
}

void check_air_gap(const Shell& s, const Tolerances& t, CheckResult& r) {
    if (!s.top_contact) return;
    if (s.top_gap < r.min_air_gap) r.min_air_gap = s.top_gap, r.min_air_gap_at = s.top;
    if (s.top_gap < t.gap_min) {
        ++r.fused_contacts;
        char b[96];
        std::snprintf(b, sizeof b, " is fused to the model: air gap %.2f mm (at least %.2f needed) at ", s.top_gap, t.gap_min);
        flag(r, "top of " + solid_name(s) + b + format_place(s.gap_at), s.top);
    }
}

// Lowest solids first: each rests on the bed, on the model, or on a grounded solid below.
void check_grounding(const ModelQuery& q, const std::vector<Shell>& shells, const Tolerances& t, CheckResult& r) {
    std::vector<size_t> order(shells.size());
    for (size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return shells[a].zmin < shells[b].zmin; });
    std::vector<char> grounded(shells.size(), 0);
    XyGrid<size_t> by_cell(4.0);  // every solid, in each cell its bounding box spans
    for (size_t i : order) {
        const Shell& s = shells[i];
        if (s.zmin > kOnBed && q.inside(s.bottom) && std::sqrt(q.squared_distance(s.bottom)) > t.penetration) {
            ++r.buried_bottoms;
            flag(r, solid_name(s) + " starts inside the model", s.bottom);
        }
        bool ok = s.zmin <= kOnBed || s.bottom_on_model ||
                  by_cell.visit_near(s.bottom, 1, [&](size_t j) { return grounded[j] && contains(shells[j], s.bottom, 0.05); });
        grounded[i] = ok;
        if (!ok) {
            ++r.ungrounded_bodies;
            flag(r, solid_name(s) + " rests on nothing", s.bottom);
        }
        Box3 bb = bounding_box(s.mesh);
        for (long a = by_cell.index(bb.min.x); a <= by_cell.index(bb.max.x); ++a)
            for (long c = by_cell.index(bb.min.y); c <= by_cell.index(bb.max.y); ++c) by_cell.insert_at(a, c, i);
    }
}

// Points in an XY grid, for "nearest within the same surface" questions.
class NearGrid {
public:
    explicit NearGrid(double cell) : grid_(cell) {}
    void add(const Vec3& p) { grid_.insert(p, p); }
    // Horizontal distance to the nearest point with |dz| <= rise, searching out to `limit`.
    double nearest(const Vec3& p, double rise, double limit) const {
        double best = INFINITY;
        const long rings = static_cast<long>(std::ceil(limit / grid_.cell())) + 1;
        for (long k = 0; k <= rings; ++k) {
            grid_.visit_ring(p, k, [&](const Vec3& q) {
                if (std::abs(q.z - p.z) <= rise) best = std::min(best, horizontal_distance(p, q));
            });
            if (best <= k * grid_.cell()) break;  // every unvisited cell is farther than k cells
        }
        return best;
    }

private:
    XyGrid<Vec3> grid_;
};

// Is an overhang point left out on purpose: inside a blocked box, or would the tip under it (the
// air gap and a tip length down, a tip diameter wide) reach into one?
bool left_out(const Vec3& x, const std::vector<Box3>& boxes, const Params& p) {
    const double half = 0.5 * p.tip_diameter, below = p.gap + p.tip_length;
    for (const auto& b : boxes)
        if (x.x >= b.min.x - half && x.x <= b.max.x + half && x.y >= b.min.y - half && x.y <= b.max.y + half &&
            x.z >= b.min.z && x.z - below <= b.max.z)
            return true;
    return false;
}

// The tops of the tips the user's omit_struts took out of the recorded tree: an omitted strut
// goes with every strut above it (the struts ending on its top, and so on up), a leaf's tip with
// the strut leaving the leaf; numbers from the strut count on are pillars. Out-of-range numbers
// name nothing, and a tree with a negative node number is taken as none (the .scad reader refuses
// both before a run is judged).
std::vector<Vec3> omitted_tip_tops(const RecordedTree& t, const std::vector<int>& omit) {
    for (const auto& s : t.struts)
        if (s[0] < 0 || s[1] < 0) return {};
    const int count = static_cast<int>(t.struts.size());
    int nodes = 0;
    for (const auto& s : t.struts) nodes = std::max({nodes, s[0] + 1, s[1] + 1});
    std::vector<std::vector<int>> ending_on(nodes);
    for (int e = 0; e < count; ++e) ending_on[t.struts[e][1]].push_back(e);
    std::vector<char> gone(count, 0);
    std::vector<int> todo;
    std::vector<Vec3> tops;
    for (int e : omit) {
        if (e >= 0 && e < count) todo.push_back(e);
        else if (e >= count && e - count < static_cast<int>(t.pillar_tops.size())) tops.push_back(t.pillar_tops[e - count]);
    }
    while (!todo.empty()) {
        const int e = todo.back();
        todo.pop_back();
        if (gone[e]) continue;
        gone[e] = 1;
        for (int f : ending_on[t.struts[e][0]]) todo.push_back(f);
    }
    std::vector<char> leaving(nodes, 0), kept(nodes, 0);  // per node: some strut leaves it; some kept one
    for (int e = 0; e < count; ++e) leaving[t.struts[e][0]] = 1, kept[t.struts[e][0]] |= !gone[e];
    for (const auto& [leaf, top] : t.tips)
        if (leaf >= 0 && leaf < nodes && leaving[leaf] && !kept[leaf]) tops.push_back(top);
    return tops;
}

// A piece's foot and the top of the tip under it, as far apart as the .scad's numbers (4 decimals)
// put them.
constexpr double kSameFoot = 1e-3;

// The tops of the hybrid pieces (walls off the bed) that stood on the tips whose tops are
// `tip_tops`: a piece is grounded by the middle of its foot (as the grounding check judges a solid),
// so it went with the tip there. Each as its top's two ends.
std::vector<std::array<Vec3, 2>> omitted_piece_tops(const RecordedTree& t, const std::vector<Vec3>& tip_tops) {
    std::vector<std::array<Vec3, 2>> tops;
    for (const auto& w : t.walls_off_bed)
        if (std::any_of(tip_tops.begin(), tip_tops.end(), [&](const Vec3& top) { return distance(top, w.foot) < kSameFoot; }))
            tops.push_back({w.top_from, w.top_to});
    return tops;
}

void check_coverage(const Mesh& model, const ModelQuery& q, const std::vector<Shell>& shells, const Params& p,
                    const Tolerances& t, const CheckOptions& o, CheckResult& r) {
    JudgeOverhangs j = judge_overhangs(model, p.critical_angle, p.layer_height, t.spacing);
    NearGrid near(t.reach);
    for (const auto& s : shells) {
        if (!s.top_contact) continue;
        ++r.contacts;
        if (!s.long_top) near.add(s.contact);
        for (const auto& c : s.contacts) near.add(c);
    }
    // Where the omitted tips would have held the print: the model right above each one's top.
    NearGrid held(t.reach);
    auto hold_above = [&](const Vec3& top) {
        const double up = gap_up(q, top);
        held.add({top.x, top.y, top.z + (std::isfinite(up) && up > 0 ? up : 0.0)});
    };
    const std::vector<Vec3> tip_tops = omitted_tip_tops(o.tree, o.omitted_struts);
    for (const Vec3& top : tip_tops) hold_above(top), ++r.omitted_tips;
    // A piece held the ceiling along its whole top (a long top is a contact along its length):
    // points half a reach apart along it, each holding what is within reach above it.
    for (const auto& [a, b] : omitted_piece_tops(o.tree, tip_tops)) {
        const int steps = static_cast<int>(std::ceil(distance(a, b) / (0.5 * t.reach)));
        for (int k = 0; k <= steps; ++k) hold_above(a + (b - a) * (steps ? double(k) / steps : 0.0));
        ++r.omitted_pieces;
    }
    r.omitted_struts = o.omitted_struts.size();
    for (const auto& a : j.corner_anchors) near.add(a);
    const Vec3 just_below{0, 0, 0.01};
    std::vector<const JudgePoint*> need;
    for (const auto& x : j.points) {
        // The first face below: leaving the solid (facing down), the point has material right
        // below it (a face inside the print, where shells overlap); else it is the floor.
        auto hit = q.first_hit(x.p - just_below, {0, 0, -1});
        if (hit && face_normal_unnormalized(model, model.faces[hit->face]).z < 0) {
            near.add(x.p);
            continue;
        }
        ++r.overhang_points;
        ++(x.kind == JudgeKind::Face ? r.face_points : x.kind == JudgeKind::Ridge ? r.ridge_points : r.lowest_points);
        if (x.p.z - (hit ? hit->point.z : 0.0) <= t.bridge_height) {
            ++r.exempt;
            near.add(x.p);
            continue;
        }
        if (left_out(x.p, o.left_out, p)) {
            ++r.left_out;
            r.left_out_area += x.area;
            continue;
        }
        need.push_back(&x);
    }
    const double limit = 8 * t.reach;
    for (const JudgePoint* x : need) {
        double d = near.nearest(x->p, t.rise, limit);
        if (d > t.reach && held.nearest(x->p, t.rise, t.reach) <= t.reach) {
            ++r.omitted;
            r.omitted_area += x->area;
            continue;
        }
        if (d > r.largest_gap) r.largest_gap = std::min(d, limit), r.largest_gap_at = x->p;
        if (d <= t.reach) {
            ++r.covered;
            continue;
        }
        r.uncovered_area += x->area;
        if (r.uncovered.size() < 10) r.uncovered.push_back(x->p);
    }
}

}  // namespace

CheckResult check_supports(const Mesh& model_in, const Mesh& supports, const Params& p, const CheckOptions& o) {
    CheckResult r;
    const Mesh model = as_written(model_in);
    ModelQuery q(model);
    const Tolerances t = tolerances(p, o);
    r.reach = t.reach;
    r.model_closed = is_watertight(model);

    std::vector<Shell> shells = shells_of(supports);
    r.bodies = shells.size();
    for (auto& s : shells) {
        find_top_contact(q, s, t);
        find_long_top(q, s, t);
        s.bottom_on_model = s.zmin > kOnBed && rests_on_model(q, s, t.gap + (t.gap - t.gap_min));
        check_shape(s, p, o, r);
        check_air_gap(s, t, r);
        check_penetration(q, s, t, r);
    }
    check_grounding(q, shells, t, r);
    r.blocked_regions = o.left_out.size();
    check_coverage(model, q, shells, p, t, o, r);
    return r;
}

}  // namespace cs

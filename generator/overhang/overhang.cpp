#include "overhang/overhang.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <tuple>

#include "core/rules.hpp"
#include "core/xy_grid.hpp"
#include "query/model_query.hpp"

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

// Points that cover overhang points around them (samples, anchors), filed in an XY grid with
// cells one reach wide: every coverer of x lies in x's cell or the eight around it.
class CoverGrid {
public:
    CoverGrid(double reach, double critical_angle) : grid_(reach), cover_(reach, critical_angle) {}

    void add(const Vec3& p) { grid_.insert(p, p); }
    // `above`: how much higher than x a coverer may lie at most (beyond the surface rule).
    // covers(q, x, reach, angle), its rise taken once.
    // `hint`: a coverer to ask first (the one that covered a point asked before), updated to the one
    // found. Points are asked in runs of neighbours, and one coverer serves most of a run. Asked
    // only where the search would visit it (in x's cell or the eight around it; coverers are never
    // taken out), so the answer is the search's: some coverer there covers x.
    bool covered(const Vec3& x, double above = INFINITY, std::optional<Vec3>* hint = nullptr) const {
        auto covers_x = [&](const Vec3& q) { return q.z <= x.z + above && cover_(q, x); };
        auto visited = [&](const Vec3& q) {
            return std::abs(grid_.index(q.x) - grid_.index(x.x)) <= 1 && std::abs(grid_.index(q.y) - grid_.index(x.y)) <= 1;
        };
        if (hint && *hint && covers_x(**hint) && visited(**hint)) return true;
        return grid_.visit_near(x, 1, [&](const Vec3& q) {
            if (!covers_x(q)) return false;
            if (hint) *hint = q;
            return true;
        });
    }

private:
    XyGrid<Vec3> grid_;
    Cover cover_;
};

void sample_segment(const Vec3& a, const Vec3& b, double spacing, std::vector<Vec3>& out) {
    int n = std::max(1, static_cast<int>(std::ceil(distance(a, b) / spacing)));
    for (int i = 0; i <= n; ++i) out.push_back(a + (b - a) * (double(i) / n));
}

// Overhang points coverage is judged on: the lattice refined this many times (`check` judges at
// half the spacing). Every point of a face lies within half a diagonal of this finer lattice of
// one of them (or near a corner or the centroid of a small face).
constexpr int kDemandRefinement = 16;
// Step along rims and ridges while looking for uncovered stretches, as a fraction of the reach.
// Sampling steps a quarter of the reach: fine enough that the sample placed past an uncovered
// point lands within a step of the best spot. The top-up steps an eighth: every point between two
// steps is then within half a step (kReachMarginOfSpacing) of one of them.
constexpr double kEdgeStepOfReach = 0.25;
constexpr double kStrictEdgeStepOfReach = 0.125;
// A rim sample goes this fraction of the reach past the first uncovered point, a hair short of the
// full reach so rounding never leaves that point just outside.
constexpr double kEdgeAdvance = 0.98;
// Our points are covered within the reach less half a diagonal of the refined lattice, so that
// every point between ours is still within the full reach. Sampling lets the lattice cover at the
// full reach (inside its cells every point is within reach of a corner: not so in a cell the
// overhang only partly fills, by up to this margin); the top-up does that only inside full cells
// (LatticeCells) and judges everything else with the margin, and so leaves no gap at all.
constexpr double kReachMarginOfSpacing = std::numbers::sqrt2 / 2 / kDemandRefinement;
// A top-up sample whose support does not fit moves to the nearest point within reach where one
// does: the points tried lie at least this far apart (mm), and at most this many are tried.
constexpr double kCandidateSpacing = 0.25;
constexpr std::size_t kMostCandidates = 64;
static_assert(kStrictEdgeStepOfReach * std::numbers::sqrt2 / 2 / 2 <= kReachMarginOfSpacing + 1e-12);

// The reach our own points cover with: the reach less that margin.
double lean_reach(const OverhangOptions& o) {
    return coverage_reach(o.sampling_distance) - kReachMarginOfSpacing * o.sampling_distance;
}

// The lattice samples by cell corner. A point inside a lattice cell whose four corners all carry
// a sample on its surface is within reach of one of them wherever it lies in the cell, so points
// between the demand points there are covered too. Elsewhere (a cell the overhang only partly
// fills) a demand point covers its neighbourhood only with the margin kReachMarginOfSpacing.
class LatticeCells {
public:
    LatticeCells(double spacing, double rise) : z_(spacing), s_(spacing), rise_(rise) {}

    void add(const Vec3& p) { z_.insert_at(std::lround(p.x / s_), std::lround(p.y / s_), p.z); }
    bool full_cell_around(const Vec3& x, double above) const {
        const long i = z_.index(x.x), j = z_.index(x.y);
        for (long a = i; a <= i + 1; ++a)
            for (long b = j; b <= j + 1; ++b)
                if (!corner_on_surface(a, b, x, above)) return false;
        return true;
    }

private:
    bool corner_on_surface(long i, long j, const Vec3& x, double above) const {
        const auto* zs = z_.at(i, j);
        return zs && std::any_of(zs->begin(), zs->end(),
                                 [&](double z) { return z <= x.z + above && std::abs(z - x.z) <= rise_; });
    }

    XyGrid<double> z_;  // lattice point (i, j): the heights of its samples
    double s_, rise_;
};

// Lattice samples of the overhang faces; marks the faces that caught one.
std::vector<Vec3> lattice_samples(const Mesh& m, const std::vector<char>& cls, double s, OverhangSamples& res) {
    std::vector<Vec3> lattice;
    for (size_t i = 0; i < m.faces.size(); ++i) {
        if (!cls[i]) continue;
        const auto& f = m.faces[i];
        ++res.overhang_faces;
        res.overhang_area += 0.5 * norm(face_normal_unnormalized(m, f));
        rasterize_triangle(m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]], s, lattice);
    }
    return lattice;
}

// From the edge (a, b) of face fi to its third corner, at right angles to the edge: where the face
// goes, seen from the edge.
Vec3 away_from_edge(const Mesh& m, std::uint32_t fi, std::uint32_t a, std::uint32_t b) {
    const auto& f = m.faces[fi];
    const std::uint32_t far = f[0] != a && f[0] != b ? f[0] : (f[1] != a && f[1] != b ? f[1] : f[2]);
    const Vec3 e = m.vertices[b] - m.vertices[a], w = m.vertices[far] - m.vertices[a];
    return w - e * (dot(w, e) / dot(e, e));
}

// A keel: two downward-facing faces that both rise away from their shared edge (the edge is the
// lowest line of its cross-section), the edge itself flatter than the critical angle. Such a line
// hangs whatever the faces' own slopes: nothing below it grows up to it.
bool hanging_keel(const Mesh& m, std::uint32_t f0, std::uint32_t f1, std::uint32_t a, std::uint32_t b,
                         const Vec3& n0, const Vec3& n1, double sin_c) {
    if (!(n0.z < 0 && n1.z < 0)) return false;
    const Vec3 e = m.vertices[b] - m.vertices[a];
    const double cos_c = std::sqrt(std::max(0.0, 1 - sin_c * sin_c));
    if (norm(e) == 0 || std::abs(e.z) / norm(e) >= cos_c) return false;
    return away_from_edge(m, f0, a, b).z > 0 && away_from_edge(m, f1, a, b).z > 0;
}

// A face reaching less than this far from its edge (a, b), per mm of the edge, is a sliver: its
// third corner lies on the edge's line (a zero-area face a mesh leaves between two faces of one
// surface, as along molecule.stl's sticks, whose normal is rounding). A nanometre per millimetre:
// far below anything a printer draws, and far above the rounding of the placed mesh's doubles.
// (A float STL's own rounding, some 10 nm at 100 mm, can leave wider ones; they count as faces.)
constexpr double kSliverWidthPerLength = 1e-6;

// Is face fi, which has the edge (a, b), a sliver (kSliverWidthPerLength)?
bool sliver_at_edge(const Mesh& m, std::uint32_t fi, std::uint32_t a, std::uint32_t b) {
    const double length = distance(m.vertices[a], m.vertices[b]);
    return !(length > 0) || !(norm(away_from_edge(m, fi, a, b)) > kSliverWidthPerLength * length);
}

// Does face fi go down from its edge (a, b): its third corner, seen across the edge, lower than
// the edge? A wall below an overhang does, and carries the overhang's edge as it is printed; a
// face that bends towards the overhang's side but rises (a curved underside going on, a little
// steeper than the critical angle) carries nothing.
bool goes_down_from_edge(const Mesh& m, std::uint32_t fi, std::uint32_t a, std::uint32_t b) {
    return away_from_edge(m, fi, a, b).z < 0;
}

// Edges that need samples of their own: region borders that are lips (one side needs support and
// the other side turns up), and downward convex ridges. Inside-corner borders (a wall going down
// from the overhang) become anchors: the wall carries the overhang there.
std::vector<EdgeSegment> support_edges(const Mesh& m, const std::vector<char>& cls, const OverhangOptions& o,
                                       const EdgeUses& edge_face, OverhangSamples& res) {
    const double sin_c = std::sin(deg_to_rad(o.critical_angle));
    // Faces facing up (or flat): an edge between two is neither a ridge nor a keel (below).
    std::vector<char> up(m.faces.size());
    for (std::size_t f = 0; f < m.faces.size(); ++f) up[f] = face_normal_unnormalized(m, m.faces[f]).z >= 0;
    std::vector<EdgeSegment> out;
    std::vector<std::uint32_t> fs;
    for (size_t run = 0, next = 0; run < edge_face.size(); run = next) {
        const std::uint64_t key = edge_face[run].first;
        fs.clear();
        for (next = run; next < edge_face.size() && edge_face[next].first == key; ++next) fs.push_back(edge_face[next].second);
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
        // (Points along it as close as the rims are judged: the whole corner carries, not just
        // points a spacing apart.) Only an edge of two faces gets here (a border of more is sampled).
        // Where either face is a sliver, there is no corner: a sliver classed an overhang has no
        // overhang to carry, and one classed a wall holds nothing up.
        if (any_border && !border && !sliver_at_edge(m, fs[0], a, b) && !sliver_at_edge(m, fs[1], a, b) &&
            goes_down_from_edge(m, fs[cls[fs[0]] ? 1 : 0], a, b))
            sample_segment(pa, pb, kEdgeStepOfReach * coverage_reach(o.sampling_distance), res.anchors);
        bool open_border = fs.size() == 1 && over == 1;
        bool ridge = false;
        if (fs.size() == 2 && over == 0) {
            // Both faces facing up (or flat): their normals' sum does not point down (past a
            // critical angle above 0), and a keel's faces face down. Neither a ridge nor a keel;
            // most edges of a mesh end here.
            if (up[fs[0]] && up[fs[1]] && sin_c >= 0) continue;
            const Vec3 n1 = normalized(face_normal_unnormalized(m, m.faces[fs[0]]));
            const Vec3 n2 = normalized(face_normal_unnormalized(m, m.faces[fs[1]]));
            ridge = (normalized(n1 + n2).z < -sin_c && convex()) || hanging_keel(m, fs[0], fs[1], a, b, n1, n2, sin_c);
        }
        if (!(border || open_border || ridge)) continue;
        res.ridge_edges += ridge;
        out.push_back({pa, pb});
    }
    return out;
}

}  // namespace

EdgeUses edge_uses(const Mesh& m) {
    // Each edge's faces in a run, edges in a deterministic order. (A flat sort: a hash map of
    // small vectors cost a scan seconds in malloc.)
    EdgeUses edge_face;
    edge_face.reserve(m.faces.size() * 3);
    for (std::uint32_t fi = 0; fi < m.faces.size(); ++fi)
        for (int k = 0; k < 3; ++k) edge_face.emplace_back(edge_key(m.faces[fi][k], m.faces[fi][(k + 1) % 3]), fi);
    sort_edge_uses(edge_face);
    return edge_face;
}

namespace {

// Vertices lower than all their neighbours (above the first layer).
std::vector<Vec3> local_minima(const Mesh& m, const OverhangOptions& o) {
    std::vector<double> min_neighbour_z(m.vertices.size(), INFINITY);
    for (const auto& f : m.faces)
        for (int k = 0; k < 3; ++k) {
            auto v = f[k];
            min_neighbour_z[v] = std::min({min_neighbour_z[v], m.vertices[f[(k + 1) % 3]].z, m.vertices[f[(k + 2) % 3]].z});
        }
    std::vector<Vec3> out;
    for (size_t v = 0; v < m.vertices.size(); ++v)
        if (m.vertices[v].z < min_neighbour_z[v] && m.vertices[v].z > o.bed_height * 0.5) out.push_back(m.vertices[v]);
    return out;
}

// Points of the overhang faces that must be covered: the refined lattice, every face's centroid and
// corners (small faces between the refined lattice's points). Sorted top down, then by x and y, so
// the gap fills chosen from them do not depend on the order of the faces.
std::vector<Vec3> face_demand(const Mesh& m, const std::vector<char>& cls, double spacing) {
    std::vector<Vec3> out;
    for (size_t i = 0; i < m.faces.size(); ++i) {
        if (!cls[i]) continue;
        const auto& f = m.faces[i];
        rasterize_triangle(m.vertices[f[0]], m.vertices[f[1]], m.vertices[f[2]], spacing, out);
        out.push_back((m.vertices[f[0]] + m.vertices[f[1]] + m.vertices[f[2]]) / 3.0);
        for (auto v : f) out.push_back(m.vertices[v]);
    }
    std::sort(out.begin(), out.end(), [](const Vec3& a, const Vec3& b) {
        if (a.z != b.z) return a.z > b.z;
        if (a.x != b.x) return a.x < b.x;
        return a.y < b.y;
    });
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return out;
}

// Points along an edge, `step` apart, both ends included.
std::vector<Vec3> edge_points(const EdgeSegment& e, double step) {
    std::vector<Vec3> out;
    sample_segment(e.a, e.b, step, out);
    return out;
}

}  // namespace

OverhangOptions overhang_options(const Params& p) {
    return {p.critical_angle, p.sampling_distance, p.layer_height, touching_space(p), p.support_bridges};
}

double coverage_reach(double sampling_distance) { return std::sqrt(0.5) * sampling_distance; }

Cover::Cover(double reach, double critical_angle_deg)
    : reach(reach), rise(surface_rise(reach, critical_angle_deg)), near(reach) {}

bool covers(const Vec3& sample, const Vec3& x, double reach, double critical_angle_deg) {
    // The rise (a tangent) only for points within reach: most points asked about are not.
    return within_reach(sample, x, reach) && std::abs(sample.z - x.z) <= surface_rise(reach, critical_angle_deg);
}

// How far under an overhang point its probes start (the ray down, the test for material right
// below): a tenth of the thinnest wall that matters, clear of the face's own rounding.
constexpr double kJustBelow = 0.01;

double air_below(const ModelQuery& model, const Vec3& x) {
    auto hit = model.first_hit(x - Vec3{0, 0, kJustBelow}, {0, 0, -1});
    return x.z - (hit ? hit->point.z : 0.0);
}

bool material_right_below(const ModelQuery& model, const Vec3& x) { return model.inside(x - Vec3{0, 0, kJustBelow}); }

bool rests_on_material(const ModelQuery& model, const Vec3& x, double touching_space) {
    if (material_right_below(model, x)) return true;  // overlapping shells: not a surface of the print
    return rests_at(air_below(model, x), touching_space);
}


bool needs_support(const Vec3& n, double critical_angle_deg) { return n.z < overhang_normal_z_limit(critical_angle_deg); }

std::vector<char> classify_faces(const Mesh& m, const OverhangOptions& o) {
    std::vector<char> out(m.faces.size(), 0);
    const double on_bed = o.bed_height * 0.5;
    // needs_support's limit, its sine taken once (per face it was a large part of this pass).
    const double nz_limit = overhang_normal_z_limit(o.critical_angle);
    for (size_t i = 0; i < m.faces.size(); ++i) {
        const auto& f = m.faces[i];
        double zmax = std::max({m.vertices[f[0]].z, m.vertices[f[1]].z, m.vertices[f[2]].z});
        if (zmax <= on_bed) continue;
        out[i] = normalized(face_normal_unnormalized(m, f)).z < nz_limit;
    }
    return out;
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

namespace {

// The points coverage is judged on: local minima, points along rims and ridges, the faces.
struct Demand {
    std::vector<Vec3> minima;
    std::vector<std::vector<Vec3>> along;  // per support edge
    std::vector<Vec3> faces;
};

Demand coverage_demand(const Mesh& m, const std::vector<char>& cls, const std::vector<EdgeSegment>& edges,
                       const OverhangOptions& o, double edge_step_of_reach) {
    Demand d;
    d.minima = local_minima(m, o);
    d.along.resize(edges.size());
    const double step = edge_step_of_reach * coverage_reach(o.sampling_distance);
    for (size_t e = 0; e < edges.size(); ++e) d.along[e] = edge_points(edges[e], step);
    d.faces = face_demand(m, cls, o.sampling_distance / kDemandRefinement);
    return d;
}

// Adds samples where the demand is not yet covered: `needs(x, above)` says whether point x still
// needs one, `add(x, kind)` records one (and makes it cover its neighbours). With `advance`, a rim
// sample goes as far along the rim as still covers the first uncovered point; without, it stands
// on that point (a top-up: its tip may be moved aside as its neighbour's was, and must still
// cover the point).
template <typename Needs, typename Rests, typename Add>
void fill_demand(const Demand& d, const OverhangOptions& o, Needs needs, Rests rests, Add add, bool advance) {
    // A local minimum is where an overhang starts printing: it keeps a sample of its own unless
    // another lies within reach and no higher than half a layer above it.
    for (const auto& x : d.minima)
        if (needs(x, 0.5 * o.bed_height)) add(x, SampleKind::Point);
    // Rims and ridges: at the first uncovered point, a sample as far along the edge as still
    // covers it, so each rim sample serves the most edge it can.
    const Cover still_covers{kEdgeAdvance * lean_reach(o), o.critical_angle};
    for (const auto& pts : d.along)
        for (size_t i = 0; i < pts.size(); ++i) {
            if (!needs(pts[i], INFINITY)) continue;
            size_t j = i;
            while (advance && j + 1 < pts.size() && still_covers(pts[j + 1], pts[i])) ++j;
            while (j > i && (pts[j].z < o.bed_height || rests(pts[j]))) --j;
            add(pts[j], SampleKind::Edge);
        }
    // Whatever the lattice and the rims still miss inside the faces: a gap fill at the point.
    for (const auto& x : d.faces)
        if (needs(x, INFINITY)) add(x, SampleKind::GapFill);
}

// Is the lattice point `p` one the print bridges: is every demand point it would cover (within the
// full reach, on its surface) already carried by the inside corners in `anchors`? Then its
// sample would hold up nothing the walls do not: a horizontal hole or a narrow slot.
// `full`: Cover(the full reach, the critical angle).
bool bridged(const Vec3& p, const XyGrid<Vec3>& demand, const CoverGrid& anchors, const Cover& full) {
    std::optional<Vec3> hint;
    if (!anchors.covered(p, INFINITY, &hint)) return false;
    const long rings = static_cast<long>(std::ceil(full.reach / demand.cell()));
    return !demand.visit_near(p, rings, [&](const Vec3& x) { return full(p, x) && !anchors.covered(x, INFINITY, &hint); });
}

// The demand points of the faces, rims and minima in an XY grid (for `bridged`).
XyGrid<Vec3> demand_grid(const Demand& d, double cell) {
    XyGrid<Vec3> g(cell);
    for (const auto& x : d.minima) g.insert(x, x);
    for (const auto& pts : d.along)
        for (const auto& x : pts) g.insert(x, x);
    for (const auto& x : d.faces) g.insert(x, x);
    return g;
}

}  // namespace

void sort_top_down(std::vector<Sample>& samples) {
    std::sort(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) {
        if (a.p.z != b.p.z) return a.p.z > b.p.z;
        if (a.p.x != b.p.x) return a.p.x < b.p.x;
        return a.p.y < b.p.y;
    });
}

OverhangSamples sample_overhangs(const Mesh& m, const OverhangOptions& o, const ModelQuery* model, const EdgeUses* edges) {
    OverhangSamples res;
    const double s = o.sampling_distance, reach = coverage_reach(s);
    auto cls = classify_faces(m, o);
    auto rests = [&](const Vec3& x) { return model && rests_on_material(*model, x, o.touching_space); };

    // The lattice, and what needs no sample: inside corners. A lattice point resting on material
    // below gets no contact, but the overhang is printed onto that material there and bridges
    // from it, as from an inside corner (`check` judges it so at the same lattice points).
    CoverGrid lattice{reach, o.critical_angle}, grid{lean_reach(o), o.critical_angle};
    std::vector<Vec3> lattice_points = lattice_samples(m, cls, s, res);
    EdgeUses own;
    if (!edges) own = edge_uses(m);
    res.edges = support_edges(m, cls, o, edges ? *edges : own, res);
    for (const auto& a : res.anchors) grid.add(a);
    const Demand demand = coverage_demand(m, cls, res.edges, o, kEdgeStepOfReach);
    // Holes and slots the print bridges: the anchors (at the lean reach) carry all their lattice
    // point would, so it gets no sample. Judged before any sample is placed: only the walls count.
    if (!o.support_bridges && !res.anchors.empty()) {
        OverhangOptions judged = o;
        judged.sampling_distance = o.bridge_sampling > 0 ? o.bridge_sampling : o.sampling_distance;
        const double bridge_reach = coverage_reach(judged.sampling_distance);
        CoverGrid walls{lean_reach(judged), o.critical_angle};
        for (const auto& a : res.anchors) walls.add(a);
        const XyGrid<Vec3> near = demand_grid(demand, bridge_reach);
        const Cover full{bridge_reach, o.critical_angle};
        std::erase_if(lattice_points, [&](const Vec3& p) { return bridged(p, near, walls, full); });
    }
    for (const auto& p : lattice_points)
        if (p.z >= o.bed_height) res.samples.push_back({p, SampleKind::Face}), lattice.add(p);
    res.point_overhangs = demand.minima.size();

    // A point needs a sample near it unless it lies in the first layer, is covered, or rests on
    // material below (it needs none itself; off the lattice it covers nothing, since `check` may
    // judge no resting point near it).
    std::optional<Vec3> lattice_hint, grid_hint;
    auto needs = [&](const Vec3& x, double above) {
        bool covered = lattice.covered(x, above, &lattice_hint) || grid.covered(x, above, &grid_hint);
        return x.z >= o.bed_height && !covered && !rests(x);
    };
    fill_demand(demand, o, needs, rests, [&](const Vec3& x, SampleKind kind) {
        grid.add(x);
        res.samples.push_back({x, kind});
    }, true);
    sort_top_down(res.samples);
    return res;
}

namespace {

// Where the top-up meets a point under which no support fits (a knife edge, a slot too low for a
// pillar): would the sample, left bare there, leave a point beyond `check`'s full reach of what
// holds the overhang up, and if so, where nearby a support fits that still covers the point. The
// demand by place is made for the first such point only (most runs meet none).
class PlacesWhereNoneFits {
public:
    using Rests = std::function<bool(const Vec3&)>;
    PlacesWhereNoneFits(const Demand& demand, const OverhangOptions& o, Rests rests, const SupportAt& support_at)
        : demand_(demand), o_(o), rests_(std::move(rests)), support_at_(support_at),
          lean_{lean_reach(o), o.critical_angle}, full_cover_{coverage_reach(o.sampling_distance), o.critical_angle},
          full_{coverage_reach(o.sampling_distance), o.critical_angle} {}

    // `at` holds the overhang up (a contact, an anchor, a support just placed).
    void holds(const Vec3& at) { full_.add(at); }

    // Would a sample left bare at x leave some point it was to cover beyond the full reach of
    // everything that holds the overhang up? A point resting on material within the full reach
    // holds it too, as `check` lets its resting points hold their neighbours (its own points,
    // though: it may have none as near).
    bool bare_leaves_beyond_full_reach(const Vec3& x) {
        const XyGrid<Vec3>& near = demand_near();
        return near.visit_near(x, 1, [&](const Vec3& y) {
            return y.z >= o_.bed_height && lean_(x, y) && !full_.covered(y) && !rests_(y) &&
                   !near.visit_near(y, 2, [&](const Vec3& z) { return full_cover_(z, y) && rests_(z); });
        });
    }

    // The nearest demand point within reach of x whose support fits and covers x, the candidates
    // kCandidateSpacing apart at least, kMostCandidates of them; nullopt when none does.
    struct Moved {
        Vec3 sample, held_at;  // where the sample goes, and where its support holds the overhang up
    };
    std::optional<Moved> moved_in(const Vec3& x) {
        std::vector<Vec3> cands;
        demand_near().visit_near(x, 1, [&](const Vec3& y) {
            if (y.z >= o_.bed_height && lean_(y, x) && !(y == x)) cands.push_back(y);
            return false;
        });
        std::sort(cands.begin(), cands.end(), [&](const Vec3& a, const Vec3& b) {
            const double da = horizontal_distance(a, x), db = horizontal_distance(b, x);
            if (da != db) return da < db;
            return std::tie(a.z, a.x, a.y) > std::tie(b.z, b.x, b.y);
        });
        std::vector<Vec3> tried;
        for (const Vec3& y : cands) {
            if (tried.size() >= kMostCandidates) break;
            if (std::any_of(tried.begin(), tried.end(), [&](const Vec3& t) { return horizontal_distance(t, y) < kCandidateSpacing; }))
                continue;
            tried.push_back(y);
            if (rests_(y)) continue;
            if (const auto c = support_at_(y); c && lean_(*c, x)) return Moved{y, *c};
        }
        return std::nullopt;
    }

private:
    const XyGrid<Vec3>& demand_near() {
        if (!near_) near_ = demand_grid(demand_, lean_.reach);
        return *near_;
    }

    const Demand& demand_;
    const OverhangOptions& o_;
    Rests rests_;
    const SupportAt& support_at_;
    const Cover lean_, full_cover_;
    CoverGrid full_;                    // what holds the overhang up, at the full reach (`check`'s)
    std::optional<XyGrid<Vec3>> near_;  // the demand by place
};

}  // namespace

std::vector<Sample> top_up_samples(const Mesh& m, const OverhangOptions& o, const ModelQuery* model,
                                   const OverhangSamples& sampled, const std::vector<Vec3>& coverers,
                                   const SupportAt& support_at) {
    const double s = o.sampling_distance, reach = coverage_reach(s);
    auto cls = classify_faces(m, o);
    auto rests = [&](const Vec3& x) { return model && rests_on_material(*model, x, o.touching_space); };
    CoverGrid grid{lean_reach(o), o.critical_angle};
    LatticeCells cells{s, surface_rise(reach, o.critical_angle)};
    // A coverer still on its lattice point completes a full cell, as its sample did.
    auto on_lattice = [&](double v) { return std::abs(v - s * std::round(v / s)) <= 1e-9 * std::max(1.0, std::abs(v)); };
    for (const auto& c : coverers) {
        grid.add(c);
        if (on_lattice(c.x) && on_lattice(c.y)) cells.add(c);
    }
    for (const auto& a : sampled.anchors) grid.add(a);
    std::vector<Sample> out;
    std::optional<Vec3> hint;
    auto needs = [&](const Vec3& x, double above) {
        return x.z >= o.bed_height && !cells.full_cell_around(x, above) && !grid.covered(x, above, &hint) && !rests(x);
    };
    const Demand demand = coverage_demand(m, cls, sampled.edges, o, kStrictEdgeStepOfReach);
    PlacesWhereNoneFits where{demand, o, rests, support_at};
    if (support_at) {
        for (const auto& c : coverers) where.holds(c);
        for (const auto& a : sampled.anchors) where.holds(a);
    }
    fill_demand(demand, o, needs, rests, [&](const Vec3& x, SampleKind kind) {
        const std::optional<Vec3> own = support_at ? support_at(x) : std::nullopt;
        if (support_at && !own && where.bare_leaves_beyond_full_reach(x))
            if (const auto moved = where.moved_in(x)) {
                where.holds(moved->held_at);
                grid.add(moved->held_at);
                out.push_back({moved->sample, kind});
                return;
            }
        grid.add(x);
        if (own) where.holds(*own);  // a sample left bare holds nothing up
        out.push_back({x, kind});
    }, false);
    sort_top_down(out);
    return out;
}

}  // namespace cs

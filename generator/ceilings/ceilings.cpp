#include "ceilings/ceilings.hpp"
#include "ceilings/hybrid.hpp"
#include "ceilings/slabs.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <numeric>
#include <optional>
#include <array>
#include <set>
#include <tuple>

#include "core/flat_index.hpp"
#include "core/rules.hpp"
#include "core/slicer_time.hpp"
#include "core/xy_grid.hpp"
#include "query/model_query.hpp"

namespace cs {

namespace {

// Pieces whose ends lie this close (mm) meet (a row's stations are written to the same
// coordinates, so theirs agree far more closely): for the walls' lines and islands, and for the
// bridges along one slab.
constexpr double kMeet = 1e-3;

// Horizontal distance from x to the centre line of piece w.
double to_centre_line(const Vec3& x, const CeilingWall& w) { return horizontal_point_segment_distance(x, w.from, w.to); }

// Does an end of u lie within `reach` of v's centre line, or an end of v within it of u's? Pieces
// are segments in a plane, so where two come nearest an end of one is nearest: the slicer's outline
// of pieces within their half thicknesses of each other is one.
bool an_end_within(const CeilingWall& u, const CeilingWall& v, double reach) {
    return to_centre_line(u.from, v) <= reach || to_centre_line(u.to, v) <= reach || to_centre_line(v.from, u) <= reach ||
           to_centre_line(v.to, u) <= reach;
}

}  // namespace

double long_top(const Params& p, double thickness) { return std::max(2 * coverage_reach(p.sampling_distance), 3 * thickness); }

double wall_line_seconds(const SlicerRoute& r, double length, double height, double thickness, const Params& p) {
    return height / p.layer_height * line_route_seconds(r, length, thickness);
}

namespace {

// Seconds the slabs among `walls` add on a route, against the loops of their rows: on every layer,
// each slab's outline in place of the two loops along it. A pair's bridges that meet end to end on
// a layer (a staircase under a round or sloping ceiling, one bridge a step) are one slab, one
// outline: priced a bridge at a time, each step's two ends made a staircase's slab dearer than its
// loops, and the walls' choice then kept trees on propeller's blades that both slicers printed
// slower (bench/results/validation.md).
double slabs_seconds(const SlicerRoute& r, const std::vector<CeilingWall>& walls, const Params& p) {
    std::vector<std::size_t> bridges;
    for (std::size_t i = 0; i < walls.size(); ++i)
        if (walls[i].bridge) bridges.push_back(i);
    if (bridges.empty()) return 0;
    // Each bridge's neighbours along its slab: the bridge of the same pair (as wide) that starts
    // where it ends, and the one that ends where it starts.
    const std::size_t none = walls.size();
    std::vector<std::size_t> next(walls.size(), none), previous(walls.size(), none);
    for (const std::size_t a : bridges)
        for (const std::size_t b : bridges)
            if (a != b && std::abs(walls[a].thickness - walls[b].thickness) < kMeet &&
                horizontal_distance(walls[a].to, walls[b].from) < kMeet)
                next[a] = b, previous[b] = a;
    double low = INFINITY, high = -INFINITY;
    for (const std::size_t i : bridges) low = std::min(low, walls[i].bottom), high = std::max(high, walls[i].top);
    double seconds = 0;
    for (long k = std::max(0L, static_cast<long>(std::floor(low / p.layer_height))); (k + 0.5) * p.layer_height < high; ++k) {
        const double z = (k + 0.5) * p.layer_height;
        auto printed = [&](std::size_t i) { return i != none && walls[i].bottom <= z && z < walls[i].top; };
        for (const std::size_t i : bridges) {
            if (!printed(i) || printed(previous[i])) continue;  // a slab from its first bridge on the layer
            double length = 0;
            std::size_t steps = 0;  // (a chain of bridges never turns back on itself; bounded anyway)
            for (std::size_t j = i; printed(j) && steps < bridges.size(); j = next[j], ++steps)
                length += horizontal_distance(walls[j].from, walls[j].to);
            const double row = walls[i].row_thickness;
            seconds += outline_route_seconds(r, length, walls[i].thickness + 2 * row) - 2 * line_route_seconds(r, length, row);
        }
    }
    return seconds;
}

}  // namespace

WallsPrinted walls_printed(const SlicerRoute& r, const std::vector<CeilingWall>& walls, const Params& p) {
    WallsPrinted out;
    if (walls.empty()) return out;
    // Slabs are built for the routes that draw a wall as a loop (CuraEngine's); the others' files
    // leave the bridges out (ceilings/slabs.hpp).
    const bool slabs_printed = r.passes > 1;
    // Pieces in line meet end to end (a row's stations are written to the same coordinates); pieces
    // touch where an end of one lies within their half thicknesses of the other's line (a join ends
    // inside the rows it joins), and the slicer's outline of the two is one.
    auto touch = [](const CeilingWall& u, const CeilingWall& v) {
        return an_end_within(u, v, 0.5 * (u.thickness + v.thickness) + kMeet);
    };
    struct Pair {
        std::size_t a, b;
        bool in_line;  // same direction and thickness: one line where both are printed
    };
    std::vector<Pair> pairs;
    auto direction = [](const CeilingWall& w) {
        const double d = horizontal_distance(w.from, w.to);
        return d > 0 ? Vec3{(w.to.x - w.from.x) / d, (w.to.y - w.from.y) / d, 0} : Vec3{0, 0, 0};
    };
    for (std::size_t a = 0; a < walls.size(); ++a)
        for (std::size_t b = a + 1; b < walls.size(); ++b) {
            const CeilingWall &u = walls[a], &v = walls[b];
            if (u.bridge || v.bridge || !touch(u, v)) continue;
            const bool meet = horizontal_distance(u.from, v.from) < kMeet || horizontal_distance(u.from, v.to) < kMeet ||
                              horizontal_distance(u.to, v.from) < kMeet || horizontal_distance(u.to, v.to) < kMeet;
            const Vec3 du = direction(u), dv = direction(v);
            pairs.push_back({a, b, meet && std::abs(du.x * dv.y - du.y * dv.x) < 1e-3 && u.thickness == v.thickness});
        }
    double low = walls.front().bottom, high = walls.front().top;
    for (const CeilingWall& w : walls) low = std::min(low, w.bottom), high = std::max(high, w.top);
    std::vector<std::size_t> island(walls.size()), line(walls.size());
    std::vector<double> length(walls.size());
    auto root = [](std::vector<std::size_t>& up, std::size_t i) {
        while (up[i] != i) i = up[i] = up[up[i]];
        return i;
    };
    for (long k = std::max(0L, static_cast<long>(std::floor(low / p.layer_height))); (k + 0.5) * p.layer_height < high; ++k) {
        const double z = (k + 0.5) * p.layer_height;
        auto printed = [&](std::size_t i) { return walls[i].bottom <= z && z < walls[i].top; };
        for (std::size_t i = 0; i < walls.size(); ++i) island[i] = line[i] = i, length[i] = 0;
        for (const Pair& q : pairs) {
            if (!printed(q.a) || !printed(q.b)) continue;
            island[root(island, q.a)] = root(island, q.b);
            if (q.in_line) line[root(line, q.a)] = root(line, q.b);
        }
        for (std::size_t i = 0; i < walls.size(); ++i)
            if (printed(i) && !walls[i].bridge) {
                out.island_layers += root(island, i) == i;
                length[root(line, i)] += horizontal_distance(walls[i].from, walls[i].to);
            }
        for (std::size_t i = 0; i < walls.size(); ++i)
            if (printed(i) && root(line, i) == i && !walls[i].bridge)
                out.line_seconds += line_route_seconds(r, length[i], walls[i].thickness);
    }
    // A slab's two rows are drawn once each, not as loops (the loops priced above).
    if (slabs_printed) out.line_seconds += slabs_seconds(r, walls, p);
    return out;
}

double walls_seconds(const SlicerRoute& r, const std::vector<CeilingWall>& walls, const Params& p) {
    const WallsPrinted w = walls_printed(r, walls, p);
    return w.line_seconds + r.wall_island_s * w.island_layers;
}

namespace {

// Is the layout the hybrid's (ceilings/hybrid.hpp)? support_ceilings and support_hybrid share it;
// support_ceilings lays out with hybrid_height set to 0 (its walls stand on the bed or a floor),
// support_hybrid with the user's (its pieces stand on the tree, that far under their tops).
bool lays_out_hybrid(const Params& p) { return p.hybrid_height > 0; }

// Stations along a wall (mm): fine enough that a round ceiling's top steps by well under a layer
// over a bore's flat crown, coarse enough to keep the SCAD small.
constexpr double kStation = 0.5;
// A wall shorter than this is not worth a line of its own; its samples stay with the tree.
constexpr double kMinWall = 1.5;
// Whether the walls carry a sample is asked at points of the surface around it (JudgedSurface) this
// fraction of the reach apart.
constexpr double kProbeStepOfReach = 0.06;
// A point of the surface lies within this many probe steps of a probed one (JudgedSurface).
constexpr double kProbeCover = 1.21;
// The walls carry a point within this fraction of coverage_reach of a wall's contact. `check`
// judges at its lattice reach (coverage_reach or a hair more), so what is left is for the probes
// and for where `check` samples a wall's top: a point of the surface lies within 0.073 of the
// reach of a probed one (1.21 steps of 0.06); `check`'s points along a top lie up to an eighth of
// a millimetre along it from the nearest point measured here, which adds under 0.01 mm at this
// distance (it is across the line of sight). 0.9 leaves 0.02 of the reach to spare.
constexpr double kWallReachMargin = 0.9;
// Points along a wall's top where the ceiling right above is asked for (mm).
constexpr double kContactStep = 0.25;
// A region needs this many samples to be worth walls.
constexpr std::size_t kMinRegion = 4;

// The ceiling over (x, y) near height z_ref: the first face above z_ref - rise when it is an
// overhang face (steeper than the critical angle, seen from below) within rise of z_ref: its height
// and that face's normal (unnormalized), where the ceiling's slope is asked too.
struct CeilingHit {
    double z;
    Vec3 normal;
};
std::optional<CeilingHit> ceiling_face_near(const ModelQuery& q, double x, double y, double z_ref, double rise,
                                            double overhang_nz) {
    auto hit = q.first_hit({x, y, z_ref - rise}, {0, 0, 1});
    if (!hit || hit->point.z > z_ref + rise) return std::nullopt;
    const Vec3 n = face_normal_unnormalized(q.mesh(), q.mesh().faces[hit->face]);
    const double l = norm(n);
    if (!(l > 0) || n.z / l > overhang_nz) return std::nullopt;
    return CeilingHit{hit->point.z, n};
}

// Its height alone.
std::optional<double> ceiling_near(const ModelQuery& q, double x, double y, double z_ref, double rise, double overhang_nz) {
    const auto hit = ceiling_face_near(q, x, y, z_ref, rise, overhang_nz);
    return hit ? std::optional<double>{hit->z} : std::nullopt;
}

// Nearly level floors only: a wall's foot is one flat piece a gap above the highest point under it.
constexpr double kLevelFloor = 0.95;

// Where a wall under x may stand: the bed (0), or a level face of the model a gap below... the
// floor's height; nothing where the fall lands on a slope or less than a wall's room is left.
std::optional<double> floor_under(const ModelQuery& q, const Vec3& x, const Params& p) {
    if (lays_out_hybrid(p)) return hybrid_floor(q, x, p);  // the hybrid's feet hang on the tree
    auto hit = q.first_hit(x - Vec3{0, 0, 1e-3}, {0, 0, -1});
    if (!hit) return 0.0;
    if (!p.supports_on_model) return std::nullopt;  // --buildplate-only: the bed or nothing
    const Vec3 n = face_normal_unnormalized(q.mesh(), q.mesh().faces[hit->face]);
    if (!(n.z > kLevelFloor * norm(n))) return std::nullopt;
    const double z = hit->point.z + p.gap;
    if (x.z - p.gap - z < touching_space(p) + p.tip_length) return std::nullopt;
    return z;
}

// How far above or below a sample its own stretch of surface may lie at `reach` from it: the
// steepest overhang's rise over that reach, plus a layer.
double same_surface_rise(const Params& p, double reach) {
    return surface_rise(reach, p.critical_angle) + p.layer_height;
}

// How far from a wall's contact a point of the ceiling counts as carried by it.
double wall_reach(const Params& p) { return kWallReachMargin * coverage_reach(p.sampling_distance); }

// A wall while it is laid out: stations along a line, the top (one gap under the ceiling) and the
// floor (the bed, or one gap over the model) at each; cut into flat pieces at the end.
struct Run {
    std::vector<Vec3> top;
    std::vector<double> floor;
    std::vector<double> thickness;
    bool join = false;
    bool tail = false;  // an outer row's tail (add_tails)
};

// The moments of a ceiling's slopes (rise per mm along x and y) over some of its points: the
// direction of least mean squared slope is where it is level (a bore's or tunnel's axis, a sloping
// roof's contour lines), and the RMS change over a distance along any direction says how level.
struct SlopeMoments {
    double mxx = 0, mxy = 0, myy = 0;
    std::size_t n = 0;
    void add(double gx, double gy) { mxx += gx * gx, mxy += gx * gy, myy += gy * gy, ++n; }
    // The steepest direction's angle turned a quarter: the level one.
    double level_angle() const { return 0.5 * std::atan2(2 * mxy, mxx - myy) + 0.5 * std::numbers::pi; }
    // RMS change in height over `length` along the unit direction e.
    double change(const Vec3& e, double length) const {
        return length * std::sqrt(std::max(0.0, (mxx * e.x * e.x + 2 * mxy * e.x * e.y + myy * e.y * e.y) / n));
    }
};

struct Region {
    std::vector<std::size_t> samples;
    Box3 box;
    SlopeMoments slopes;  // of the ceiling right above its samples (level_direction)
    std::vector<std::size_t> beside;  // neighbours the region's structure cannot take (samples_beside)
};

// Lattice neighbours this many sampling distances apart (or less) join a region.
constexpr double kRegionJoin = 1.5;

// Do samples at a and b join one region: lattice neighbours (kRegionJoin sampling distances `sd`
// apart or less) on the same stretch of surface (heights within `rise`, same_surface_rise)?
bool join_region(const Vec3& a, const Vec3& b, double sd, double rise) {
    return horizontal_distance(a, b) <= kRegionJoin * sd && std::abs(a.z - b.z) <= rise;
}

// Two samples' ceilings are level along directions at most kLevelApart apart, or one has none: a
// pipe tee's run and branch, each level along its own axis, become regions of their own, each with
// rows along its axis (one region's rows cross the other's bore as short pieces, a staircase).
constexpr double kLevelApart = 45.0;  // degrees
bool level_alike(const Vec3& a, const Vec3& b) {
    if (norm(a) == 0 || norm(b) == 0) return true;
    return std::abs(dot(a, b)) >= std::cos(deg_to_rad(kLevelApart));
}

// Each region's `beside`: the samples that would join it (lattice neighbours on the same stretch of
// surface) but that its structure cannot take, so the tree takes them: a bore's sloping sides beside
// the ridge along its crown, where walls could stand only under the ridge (on the nearly level
// facets along the bore's floor). Walls between those samples and the region's own tips split the
// tree that would have merged them, so a region is priced with them (lay_out_ceilings).
void samples_beside(const std::vector<Sample>& samples, const std::vector<char>& free, const Params& p,
                    std::vector<Region>& regions) {
    const double sd = p.sampling_distance, rise = same_surface_rise(p, kRegionJoin * sd);
    XyGrid<std::size_t> others(sd);
    for (std::size_t i = 0; i < samples.size(); ++i)
        if (!free[i]) others.insert(samples[i].p, i);
    for (Region& r : regions) {
        for (std::size_t k : r.samples)
            others.visit_near(samples[k].p, 2, [&](std::size_t j) {
                if (join_region(samples[k].p, samples[j].p, sd, rise)) r.beside.push_back(j);
            });
        std::sort(r.beside.begin(), r.beside.end());
        r.beside.erase(std::unique(r.beside.begin(), r.beside.end()), r.beside.end());
    }
}

// The slope of the ceiling's face right above each free sample (as ceiling_near finds it, within
// the rise of a sampling distance), rise per mm along x and y; nothing where no overhang face is
// there, or the sample is not free. Asked once: the regions' level directions take them too.
using Slope = std::optional<std::array<double, 2>>;
std::vector<Slope> ceiling_slopes(const ModelQuery& q, const std::vector<Sample>& samples, const std::vector<char>& free,
                                  const Params& p) {
    const double rise = same_surface_rise(p, p.sampling_distance), overhang_nz = -std::sin(deg_to_rad(p.critical_angle));
    std::vector<Slope> slope(samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        if (!free[i]) continue;
        const Vec3& a = samples[i].p;
        if (const auto hit = ceiling_face_near(q, a.x, a.y, a.z, rise, overhang_nz))
            slope[i] = std::array<double, 2>{-hit->normal.x / hit->normal.z, -hit->normal.y / hit->normal.z};
    }
    return slope;
}

// A sample's ceiling is level along a direction (local_level) where a sampling distance across it
// changes height this many times as much as along it: a bore, a tunnel or a channel, drawn as an
// extrusion (CAD parts). level_direction asks only twice as much of a whole region; asked of each
// sample's neighbourhood (in an earlier form of this split), that cut the stanford_bunny's
// undersides into regions along their gentle curves, and its walls printed slower on PrusaSlicer
// (16.9 -> 17.8 min); up to 4 it still changes the bunny. From 5 to 20 the pipe_tee's run and
// branch come apart alike; from 10 also two of fandisk's slopes. Both print faster for it (support
// minutes, Cura / PrusaSlicer: pipe_tee 23.3 / 23.1 -> 18.8 / 18.3, fandisk 38.2 / 36.3 -> 36.8 /
// 34.7), and no other part of the tuning set, the validation set or the examples changes.
constexpr double kLevelSplitContrast = 10.0;

// The direction along which the ceiling around each free sample is level, where it has one: the
// slope moments of the ceiling right above the sample's free lattice neighbours on its stretch of
// surface (joined as regions join them, the sample itself among them), given where a sampling
// distance across the least-slope direction changes height by more than half a layer more than
// along it and by kLevelSplitContrast times as much. A unit vector, or zero where the ceiling is
// flat or curved alike every way (a flat roof, a dome, where a tee's bores cross).
std::vector<Vec3> local_level(const std::vector<Slope>& slope, const std::vector<Sample>& samples,
                              const std::vector<char>& free, const XyGrid<std::size_t>& grid, const Params& p) {
    const double sd = p.sampling_distance, join_rise = same_surface_rise(p, kRegionJoin * sd);
    std::vector<Vec3> level(samples.size(), Vec3{0, 0, 0});
    for (std::size_t i = 0; i < samples.size(); ++i) {
        if (!free[i]) continue;
        SlopeMoments m;
        grid.visit_near(samples[i].p, 2, [&](std::size_t j) {
            if (slope[j] && join_region(samples[i].p, samples[j].p, sd, join_rise)) m.add((*slope[j])[0], (*slope[j])[1]);
            return false;
        });
        if (m.n < kMinRegion) continue;
        const double angle = m.level_angle();
        const Vec3 d{std::cos(angle), std::sin(angle), 0}, across{-d.y, d.x, 0};
        const double rises = m.change(across, sd), stays = m.change(d, sd);
        if (rises - stays > 0.5 * p.layer_height && rises > kLevelSplitContrast * stays) level[i] = d;
    }
    return level;
}

// Samples that fall freely to the bed, joined into regions where lattice neighbours lie on the
// same stretch of surface and their ceilings are level alike (local_level, level_alike); none of
// those that `stay` with the tree. Regions in the order of their first sample.
std::vector<Region> free_regions(const ModelQuery& q, const std::vector<Sample>& samples, const Params& p,
                                 const std::vector<char>& stay) {
    const double sd = p.sampling_distance, low = touching_space(p) + p.tip_length;
    std::vector<char> free(samples.size(), 0);
    XyGrid<std::size_t> grid(sd);
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const Vec3& s = samples[i].p;
        if ((!stay.empty() && stay[i]) || s.z < low || !floor_under(q, s, p)) continue;
        free[i] = 1;
        grid.insert(s, i);
    }
    const double rise = same_surface_rise(p, kRegionJoin * sd);
    const std::vector<Slope> slope = ceiling_slopes(q, samples, free, p);
    const std::vector<Vec3> level = local_level(slope, samples, free, grid, p);
    std::vector<char> seen(samples.size(), 0);
    std::vector<Vec3> along(samples.size(), Vec3{0, 0, 0});
    std::vector<Region> regions;
    // Regions grow first from samples whose ceiling is level along a direction, in their order; a
    // sample without one (where a tee's bores meet) joins the region that reaches it first.
    std::vector<std::size_t> seeds;
    for (const bool with_level : {true, false})
        for (std::size_t i = 0; i < samples.size(); ++i)
            if (free[i] && (norm(level[i]) > 0) == with_level) seeds.push_back(i);
    for (std::size_t i : seeds) {
        if (seen[i]) continue;
        Region r;
        r.box.min = r.box.max = samples[i].p;
        std::vector<std::size_t> stack{i};
        seen[i] = 1;
        // Each sample's level direction, or where it has none (a bore's crown where a tee's run
        // and branch meet) the one of the sample it was reached from: a region grows only to
        // neighbours level alike (a direction that turns slowly, along a curved channel, is
        // followed; the branch's, at a right angle, is not).
        along[i] = level[i];
        while (!stack.empty()) {
            const std::size_t k = stack.back();
            stack.pop_back();
            r.samples.push_back(k);
            const Vec3& a = samples[k].p;
            r.box.min = {std::min(r.box.min.x, a.x), std::min(r.box.min.y, a.y), std::min(r.box.min.z, a.z)};
            r.box.max = {std::max(r.box.max.x, a.x), std::max(r.box.max.y, a.y), std::max(r.box.max.z, a.z)};
            grid.visit_near(a, 2, [&](std::size_t j) {
                const Vec3& b = samples[j].p;
                if (!seen[j] && join_region(a, b, sd, rise) && level_alike(along[k], level[j])) {
                    seen[j] = 1, stack.push_back(j);
                    along[j] = norm(level[j]) > 0 ? level[j] : along[k];
                }
            });
        }
        std::sort(r.samples.begin(), r.samples.end());
        for (std::size_t k : r.samples)
            if (slope[k]) r.slopes.add((*slope[k])[0], (*slope[k])[1]);
        if (r.samples.size() >= kMinRegion) regions.push_back(std::move(r));
    }
    std::sort(regions.begin(), regions.end(),
              [](const Region& a, const Region& b) { return a.samples.front() < b.samples.front(); });
    samples_beside(samples, free, p, regions);
    return regions;
}

// A row or join is laid in (u, v) coordinates: u along it, v across. Rows run along x (u = x,
// v = y), along y (u = y, v = x), or along any horizontal direction `d` (v along `n`, d turned a
// quarter counter-clockwise). The axes' frames are computed as such (no rounding).
struct Frame {
    enum Axis { x, y, any } axis = x;
    Vec3 d{1, 0, 0}, n{0, 1, 0};
    static Frame along(double angle) {
        Frame f;
        f.axis = any, f.d = {std::cos(angle), std::sin(angle), 0}, f.n = {-f.d.y, f.d.x, 0};
        return f;
    }
    static Frame along_axis(bool along_x) {
        Frame f;
        if (!along_x) f.axis = y, f.d = {0, 1, 0}, f.n = {1, 0, 0};
        return f;
    }
    Vec3 at(double u, double v, double z) const {
        if (axis == x) return {u, v, z};
        if (axis == y) return {v, u, z};
        return {u * d.x + v * n.x, u * d.y + v * n.y, z};
    }
    double u(const Vec3& a) const { return axis == x ? a.x : axis == y ? a.y : a.x * d.x + a.y * d.y; }
    double v(const Vec3& a) const { return axis == x ? a.y : axis == y ? a.x : a.x * n.x + a.y * n.y; }
};

// The floor and top of a wall at one station: the top a gap under the lowest ceiling over its
// width (its middle and both faces), and no higher than the ceiling a side clearance beside it
// (and beyond it along the row, where it may end), all of it this region's overhang (near a
// sample of it); the floor the bed, or a gap over a level face of the model the same under all of
// it (the hybrid's: hybrid_height under the top, with room below every probe: hybrid_floor).
// Nothing where any part is not so. Under a ceiling sloping across the wall the gap alone keeps the
// side clearance at the top (an overhang rises at most 1 : tan(critical angle) < gap : clearance
// over it), so the top is not lowered by the slope over the clearance: the lower face's edge of a
// long top stays a contact along its length under a 35 degree slope (a twisted blade's underside).
// The hybrid's tops stay a gap under the lowest ceiling over the clearance too: its regions are
// priced with the tree under their feet, and with the raised tops the wheel at 80 mm lost its
// hybrid (estimate 26.5 -> 31.2 min on Cura) and rocker_arm got a dearer one (12.7 -> 13.3).
std::optional<std::pair<double, double>> station_of(const ModelQuery& q, const XyGrid<std::size_t>& region,
                                                    const std::vector<Sample>& samples, const Vec3& c, const Vec3& across,
                                                    const Params& p, double overhang_nz, double thickness, bool wide_ref = false) {
    const double half = 0.5 * thickness + tip_side_clearance(p), rise = same_surface_rise(p, p.sampling_distance);
    const Vec3 along{across.y, -across.x, 0};  // a wall may end at this station: clearance beyond it too
    const double side = tip_side_clearance(p);
    const bool walls = !lays_out_hybrid(p);
    const double edge = 0.5 * thickness;
    double lowest = INFINITY, floor_lo = INFINITY, floor_hi = -INFINITY, beside = INFINITY;
    const std::array<Vec3, 7> offsets{Vec3{}, across * -half, across * half, along * side, along * -side, across * -edge, across * edge};
    for (std::size_t k = 0; k < (walls ? 7u : 5u); ++k) {
        const Vec3 x = c + offsets[k];
        std::optional<double> z_ref;
        // The stretch of surface of a sample within a sampling distance; else within the reach
        // by which regions join samples (a narrow strip sampled along its edge only).
        for (const double within : {1.0, wide_ref ? kRegionJoin : 1.0}) {
            region.visit_near(x, within > 1 ? 2 : 1, [&](std::size_t i) {
                if (horizontal_distance(samples[i].p, x) > within * p.sampling_distance) return false;
                z_ref = samples[i].p.z;
                return true;
            });
            if (z_ref) break;
        }
        if (!z_ref) return std::nullopt;
        auto z = ceiling_near(q, x.x, x.y, *z_ref, rise, overhang_nz);
        if (!z) return std::nullopt;
        auto floor = floor_under(q, {x.x, x.y, *z}, p);
        if (!floor) return std::nullopt;
        const bool over_width = k == 0 || k >= 5 || !walls;
        (over_width ? lowest : beside) = std::min(over_width ? lowest : beside, *z);
        floor_lo = std::min(floor_lo, *floor), floor_hi = std::max(floor_hi, *floor);
    }
    const double top = std::min(lowest - p.gap, beside);
    if (lays_out_hybrid(p)) return std::pair{top - p.hybrid_height, top};  // the foot follows the top
    if (floor_hi - floor_lo > p.layer_height) return std::nullopt;
    if (top - floor_hi < touching_space(p)) return std::nullopt;
    return std::pair{floor_hi, top};
}

// A station of a wall as thick as its height asks (wall_thickness_for): probed at the wall
// thickness, and again at the strength rule's width where the wall is taller (its side clearance
// then kept from the thicker wall). {floor, top, thickness}.
struct Station {
    double floor, top, thickness;
};
std::optional<Station> station(const ModelQuery& q, const XyGrid<std::size_t>& region, const std::vector<Sample>& samples,
                               const Vec3& c, const Vec3& across, const Params& p, double overhang_nz,
                               bool wide_ref = false) {
    auto st = station_of(q, region, samples, c, across, p, overhang_nz, p.wall_thickness, wide_ref);
    if (!st) return std::nullopt;
    const double t = wall_thickness_for(p, st->second - st->first);
    if (t <= p.wall_thickness) return Station{st->first, st->second, p.wall_thickness};
    auto thick = station_of(q, region, samples, c, across, p, overhang_nz, t, wide_ref);
    if (!thick) return std::nullopt;
    return Station{thick->first, thick->second, t};  // no taller than the first probe: t is enough
}

// A row goes on under a hole through its ceiling (a screw or button hole in a lid, an ear's bolt
// hole) rather than stopping a side clearance short of it on both sides: one piece, so one island
// fewer on every layer, and its top holds the hole's rim up to its edge (the lid of
// bench/validation/enclosure_lid left its holes' rims to small trees). Crossed where the row's
// stations stop for at most this far (mm) and go on over the same floor: a PCB tray's 20 mm
// connector cutout and a motor mount's 22 mm bore, parts the generator was never tuned on, are
// crossed (at 15 mm the tray kept 14 tips, at 25 mm 1). Longer stretches were not measured: the
// wall there holds nothing up.
constexpr double kMostCrossed = 25;

// May the wall go on at `top` over `floor`, `thickness` wide, from station u_from to u_to of the
// row at v, where no station fits? Where nothing of the model comes within a gap over that top and
// a side clearance beside it, the floor is the same all along, and the model right above is the
// ceiling the wall holds (within a gap and a layer, as contact_above finds it), nothing (a hole
// through it) or no overhang (nothing the tree must still reach from below). Walls cross up to
// kMostCrossed; the hybrid's piece (lays_out_hybrid) only what one of its pieces spans from its
// foot (cut_at_feet: twice the long top): a longer crossing stands a foot, a tip of the tree, under
// the hole, holding nothing (a motor mount's 22 mm bore, crossed whole, printed slower on both
// slicers; within one piece, faster on both).
bool may_cross(const ModelQuery& q, const Frame& f, double v, double u_from, double u_to, double top, double floor,
               double thickness, const Params& p, double overhang_nz) {
    const double most = lays_out_hybrid(p) ? 2 * long_top(p, thickness) : kMostCrossed;  // walls: on the bed
    if (u_to - u_from > most || top - floor < touching_space(p)) return false;
    const double half = 0.5 * thickness + tip_side_clearance(p), over = top + 0.5 * p.gap, lowest = floor + 1e-3;
    const int n = static_cast<int>(std::ceil((u_to - u_from) / kStation));
    for (const double off : {-half, 0.0, half}) {
        if (q.segment_hits(f.at(u_from, v + off, over), f.at(u_to, v + off, over))) return false;
        for (int k = 1; k < n; ++k) {
            const Vec3 c = f.at(u_from + (u_to - u_from) * k / n, v + off, top);
            if (q.segment_hits({c.x, c.y, lowest}, {c.x, c.y, over})) return false;
            if (off == 0) {
                const auto under = floor_under(q, {c.x, c.y, top + p.gap}, p);
                if (!under || (!lays_out_hybrid(p) && std::abs(*under - floor) > 0.5 * p.layer_height)) return false;
            }
            if (auto hit = q.first_hit(c, {0, 0, 1}); hit && hit->point.z - top > p.gap + p.layer_height) {
                const Vec3 nrm = face_normal_unnormalized(q.mesh(), q.mesh().faces[hit->face]);
                if (nrm.z < overhang_nz * norm(nrm)) return false;
            }
        }
    }
    return true;
}

// The walls along one line (u from u0 to u1 at v): runs of stations where a wall fits, crossing
// holes (may_cross).
std::vector<Run> walls_along(const ModelQuery& q, const XyGrid<std::size_t>& region, const std::vector<Sample>& samples,
                             const Frame& f, double v, double u0, double u1, const Params& p, double overhang_nz,
                             bool wide_ref = false) {
    const Vec3 across = f.at(0, 1, 0);
    const int n = static_cast<int>(std::floor((u1 - u0) / kStation));
    std::vector<std::optional<Station>> st(n + 1);
    for (int i = 0; i <= n; ++i) st[i] = station(q, region, samples, f.at(u0 + i * kStation, v, 0), across, p, overhang_nz, wide_ref);
    std::vector<Run> out;
    Run cur;
    auto close = [&] {
        if (cur.top.size() >= 2 && horizontal_distance(cur.top.front(), cur.top.back()) >= kMinWall) out.push_back(cur);
        cur = Run{};
    };
    auto add = [&](int i, double top, double floor, double thickness) {
        const Vec3 c = f.at(u0 + i * kStation, v, 0);
        cur.top.push_back({c.x, c.y, top});
        cur.floor.push_back(floor);
        cur.thickness.push_back(thickness);
    };
    for (int i = 0; i <= n; ++i) {
        if (st[i]) {
            add(i, st[i]->top, st[i]->floor, st[i]->thickness);
            continue;
        }
        int j = i;
        while (j <= n && !st[j]) ++j;
        if (!cur.top.empty() && j <= n && std::abs(st[j]->floor - cur.floor.back()) <= 0.5 * p.layer_height) {
            const double top = std::min(cur.top.back().z, st[j]->top), floor = std::max(cur.floor.back(), st[j]->floor);
            // Both ends are at least as tall as the crossing, so as thick as its height asks.
            const double thickness = std::max(cur.thickness.back(), st[j]->thickness);
            if (may_cross(q, f, v, u0 + (i - 1) * kStation, u0 + j * kStation, top, floor, thickness, p, overhang_nz)) {
                for (int k = i; k < j; ++k) add(k, top, floor, thickness);
                i = j - 1;
                continue;
            }
        }
        close();
        i = j - 1;
    }
    close();
    return out;
}

// A join between rows at v_a and v_b, at u: the wall across, or nothing where it does not fit.
std::optional<Run> join_at(const ModelQuery& q, const XyGrid<std::size_t>& region, const std::vector<Sample>& samples,
                           const Frame& f, double u, double v_a, double v_b, const Params& p, double overhang_nz,
                           bool wide_ref = false) {
    const Vec3 side = f.at(1, 0, 0);
    Run w;
    w.join = true;
    const int n = std::max(1, static_cast<int>(std::ceil((v_b - v_a) / kStation)));
    for (int i = 0; i <= n; ++i) {
        const Vec3 c = f.at(u, v_a + (v_b - v_a) * i / n, 0);
        auto st = station(q, region, samples, c, side, p, overhang_nz, wide_ref);
        if (!st) return std::nullopt;
        w.top.push_back({c.x, c.y, st->top});
        w.floor.push_back(st->floor);
        w.thickness.push_back(st->thickness);
    }
    return w;
}

// A wall along the segment from `from` to `to` (their z ignored), stations kStation apart, up to
// the first station where none fits or where its top rises more than half a layer over the first
// station's; nothing where not even two stations are left (a slanted tail).
std::optional<Run> level_run(const ModelQuery& q, const XyGrid<std::size_t>& region, const std::vector<Sample>& samples,
                             const Vec3& from, const Vec3& to, const Params& p, double overhang_nz, bool wide_ref) {
    const double length = horizontal_distance(from, to);
    if (length <= 0) return std::nullopt;
    const Vec3 side{(to.y - from.y) / length, -(to.x - from.x) / length, 0};
    Run w;
    const int n = std::max(1, static_cast<int>(std::ceil(length / kStation)));
    for (int i = 0; i <= n; ++i) {
        const Vec3 c = from + (to - from) * (static_cast<double>(i) / n);
        auto st = station(q, region, samples, {c.x, c.y, 0}, side, p, overhang_nz, wide_ref);
        if (!st || (!w.top.empty() && st->top > w.top.front().z + 0.5 * p.layer_height)) break;
        w.top.push_back({c.x, c.y, st->top});
        w.floor.push_back(st->floor);
        w.thickness.push_back(st->thickness);
    }
    if (w.top.size() < 2) return std::nullopt;
    return w;
}

// How far a row may be cut back to end flush with a join.
constexpr double kMaxCut = 1.5;

// Can the row (stations in increasing u) end at u = `end` on that side, cutting at most kMaxCut,
// without losing its other end?
bool can_end_at(const Run& w, double end, const Frame& f, bool high_end) {
    const double first = f.u(w.top.front()), last = f.u(w.top.back());
    if (high_end) return end <= last + 1e-9 && last - end <= kMaxCut && end - first >= kMinWall;
    return end >= first - 1e-9 && end - first <= kMaxCut && last - end >= kMinWall;
}

// Cuts the row to end at u = `end` on that side; the new end's top is the lower, its floor the
// higher, of the stations around it (the ceiling between them is not known finer).
void end_at(Run& w, double end, const Frame& f, bool high_end) {
    Run kept;
    kept.join = w.join, kept.tail = w.tail;
    double z = INFINITY, floor = -INFINITY, thickness = 0;
    for (std::size_t i = 0; i < w.top.size(); ++i) {
        const double u = f.u(w.top[i]);
        const bool inside = high_end ? u < end - 1e-9 : u > end + 1e-9;
        if (std::abs(u - end) < kStation - 1e-9)
            z = std::min(z, w.top[i].z), floor = std::max(floor, w.floor[i]), thickness = std::max(thickness, w.thickness[i]);
        if (inside) kept.top.push_back(w.top[i]), kept.floor.push_back(w.floor[i]), kept.thickness.push_back(w.thickness[i]);
    }
    const Vec3 cut = f.at(end, f.v(w.top.front()), z);
    if (high_end) kept.top.push_back(cut), kept.floor.push_back(floor), kept.thickness.push_back(thickness);
    else
        kept.top.insert(kept.top.begin(), cut), kept.floor.insert(kept.floor.begin(), floor),
            kept.thickness.insert(kept.thickness.begin(), thickness);
    w = std::move(kept);
}

struct RegionWalls {
    std::vector<Run> walls;
    double length = 0;        // of all walls, mm
    std::size_t pieces = 0;   // separate meanders (islands per layer)
    std::size_t turned = 0;   // joins placed at the other end than the meander's (prefer_near)
    std::size_t tails = 0;    // the rows' tails (add_tails, slanted_tails)
    double height = 0;        // mean top height
};

// Seconds the region's walls add on a route: each run's line on every layer it spans, plus, on
// every layer, the route's price of each meander's island (SlicerRoute::wall_island_s: the hop to
// it, its retraction, start and stop), as walls_seconds prices the walls the pipeline keeps.
double walls_route_seconds(const SlicerRoute& r, const RegionWalls& w, const Params& p) {
    double s = 0;
    for (const Run& run : w.walls) {
        double height = 0, thickness = 0;
        for (std::size_t i = 0; i < run.top.size(); ++i)
            height += run.top[i].z - run.floor[i], thickness = std::max(thickness, run.thickness[i]);
        height /= run.top.size();
        s += wall_line_seconds(r, horizontal_distance(run.top.front(), run.top.back()), height, thickness, p);
    }
    const double layers = w.height / p.layer_height, pieces = static_cast<double>(w.pieces);
    return s + layers * pieces * r.wall_island_s;
}

// Rows along a region's longer side: fewer, longer rows.
bool longer_along_x(const Region& r) { return r.box.max.x - r.box.min.x >= r.box.max.y - r.box.min.y; }

// Which way the rows run: where the ceiling is level. A sloping or round ceiling then gets long
// flat pieces, each a contact along its whole top (a row down a slope would be a staircase of
// short pieces, each holding the ceiling at its middle only). Level is judged between lattice
// neighbours: along x or y, whichever changes height less, where they differ by more than half a
// layer over a sampling distance on average (a flat piece ends where its ceiling changes by half
// a layer); where it changes alike both ways (a dome, a slope diagonal to the axes), along the
// region's longer side; nothing where it is level both ways, changing by half a layer or less
// (flat: rows along the longer side, and the hybrid's across it too). Taken as flat where the
// changes rose alike, rows across cost spot 35 % more CPU in the kept pose and changed nothing.
std::optional<bool> level_along_x(const Region& r, const XyGrid<std::size_t>& grid, const std::vector<Sample>& samples, const Params& p) {
    const double sd = p.sampling_distance;
    double change[2] = {0, 0};
    std::size_t pairs[2] = {0, 0};
    for (std::size_t i : r.samples)
        for (int axis = 0; axis < 2; ++axis) {
            const Vec3 at = samples[i].p + (axis == 0 ? Vec3{sd, 0, 0} : Vec3{0, sd, 0});
            grid.visit_near(at, 1, [&](std::size_t j) {
                if (horizontal_distance(samples[j].p, at) > 0.25 * sd) return false;
                change[axis] += std::abs(samples[j].p.z - samples[i].p.z), ++pairs[axis];
                return true;
            });
        }
    if (pairs[0] > 0 && pairs[1] > 0) {
        const double along_x = change[0] / pairs[0], along_y = change[1] / pairs[1];
        if (std::abs(along_x - along_y) > 0.5 * p.layer_height) return along_x < along_y;
        if (std::max(along_x, along_y) > 0.5 * p.layer_height) return longer_along_x(r);
    }
    return std::nullopt;
}

// The direction between x and y along which the region's ceiling changes height least (a bore or
// tunnel whose axis runs diagonally, a sloped roof whose contour lines do, a twisted blade's
// underside along its length), where rows along it would be level and rows along `axis` (the
// axis level_along_x chose, or the longer side) would not: the slope at each sample is the slope
// of the face of the ceiling right above it (Region::slopes, as free_regions asked them), and the direction is the one of least mean
// squared slope over the region's samples (the smaller principal direction of the slopes). Given
// where it is more than kLevelTurn from the axis, and a sampling distance along the axis changes
// height by more than half a layer more than along it (level_along_x's threshold) and by more than
// kLevelContrast times as much: the ceiling is level along it, not merely less curved (a curved
// organic underside has no level direction; rows there stay along an axis).
constexpr double kLevelTurn = 5.0;  // degrees
constexpr double kLevelContrast = 2.0;

std::optional<double> level_direction(const Region& r, const Params& p, const Frame& axis) {
    const double sd = p.sampling_distance;
    const SlopeMoments& m = r.slopes;
    if (m.n < kMinRegion) return std::nullopt;
    const double level = m.level_angle();
    const Vec3 d{std::cos(level), std::sin(level), 0};
    const double turn = rad_to_deg(std::acos(std::min(1.0, std::abs(dot(d, axis.d)))));
    const double across = m.change(axis.d, sd), along = m.change(d, sd);
    if (turn <= kLevelTurn || across - along <= 0.5 * p.layer_height || across <= kLevelContrast * along) return std::nullopt;
    return level;
}

// Where a region's rows run (level_along_x), and its outer rows, which do not depend on the span:
// as far out as walls stand along them (as long as a row just inside the outer samples would):
// where the ceiling goes on past the outer samples (a bore's or tunnel's sides beyond the last
// lattice row) the walls then reach what those samples cover. Where the outer samples lie on the
// rim, the rows stand just inside them (a wall's half width, its side clearance and half a
// station: nothing is above a wall centred on a rim). A region narrower than that gets one row
// down its middle.
struct RowPlan {
    XyGrid<std::size_t> grid;  // the region's samples
    Frame f;
    double u0, u1;             // where rows start and end
    double v_lo, v_hi;         // the outer rows (equal: one row)
    std::vector<Run> lo_runs, hi_runs;
    bool moved = false;        // an outer row stands beyond the outer samples
    double mid = 0, across = 0;  // the rows' middle and the outer rows' distance
    std::vector<Vec3> members;   // the region's samples
};

RowPlan plan_rows(const ModelQuery& q, const Region& r, XyGrid<std::size_t> grid, const Frame& f,
                  const std::vector<Sample>& samples, const Params& p, double overhang_nz) {
    const double inset = 0.5 * p.wall_thickness + tip_side_clearance(p) + 0.5 * kStation;
    // The region's extent across and along the rows (its box, in the axes' frames).
    double lo_u = INFINITY, hi_u = -INFINITY, lo_v = INFINITY, hi_v = -INFINITY;
    std::vector<Vec3> members;
    for (std::size_t i : r.samples) {
        const Vec3& a = samples[i].p;
        members.push_back(a);
        lo_u = std::min(lo_u, f.u(a)), hi_u = std::max(hi_u, f.u(a)), lo_v = std::min(lo_v, f.v(a)), hi_v = std::max(hi_v, f.v(a));
    }
    const double u0 = lo_u - p.sampling_distance, u1 = hi_u + p.sampling_distance;
    auto row_length = [](const std::vector<Run>& runs) {
        double l = 0;
        for (const Run& w : runs) l += horizontal_distance(w.top.front(), w.top.back());
        return l;
    };
    // The outer row on one side (`out` -1: low v, +1: high v), and its walls: stepped out a station
    // at a time from just inside the outer samples while the row stays as long, at most the walls'
    // reach and the inset past them.
    auto outer_row = [&](double sample_v, double out) {
        double v = sample_v - out * inset;
        std::vector<Run> best = walls_along(q, grid, samples, f, v, u0, u1, p, overhang_nz);
        const double need = row_length(best);
        const int steps = static_cast<int>(std::floor((wall_reach(p) + inset) / kStation));
        for (int k = 1; k <= steps && need > 0; ++k) {
            auto runs = walls_along(q, grid, samples, f, sample_v - out * inset + out * k * kStation, u0, u1, p, overhang_nz);
            if (row_length(runs) < need) break;
            v = sample_v - out * inset + out * k * kStation, best = std::move(runs);
        }
        return std::pair{v, best};
    };
    auto one_row = [&](double v, const Params& walls) {
        auto runs = walls_along(q, grid, samples, f, v, u0, u1, walls, overhang_nz);
        return RowPlan{std::move(grid), f, u0, u1, v, v, runs, runs, false, v, 0, members};
    };
    if (hi_v - lo_v - 2 * inset <= 0) return one_row(0.5 * (lo_v + hi_v), p);
    auto [v_lo, lo_runs] = outer_row(lo_v, -1);
    auto [v_hi, hi_runs] = outer_row(hi_v, 1);
    // Outer rows closer than two walls' thickness leave a slot narrower than a wall between them,
    // which a slicer fills or drops and `check` judges as a sliver beside them (0.12 mm wide,
    // failing the strength rule: two rows 0.6 mm apart on enclosure_lid's lip): one row as thick
    // as the two and the slot instead, reaching as far as they did.
    if (v_hi - v_lo < 2 * p.wall_thickness) {
        Params thick = p;
        thick.wall_thickness = v_hi - v_lo + p.wall_thickness;
        return one_row(0.5 * (v_lo + v_hi), thick);
    }
    const bool moved = v_lo != lo_v + inset || v_hi != hi_v - inset;
    const double mid = moved ? 0.5 * (v_lo + v_hi) : 0.5 * (lo_v + hi_v);
    const double across = moved ? v_hi - v_lo : hi_v - lo_v - 2 * inset;
    return {std::move(grid), f, u0, u1, v_lo, v_hi, std::move(lo_runs), std::move(hi_runs), moved, mid, across, std::move(members)};
}

// The region's walls: its planned outer rows, as few rows between as keep them at most `span`
// apart, and the joins.
// Rows at most this far inside the outer samples still reach them (a long top holds the ceiling
// along both its edges; the wall's reach from there, less the inset the outer rows stand at).
double most_pull(const Params& p) { return wall_reach(p) - tip_side_clearance(p) - 0.5 * kStation; }

// A region that narrows along its rows (a blade tapering to its tip, a wedge-shaped ledge): its
// outer row, laid straight at the region's widest, runs off the rim where the rim turns in, and the
// samples past its end that the next row does not reach stay with the tree (each blade of
// bench/validation/propeller kept about 20 tips that way). So the outer row goes on stepped in:
// from its end, on the nearest line a station at a time towards the next row on which a wall
// fits from there on, joined to the end by a short jog across: one line turning twice, the same
// island on every layer. At most kMostTails steps at each end; never closer to the next row than
// two walls' thickness (a slot narrower than a wall, plan_rows).
constexpr int kMostTails = 8;
// An inner row goes on past its end only where a neighbour reaches on past it by more than this:
// rows ending within it of each other end on a rim square to them (their ends waver by a station
// or two along it), not on one crossing them.
constexpr double kTailsPast = 4 * kStation;

// Which tails a layout gives its rows where the region narrows past their ends: none; stepped
// (add_tails: the row goes on parallel, stepped in by jogs, each step a long top); or slanted
// (slanted_tails: straight on from the row's end along the rim). Each is a layout of its own,
// kept where it is faster on both routes (lay_out_ceilings).
enum class Tails { none, stepped, slanted };

// A run made one flat piece: its top the lowest, its floor the highest, its thickness the
// thickest of its stations; false where its floor is not flat (within half a layer).
bool flatten(Run& w, const Params& p) {
    const auto [lo, hi] = std::minmax_element(w.floor.begin(), w.floor.end());
    if (*hi - *lo > 0.5 * p.layer_height) return false;
    double top = INFINITY;
    for (const Vec3& x : w.top) top = std::min(top, x.z);
    for (Vec3& x : w.top) x.z = top;
    std::fill(w.floor.begin(), w.floor.end(), *hi);
    std::fill(w.thickness.begin(), w.thickness.end(), *std::max_element(w.thickness.begin(), w.thickness.end()));
    return true;
}

// Which of a row's runs (stations in increasing u) reaches furthest towards its high end (else
// its low end): where the row ends on that side.
std::size_t furthest_run(const std::vector<Run>& row, const Frame& f, bool high_end) {
    std::size_t at = 0;
    for (std::size_t i = 1; i < row.size(); ++i)
        if (high_end ? f.u(row[i].top.back()) > f.u(row[at].top.back()) : f.u(row[i].top.front()) < f.u(row[at].top.front()))
            at = i;
    return at;
}

// The tails of one row (`row`, at v_row; the next row at v_next) at its `ends` (low, high):
// appended to `row`, each with its `chain` (the run it goes on from's), and their jogs to `jogs`;
// `jogged` per run of `row`: which of its ends a jog holds. An inner row's tails hold the samples
// between its outer neighbour (at v_outer) and the next row; an outer row's (v_outer NaN) all
// those on its side of the next row.
void add_tails(const ModelQuery& q, const RowPlan& plan, const std::vector<Sample>& samples, const Params& p,
               double overhang_nz, double v_row, double v_next, double v_outer, std::array<bool, 2> ends,
               std::vector<Run>& row, std::vector<int>& chain, std::vector<std::array<char, 2>>& jogged,
               std::vector<Run>& jogs, bool wide_ref) {
    const Frame& f = plan.f;
    const double inward = v_next > v_row ? 1 : -1;
    // How far along the rows the region's samples go on the row's side of the next row (and,
    // for an inner row, beyond its outer neighbour: a NaN v_outer compares false).
    double need_lo = INFINITY, need_hi = -INFINITY;
    for (const Vec3& a : plan.members)
        if ((f.v(a) - v_next) * inward < 0 && !((f.v(a) - v_outer) * inward <= 0))
            need_lo = std::min(need_lo, f.u(a)), need_hi = std::max(need_hi, f.u(a));
    if (row.empty() || !(need_lo <= need_hi)) return;
    for (const bool high_end : {false, true}) {
        if (!ends[high_end ? 1 : 0]) continue;
        std::size_t at = furthest_run(row, f, high_end);
        for (int n = 0; n < kMostTails; ++n) {
            const Run& last = row[at];
            const double end = f.u(high_end ? last.top.back() : last.top.front());
            if (high_end ? end >= need_hi - kStation : end <= need_lo + kStation) break;
            const double v_last = f.v(last.top.front());
            const double t = high_end ? last.thickness.back() : last.thickness.front();
            // The jog's outer face is flush with the end; the tail starts at its inner face.
            const double u_jog = high_end ? end - 0.5 * t : end + 0.5 * t, start = high_end ? end - t : end + t;
            const double from = high_end ? start : start - kStation * std::floor((start - plan.u0) / kStation);
            const double to = high_end ? plan.u1 : start;
            std::optional<Run> tail, jog;
            for (int k = 1; !tail; ++k) {
                const double v = v_last + inward * k * kStation;
                if ((v_next - v) * inward < 2 * p.wall_thickness) break;
                auto runs = walls_along(q, plan.grid, samples, f, v, from, to, p, overhang_nz, wide_ref);
                if (runs.empty()) continue;
                Run& first = high_end ? runs.front() : runs.back();
                if (std::abs(f.u(high_end ? first.top.front() : first.top.back()) - start) > 1e-6) continue;
                // A tail holds the rim along its length, a long top (a shorter one holds the ceiling
                // at its middle only: a step round a post at a lid's corner, not a rim turning in).
                if (horizontal_distance(first.top.front(), first.top.back()) < long_top(p, first.thickness.front())) continue;
                // The jog reaches from the row's outer face to the tail's inner one, as one flat
                // piece (the lowest top over it): a step of a station is shorter than a tall
                // wall is thick (the strength rule's), and a piece shorter than it is not built.
                jog = join_at(q, plan.grid, samples, f, u_jog, v_last - inward * 0.5 * t, v + inward * 0.5 * first.thickness.front(),
                              p, overhang_nz, wide_ref);
                if (!jog || !flatten(*jog, p)) continue;
                tail = std::move(first), tail->tail = true;
            }
            if (!tail) break;
            jogged[at][high_end ? 1 : 0] = 1;
            jogs.push_back(std::move(*jog));
            row.push_back(std::move(*tail));
            chain.push_back(chain[at]);
            jogged.push_back({0, 0});
            jogged.back()[high_end ? 0 : 1] = 1;
            at = row.size() - 1;
        }
    }
}

// A row's free end on a rim that crosses the rows (a wedge's diagonal front, a triangular shelf's
// sides, a blade's tapering tip): one neighbour reaches on past it along the rim by more than
// kTailsPast, and the samples between the two ends stayed with the tree, a tip each and an island
// on every layer (bench/validation/wedge_ledge kept about 110 tips so). So the row goes on from its
// end straight towards the neighbour's end, along the rim, and stops with two walls' thickness of
// air left to the neighbour (no slot narrower than a wall, plan_rows). It turns off the row by
// less than a right angle, so a slicer prints row and tail as one line: a tail reaching the
// neighbour would meet it at the rim's acute angle, and PrusaSlicer printed each such corner as an
// island of its own. The tail starts half its thickness back inside the row (no face of one lies
// on the other's) and ends at the first station where no wall fits, or where its top rises more
// than half a layer over the row's end: a tail rising with the ceiling off its row stands alone,
// an island of its own, on the layers over its row's top (on delta_wing's sloping wing slanted
// tails so printed slower on both slicers, and on spot in its auto pose slower on PrusaSlicer,
// 13.0 -> 13.3 min).
// Not where both neighbours reach on (a notch, a hole's rim), nor at ends a join or a stepped tail
// holds (`held`, per run: low, high).
std::vector<Run> slanted_tails(const ModelQuery& q, const RowPlan& plan, const std::vector<Sample>& samples, const Params& p,
                               double overhang_nz, const std::vector<std::vector<Run>>& by_row,
                               const std::vector<std::vector<std::array<char, 2>>>& held, bool wide_ref) {
    const Frame& f = plan.f;
    std::vector<Run> out;
    auto end_point = [&](const Run& r, bool high) { return high ? r.top.back() : r.top.front(); };
    for (std::size_t j = 0; j < by_row.size(); ++j) {
        if (by_row[j].empty()) continue;
        for (const bool high : {false, true}) {
            const std::size_t a = furthest_run(by_row[j], f, high);
            const Run& row = by_row[j][a];
            if (held[j][a][high ? 1 : 0]) continue;
            const Vec3 e = end_point(row, high);
            // The neighbour's end where it reaches on past this one.
            auto past = [&](std::size_t k) -> std::optional<Vec3> {
                if (k >= by_row.size() || by_row[k].empty()) return std::nullopt;
                const Vec3 ek = end_point(by_row[k][furthest_run(by_row[k], f, high)], high);
                if (high ? f.u(ek) > f.u(e) + kTailsPast : f.u(ek) < f.u(e) - kTailsPast) return ek;
                return std::nullopt;
            };
            const auto lo = j > 0 ? past(j - 1) : std::nullopt, hi = past(j + 1);
            if (lo.has_value() == hi.has_value()) continue;
            const Vec3 toward = lo ? *lo : *hi;
            const double t = high ? row.thickness.back() : row.thickness.front();
            const Vec3 from = f.at(f.u(e) + (high ? -0.5 : 0.5) * t, f.v(e), 0);
            const double across = std::abs(f.v(toward) - f.v(e)), keep = (across - 2 * p.wall_thickness - t) / across;
            if (keep <= 0) continue;
            const Vec3 to{from.x + (toward.x - from.x) * keep, from.y + (toward.y - from.y) * keep, 0};
            auto tail = level_run(q, plan.grid, samples, from, to, p, overhang_nz, wide_ref);
            if (tail && horizontal_distance(tail->top.front(), tail->top.back()) >= kMinWall)
                tail->tail = true, out.push_back(std::move(*tail));
        }
    }
    return out;
}

RegionWalls region_walls(const ModelQuery& q, const RowPlan& plan, const std::vector<Sample>& samples, const Params& p,
                         double overhang_nz, double span, const std::vector<Vec3>* prefer_near = nullptr,
                         bool fewer_rows = false, Tails tails = Tails::none) {
    const XyGrid<std::size_t>& grid = plan.grid;
    const Frame& f = plan.f;
    std::vector<std::vector<Run>> by_row;
    std::vector<double> row_v;
    if (plan.v_hi == plan.v_lo) {
        row_v.push_back(plan.v_lo);
        by_row.push_back(plan.lo_runs);
    } else {
        // Spaced from the middle out (the outer rows' own walls where they stand beyond the
        // outer samples).
        int gaps = static_cast<int>(std::ceil(plan.across / span - 1e-9));
        double spacing = plan.across / gaps;
        const double mid = plan.mid;
        // With `fewer_rows`: a row fewer, the span apart, the outer rows pulled in from the outer
        // samples as far as they still reach them (none where that is not enough).
        if (fewer_rows) {
            if (plan.moved || gaps < 2 || 0.5 * (plan.across - (gaps - 1) * span) > most_pull(p)) return {};
            gaps -= 1, spacing = span;
        }
        for (int j = 0; j <= gaps; ++j) {
            const double v = plan.moved && j == 0 ? plan.v_lo : plan.moved && j == gaps ? plan.v_hi : mid + (j - 0.5 * gaps) * spacing;
            row_v.push_back(v);
            by_row.push_back(plan.moved && j == 0      ? plan.lo_runs
                             : plan.moved && j == gaps ? plan.hi_runs
                                                       : walls_along(q, grid, samples, f, v, plan.u0, plan.u1, p, overhang_nz, prefer_near != nullptr));
        }
    }
    RegionWalls out;
    // The outer rows' tails (add_tails), where the region narrows past their ends.
    std::vector<std::vector<int>> chain(by_row.size());
    std::vector<std::vector<std::array<char, 2>>> jogged(by_row.size());
    for (std::size_t j = 0; j < by_row.size(); ++j) {
        chain[j].resize(by_row[j].size());
        std::iota(chain[j].begin(), chain[j].end(), 0);
        jogged[j].assign(by_row[j].size(), {0, 0});
    }
    std::vector<Run> jogs;
    if (tails == Tails::stepped && by_row.size() >= 2) {
        // How far each row reaches along at its low and high end, before any tails.
        std::vector<std::array<double, 2>> reach(by_row.size(), {INFINITY, -INFINITY});
        for (std::size_t j = 0; j < by_row.size(); ++j)
            for (const Run& r : by_row[j])
                reach[j] = {std::min(reach[j][0], f.u(r.top.front())), std::max(reach[j][1], f.u(r.top.back()))};
        for (const std::size_t j : {std::size_t{0}, by_row.size() - 1}) {
            const std::size_t next = j == 0 ? 1 : j - 1;
            add_tails(q, plan, samples, p, overhang_nz, row_v[j], row_v[next], NAN, {true, true}, by_row[j], chain[j],
                      jogged[j], jogs, prefer_near != nullptr);
        }
        // An inner row's end where a rim crosses the rows (a delta wing's leading edge, a wedge's
        // diagonal front): the rows end one by one along it, each past its outer neighbour's end
        // and short of its inner one's, and the samples between it and the inner one past its end
        // stayed with the tree. So it goes on stepped in towards the neighbour that reaches on
        // (kTailsPast beyond it); not where both neighbours do (a notch, a hole's rim).
        for (std::size_t j = 1; j + 1 < by_row.size(); ++j)
            for (const int e : {0, 1}) {
                auto further = [&](std::size_t k) {
                    return e == 1 ? reach[k][1] > reach[j][1] + kTailsPast : reach[k][0] < reach[j][0] - kTailsPast;
                };
                if (!(reach[j][0] <= reach[j][1]) || further(j - 1) == further(j + 1)) continue;
                const std::size_t next = further(j - 1) ? j - 1 : j + 1, outer = next == j - 1 ? j + 1 : j - 1;
                add_tails(q, plan, samples, p, overhang_nz, row_v[j], row_v[next], row_v[outer], {e == 0, e == 1}, by_row[j],
                          chain[j], jogged[j], jogs, prefer_near != nullptr);
            }
    }
    // Which ends (low, high) of each run a join or a stepped tail's jog holds.
    std::vector<std::vector<std::array<char, 2>>> held = jogged;
    std::size_t joins = 0;
    // One join between two rows' chains (a row and its tails): a second would close a cell.
    std::set<std::tuple<std::size_t, int, int>> chains_joined;
    // Where a run stands across: its row's line, or a tail's own.
    auto run_v = [&](std::size_t j, std::size_t a) {
        return chain[j][a] == static_cast<int>(a) ? row_v[j] : f.v(by_row[j][a].top.front());
    };
    // Alternate ends: a meander, one line through the region. With `prefer_near` (samples the
    // meander leaves to the tree) a join goes to the other end where that end is nearer to one of
    // them, within a coverage reach (a rim or a narrow strip at the rows' ends): one join per pair
    // of rows still, so no closed cell (a slicer prints every cell of a ladder as a loop of its own).
    const double near_join = coverage_reach(p.sampling_distance);
    auto nearest = [&](double u, std::size_t j) {
        const Vec3 ja = f.at(u, row_v[j], 0), jb = f.at(u, row_v[j + 1], 0);
        double d = INFINITY;
        for (const Vec3& x : *prefer_near) {
            const double t = std::clamp((f.v(x) - row_v[j]) / (row_v[j + 1] - row_v[j]), 0.0, 1.0);
            d = std::min(d, horizontal_distance(x, ja + (jb - ja) * t));
        }
        return d;
    };
    for (std::size_t j = 0; j + 1 < by_row.size(); ++j)
        for (std::size_t a = 0; a < by_row[j].size(); ++a)
            for (std::size_t b = 0; b < by_row[j + 1].size(); ++b) {
                const auto &wa = by_row[j][a].top, &wb = by_row[j + 1][b].top;
                const double a0 = f.u(wa.front()), a1 = f.u(wa.back());
                const double b0 = f.u(wb.front()), b1 = f.u(wb.back());
                const double lo = std::max(a0, b0), hi = std::min(a1, b1);
                if (hi - lo < kMinWall || chains_joined.count({j, chain[j][a], chain[j + 1][b]})) continue;
                // The join's outer face is flush with the rows' ends, which are cut back to it: a
                // slicer then prints the corner as one line turning (a stub or a T beside it
                // becomes a line of its own).
                const double half = 0.5 * p.wall_thickness;
                bool high_end = j % 2 == 0;
                bool turned = false;
                if (prefer_near) {
                    const double here = nearest(high_end ? hi - half : lo + half, j), there = nearest(high_end ? lo + half : hi - half, j);
                    if (there <= near_join && there < here) high_end = !high_end, turned = true;
                }
                for (int end_tried = 0; end_tried < (turned ? 2 : 1); ++end_tried, high_end = !high_end)
                for (int k = 0; k < 4; ++k) {
                    // An end a tail's jog holds is not cut back.
                    if (jogged[j][a][high_end ? 1 : 0] || jogged[j + 1][b][high_end ? 1 : 0]) break;
                    const double u = high_end ? hi - half - k * kStation : lo + half + k * kStation;
                    const double end = high_end ? u + half : u - half;
                    if (!can_end_at(by_row[j][a], end, f, high_end) || !can_end_at(by_row[j + 1][b], end, f, high_end))
                        break;
                    if (auto w = join_at(q, grid, samples, f, u, run_v(j, a), run_v(j + 1, b), p, overhang_nz, prefer_near != nullptr)) {
                        end_at(by_row[j][a], end, f, high_end);
                        end_at(by_row[j + 1][b], end, f, high_end);
                        out.walls.push_back(*w);
                        held[j][a][high_end ? 1 : 0] = held[j + 1][b][high_end ? 1 : 0] = 1;
                        chains_joined.insert({j, chain[j][a], chain[j + 1][b]});
                        ++joins;
                        if (turned && end_tried == 0) ++out.turned;
                        end_tried = 2;  // placed: the other end is not tried
                        break;
                    }
                }
            }
    // A slanted tail goes on from its row's end, one line with it: an island neither more nor fewer,
    // so it counts as neither a row nor a join.
    if (tails == Tails::slanted && by_row.size() >= 2)
        for (Run& tail : slanted_tails(q, plan, samples, p, overhang_nz, by_row, held, prefer_near != nullptr))
            out.walls.push_back(std::move(tail)), ++out.tails;
    std::size_t rows_kept = 0;
    for (std::size_t j = 0; j < by_row.size(); ++j)
        for (std::size_t a = 0; a < by_row[j].size(); ++a) {
            // Strength: every piece is as thick as the strength rule asks for its height (station).
            out.walls.push_back(std::move(by_row[j][a]));
            ++rows_kept;
        }
    out.tails += jogs.size();
    for (Run& jog : jogs) out.walls.push_back(std::move(jog)), ++joins;
    double height_sum = 0;
    std::size_t stations = 0;
    for (const auto& w : out.walls) {
        out.length += horizontal_distance(w.top.front(), w.top.back());
        for (std::size_t i = 0; i < w.top.size(); ++i) height_sum += w.top[i].z - w.floor[i], ++stations;
    }
    out.height = stations ? height_sum / stations : 0;  // mean wall height
    out.pieces = rows_kept > joins ? rows_kept - joins : 1;
    return out;
}

// A run cut into pieces with a flat top and floor: each as long as the ceiling and floor above and
// below it stay within half a layer, its top the lowest top and its floor the highest floor over
// it. Neighbouring pieces share the station between them.
// Strength: `check` judges each piece as a solid of its own, by its narrower side. Under a steep
// ceiling a flat piece may be one station long (0.5 mm), narrower along the row than the
// thickness the strength rule gave it for its height, and so too slender (the wheel at 80 mm in its
// auto pose: 0.45 mm x 7.5 mm). So a piece goes on past where the ceiling steps, its top the lowest
// over it, until it is as long as it is thick, while its floor stays flat (a piece may not hang over a
// lower floor). One that cannot grow so long is not built: its samples stay with the tree
// (the walls' contacts are found on the pieces built).
// Within kUnsureTop of long_top `check` may judge a top either way (its lattice reach is
// coverage_reach rounded up).
constexpr double kUnsureTop = 1.02;

// A piece shorter than a long top holds the ceiling at its middle only (wall_contacts): a faceted
// or twisted ceiling (a blade exported as facets) wavers along a level row by about half a layer
// every few millimetres, which cut its rows into pieces just short of a long top. So a piece goes
// on past where its ceiling steps by half a layer, while its top stays within a layer (each of its
// points then within a gap and a layer of the ceiling: a contact), until it is surely long.

std::vector<CeilingWall> flat_pieces(const Run& r, const Params& p) {
    std::vector<CeilingWall> out;
    const double flat = 0.5 * p.layer_height;
    auto length = [&](std::size_t a, std::size_t b) { return horizontal_distance(r.top[a], r.top[b]); };
    auto thickest = [&](std::size_t a, std::size_t b) {
        return *std::max_element(r.thickness.begin() + a, r.thickness.begin() + b + 1);
    };
    struct Piece {
        std::size_t end;
        double top, floor;
    };
    // The piece from station i on: flat within half a layer (or, `to_long`, within a layer while
    // shorter than a long top), and on until it is as long as it is thick.
    auto piece_from = [&](std::size_t i, bool to_long) {
        double top_lo = std::min(r.top[i].z, r.top[i + 1].z), top_hi = std::max(r.top[i].z, r.top[i + 1].z);
        double fl_lo = std::min(r.floor[i], r.floor[i + 1]), fl_hi = std::max(r.floor[i], r.floor[i + 1]);
        std::size_t k = i + 1;
        while (k + 1 < r.top.size()) {
            const double t = r.top[k + 1].z, fl = r.floor[k + 1];
            const bool floor_flat = std::max(fl_hi, fl) - std::min(fl_lo, fl) <= flat;
            const double top_range = std::max(top_hi, t) - std::min(top_lo, t);
            const bool too_short = length(i, k) < thickest(i, k);
            const bool short_top = to_long && length(i, k) < kUnsureTop * long_top(p, thickest(i, k)) && top_range <= p.layer_height;
            if (!floor_flat || (top_range > flat && !too_short && !short_top)) break;
            top_lo = std::min(top_lo, t), top_hi = std::max(top_hi, t), fl_lo = std::min(fl_lo, fl), fl_hi = std::max(fl_hi, fl);
            ++k;
        }
        return Piece{k, top_lo, fl_hi};
    };
    std::size_t i = 0;
    while (i + 1 < r.top.size()) {
        Piece piece = piece_from(i, false);
        // Short: longer within a layer where that makes it a long top (else as it was: a staircase
        // down a slope keeps its short pieces, each held at its middle, the middles close).
        if (length(i, piece.end) < kUnsureTop * long_top(p, thickest(i, piece.end)))
            if (const Piece longer = piece_from(i, true); length(i, longer.end) >= kUnsureTop * long_top(p, thickest(i, longer.end)))
                piece = longer;
        const std::size_t k = piece.end;
        const double t = thickest(i, k);
        if (length(i, k) >= t)
            out.push_back({{r.top[i].x, r.top[i].y, 0}, {r.top[k].x, r.top[k].y, 0}, piece.floor, piece.top, r.join, t}),
                out.back().tail = r.tail;
        i = k;
    }
    return out;
}

// Where the model right above a point of a wall's top holds the ceiling, as `check` finds a
// contact: the first face above faces down and lies no more than a gap and a layer up.
std::optional<Vec3> contact_above(const ModelQuery& q, const Vec3& x, const Params& p) {
    Vec3 from = x;
    for (int grazes = 0; grazes < 8; ++grazes) {
        auto hit = q.first_hit(from, {0, 0, 1});
        if (!hit) return std::nullopt;
        const Vec3 n = face_normal_unnormalized(q.mesh(), q.mesh().faces[hit->face]);
        if (std::abs(n.z) <= 1e-9 * norm(n)) {  // along a vertical face: the model is not above
            from = hit->point + Vec3{0, 0, 1e-6};
            continue;
        }
        if (n.z > 0 || hit->point.z - x.z > p.gap + p.layer_height) return std::nullopt;
        return hit->point;
    }
    return std::nullopt;
}

// Where the walls hold the ceiling up, as `check` judges their solids (README "check"): a piece
// whose top is long (two coverage reaches, three times its thickness) along its whole top, one
// whose top is short at its middle. A piece within 2 % of either bound may be judged either way
// (`check`'s lattice reach is coverage_reach rounded up): it counts as holding nothing. Each line
// of contacts is kept as short segments between points the model is right above.
struct Contacts {
    std::vector<std::pair<Vec3, Vec3>> segments;
    XyGrid<std::size_t> near{1.0};  // by each segment's middle
    // The walls' length, and how much of it holds the ceiling narrower than along both edges of
    // its top (short tops, and long ones with an edge held on less than half their length: the
    // ceiling sloping across them).
    double length = 0, narrow = 0;
};

Contacts wall_contacts(const ModelQuery& q, const std::vector<CeilingWall>& walls, const Params& p) {
    Contacts out;
    auto add = [&](const Vec3& a, const Vec3& b) {
        out.near.insert((a + b) * 0.5, out.segments.size());
        out.segments.push_back({a, b});
    };
    const double two_reaches = 2 * coverage_reach(p.sampling_distance);
    for (const auto& w : walls) {
        const Vec3 a{w.from.x, w.from.y, w.top}, b{w.to.x, w.to.y, w.top};
        const double length = horizontal_distance(a, b);
        const bool is_long = length >= kUnsureTop * long_top(p, w.thickness);
        const Vec3 d = (b - a) * (1.0 / length), across = Vec3{-d.y, d.x, 0} * (0.5 * w.thickness);
        out.length += length;
        if (!is_long) {
            out.narrow += length;
            if (length >= two_reaches && length >= 3 * w.thickness / kUnsureTop) continue;  // unsure
            // As `check` finds a short top's contact: at its middle, with the model over the corner
            // (or middle) nearest below it, where that is within a gap and a layer.
            const Vec3 mid = (a + b) * 0.5;
            std::optional<Vec3> nearest;
            for (const Vec3& x : {mid, a + across, a - across, b + across, b - across})
                if (auto c = contact_above(q, x, p); c && (!nearest || c->z - x.z < nearest->z - mid.z))
                    nearest = Vec3{mid.x, mid.y, mid.z + (c->z - x.z)};
            if (nearest) add(*nearest, *nearest);
            continue;
        }
        const int n = static_cast<int>(std::ceil(length / kContactStep));
        bool edges_held = true;
        for (const Vec3 side : {Vec3{}, across, across * -1.0}) {
            std::optional<Vec3> last;
            int held = 0;
            for (int k = 0; k <= n; ++k) {
                const auto c = contact_above(q, a + side + (b - a) * (double(k) / n), p);
                if (c) add(last ? *last : *c, *c), ++held;
                last = c;
            }
            if (side.x != 0 || side.y != 0) edges_held = edges_held && 2 * held >= n + 1;
        }
        if (!edges_held) out.narrow += length;
    }
    return out;
}

// Is x within `reach` of a contact of the walls, on the same stretch of surface (overhang.hpp's
// `covers`, the sampling's own rule)?
// `hint`: a segment to ask first (the one that covered a point nearby), updated to the one found.
// `reach`: Cover(the reach, the critical angle).
bool near_contact(const Contacts& c, const Vec3& x, const Cover& reach, std::size_t* hint = nullptr) {
    auto covered_by = [&](std::size_t i) {
        const auto& [a, b] = c.segments[i];
        const double dx = b.x - a.x, dy = b.y - a.y, l2 = dx * dx + dy * dy;
        const double t = l2 > 0 ? std::clamp(((x.x - a.x) * dx + (x.y - a.y) * dy) / l2, 0.0, 1.0) : 0.0;
        return reach(a + (b - a) * t, x);
    };
    if (hint && *hint < c.segments.size() && covered_by(*hint)) return true;
    const long rings = static_cast<long>(std::ceil((reach.reach + kContactStep) / c.near.cell()));
    return c.near.visit_near(x, rings, [&](std::size_t i) {
        if (!covered_by(i)) return false;
        if (hint) *hint = i;
        return true;
    });
}

// What `check` judges of the model's surface (check/judge_overhangs.hpp, on the model as written:
// float vertices, identical ones welded), as points: overhang faces (the lattice points a probe
// step apart inside each, and points as far apart along its edges, its corners among them), ridges
// (convex edges between two faces facing down, flatter than the critical angle) along their
// length, and lowest vertices (every neighbour higher). A point `check` judges lies within 1.21
// probe steps of one (half a diagonal to the nearest lattice point, or across the face's edge to
// it and half a step along the edge). A superset by a hair (kJudgedSlack): a face, edge or vertex
// within rounding of check's bounds counts. The steep undersides beside an overhang (a bore's
// sides) are not judged, so they ask nothing of the walls. Made cell by cell on first use, from the
// faces that touch the cell: an edge or vertex inside it has all its faces there.
constexpr double kJudgedSlack = 1e-6;

class JudgedSurface {
public:
    JudgedSurface(const Mesh& m, double step, const Box3& near, double critical_angle)
        : step_(step), overhang_nz_(-std::sin(deg_to_rad(critical_angle))), line_ez_(std::cos(deg_to_rad(critical_angle))),
          faces_(kCell), points_(kCell) {
        // As written: float vertices (the .model.stl), equal ones (as floats compare: -0 is +0, a
        // NaN equals nothing) one vertex, numbered as they first come. Only the faces near the
        // walls are kept (welded as they come).
        FlatIndex welded;
        std::vector<std::uint32_t> vertex(m.vertices.size(), kNone);
        auto weld = [&](std::uint32_t v) {
            if (vertex[v] == kNone) {
                const Vec3 key{float(m.vertices[v].x), float(m.vertices[v].y), float(m.vertices[v].z)};
                const auto [at, fresh] = welded.insert(
                    float_hash(key), at_.size(), [&](std::size_t i) { return at_[i] == key; },
                    [&](std::size_t i) { return float_hash(at_[i]); });
                if (fresh) at_.push_back(key);
                vertex[v] = static_cast<std::uint32_t>(at);
            }
            return vertex[v];
        };
        for (const auto& f : m.faces) {
            // The face's box (Box3::add's, by comparisons: its std::fmin and std::fmax are library
            // calls, six a corner, for every face of the model; they differ only in which zero
            // they keep of -0 and +0, which compare and index the same here, and both skip a NaN).
            Box3 box;
            for (auto v : f) {
                const Vec3& p = m.vertices[v];
                box.min = {p.x < box.min.x ? p.x : box.min.x, p.y < box.min.y ? p.y : box.min.y, p.z < box.min.z ? p.z : box.min.z};
                box.max = {p.x > box.max.x ? p.x : box.max.x, p.y > box.max.y ? p.y : box.max.y, p.z > box.max.z ? p.z : box.max.z};
            }
            if (!overlaps(box, near)) continue;
            const Triangle t{weld(f[0]), weld(f[1]), weld(f[2])};
            if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) continue;  // welded away
            for (long i = faces_.index(box.min.x); i <= faces_.index(box.max.x); ++i)
                for (long j = faces_.index(box.min.y); j <= faces_.index(box.max.y); ++j) faces_.insert_at(i, j, tris_.size());
            tris_.push_back(t);
        }
    }

    // Calls visit(point) for the points within `radius` of c (horizontally) until it returns true.
    template <typename Visit>
    bool visit_near(const Vec3& c, double radius, Visit visit) {
        const Reach near(radius);
        for (long i = points_.index(c.x - radius); i <= points_.index(c.x + radius); ++i)
            for (long j = points_.index(c.y - radius); j <= points_.index(c.y + radius); ++j)
                for (const Vec3& x : cell(i, j))
                    if (near(x, c) && visit(x)) return true;
        return false;
    }

private:
    static constexpr double kCell = 1.0;
    static constexpr std::uint32_t kNone = ~std::uint32_t{0};
    // A hash of a vertex at float precision, equal for equal vertices (-0 as +0).
    static std::uint64_t float_hash(const Vec3& v) {
        std::uint64_t h = 0x9e3779b97f4a7c15ull;
        for (const double x : {v.x, v.y, v.z}) {  // splitmix64 over each coordinate's bits
            std::uint64_t z = h ^ std::bit_cast<std::uint64_t>(x == 0 ? 0.0 : x);
            z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
            z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
            h = z ^ (z >> 31);
        }
        return h;
    }

    Vec3 unit_normal(const Triangle& t) const {
        const Vec3 n = cross(at_[t[1]] - at_[t[0]], at_[t[2]] - at_[t[0]]);
        const double l = norm(n);
        return l > 0 ? n / l : Vec3{};
    }

    const std::vector<Vec3>& cell(long i, long j) {
        if (const auto* done = points_.at(i, j)) return *done;
        std::vector<Vec3> out;
        auto inside_cell = [&](const Vec3& x) { return points_.index(x.x) == i && points_.index(x.y) == j; };
        auto along = [&](const Vec3& u, const Vec3& v) {
            const int n = std::max(1, static_cast<int>(std::ceil(distance(u, v) / step_)));
            // Only the steps near the cell are made (a long edge crosses many cells); which of
            // them lie inside is decided as before, on the point itself.
            double lo = 0, hi = n;
            for (const auto [a, b, c0] : {std::array{u.x, v.x, double(i)}, std::array{u.y, v.y, double(j)}}) {
                const double d = b - a;
                if (d == 0) continue;
                const double t0 = (c0 * kCell - a) / d * n, t1 = ((c0 + 1) * kCell - a) / d * n;
                lo = std::max(lo, std::floor(std::min(t0, t1)) - 2), hi = std::min(hi, std::ceil(std::max(t0, t1)) + 2);
            }
            if (!(lo <= hi)) return;  // the edge passes by (or a NaN, which no cell holds)
            for (int k = static_cast<int>(lo); k <= static_cast<int>(hi); ++k)
                if (const Vec3 x = u + (v - u) * (double(k) / n); inside_cell(x)) out.push_back(x);
        };
        if (const auto* faces = faces_.at(i, j)) {
            // Each face's corners by edge and by vertex, tagged with their order here (face, then
            // corner), sorted by key, then by that order: the edges and vertices come in key order and
            // each one's faces in the order they came, as a std::map of lists gives them, without a
            // node per entry (this was most of the stage on small models).
            const std::size_t corners = 3 * faces->size();
            std::vector<std::pair<std::uint64_t, std::uint32_t>> by_edge(corners), by_vertex(corners);
            for (std::size_t n = 0; n < faces->size(); ++n) {
                const Triangle& t = tris_[(*faces)[n]];
                for (int k = 0; k < 3; ++k) {
                    const auto [a, b] = std::minmax(t[k], t[(k + 1) % 3]);
                    const auto corner = static_cast<std::uint32_t>(3 * n + k);
                    by_edge[3 * n + k] = {(std::uint64_t(a) << 32) | b, corner};
                    by_vertex[3 * n + k] = {t[k], corner};
                }
                if (unit_normal(t).z < overhang_nz_ + kJudgedSlack) face_points(t, i, j, out, along);
            }
            std::sort(by_edge.begin(), by_edge.end());
            std::sort(by_vertex.begin(), by_vertex.end());
            auto face_of = [&](std::uint32_t corner) { return (*faces)[corner / 3]; };
            for (std::size_t r = 0; r < corners;) {  // each edge's run of faces: a ridge has two
                std::size_t end = r + 1;
                while (end < corners && by_edge[end].first == by_edge[r].first) ++end;
                const std::pair<std::uint32_t, std::uint32_t> e{std::uint32_t(by_edge[r].first >> 32), std::uint32_t(by_edge[r].first)};
                if (end - r == 2 && is_ridge(e, tris_[face_of(by_edge[r].second)], tris_[face_of(by_edge[r + 1].second)]))
                    along(at_[e.first], at_[e.second]);
                r = end;
            }
            // Every neighbour higher, compared exactly: these are check's own float coordinates
            // (a flat face's corners are not lowest). A vertex's lowest neighbour is folded in the
            // faces' order, as std::min({lowest, ...}) did it (the same value, NaNs included).
            for (std::size_t r = 0; r < corners;) {
                const std::uint32_t v = static_cast<std::uint32_t>(by_vertex[r].first);
                double z = INFINITY;
                for (; r < corners && by_vertex[r].first == v; ++r) {
                    const std::uint32_t corner = by_vertex[r].second;
                    const Triangle& t = tris_[face_of(corner)];
                    const int k = static_cast<int>(corner % 3);
                    z = std::min({z, at_[t[(k + 1) % 3]].z, at_[t[(k + 2) % 3]].z});
                }
                if (z > at_[v].z && inside_cell(at_[v])) out.push_back(at_[v]);
            }
        }
        points_.insert_at(i, j, Vec3{});  // marks the cell made (an empty list stays findable)
        auto& stored = const_cast<std::vector<Vec3>&>(*points_.at(i, j));
        stored = std::move(out);
        return stored;
    }

    // The lattice points of cell (i, j) inside an overhang face (projected), z from its plane,
    // and points along its edges.
    template <typename Along>
    void face_points(const Triangle& t, long i, long j, std::vector<Vec3>& out, Along along) const {
        const Vec3 &a = at_[t[0]], &b = at_[t[1]], &c = at_[t[2]];
        along(a, b), along(b, c), along(c, a);
        const double det = (b.x - a.x) * (c.y - a.y) - (c.x - a.x) * (b.y - a.y);
        if (std::abs(det) < 1e-12) return;
        const double x0 = i * kCell, y0 = j * kCell;
        const double lo_x = std::max(x0, std::min({a.x, b.x, c.x})), hi_x = std::min(x0 + kCell, std::max({a.x, b.x, c.x}));
        const double lo_y = std::max(y0, std::min({a.y, b.y, c.y})), hi_y = std::min(y0 + kCell, std::max({a.y, b.y, c.y}));
        for (double x = std::ceil(lo_x / step_) * step_; x <= hi_x; x += step_)
            for (double y = std::ceil(lo_y / step_) * step_; y <= hi_y; y += step_) {
                const double l1 = ((x - a.x) * (c.y - a.y) - (c.x - a.x) * (y - a.y)) / det;
                const double l2 = ((b.x - a.x) * (y - a.y) - (x - a.x) * (b.y - a.y)) / det;
                if (l1 < 0 || l2 < 0 || l1 + l2 > 1) continue;
                const Vec3 pt{x, y, a.z + l1 * (b.z - a.z) + l2 * (c.z - a.z)};
                if (points_.index(pt.x) == i && points_.index(pt.y) == j) out.push_back(pt);
            }
    }

    // A ridge as `check` finds one: two faces facing down, not both overhangs (their points are
    // judged already), the edge flatter than the critical angle and the lowest line of its
    // cross-section (both faces rise away from it).
    bool is_ridge(std::pair<std::uint32_t, std::uint32_t> e, const Triangle& f0, const Triangle& f1) const {
        const Vec3 n0 = unit_normal(f0), n1 = unit_normal(f1);
        if (n0.z < overhang_nz_ - kJudgedSlack && n1.z < overhang_nz_ - kJudgedSlack) return false;
        if (!(n0.z < kJudgedSlack && n1.z < kJudgedSlack)) return false;
        const Vec3 &u = at_[e.first], d = at_[e.second] - u;
        const double l = norm(d);
        if (!(l > 0) || std::abs(d.z) / l >= line_ez_ + kJudgedSlack) return false;
        auto rises = [&](const Triangle& f) {
            Vec3 w;
            for (auto c : f)
                if (c != e.first && c != e.second) w = at_[c] - u;
            const Vec3 away = w - d * (dot(w, d) / dot(d, d));
            return away.z > -kJudgedSlack * norm(away);
        };
        return rises(f0) && rises(f1);
    }

    double step_, overhang_nz_, line_ez_;
    std::vector<Vec3> at_;               // welded vertices, at float precision
    std::vector<Triangle> tris_;         // welded faces near the walls
    XyGrid<std::size_t> faces_;
    XyGrid<Vec3> points_;
};

// Do the walls carry everything the sample at s covers: every point of the surface `check` judges
// within coverage_reach of it on its own stretch of surface (overhang.hpp's `covers`, as the
// sampling counts it) lies within the walls' reach of a contact? Then its tip may go:
// `check` finds every point it held within its own reach of a wall.
// The reaches walls_carry asks at, their rises taken once per stage.
double probe_disc(double r) { return r + kProbeCover * kProbeStepOfReach * r; }
struct CarryReach {
    explicit CarryReach(const Params& p)
        : walls(wall_reach(p), p.critical_angle), disc(probe_disc(coverage_reach(p.sampling_distance)), p.critical_angle) {}
    Cover walls;  // a wall's contact carries what lies within this
    Cover disc;   // every point within coverage_reach has a probe within this
};
bool walls_carry(JudgedSurface& surface, const Contacts& contacts, const Vec3& s, const CarryReach& reach) {
    std::size_t hint = contacts.segments.size();  // the probes come in runs of neighbours
    if (!near_contact(contacts, s, reach.walls, &hint)) return false;
    return !surface.visit_near(s, reach.disc.reach, [&](const Vec3& x) {
        return reach.disc(s, x) && !near_contact(contacts, x, reach.walls, &hint);
    });
}

// One way of laying a region's walls: the runs, their flat pieces, the pieces' contacts as `check`
// finds them, and the region's samples they do not carry.
struct Layout {
    double span = 0;  // the rows' distance
    RegionWalls w;
    std::vector<CeilingWall> pieces;
    Contacts tops;
    std::vector<Sample> left;
    std::vector<std::size_t> carried;  // indices of the region's samples they carry
    std::vector<std::size_t> relied;   // left samples whose tips hold what a carried one held
    std::vector<std::size_t> released; // carried samples release_held let go (of `carried`)
};

// Of the region's samples the walls do not carry (`left`, indices), those whose every point the
// walls leave another left sample's tip also holds: the walls and those tips hold all it held, so
// it goes too (moved to `carried`), and the tips it leans on stay (`relied`: never let go after).
// Under a tapering or sloping ceiling the rows stop short of the rims: a sample between a wall and
// a rim then covers a little of the rim the walls do not reach, and kept it, though the rim's own
// tips hold that. Interior samples first (fewest points left to tips). Each tip holds from where
// it stands (`tip_at`: placement moves it aside), at the walls' reach.
void release_held(JudgedSurface& surface, const Contacts& contacts, const std::vector<Sample>& samples,
                  const TipAt& tip_at, std::vector<std::size_t>& left, std::vector<std::size_t>& carried,
                  std::vector<std::size_t>& relied, std::vector<std::size_t>& released, const CarryReach& reach,
                  const Params& p) {
    if (left.size() < 2) return;
    auto hold = [&](std::size_t i) { return tip_at ? tip_at(samples[i]) : samples[i].p; };
    XyGrid<std::size_t> near(p.sampling_distance);
    for (std::size_t k = 0; k < left.size(); ++k) near.insert(hold(left[k]), k);
    // Each left sample's points the walls leave (as walls_carry finds them, from where its tip holds).
    std::vector<std::vector<Vec3>> bare(left.size());
    std::vector<std::size_t> order(left.size());
    for (std::size_t k = 0; k < left.size(); ++k) {
        order[k] = k;
        const Vec3 h = hold(left[k]);
        std::size_t hint = contacts.segments.size();
        surface.visit_near(h, reach.disc.reach, [&](const Vec3& x) {
            if (reach.disc(h, x) && !near_contact(contacts, x, reach.walls, &hint)) bare[k].push_back(x);
            return false;
        });
    }
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return bare[a].size() < bare[b].size(); });
    std::vector<char> gone(left.size(), 0), pinned(left.size(), 0);
    const long rings = static_cast<long>(std::ceil(reach.walls.reach / p.sampling_distance)) + 1;
    for (std::size_t k : order) {
        if (pinned[k]) continue;
        std::vector<std::size_t> leans;
        bool held = true;
        for (const Vec3& x : bare[k]) {
            std::optional<std::size_t> by;
            near.visit_near(x, rings, [&](std::size_t j) {
                if (j == k || gone[j] || !reach.walls(hold(left[j]), x)) return false;
                if (!by || (pinned[j] && !pinned[*by])) by = j;
                return pinned[j] != 0;
            });
            if (!by) {
                held = false;
                break;
            }
            if (!pinned[*by]) leans.push_back(*by), pinned[*by] = 2;  // tentatively: the next points prefer it
        }
        for (std::size_t j : leans)
            if (pinned[j] == 2) pinned[j] = held ? 1 : 0;
        if (held) gone[k] = 1;
    }
    std::vector<std::size_t> kept;
    for (std::size_t k = 0; k < left.size(); ++k) {
        if (gone[k]) carried.push_back(left[k]), released.push_back(left[k]);
        else kept.push_back(left[k]);
        if (pinned[k]) relied.push_back(left[k]);
    }
    std::sort(carried.begin(), carried.end());
    left = std::move(kept);
}
// Rows this share of twice the walls' reach apart hold the ceiling midway between them where the
// walls hold it along a narrow line: a staircase down a slope is held at each piece's middle only,
// the middles up to a piece (a millimetre or so) apart along the row, so a point midway is a little
// farther from the nearest than half the rows' distance; a ceiling sloping steeply across a row is
// held along the wall's lower edge only. At the span, rows need long tops held along both edges.
// Tried where at least half the walls' length is held so narrowly and rows the span apart leave
// samples to a tree. (Rows
// along the most level direction between x and y leave more than these on a tilted plane over an
// axis-aligned floor plan, at both distances: level_direction's rows are laid out beside the
// axis' and kept only where they leave fewer.)
constexpr double kTightRows = 0.9;

// Walls that cost less than this share of their region's tree on a route are not weighed against
// the rival (support_ceilings): the hybrid puts a tree under its feet below the same tops, and
// where walls were that cheap it never came near them (tuning set and examples at 80 mm: closest
// on bridge, walls 0.38 and 0.23 of the tree on the Cura and PrusaSlicer routes, the hybrid 0.46
// and 0.33), while laying it out cost bridge a third more instructions for the whole run.
constexpr double kRivalFromShare = 1.0 / 3;

// Pieces end to end along one line, with the same top, floor and thickness (a chain of joins down a
// narrow strip), made one: a slicer prints them as one wall anyway, and `check` then finds the long
// top a contact along its length (each short one held the ceiling at its middle only).
std::vector<CeilingWall> merge_in_line(std::vector<CeilingWall> pieces) {
    auto same = [](double a, double b) { return std::abs(a - b) < 1e-9; };
    for (bool merged = true; merged;) {
        merged = false;
        for (std::size_t i = 0; i < pieces.size() && !merged; ++i)
            for (std::size_t j = i + 1; j < pieces.size() && !merged; ++j) {
                CeilingWall &u = pieces[i], &v = pieces[j];
                if (u.on_tree || v.on_tree || !same(u.top, v.top) || !same(u.bottom, v.bottom) || !same(u.thickness, v.thickness))
                    continue;
                const Vec3 du = u.to - u.from, dv = v.to - v.from;
                if (std::abs(du.x * dv.y - du.y * dv.x) > 1e-9 * norm(du) * norm(dv)) continue;  // not parallel
                for (int k = 0; k < 4 && !merged; ++k) {
                    const Vec3 &shared_u = k & 1 ? u.to : u.from, &shared_v = k & 2 ? v.to : v.from;
                    if (horizontal_distance(shared_u, shared_v) > 1e-6) continue;
                    const Vec3 far_u = k & 1 ? u.from : u.to, far_v = k & 2 ? v.from : v.to;
                    // End to end: the shared point between the far ends.
                    if (dot(far_u - shared_u, far_v - shared_u) >= 0) continue;
                    u.from = far_u, u.to = far_v, u.join = u.join && v.join;
                    pieces.erase(pieces.begin() + static_cast<long>(j));
                    merged = true;
                }
            }
    }
    return pieces;
}

// How many separate solids the pieces make as a slicer sees them (pieces touching or overlapping,
// horizontally: they stand on one floor here).
std::size_t islands(const std::vector<CeilingWall>& pieces) {
    std::vector<std::size_t> parent(pieces.size());
    for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = i;
    auto root = [&](std::size_t i) {
        while (parent[i] != i) i = parent[i] = parent[parent[i]];
        return i;
    };
    std::size_t n = pieces.size();
    for (std::size_t i = 0; i < pieces.size(); ++i)
        for (std::size_t j = i + 1; j < pieces.size(); ++j) {
            const CeilingWall &u = pieces[i], &v = pieces[j];
            if (an_end_within(u, v, 0.5 * (u.thickness + v.thickness) + 1e-6) && root(i) != root(j))
                parent[root(i)] = root(j), --n;
        }
    return n;
}

// Rows' short runs that carry nothing the rest does not (a narrow strip crossed by the rows, held
// by the joins along it): dropped, one at a time, where every sample the layout carries stays
// carried. Each is a line of its own to a slicer (a comb's teeth: PrusaSlicer travels and retracts
// to each, CuraEngine draws each out and back). Walls only (a run is one flat piece there).
void drop_idle_stubs(const ModelQuery& q, JudgedSurface& surface, const std::vector<Sample>& samples, const Params& p,
                     Layout& l) {
    const double short_top = 2 * coverage_reach(p.sampling_distance);
    const double near = short_top + 2 * coverage_reach(p.sampling_distance) + p.sampling_distance;
    const CarryReach carry(p);
    for (std::size_t k = l.w.walls.size(); k-- > 0;) {
        const Run& run = l.w.walls[k];
        const Vec3 a = run.top.front(), b = run.top.back();
        if (run.join || horizontal_distance(a, b) >= short_top) continue;
        std::vector<CeilingWall> others;
        for (const CeilingWall& w : l.pieces)
            if (w.join || horizontal_distance(w.from, a) > 1e-9 || horizontal_distance(w.to, b) > 1e-9) others.push_back(w);
        if (others.size() + 1 != l.pieces.size()) continue;         // not one piece of its own
        if (islands(others) > islands(l.pieces)) continue;          // it joins the walls around it
        const Contacts tops = wall_contacts(q, others, p);
        const Vec3 mid = (a + b) * 0.5;
        const bool idle = std::all_of(l.carried.begin(), l.carried.end(), [&](std::size_t i) {
            return horizontal_distance(samples[i].p, mid) > near || walls_carry(surface, tops, samples[i].p, carry);
        });
        if (!idle) continue;
        l.pieces = std::move(others);
        l.tops = tops;
        l.w.length -= horizontal_distance(a, b);
        l.w.walls.erase(l.w.walls.begin() + static_cast<long>(k));
    }
}

// Seconds on the two routes: the Cura support mesh's, then PrusaSlicer's from our 3MF.
using RouteSeconds = std::pair<double, double>;

// Is `a` faster than `b` on both routes? Either slicer may print what is chosen, so a structure
// takes another's place only where both print it faster.
bool faster_on_both(const RouteSeconds& a, const RouteSeconds& b) { return a.first < b.first && a.second < b.second; }

// Seconds the slabs the pipeline makes of these pieces (join_rows_into_slabs) save on the Cura
// route, against the pieces alone: each slab's outline in place of its rows' loops.
double slabs_saving(const ModelQuery& q, const std::vector<CeilingWall>& pieces, const Params& p) {
    return -slabs_seconds(kCuraRoute, join_rows_into_slabs(q, pieces, p), p);
}

// Does any wall's solid (its width across, foot to top) overlap one of the boxes?
bool enters_blocker(const std::vector<Run>& walls, const std::vector<Box3>& blockers, const Params& p) {
    const double half = 0.5 * p.wall_thickness;
    for (const Run& w : walls)
        for (std::size_t i = 0; i < w.top.size(); ++i)
            for (const Box3& b : blockers)
                if (w.top[i].x + half > b.min.x && w.top[i].x - half < b.max.x && w.top[i].y + half > b.min.y &&
                    w.top[i].y - half < b.max.y && w.top[i].z > b.min.z && w.floor[i] < b.max.z)
                    return true;
    return false;
}

}  // namespace

bool ceilings_laid_out(const Params& p) {
    // Rows farther apart than twice the walls' reach (and a wall) carry nothing between them.
    const bool rows_reach = p.ceiling_span <= 2 * wall_reach(p) + p.wall_thickness;
    return p.ceiling_span > 0 && rows_reach && p.strategy == Strategy::tree;
}

Ceilings support_ceilings(const ModelQuery& q, const std::vector<Sample>& samples, const Params& p,
                          const TreeCounter& tree_count, const std::vector<Box3>& blockers, double most_left,
                          const TipAt& tip_at, const RivalSaving& rival) {
    Params walls = p;
    walls.hybrid_height = 0;  // walls stand on the bed or a floor (the hybrid: support_hybrid)
    return lay_out_ceilings(q, samples, walls, [](std::vector<CeilingWall> pieces) { return pieces; },
                            [&](const std::vector<Sample>& s, const std::vector<CeilingWall>&) {
                                return s.empty() ? TreeCount{} : tree_count(s);
                            },
                            blockers, most_left, tip_at, {}, rival);
}

Ceilings lay_out_ceilings(const ModelQuery& q, const std::vector<Sample>& samples, const Params& p,
                          const PiecesRule& finish, const PiecesTreeCounter& tree_count, const std::vector<Box3>& blockers,
                          double most_left, const TipAt& tip_at, const std::vector<char>& stay,
                          const RivalSaving& rival, bool rows_across) {
    Ceilings out;
    if (!ceilings_laid_out(p)) {
        out.rest = samples, out.stay = stay;
        return out;
    }
    const double overhang_nz = -std::sin(deg_to_rad(p.critical_angle));
    const std::vector<Region> regions = free_regions(q, samples, p, stay);
    if (regions.empty()) {
        out.rest = samples, out.stay = stay;
        return out;
    }
    // The surface a sample near the walls may cover: around every region, as far as a sample
    // within reach of its walls covers, and more.
    Box3 near = regions.front().box;
    for (const Region& r : regions)
        near.min = {std::min(near.min.x, r.box.min.x), std::min(near.min.y, r.box.min.y), std::min(near.min.z, r.box.min.z)},
        near.max = {std::max(near.max.x, r.box.max.x), std::max(near.max.y, r.box.max.y), std::max(near.max.z, r.box.max.z)};
    const double margin = 2 * p.sampling_distance + 2 * coverage_reach(p.sampling_distance);
    near.min = near.min - Vec3{margin, margin, margin}, near.max = near.max + Vec3{margin, margin, margin};
    JudgedSurface surface(q.mesh(), kProbeStepOfReach * coverage_reach(p.sampling_distance), near, p.critical_angle);
    const CarryReach carry(p);
    const double tight = std::min(p.ceiling_span, kTightRows * 2 * wall_reach(p));
    // What the chosen regions' own walls carry: more walls only add contacts, so those stay carried.
    std::vector<char> carried(samples.size(), 0), relied = stay;
    relied.resize(samples.size(), 0);
    // Every region whose layout was priced: its layout, its walls' own seconds on both routes (the
    // lines and meanders), the estimates of its choice, and whether it is taken.
    struct Priced {
        Layout l;
        double lines_cura = 0, lines_prusa = 0;
        double tree_cura = 0, tree_prusa = 0, walls_cura = 0, walls_prusa = 0;
        bool taken = false;
    };
    std::vector<Priced> priced;
    auto tree_s = [](const SlicerRoute& route, const TreeCount& c) {
        return tree_route_seconds(route, c.island_layers, c.outline_mm, c.hop_mm);
    };
    for (const Region& r : regions) {
        // Rows the span apart; where they leave samples to a tree, also `tight` apart (a slope's
        // staircase of short pieces), keeping the layout that leaves fewer (the first of equals).
        XyGrid<std::size_t> grid(p.sampling_distance);
        for (std::size_t i : r.samples) grid.insert(samples[i].p, i);
        // Rows along x or y (level_along_x); where the ceiling is level along a direction between
        // them (level_direction), also along that, keeping the rows that leave fewer samples (a
        // region whose rims run along the axes, a tilted rectangle, leaves triangles at the rows'
        // ends that no row reaches and rows no join fits between), of equals the fewer pieces
        // (rows along x or y cross a blade's underside as a staircase).
        const std::optional<bool> level_x = level_along_x(r, grid, samples, p);
        const bool axis_x = level_x.value_or(longer_along_x(r));
        const Frame axis = Frame::along_axis(axis_x);
        std::vector<RowPlan> plans;
        if (auto d = level_direction(r, p, axis)) plans.push_back(plan_rows(q, r, grid, Frame::along(*d), samples, p, overhang_nz));
        std::vector<RowPlan> across;
        if (!level_x && rows_across) across.push_back(plan_rows(q, r, grid, Frame::along_axis(!axis_x), samples, p, overhang_nz));
        plans.insert(plans.begin(), plan_rows(q, r, std::move(grid), axis, samples, p, overhang_nz));
        auto lay = [&](const RowPlan& plan, double span, const std::vector<Vec3>* prefer_near, bool fewer_rows = false,
                       Tails tails = Tails::none) -> std::optional<Layout> {
            Layout l;
            l.span = span;
            l.w = region_walls(q, plan, samples, p, overhang_nz, span, prefer_near, fewer_rows, tails);
            if (tails != Tails::none && l.w.tails == 0) return std::nullopt;  // the layout without them
            if (l.w.walls.empty() || enters_blocker(l.w.walls, blockers, p)) return std::nullopt;
            if (prefer_near && l.w.turned == 0) return std::nullopt;  // the meander again
            for (const Run& run : l.w.walls)
                for (auto& piece : flat_pieces(run, p)) l.pieces.push_back(piece);
            l.pieces = finish(printable_tops(std::move(l.pieces), p));
            if (l.pieces.empty()) return std::nullopt;
            if (prefer_near) l.pieces = merge_in_line(std::move(l.pieces));
            l.tops = wall_contacts(q, l.pieces, p);
            std::vector<std::size_t> left;
            for (std::size_t i : r.samples)
                if (walls_carry(surface, l.tops, samples[i].p, carry)) l.carried.push_back(i);
                else left.push_back(i);
            if (prefer_near && !lays_out_hybrid(p)) drop_idle_stubs(q, surface, samples, p, l);
            // Walls only: the hybrid's pieces each add a foot to the tree, and its regions are
            // priced against their own tree alone; with this the wheel at 80 mm got a hybrid its
            // whole tree printed slower (Cura 29.4 -> 32.4 min, PrusaSlicer 21.8 -> 23.5).
            if (!lays_out_hybrid(p)) release_held(surface, l.tops, samples, tip_at, left, l.carried, l.relied, l.released, carry, p);
            for (std::size_t i : left) l.left.push_back(samples[i]);
            return l;
        };
        // The layout leaving fewest samples over the plans and spans (with `tails`: only layouts
        // where rows get such tails), and its plan.
        auto choose = [&](const std::vector<RowPlan>& plans, Tails tails) {
            std::optional<Layout> best;
            const RowPlan* chosen = &plans.front();
            for (const RowPlan& plan : plans) {
                std::optional<Layout> mine;
                for (double span : {p.ceiling_span, tight}) {
                    if (mine && (mine->left.empty() || span == p.ceiling_span || mine->tops.narrow < 0.5 * mine->tops.length)) break;
                    auto l = lay(plan, span, nullptr, false, tails);
                    if (l && (!mine || l->left.size() < mine->left.size())) mine = std::move(l);
                }
                if (mine && (!best || mine->left.size() < best->left.size() ||
                             (mine->left.size() == best->left.size() && mine->pieces.size() < best->pieces.size())))
                    best = std::move(mine), chosen = &plan;
            }
            return std::pair{std::move(best), chosen};
        };
        std::vector<Sample> own;
        for (std::size_t i : r.samples) own.push_back(samples[i]);
        // The samples beside the region go to the tree either way, and walls split it from them:
        // the region is priced with them on both sides. Priced alone, walls under the ridge along
        // a bore's crown (tests/data/ceilings/bore_ridge.scad) beat the region's own tree and left
        // the crown's sloping sides two trees that printed slower than one tree for all (Cura 5.7
        // -> 4.6 min, PrusaSlicer 7.0 -> 5.5 min with the one tree).
        auto and_beside = [&](std::vector<Sample> v) {
            for (std::size_t i : r.beside) v.push_back(samples[i]);
            return v;
        };
        // The region's own tree on both routes, grown once, when a layout is first priced.
        std::optional<RouteSeconds> tree_price;
        auto region_tree = [&] {
            if (!tree_price) {
                const TreeCount t = tree_count(and_beside(own), {});
                tree_price = std::pair{tree_s(kCuraRoute, t), tree_s(kPrusaRoute, t)};
            }
            return *tree_price;
        };
        // A layout's seconds on both routes: its walls, and the tree for the samples they leave.
        // Walls that alone cost more than the tree lose whatever the rest costs: its tree is not grown.
        // On the Cura route the walls are priced as the slabs the pipeline makes of them
        // (ceilings/slabs.hpp): priced as loops, the blades of propeller and the pipe_tee's
        // underside kept trees that both slicers printed slower (bench/results/validation.md).
        // (PrusaSlicer's first: the slabs are laid out only for walls it prices below the tree.)
        auto price = [&](const Layout& l) -> std::optional<RouteSeconds> {
            const auto [tree_cura, tree_prusa] = region_tree();
            const double prusa = walls_route_seconds(kPrusaRoute, l.w, p);
            if (!(prusa < tree_prusa)) return std::nullopt;
            const double cura = walls_route_seconds(kCuraRoute, l.w, p) - slabs_saving(q, l.pieces, p);
            if (!(cura < tree_cura)) return std::nullopt;
            const TreeCount rest = tree_count(and_beside(l.left), l.pieces);
            return std::pair{cura + tree_s(kCuraRoute, rest), prusa + tree_s(kPrusaRoute, rest)};
        };
        // Where the meander leaves samples at the rows' open ends (a rim, a narrow strip beside
        // the region), its joins at the ends near them; a row fewer, the span apart (the outer rows
        // pulled in from the outer samples) where it carries as much: each kept where it is faster
        // on both routes. `near_left` holds the samples a layout's joins were turned to.
        auto refine = [&](std::optional<Layout>& best, std::optional<RouteSeconds>& cost, const RowPlan& chosen,
                          std::vector<Vec3>& near_left, Tails tails) {
            if (!best->left.empty()) {
                for (const Sample& x : best->left) near_left.push_back(x.p);
                auto turned = lay(chosen, best->span, &near_left, false, tails);
                if (turned && turned->left.size() < best->left.size())
                    if (auto c = price(*turned); c && (!cost || faster_on_both(*c, *cost)))
                        best = std::move(turned), cost = c;
            }
            if (auto fewer = lay(chosen, best->span, nullptr, true, tails); fewer && fewer->left.size() <= best->left.size())
                if (auto c = price(*fewer); c && (!cost || faster_on_both(*c, *cost)))
                    best = std::move(fewer), cost = c;
        };
        // The layout over `plans`, refined and with tails where that is faster, and its price;
        // nothing where its walls alone cost more than the region's tree.
        auto lay_out = [&](const std::vector<RowPlan>& plans) -> std::optional<std::pair<Layout, RouteSeconds>> {
            auto [best, chosen] = choose(plans, Tails::none);
            if (!best) return std::nullopt;
            // Pricing grows the region's tree twice (for all its samples, and for those the walls
            // leave): the stage's cost. Walls that leave a tree under most of the region only add to it.
            if (best->left.size() > most_left * own.size()) return std::nullopt;
            auto cost = price(*best);
            std::vector<Vec3> near_left;
            refine(best, cost, *chosen, near_left, Tails::none);
            // Rows with tails where the region narrows past their ends, stepped and then slanted: kept
            // where they carry more than the layout without and are faster on both routes than the
            // best so far (under stanford_bunny's belly stepped tails carried one sample more and the
            // region's walls lost to its tree on the Cura route; given to every layout, slanted tails
            // took delta_wing's stepped ones' place, and both slicers printed it slower). Stepped tails
            // are laid out over the plans and spans and refined as the layout without; slanted ones on
            // that layout's plan and span alone: laid out like the stepped ones they cost spot 6 % more
            // CPU and changed no output of the validation set or the shared models.
            const std::size_t untailed_left = best->left.size();
            const double untailed_span = best->span;
            for (const Tails kind : {Tails::stepped, Tails::slanted}) {
                if (untailed_left == 0) break;
                const bool stepped = kind == Tails::stepped;
                auto [tailed, tailed_plan] =
                    stepped ? choose(plans, kind) : std::pair{lay(*chosen, untailed_span, nullptr, false, kind), chosen};
                if (!tailed || tailed->left.size() >= untailed_left) continue;
                auto tailed_cost = price(*tailed);
                std::vector<Vec3> near_left_tailed;
                if (stepped) refine(tailed, tailed_cost, *tailed_plan, near_left_tailed, kind);
                if (tailed_cost && (!cost || faster_on_both(*tailed_cost, *cost)))
                    best = std::move(tailed), cost = tailed_cost;
            }
            if (!cost) return std::nullopt;
            return std::pair{std::move(*best), *cost};
        };
        auto found = lay_out(plans);
        // A flat ceiling (level both ways), `rows_across`: also rows across its longer side, kept
        // where they are faster on both routes. Rows that end on a straight rim (a shelf's wall)
        // all join there; along the longer side their ends may all lie on slanted rims, where no
        // join fits (wedge_ledge's triangular shelf: its hybrid, Cura 12.7 -> 10.9 min, PrusaSlicer
        // 12.1 -> 9.7 min).
        if (!across.empty())
            if (auto turned = lay_out(across); turned && (!found || faster_on_both(turned->second, found->second)))
                found = std::move(turned);
        if (!found) continue;
        Layout& best = found->first;
        const RouteSeconds cost = found->second;
        const auto [tree_cura, tree_prusa] = region_tree();
        bool taken = faster_on_both(cost, region_tree());
        // Asked only of walls that beat the tree, and not by much (kRivalFromShare): the rival lays
        // out and prices another structure. Walls give way only where it is cheaper on both routes,
        // as they are taken over the tree only where both print them faster (priced alone, the
        // hybrid over enclosure_lid's ears beat the walls on Cura only, and the whole printed slower).
        if (taken && rival && cost.first >= kRivalFromShare * tree_cura && cost.second >= kRivalFromShare * tree_prusa) {
            const auto [cura, prusa] = rival(own);
            taken = !faster_on_both({tree_cura - cura, tree_prusa - prusa}, cost);
        }
        // The hybrid's regions are weighed in the whole below where taken, or where one route
        // alone prefers them. One both routes price dearer alone is left: each weighing grows a
        // tree for the whole, and on the tuning set, the validation parts and the examples (both
        // poses) one such region was cheaper in the whole, by 0.1 % and 0.3 % (the wheel at 80 mm).
        const bool contested = (cost.first < tree_cura) != (cost.second < tree_prusa);
        if (!taken && (!lays_out_hybrid(p) || !contested)) continue;
        const double lines_cura = walls_route_seconds(kCuraRoute, best.w, p), lines_prusa = walls_route_seconds(kPrusaRoute, best.w, p);
        priced.push_back({std::move(best), lines_cura, lines_prusa, tree_cura, tree_prusa, cost.first, cost.second, taken});
    }
    // The hybrid's pieces each add a foot to the one tree the rest grows into, with its neighbours'
    // leaves: a region priced against its own tree alone may be dearer or cheaper in the whole (the
    // wheel at 80 mm). So the regions' choices are weighed in the whole, one region at a time in
    // their order: its choice flips where the whole (the taken regions' walls and the tree for all
    // the samples they leave, with their feet) is then faster on both routes.
    if (lays_out_hybrid(p) && !priced.empty()) {
        auto whole = [&](const std::vector<Priced>& choice) {
            std::vector<CeilingWall> pieces;
            double cura = 0, prusa = 0;
            std::vector<char> held(samples.size(), 0);
            for (const Priced& c : choice)
                if (c.taken) {
                    pieces.insert(pieces.end(), c.l.pieces.begin(), c.l.pieces.end());
                    cura += c.lines_cura, prusa += c.lines_prusa;
                    for (std::size_t i : c.l.carried) held[i] = 1;
                }
            std::vector<Sample> left;
            const Contacts tops = wall_contacts(q, pieces, p);
            for (std::size_t i = 0; i < samples.size(); ++i)
                if (!held[i] && (relied[i] || pieces.empty() || !walls_carry(surface, tops, samples[i].p, carry)))
                    left.push_back(samples[i]);
            const TreeCount t = left.empty() && pieces.empty() ? TreeCount{} : tree_count(left, pieces);
            return std::pair{cura + tree_s(kCuraRoute, t), prusa + tree_s(kPrusaRoute, t)};
        };
        auto now = whole(priced);
        for (Priced& c : priced) {
            c.taken = !c.taken;
            const auto flipped = whole(priced);
            if (faster_on_both(flipped, now)) now = flipped;
            else c.taken = !c.taken;
        }
    }
    for (const Priced& c : priced) {
        if (!c.taken) continue;
        ++out.regions;
        out.tree_cura_s += c.tree_cura, out.tree_prusa_s += c.tree_prusa;
        out.walls_cura_s += c.walls_cura, out.walls_prusa_s += c.walls_prusa;
        out.walls.insert(out.walls.end(), c.l.pieces.begin(), c.l.pieces.end());
        for (std::size_t i : c.l.carried) carried[i] = 1;
        for (std::size_t i : c.l.relied) relied[i] = 1;
        for (std::size_t i : c.l.released) out.released.push_back(samples[i].p);
    }
    if (out.walls.empty()) {
        out.rest = samples, out.stay = stay;
        return out;
    }
    const Contacts tops = wall_contacts(q, out.walls, p);
    for (std::size_t i = 0; i < samples.size(); ++i) {
        if (carried[i] || (!relied[i] && walls_carry(surface, tops, samples[i].p, carry))) ++out.covered;
        else out.rest.push_back(samples[i]), out.stay.push_back(relied[i]);
    }
    return out;
}

Ceilings carried_by(const ModelQuery& q, const std::vector<Sample>& samples, const std::vector<char>& stay,
                    std::vector<CeilingWall> pieces, const Params& p) {
    Ceilings out;
    out.walls = std::move(pieces);
    if (out.walls.empty()) {
        out.rest = samples, out.stay = stay;
        return out;
    }
    // The surface a sample the pieces carry may cover, as lay_out_ceilings takes it around its
    // regions: as far from the pieces as such a sample covers, and more.
    const double margin = 2 * p.sampling_distance + 2 * coverage_reach(p.sampling_distance);
    Box3 near = wall_box(out.walls.front(), margin);
    for (const CeilingWall& w : out.walls) {
        const Box3 b = wall_box(w, margin);
        near.min = {std::min(near.min.x, b.min.x), std::min(near.min.y, b.min.y), std::min(near.min.z, b.min.z)};
        near.max = {std::max(near.max.x, b.max.x), std::max(near.max.y, b.max.y), std::max(near.max.z, b.max.z)};
    }
    near.min.z -= margin, near.max.z += margin;
    JudgedSurface surface(q.mesh(), kProbeStepOfReach * coverage_reach(p.sampling_distance), near, p.critical_angle);
    const CarryReach carry(p);
    const Contacts tops = wall_contacts(q, out.walls, p);
    for (std::size_t i = 0; i < samples.size(); ++i) {
        const bool stays = i < stay.size() && stay[i];
        if (!stays && walls_carry(surface, tops, samples[i].p, carry)) ++out.covered;
        else out.rest.push_back(samples[i]), out.stay.push_back(stays);
    }
    return out;
}

double wall_thickness_for(const Params& p, double height) {
    return std::max(p.wall_thickness, strength_width(p, height, 0));
}

std::vector<CeilingWall> printable_tops(std::vector<CeilingWall> pieces, const Params& p) {
    // Lengths are sums of station distances: two 0.5 mm stations are exactly long enough
    // (measured), and may come out a rounding short of it.
    constexpr double kRounding = 1e-6;
    auto length = [](const CeilingWall& w) { return horizontal_distance(w.from, w.to); };
    // Pieces touch where an end of one lies in the other's footprint: end to end along a row,
    // a join's end inside the row it joins.
    auto within = [&](const Vec3& x, const CeilingWall& w) { return to_centre_line(x, w) <= 0.5 * w.thickness + kRounding; };
    auto touch = [&](const CeilingWall& a, const CeilingWall& b) {
        return within(a.from, b) || within(a.to, b) || within(b.from, a) || within(b.to, a);
    };
    auto is_short = [&](const CeilingWall& w) { return length(w) + kRounding < kClassicLengthOverThickness * w.thickness; };
    if (std::none_of(pieces.begin(), pieces.end(), is_short)) return pieces;  // most layouts
    for (bool removed = true; removed;) {
        removed = false;
        const std::size_t n = pieces.size();
        double thickest = 0;
        for (const CeilingWall& w : pieces) thickest = std::max(thickest, w.thickness);
        std::vector<std::vector<std::size_t>> near(n);
        std::vector<double> levels;
        for (std::size_t i = 0; i < n; ++i) {
            levels.push_back(pieces[i].top);
            for (std::size_t j = i + 1; j < n; ++j)
                if (touch(pieces[i], pieces[j])) near[i].push_back(j), near[j].push_back(i);
        }
        std::sort(levels.begin(), levels.end(), std::greater<>());
        levels.erase(std::unique(levels.begin(), levels.end()), levels.end());
        // Is the stretch holding piece i at `level` (the pieces there reaching it, touching) long
        // enough for its thickest piece? Found as soon as it is long enough for any piece.
        std::vector<std::size_t> seen(n, 0), stack;
        std::size_t search = 0;
        auto long_enough = [&](std::size_t i, double level) {
            double len = 0, thick = 0;
            stack.assign(1, i), seen[i] = ++search;
            while (!stack.empty()) {
                const CeilingWall& w = pieces[stack.back()];
                stack.pop_back();
                len += length(w), thick = std::max(thick, w.thickness);
                if (len + kRounding >= kClassicLengthOverThickness * thickest) return true;
                for (std::size_t j : near[&w - pieces.data()])
                    if (seen[j] != search && pieces[j].top >= level && pieces[j].bottom < level) seen[j] = search, stack.push_back(j);
            }
            return len + kRounding >= kClassicLengthOverThickness * thick;
        };
        std::vector<double> tops(n);
        for (std::size_t i = 0; i < n && !removed; ++i) {
            const CeilingWall& w = pieces[i];
            tops[i] = w.top;
            if (!is_short(w)) continue;  // stands long enough on its own
            // The highest level at or under its top where it stands long enough (the stretch
            // holding it only grows lower down).
            auto level = std::find_if(std::lower_bound(levels.begin(), levels.end(), w.top, std::greater<>()), levels.end(),
                                      [&](double z) { return z <= w.bottom || long_enough(i, z); });
            if (level == levels.end() || *level <= w.bottom) continue;  // never long enough: as it is
            tops[i] = *level;
            if (tops[i] - w.bottom < p.layer_height) {  // less than a layer left: not built
                pieces.erase(pieces.begin() + static_cast<long>(i));
                removed = true;
            }
        }
        if (!removed)
            for (std::size_t i = 0; i < n; ++i) pieces[i].top = tops[i];
    }
    return pieces;
}

Box3 wall_box(const CeilingWall& w, double margin) {
    const double side = 0.5 * w.thickness + margin;
    Box3 b;
    b.min = {std::min(w.from.x, w.to.x) - side, std::min(w.from.y, w.to.y) - side, w.bottom};
    b.max = {std::max(w.from.x, w.to.x) + side, std::max(w.from.y, w.to.y) + side, w.top};
    return b;
}

double bridges_volume(const std::vector<CeilingWall>& walls) {
    double v = 0;
    for (const CeilingWall& w : walls)
        if (w.bridge) v += signed_volume(wall_mesh(w));
    return v;
}

Mesh wall_mesh(const CeilingWall& w) {
    const double thickness = w.thickness;
    Mesh m;
    const Vec3 d = normalized(Vec3{w.to.x - w.from.x, w.to.y - w.from.y, 0});
    const Vec3 o = Vec3{-d.y, d.x, 0} * (0.5 * thickness);
    // Cross-section at each end, counter-clockwise seen from ahead (+d): right foot, left foot,
    // left top, right top.
    for (const Vec3& c : {w.from, w.to}) {
        const Vec3 foot{c.x, c.y, w.bottom}, top{c.x, c.y, w.top};
        m.vertices.insert(m.vertices.end(), {foot - o, foot + o, top + o, top - o});
    }
    m.faces = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}};
    for (std::uint32_t i = 0; i < 4; ++i) {
        const std::uint32_t b = (i + 1) % 4;
        m.faces.push_back({i, b, b + 4});
        m.faces.push_back({i, b + 4, i + 4});
    }
    return m;
}

}  // namespace cs

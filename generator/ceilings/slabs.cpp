#include "ceilings/slabs.hpp"

#include <algorithm>
#include <cmath>

#include "core/rules.hpp"
#include "query/model_query.hpp"

namespace cs {

namespace {

// Pieces closer than this (mm) in direction, offset, foot or top count as the same: a region's
// rows are written from the same numbers, so theirs agree far more closely.
constexpr double kSame = 1e-6;
// A bridge reaches this far (mm) into each of its rows: no face or corner of it lies on one of
// theirs, so each stays a closed solid of its own to `check` (which splits a mesh into solids where
// faces meet), and the slicers' union is the same (CuraEngine unions a support mesh's solids:
// enclosure_lid's supports slice to the same G-code time with bridges 0.001 and 0.1 mm into rows).
constexpr double kIntoRows = 0.01;
// A bridge's foot is flat at the higher of its two rows' feet. Over a floor sloping between the
// rows it hangs over the floor beside the lower row, standing neither on the floor nor, at its
// middle, inside a row: a bridge only where the rows' feet differ by at most this share of a layer.
// (tests/data/cad/tilted_slots: rows 2.8 mm apart on a 6 degree floor, feet 0.29 mm apart, gave a
// bridge that `check` found resting on nothing; the slabs built there have feet at most 0.09 apart.)
constexpr double kMostFootStepOfLayer = 0.5;
// Two lines pair where their bridges are this many spans long in all: shorter, a slab's two ends
// add about as much outline as the loops it saves.
constexpr double kLeastOverlapOfSpan = 1.0;

// A piece's line: its direction (one sign for both ways along it), the normal across it, and the
// line's offset along that normal.
struct OnLine {
    Vec3 d, n;
    double offset = 0;
};

OnLine on_line(const CeilingWall& w) {
    Vec3 d = normalized(Vec3{w.to.x - w.from.x, w.to.y - w.from.y, 0});
    if (d.x < -kSame || (std::abs(d.x) <= kSame && d.y < 0)) d = d * -1.0;
    const Vec3 n{-d.y, d.x, 0};
    return {d, n, w.from.x * n.x + w.from.y * n.y};
}

Vec3 at(const OnLine& l, double s, double offset, double z) {
    return Vec3{l.d.x * s + l.n.x * offset, l.d.y * s + l.n.y * offset, z};
}

bool same_direction(const OnLine& a, const OnLine& b) {
    return std::abs(a.d.x * b.d.y - a.d.y * b.d.x) < kSame && a.d.x * b.d.x + a.d.y * b.d.y > 0;
}

// Does the model come into the box spanned by `lo`..`hi` along the line, `across0`..`across1`
// across it and `z0`..`z1`? Its faces are asked (the model's surface crossing any of them), and its
// middle (the model wholly around it).
bool model_in_box(const ModelQuery& q, const OnLine& l, double lo, double hi, double across0, double across1, double z0,
                  double z1) {
    Vec3 c[8];
    for (int i = 0; i < 8; ++i)
        c[i] = at(l, i & 1 ? hi : lo, i & 2 ? across1 : across0, i & 4 ? z1 : z0);
    static constexpr int kFaces[6][4] = {{0, 1, 3, 2}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 3, 7, 6}, {0, 2, 6, 4}, {1, 3, 7, 5}};
    for (const auto& f : kFaces)
        if (q.triangle_hits(c[f[0]], c[f[1]], c[f[2]]) || q.triangle_hits(c[f[0]], c[f[2]], c[f[3]])) return true;
    return q.inside(at(l, 0.5 * (lo + hi), 0.5 * (across0 + across1), 0.5 * (z0 + z1)));
}

// A pair's bridges (one line pair, the same two planes), each standing on its own as `check`
// judges a solid: at least as long as the strength rule's width for a column its height. A shorter
// one merges with the bridge it meets end to end (the two as high as both stand), the shorter
// neighbour first; one that meets none is dropped.
std::vector<CeilingWall> stand_alone(std::vector<CeilingWall> bridges, const Params& p, double least_height) {
    auto length = [](const CeilingWall& b) { return horizontal_distance(b.from, b.to); };
    auto too_short = [&](const CeilingWall& b) { return length(b) < wall_thickness_for(p, b.top - b.bottom); };
    const Vec3 d = bridges.empty() ? Vec3{} : normalized(Vec3{bridges[0].to.x - bridges[0].from.x, bridges[0].to.y - bridges[0].from.y, 0});
    auto start = [&](const CeilingWall& b) { return b.from.x * d.x + b.from.y * d.y; };
    std::sort(bridges.begin(), bridges.end(), [&](const CeilingWall& a, const CeilingWall& b) { return start(a) < start(b); });
    for (bool merged = true; merged;) {
        merged = false;
        for (std::size_t k = 0; k < bridges.size() && !merged; ++k) {
            if (!too_short(bridges[k])) continue;
            const bool meets_before = k > 0 && horizontal_distance(bridges[k - 1].to, bridges[k].from) < kSame;
            const bool meets_after = k + 1 < bridges.size() && horizontal_distance(bridges[k].to, bridges[k + 1].from) < kSame;
            if (!meets_before && !meets_after) {
                bridges.erase(bridges.begin() + static_cast<long>(k));
                merged = true;
                continue;
            }
            const bool with_before = meets_before && (!meets_after || length(bridges[k - 1]) <= length(bridges[k + 1]));
            const std::size_t a = with_before ? k - 1 : k, b = a + 1;
            CeilingWall both = bridges[a];
            both.to = bridges[b].to;
            both.bottom = std::max(bridges[a].bottom, bridges[b].bottom), both.top = std::min(bridges[a].top, bridges[b].top);
            bridges.erase(bridges.begin() + static_cast<long>(b));
            if (both.top - both.bottom < least_height) bridges.erase(bridges.begin() + static_cast<long>(a));
            else bridges[a] = both;
            merged = true;
        }
    }
    return bridges;
}

}  // namespace

std::vector<CeilingWall> join_rows_into_slabs(const ModelQuery& q, std::vector<CeilingWall> walls, const Params& p) {
    if (p.ceiling_span <= 0) return walls;
    // The rows' pieces, gathered into lines (same direction, same offset across it); the tails'
    // apart (ceilings.cpp, add_tails: an outer row stepped in where its region narrows).
    struct Line {
        OnLine frame;                     // of its first piece
        std::vector<std::size_t> pieces;  // along it in order
        int side = 0;                     // where its bridges lie: -1 the lower offset, +1 the higher, 0 none
        std::vector<std::pair<double, double>> bridged;  // along it, where they stand
    };
    auto along = [](const OnLine& l, const Vec3& x) { return x.x * l.d.x + x.y * l.d.y; };
    // Where two pieces run beside each other along `l`: {lo, hi} (hi <= lo where they do not).
    auto beside_along = [&](const OnLine& l, const CeilingWall& wa, const CeilingWall& wb) {
        return std::pair{std::max(std::min(along(l, wa.from), along(l, wa.to)), std::min(along(l, wb.from), along(l, wb.to))),
                         std::min(std::max(along(l, wa.from), along(l, wa.to)), std::max(along(l, wb.from), along(l, wb.to)))};
    };
    auto lines_of = [&](bool tails) {
        std::vector<Line> lines;
        for (std::size_t i = 0; i < walls.size(); ++i) {
            const CeilingWall& w = walls[i];
            if (w.join || w.tail != tails || w.on_tree || w.bridge || horizontal_distance(w.from, w.to) <= 0) continue;
            const OnLine l = on_line(w);
            auto same = std::find_if(lines.begin(), lines.end(), [&](const Line& x) {
                return same_direction(x.frame, l) && std::abs(x.frame.offset - l.offset) <= kSame;
            });
            if (same == lines.end()) lines.push_back({l, {i}, 0, {}});
            else same->pieces.push_back(i);
        }
        for (Line& line : lines)
            std::sort(line.pieces.begin(), line.pieces.end(), [&](std::size_t a, std::size_t b) {
                return std::min(along(line.frame, walls[a].from), along(line.frame, walls[a].to)) <
                       std::min(along(line.frame, walls[b].from), along(line.frame, walls[b].to));
            });
        // In order across, so each line meets its neighbour first.
        std::stable_sort(lines.begin(), lines.end(), [](const Line& a, const Line& b) { return a.frame.offset < b.frame.offset; });
        return lines;
    };
    std::vector<Line> lines = lines_of(false);
    const std::vector<Line> tails = lines_of(true);
    // A bridge lower than two layers saves less than its two ends print.
    const double clearance = tip_side_clearance(p), least_height = 2 * p.layer_height;
    auto thinnest = [&](const Line& x) {
        double t = INFINITY;
        for (std::size_t k : x.pieces) t = std::min(t, walls[k].thickness);
        return t;
    };
    // The bridges between two lines (`a` at the lower offset): one under each stretch where a piece
    // of one runs beside a piece of the other, as high as both stand there, outside `taken` (along
    // them). All of them between the same two planes, a hair into the thinnest piece of each line
    // (the strength rule thickens taller pieces a little), so bridges meeting end to end meet face
    // to face, corner on corner.
    auto bridges_between = [&](const Line& a, const Line& b, const std::vector<std::pair<double, double>>& taken) {
        const OnLine &l = a.frame, &m = b.frame;
        std::vector<CeilingWall> bridges;
        const double inner0 = l.offset + 0.5 * thinnest(a), inner1 = m.offset - 0.5 * thinnest(b);
        for (std::size_t ia : a.pieces)
            for (std::size_t ib : b.pieces) {
                const CeilingWall &wa = walls[ia], &wb = walls[ib];
                const double bottom = std::max(wa.bottom, wb.bottom), top = std::min(wa.top, wb.top);
                if (top - bottom < least_height) continue;
                if (std::abs(wa.bottom - wb.bottom) > kMostFootStepOfLayer * p.layer_height) continue;
                const auto [lo, hi] = beside_along(l, wa, wb);
                // The stretch less what is taken.
                std::vector<std::pair<double, double>> free{{lo, hi}};
                for (const auto& [t0, t1] : taken) {
                    std::vector<std::pair<double, double>> left;
                    for (const auto& [f0, f1] : free) {
                        if (t0 > f0) left.push_back({f0, std::min(f1, t0)});
                        if (t1 < f1) left.push_back({std::max(f0, t1), f1});
                    }
                    free = std::move(left);
                }
                for (auto [f0, f1] : free) {
                    if (f1 - f0 <= kSame) continue;
                    // Where it meets a bridge taken, it reaches kIntoRows into it: no corner of
                    // one on a corner of the other (bridges of other widths), so each stays a
                    // closed solid of its own to `check`.
                    if (f0 > lo + kSame) f0 -= kIntoRows;
                    if (f1 < hi - kSame) f1 += kIntoRows;
                    // The bridge, and the air over it, keep the clearance the rows keep.
                    if (model_in_box(q, l, f0 - clearance, f1 + clearance, inner0, inner1, bottom + 1e-3, top + p.gap - 1e-3))
                        continue;
                    CeilingWall bridge = wa;
                    const double middle = 0.5 * (inner0 + inner1);
                    bridge.from = at(l, f0, middle, 0), bridge.to = at(l, f1, middle, 0);
                    bridge.bottom = bottom, bridge.top = top;
                    bridge.thickness = inner1 - inner0 + 2 * kIntoRows, bridge.row_thickness = 0.5 * (wa.thickness + wb.thickness);
                    bridge.join = false, bridge.tail = false, bridge.bridge = true;
                    bridges.push_back(bridge);
                }
            }
        return stand_alone(std::move(bridges), p, least_height);
    };
    auto length_of = [](const std::vector<CeilingWall>& bridges) {
        double length = 0;
        for (const CeilingWall& b : bridges) length += horizontal_distance(b.from, b.to);
        return length;
    };
    auto record = [&](Line& x, int side, const std::vector<CeilingWall>& bridges) {
        x.side = side;
        for (const CeilingWall& b : bridges)
            x.bridged.push_back(std::minmax(along(x.frame, b.from), along(x.frame, b.to)));
    };
    std::vector<CeilingWall> added;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (lines[i].side) continue;
        const OnLine& l = lines[i].frame;
        for (std::size_t j = i + 1; j < lines.size(); ++j) {
            const OnLine& m = lines[j].frame;
            const double apart = m.offset - l.offset;
            if (apart > p.ceiling_span + kSame) break;  // in order across: no farther line is nearer
            if (lines[j].side || apart <= kSame || !same_direction(l, m)) continue;
            std::vector<CeilingWall> bridges = bridges_between(lines[i], lines[j], {});
            // Shorter than the span in all, the slab's two ends add about as much as it saves.
            if (length_of(bridges) < kLeastOverlapOfSpan * p.ceiling_span) continue;
            record(lines[i], 1, bridges), record(lines[j], -1, bridges);
            added.insert(added.end(), bridges.begin(), bridges.end());
            break;
        }
    }
    // A tail stands between its row's neighbour and where its row ended: the neighbour's slab with
    // that row goes on beside the tail (its ends are the slab's, no new ones: no least length),
    // where the neighbour has no bridge yet on the tail's side. The neighbour is the line the span
    // or less away that runs beside the tail longest (the row it was stepped from only meets it at
    // the jog). Left out where the neighbour's bridges lie on its other side: a slab of three rows
    // would bury the middle one.
    for (const Line& t : tails) {
        std::size_t best = lines.size();
        double best_length = 0;
        for (std::size_t i = 0; i < lines.size(); ++i) {
            const Line& n = lines[i];
            const double apart = t.frame.offset - n.frame.offset;
            if (std::abs(apart) > p.ceiling_span + kSame || std::abs(apart) <= kSame || !same_direction(t.frame, n.frame)) continue;
            double beside = 0;
            for (std::size_t a : t.pieces)
                for (std::size_t b : n.pieces) {
                    const auto [lo, hi] = beside_along(n.frame, walls[a], walls[b]);
                    beside += std::max(0.0, hi - lo);
                }
            if (beside > best_length) best = i, best_length = beside;
        }
        if (best == lines.size()) continue;
        Line& n = lines[best];
        const int side = t.frame.offset > n.frame.offset ? 1 : -1;
        if (n.side == -side) continue;
        std::vector<CeilingWall> bridges = side > 0 ? bridges_between(n, t, n.bridged) : bridges_between(t, n, n.bridged);
        if (bridges.empty()) continue;
        record(n, side, bridges);
        added.insert(added.end(), bridges.begin(), bridges.end());
    }
    walls.insert(walls.end(), added.begin(), added.end());
    return walls;
}

}  // namespace cs

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
    // The rows' pieces, gathered into lines (same direction, same offset across it).
    struct Line {
        OnLine frame;                     // of its first piece
        std::vector<std::size_t> pieces;  // along it in order
    };
    std::vector<Line> lines;
    for (std::size_t i = 0; i < walls.size(); ++i) {
        const CeilingWall& w = walls[i];
        if (w.join || w.on_tree || w.bridge || horizontal_distance(w.from, w.to) <= 0) continue;
        const OnLine l = on_line(w);
        auto same = std::find_if(lines.begin(), lines.end(), [&](const Line& x) {
            return same_direction(x.frame, l) && std::abs(x.frame.offset - l.offset) <= kSame;
        });
        if (same == lines.end()) lines.push_back({l, {i}});
        else same->pieces.push_back(i);
    }
    auto along = [](const OnLine& l, const Vec3& x) { return x.x * l.d.x + x.y * l.d.y; };
    for (Line& line : lines)
        std::sort(line.pieces.begin(), line.pieces.end(), [&](std::size_t a, std::size_t b) {
            return std::min(along(line.frame, walls[a].from), along(line.frame, walls[a].to)) <
                   std::min(along(line.frame, walls[b].from), along(line.frame, walls[b].to));
        });
    // In order across, so each line meets its neighbour first.
    std::stable_sort(lines.begin(), lines.end(), [](const Line& a, const Line& b) { return a.frame.offset < b.frame.offset; });
    // A bridge lower than two layers saves less than its two ends print.
    const double clearance = tip_side_clearance(p), least_height = 2 * p.layer_height;
    auto thinnest = [&](const Line& x) {
        double t = INFINITY;
        for (std::size_t k : x.pieces) t = std::min(t, walls[k].thickness);
        return t;
    };
    std::vector<char> paired(lines.size(), 0);
    std::vector<CeilingWall> added;
    for (std::size_t i = 0; i < lines.size(); ++i) {
        if (paired[i]) continue;
        const OnLine& l = lines[i].frame;
        for (std::size_t j = i + 1; j < lines.size(); ++j) {
            const OnLine& m = lines[j].frame;
            const double apart = m.offset - l.offset;
            if (apart > p.ceiling_span + kSame) break;  // in order across: no farther line is nearer
            if (paired[j] || apart <= kSame || !same_direction(l, m)) continue;
            // A bridge under each stretch where a piece of one line runs beside a piece of the other,
            // as high as both stand there. All of them between the same two planes, a hair into the
            // thinnest piece of each line (the strength rule thickens taller pieces a little), so
            // bridges meeting end to end meet face to face, corner on corner.
            std::vector<CeilingWall> bridges;
            double length = 0;
            const double inner0 = l.offset + 0.5 * thinnest(lines[i]), inner1 = m.offset - 0.5 * thinnest(lines[j]);
            for (std::size_t a : lines[i].pieces)
                for (std::size_t b : lines[j].pieces) {
                    const CeilingWall &wa = walls[a], &wb = walls[b];
                    const double lo = std::max(std::min(along(l, wa.from), along(l, wa.to)), std::min(along(l, wb.from), along(l, wb.to)));
                    const double hi = std::min(std::max(along(l, wa.from), along(l, wa.to)), std::max(along(l, wb.from), along(l, wb.to)));
                    const double bottom = std::max(wa.bottom, wb.bottom), top = std::min(wa.top, wb.top);
                    if (hi - lo <= kSame || top - bottom < least_height) continue;
                    if (std::abs(wa.bottom - wb.bottom) > kMostFootStepOfLayer * p.layer_height) continue;
                    // The bridge, and the air over it, keep the clearance the rows keep.
                    if (model_in_box(q, l, lo - clearance, hi + clearance, inner0, inner1, bottom + 1e-3, top + p.gap - 1e-3))
                        continue;
                    CeilingWall bridge = wa;
                    const double middle = 0.5 * (inner0 + inner1);
                    bridge.from = at(l, lo, middle, 0), bridge.to = at(l, hi, middle, 0);
                    bridge.bottom = bottom, bridge.top = top;
                    bridge.thickness = inner1 - inner0 + 2 * kIntoRows, bridge.row_thickness = 0.5 * (wa.thickness + wb.thickness);
                    bridge.join = false, bridge.bridge = true;
                    bridges.push_back(bridge);
                    length += hi - lo;
                }
            bridges = stand_alone(std::move(bridges), p, least_height);
            length = 0;
            for (const CeilingWall& b : bridges) length += horizontal_distance(b.from, b.to);
            // Shorter than the span in all, the slab's two ends add about as much as it saves.
            if (length < kLeastOverlapOfSpan * p.ceiling_span) continue;
            added.insert(added.end(), bridges.begin(), bridges.end());
            paired[i] = paired[j] = 1;
            break;
        }
    }
    walls.insert(walls.end(), added.begin(), added.end());
    return walls;
}

}  // namespace cs

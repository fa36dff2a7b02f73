#include "tree/placement.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <utility>

#include "query/model_query.hpp"
#include "tree/verdicts.hpp"

namespace cs {
namespace {

// How far a tip's top or a pillar may move off its sample: well inside the reach of its contact
// (the lattice cell's radius, (sqrt 2 / 2) * sampling, for any sampling of a millimetre or more).
constexpr double kMaxShift = 0.5;
// A footprint counts as level when its floor's heights differ by no more than this: such a
// placement is preferred, it stands on all of its foot.
constexpr double kLevel = 0.05;

// Straight below the sample first, then rings of eight directions a quarter and a half millimetre
// aside: nearest first, so a top or a pillar moves no further than it must.
const std::vector<Vec3>& nearby_offsets() {
    static const std::vector<Vec3> offsets = [] {
        std::vector<Vec3> out{{0, 0, 0}};
        for (double r : {0.5 * kMaxShift, kMaxShift})
            for (int i = 0; i < 8; ++i) out.push_back({r * std::cos(i * std::numbers::pi / 4), r * std::sin(i * std::numbers::pi / 4), 0});
        return out;
    }();
    return offsets;
}

// The centre and the four corners of a horizontal square of side w around c.
std::array<Vec3, 5> square_points(const Vec3& c, double w) {
    const double h = 0.5 * w;
    return {c, c + Vec3{h, h, 0}, c + Vec3{h, -h, 0}, c + Vec3{-h, -h, 0}, c + Vec3{-h, h, 0}};
}

// The overhang above a horizontal square: how far it comes down below `z` over the square's
// corners (0 when it does not), and its height straight above the centre.
struct Ceiling {
    double drop = 0;
    double over_centre = 0;
    double lowest = INFINITY;  // the lowest of the model over the square
};

// nullopt when nothing is above the centre.
std::optional<Ceiling> ceiling_above(const ModelQuery& model, const std::array<Vec3, 5>& square, double z) {
    Ceiling c;
    for (size_t i = 0; i < square.size(); ++i) {
        auto hit = model.first_hit(square[i], {0, 0, 1});
        if (!hit) {
            if (i == 0) return std::nullopt;
            continue;  // this corner reaches past the overhang's edge
        }
        if (i == 0) c.over_centre = hit->point.z;
        c.drop = std::max(c.drop, z - hit->point.z);
        c.lowest = std::min(c.lowest, hit->point.z);
    }
    return c;
}

// A square w wide with tip_side_clearance on every side: what must stay clear of the model for a
// tip's top or a pillar to keep that clearance.
double with_side_clearance(double w, const Params& p) { return w + 2 * tip_side_clearance(p); }

// Does a tip's top square at `top` keep tip_side_clearance from a wall beside it (a slot's or a
// hole's ceiling meeting its side)? Under a sloping ceiling the wider square's downhill corners
// reach into the overhang itself: such tops fail this test wherever they go, and placement keeps
// the nearest plain fit.
bool keeps_clearance_beside(const ModelQuery& model, const Vec3& top, const Params& p) {
    return square_is_clear(model, top, with_side_clearance(p.tip_diameter, p));
}

// How much lower than a gap under the sample a tip's top may sit and still count as a contact.
double allowed_drop(const Params& p) { return contact_tolerance(p) - p.gap - 0.05; }

// The same for a square whose slope runs along its diagonal: its corner is half a diagonal out.
double diagonal_drop(const Params& p) { return std::sqrt(2.0) * allowed_drop(p); }

// A foot bears on the model near its axis, not at a corner: on a slope, a foot a gap above its
// highest corner would hang over the model everywhere else (and `check` would not see it standing).
// So its gap is measured from the highest floor under a central cross (the centre and four
// points this share of the foot's width out along its axes), and a placement is preferred where
// every corner then keeps at least kMinFootAir of air.
constexpr double kBearing = 0.45;
// Air kept under the highest corner of a foot on a slope: a quarter of the default gap, enough
// that no corner fuses to the model.
constexpr double kMinFootAir = 0.05;
// To keep that air a foot may stand this much more than a gap above its cross's floor (a fifth
// of the default gap: it still bears there).
constexpr double kMaxFootRaise = 0.04;

struct Floor {
    double z = 0;          // the gap under the foot is measured from here
    bool on_model = false;
    bool level = false;    // corners and centre within kLevel of each other
    bool clear = false;    // every corner keeps kMinFootAir under a foot a gap above z
};

struct Span {
    double high = -INFINITY, low = INFINITY;
};

// Highest and lowest of the model (or the bed, 0) straight below the points.
template <size_t N>
Span heights_below(const ModelQuery& model, const std::array<Vec3, N>& points, bool& on_model) {
    Span s;
    for (const auto& q : points) {
        auto hit = model.first_hit(q, {0, 0, -1});
        on_model = on_model || hit.has_value();
        double z = hit ? hit->point.z : 0.0;
        s.high = std::max(s.high, z), s.low = std::min(s.low, z);
    }
    return s;
}

// What a square foot of width w around c (at the height rays start from) stands on.
Floor floor_under(const ModelQuery& model, const Vec3& c, double w, double gap) {
    const double b = kBearing * w;
    const std::array<Vec3, 5> cross{c, c + Vec3{b, 0, 0}, c + Vec3{-b, 0, 0}, c + Vec3{0, b, 0}, c + Vec3{0, -b, 0}};
    Floor fl;
    const Span corners = heights_below(model, square_points(c, w), fl.on_model);
    const Span central = heights_below(model, cross, fl.on_model);
    const double corner_air_floor = corners.high - (gap - kMinFootAir);
    fl.z = std::max(central.high, std::min(corner_air_floor, central.high + kMaxFootRaise));
    fl.clear = corner_air_floor <= fl.z;
    fl.level = std::max(corners.high, central.high) - std::min(corners.low, central.low) <= kLevel;
    return fl;
}

// Is every point of the squares in the air, with no wall between it and the centre?
bool in_open_air(const ModelQuery& model, const Vec3& centre, const std::array<Vec3, 5>& a,
                 const std::array<Vec3, 5>& b) {
    // The segments first: they are cheap, and one that hits decides without the costlier inside test.
    for (const auto& set : {a, b})
        for (const auto& q : set)
            if (q != centre && model.segment_hits(centre, q)) return false;
    // None of them crosses the surface on its way from the centre: all lie on the centre's side of
    // a closed surface, and one inside test answers for every point.
    return !model.inside(a[0]);
}

struct Attempt {
    PillarFit fit = PillarFit::NoRoom;
    Pillar pillar;
    // Lower is better. Holding the overhang counts for most: a pillar moved where the overhang
    // is higher over all of its top holds nothing up. A level floor counts for more than the side
    // clearance: a pillar that stands on a corner may break off, one beside a wall only prints
    // fused to it.
    int rank = 7;
};

constexpr int kRankAway = 4;      // moved where the overhang over all of its top is higher than its sample
constexpr int kRankSlope = 2;     // on a slope (air under every corner)
constexpr int kRankAgainst = 1;   // nearer a wall beside it than tip_side_clearance

// Does the pillar keep tip_side_clearance from a wall beside it, all the way up? It is a tip with
// no strut: the same clearance keeps its lines from printing fused to a slot's side.
bool pillar_keeps_clearance_beside(const ModelQuery& model, const Pillar& pl, const Params& p) {
    return prism_is_clear(model, pl.bottom, with_side_clearance(p.d_min, p), pl.top, with_side_clearance(p.tip_diameter, p));
}

Attempt pillar_at(const ModelQuery& model, const Vec3& sample, const Vec3& centre, double below, const Params& p) {
    // Rays start half-way between the overhang and what is below it, in the slot's air.
    const Vec3 mid{centre.x, centre.y, 0.5 * (sample.z + below)};
    const auto top = square_points(mid, p.tip_diameter), foot = square_points(mid, p.d_min);
    if (!in_open_air(model, mid, top, foot)) return {};
    auto ceiling = ceiling_above(model, top, sample.z);
    if (!ceiling || ceiling->drop > allowed_drop(p)) return {};
    const Floor fl = floor_under(model, mid, p.d_min, p.gap);
    Pillar pl;
    pl.on_model = fl.on_model;
    pl.top = {centre.x, centre.y, sample.z - ceiling->drop - p.gap};
    pl.bottom = {centre.x, centre.y, fl.on_model ? fl.z + p.gap : 0.0};
    if (pl.top.z - pl.bottom.z < p.layer_height) return {PillarFit::TooLow, pl};
    // A foot that would have to stand on its uphill corner (a slope too steep across it) does not fit.
    if (!fl.clear || !prism_is_clear(model, pl.bottom, p.d_min, pl.top, p.tip_diameter)) return {};
    // Its top a gap below the sample's height: where the overhang over the whole top is higher
    // (a pillar moved off the rim of a ridge), nothing is right above the top and it holds
    // nothing up (`check` finds no contact there).
    const bool away = ceiling->lowest - sample.z > kLevel;
    const int rank = (away ? kRankAway : 0) + (fl.level ? 0 : kRankSlope) +
                     (pillar_keeps_clearance_beside(model, pl, p) ? 0 : kRankAgainst);
    return {PillarFit::Fits, pl, rank};
}

}  // namespace

std::optional<Vec3> clear_tip_foot(const ModelQuery& model, const Vec3& foot, const Vec3& top, const Params& p) {
    const double max_slant = 0.9 * std::tan(deg_to_rad(p.critical_angle)) * (top.z - foot.z);
    for (const auto& off : nearby_offsets()) {
        const Vec3 c = foot + off;
        if (horizontal_distance(c, top) > max_slant) continue;
        if (square_is_clear(model, c, p.d_min) && prism_is_clear(model, c, p.d_min, top, p.tip_diameter)) return c;
    }
    return std::nullopt;
}

bool square_is_clear(const ModelQuery& model, const Vec3& c, double w) {
    return model.verdict(tree_question(TreeVerdict::square, {c.x, c.y, c.z, w}), [&] {
        const auto sq = square_points(c, w);
        // The edges first: they are cheap, and one that hits decides without the costlier inside test.
        for (size_t i = 1; i < sq.size(); ++i)
            if (model.segment_hits(sq[i], sq[i % 4 + 1])) return false;
        // No edge crosses the surface: the four corners lie on one side of a closed surface, and
        // one inside test answers for all of them.
        return !model.inside(sq[1]);
    });
}

bool prism_is_clear(const ModelQuery& model, const Vec3& bottom, double wb, const Vec3& top, double wt) {
    return model.verdict(tree_question(TreeVerdict::prism, {bottom.x, bottom.y, bottom.z, wb, top.x, top.y, top.z, wt}), [&] {
        const auto lo = square_points(bottom, wb), hi = square_points(top, wt);
        for (size_t i = 0; i < lo.size(); ++i)
            if (model.segment_hits(lo[i], hi[i])) return false;
        for (size_t i = 1; i < lo.size(); ++i) {
            size_t j = i % 4 + 1;
            if (model.segment_hits(lo[i], lo[j]) || model.segment_hits(hi[i], hi[j])) return false;
        }
        return true;
    });
}

PillarPlacement fit_pillar(const ModelQuery& model, const Vec3& sample, const Params& p) {
    auto hit = model.first_hit(sample - Vec3{0, 0, 1e-4}, {0, 0, -1});
    const double below = hit ? hit->point.z : 0.0;
    std::optional<Attempt> best;
    bool too_low = false;
    for (const auto& off : nearby_offsets()) {
        Attempt a = pillar_at(model, sample, sample + off, below, p);
        too_low = too_low || a.fit == PillarFit::TooLow;
        if (a.fit != PillarFit::Fits || (best && best->rank <= a.rank)) continue;
        best = a;
        if (a.rank == 0) break;
    }
    if (best) return {PillarFit::Fits, best->pillar};
    return {too_low ? PillarFit::TooLow : PillarFit::NoRoom, {}};
}

Vec3 contact_under_tip(const ModelQuery& model, const Vec3& contact, double from_z, const Params& p) {
    const Floor fl = floor_under(model, {contact.x, contact.y, from_z}, p.tip_diameter, p.gap);
    return {contact.x, contact.y, std::max(contact.z, fl.z)};
}

std::optional<Vec3> place_tip_top(const ModelQuery& model, const Vec3& sample, const Params& p) {
    // Rays start a tip's length below the gap, under the overhang.
    const double start = sample.z - p.gap - p.tip_length;
    bool any_ceiling = false;
    // The top at `off` from the sample, if its square keeps the gap within a contact's tolerance
    // and no corner of it is in the model; with the ceiling's height over its centre, and whether
    // it is away from the overhang: moved where the overhang over all of its square is higher
    // than the sample, the top (a gap under the sample) has nothing right above it and holds
    // nothing up (`check` finds no contact there).
    struct Fit {
        Vec3 top;
        double over_centre;
        bool away;
    };
    auto fit_at = [&](const Vec3& off, double allowed) -> std::optional<Fit> {
        const Vec3 c{sample.x + off.x, sample.y + off.y, start};
        auto ceiling = ceiling_above(model, square_points(c, p.tip_diameter), sample.z);
        any_ceiling = any_ceiling || ceiling;
        if (!ceiling || ceiling->drop > allowed) return std::nullopt;
        Vec3 top{c.x, c.y, sample.z - p.gap - ceiling->drop};
        // A corner of the top in the model (the overhang's edge turning down beside the sample)
        // is no place for a tip.
        if (!square_is_clear(model, top, p.tip_diameter)) return std::nullopt;
        return Fit{top, ceiling->over_centre, ceiling->lowest - sample.z > kLevel};
    };
    std::optional<Vec3> nearest_fit;   // taken when no top that fits keeps the side clearance
    std::optional<Vec3> nearest_away;  // taken when no top that holds the overhang fits at all
    for (const auto& off : nearby_offsets()) {
        const auto fit = fit_at(off, allowed_drop(p));
        if (!fit) continue;
        const auto& [top, over_centre, away] = *fit;
        if (away) {
            if (!nearest_away) nearest_away = top;
            continue;
        }
        // A top moved off a wall must still touch what its sample hangs from: beside a lowest
        // point or under a curve the ceiling rises away from the sample, and a top left at the
        // sample's height would hang below it in air.
        const bool moved = nearest_fit.has_value();
        if (!moved) nearest_fit = top;
        if (keeps_clearance_beside(model, top, p) && (!moved || over_centre - top.z <= p.gap + kLevel)) return top;
    }
    if (nearest_fit) return nearest_fit;
    // A sample on the very edge of a slope that runs diagonally to the tip's square (the upper
    // edge of a twisted blade): uphill is past the edge, and the square below dips its far corner
    // further than allowed_drop, which allows for a slope along a side of the square. The corner
    // is half a diagonal out: the top may drop that much more, there only. Its nearest corner
    // still keeps the gap, and it stays as near the sample as any other top.
    std::optional<Vec3> diagonal_away;
    for (const auto& off : nearby_offsets())
        if (const auto fit = fit_at(off, diagonal_drop(p))) {
            if (!fit->away) return fit->top;
            if (!diagonal_away) diagonal_away = fit->top;
        }
    // Only tops away from the overhang fit: the nearest (a tip there still stands under the model).
    if (nearest_away) return nearest_away;
    if (diagonal_away) return diagonal_away;
    // Nothing above at all (a point given in open air): no gap to keep but the sample's own.
    if (!any_ceiling) return sample - Vec3{0, 0, p.gap};
    return std::nullopt;
}

}  // namespace cs

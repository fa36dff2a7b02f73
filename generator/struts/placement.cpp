#include "struts/placement.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>

#include "query/model_query.hpp"

namespace cs {
namespace {

// How far a tip's top or a pillar may move off its sample: well inside the reach of its contact
// (the lattice cell's radius, (sqrt 2 / 2) * sampling, for any sampling of a millimetre or more).
constexpr double kMaxShift = 0.5;
// A pillar's footprint counts as level when its corners' floors differ by no more than this:
// such a placement is preferred, it stands on all of its foot.
constexpr double kLevel = 0.05;

// Straight below the sample first, then rings of eight directions a quarter and a half millimetre
// aside: nearest first, so a top or a pillar moves no further than it must.
const std::vector<Vec3>& nearby_offsets() {
    static const std::vector<Vec3> offsets = [] {
        std::vector<Vec3> out{{0, 0, 0}};
        for (double r : {0.5 * kMaxShift, kMaxShift})
            for (int i = 0; i < 8; ++i) out.push_back({r * std::cos(i * M_PI / 4), r * std::sin(i * M_PI / 4), 0});
        return out;
    }();
    return offsets;
}

// The centre and the four corners of a horizontal square of side w around c.
std::array<Vec3, 5> square_points(const Vec3& c, double w) {
    const double h = 0.5 * w;
    return {c, c + Vec3{h, h, 0}, c + Vec3{h, -h, 0}, c + Vec3{-h, -h, 0}, c + Vec3{-h, h, 0}};
}

// How far the overhang above a square's corners comes down below `z` (0 when it does not),
// nullopt when nothing is above the centre.
std::optional<double> ceiling_drop(const ModelQuery& model, const std::array<Vec3, 5>& square, double z) {
    double drop = 0;
    for (size_t i = 0; i < square.size(); ++i) {
        auto hit = model.first_hit(square[i], {0, 0, 1});
        if (!hit) {
            if (i == 0) return std::nullopt;
            continue;  // this corner reaches past the overhang's edge
        }
        drop = std::max(drop, z - hit->point.z);
    }
    return drop;
}

// How much lower than a gap under the sample a tip's top may sit and still count as a contact.
double allowed_drop(const Params& p) { return contact_tolerance(p) - p.gap - 0.05; }

struct Floor {
    double highest = -INFINITY, lowest = INFINITY;
    bool on_model = false;
};

// What is below a square's corners: the model (highest point under any corner) or the bed.
Floor floor_under(const ModelQuery& model, const std::array<Vec3, 5>& square) {
    Floor fl;
    for (const auto& q : square) {
        auto hit = model.first_hit(q, {0, 0, -1});
        double z = hit ? hit->point.z : 0.0;
        fl.on_model = fl.on_model || hit.has_value();
        fl.highest = std::max(fl.highest, z), fl.lowest = std::min(fl.lowest, z);
    }
    return fl;
}

// Is every point of the squares in the air, with no wall between it and the centre?
bool in_open_air(const ModelQuery& model, const Vec3& centre, const std::array<Vec3, 5>& a,
                 const std::array<Vec3, 5>& b) {
    for (const auto& set : {a, b})
        for (const auto& q : set)
            if (model.inside(q) || (q != centre && model.segment_hits(centre, q))) return false;
    return true;
}

struct Attempt {
    PillarFit fit = PillarFit::NoRoom;
    Pillar pillar;
    bool level = false;
};

Attempt pillar_at(const ModelQuery& model, const Vec3& sample, const Vec3& centre, double below, const Params& p) {
    // Rays start half-way between the overhang and what is below it, in the slot's air.
    const Vec3 mid{centre.x, centre.y, 0.5 * (sample.z + below)};
    const auto top = square_points(mid, p.tip_diameter), foot = square_points(mid, p.d_min);
    if (!in_open_air(model, mid, top, foot)) return {};
    auto drop = ceiling_drop(model, top, sample.z);
    if (!drop || *drop > allowed_drop(p)) return {};
    const Floor fl = floor_under(model, foot);
    Pillar pl;
    pl.on_model = fl.on_model;
    pl.top = {centre.x, centre.y, sample.z - *drop - p.gap};
    pl.bottom = {centre.x, centre.y, fl.on_model ? fl.highest + p.gap : 0.0};
    if (pl.top.z - pl.bottom.z < p.layer_height) return {PillarFit::TooLow, pl};
    if (!prism_is_clear(model, pl.bottom, p.d_min, pl.top, p.tip_diameter)) return {};
    return {PillarFit::Fits, pl, fl.highest - fl.lowest <= kLevel};
}

}  // namespace

bool prism_is_clear(const ModelQuery& model, const Vec3& bottom, double wb, const Vec3& top, double wt) {
    const auto lo = square_points(bottom, wb), hi = square_points(top, wt);
    for (size_t i = 0; i < lo.size(); ++i)
        if (model.segment_hits(lo[i], hi[i])) return false;
    for (size_t i = 1; i < lo.size(); ++i) {
        size_t j = i % 4 + 1;
        if (model.segment_hits(lo[i], lo[j]) || model.segment_hits(hi[i], hi[j])) return false;
    }
    return true;
}

PillarPlacement fit_pillar(const ModelQuery& model, const Vec3& sample, const Params& p) {
    auto hit = model.first_hit(sample - Vec3{0, 0, 1e-4}, {0, 0, -1});
    const double below = hit ? hit->point.z : 0.0;
    std::optional<Pillar> first_fit;
    bool too_low = false;
    for (const auto& off : nearby_offsets()) {
        Attempt a = pillar_at(model, sample, sample + off, below, p);
        too_low = too_low || a.fit == PillarFit::TooLow;
        if (a.fit != PillarFit::Fits) continue;
        if (a.level) return {PillarFit::Fits, a.pillar};
        if (!first_fit) first_fit = a.pillar;
    }
    if (first_fit) return {PillarFit::Fits, *first_fit};
    return {too_low ? PillarFit::TooLow : PillarFit::NoRoom, {}};
}

Vec3 contact_under_tip(const ModelQuery& model, const Vec3& contact, double from_z, const Params& p) {
    const Floor fl = floor_under(model, square_points({contact.x, contact.y, from_z}, p.tip_diameter));
    return {contact.x, contact.y, std::max(contact.z, fl.highest)};
}

Vec3 place_tip_top(const ModelQuery& model, const Vec3& sample, const Params& p) {
    // Rays start a tip's length below the gap, under the overhang.
    const double start = sample.z - p.gap - p.tip_length;
    std::optional<Vec3> least;
    double least_drop = INFINITY;
    for (const auto& off : nearby_offsets()) {
        const Vec3 c{sample.x + off.x, sample.y + off.y, start};
        auto drop = ceiling_drop(model, square_points(c, p.tip_diameter), sample.z);
        if (!drop) continue;
        Vec3 top{c.x, c.y, sample.z - p.gap - *drop};
        if (*drop <= allowed_drop(p)) return top;
        if (*drop < least_drop) least_drop = *drop, least = top;
    }
    Vec3 top = least ? *least : sample - Vec3{0, 0, p.gap};
    return {top.x, top.y, std::max(top.z, sample.z - p.gap - allowed_drop(p))};
}

}  // namespace cs

#include "ceilings/hybrid.hpp"

#include <algorithm>
#include <cmath>

#include "core/rules.hpp"
#include "query/model_query.hpp"

namespace cs {
namespace {

// A piece this much longer than `check`'s bound for a long top (two coverage reaches, three times
// its thickness) is judged long however the judge rounds its reach (it rounds up by under 2 %).
constexpr double kSurelyLong = 1.05;
// Under a foot: its tip, then a strut this many d_min long with its air from the model, before
// the model or the bed (can_escape tries a strut of about two widths).
constexpr double kStrutsUnderFoot = 2.0;

// Does a tip fit under the foot: its column (tip_diameter at the foot, d_min at the leaf a tip
// length down) keeps the air a strut keeps from the model (leaf_position's clearance)?
bool tip_fits(const ModelQuery& q, const Vec3& foot, const Params& p) {
    const Vec3 leaf = foot - Vec3{0, 0, p.tip_length};
    const double at_leaf = 0.5 * std::sqrt(2.0) * p.d_min + p.model_clearance;
    const double at_foot = 0.5 * std::sqrt(2.0) * p.tip_diameter + p.model_clearance;
    return !q.inside(leaf) && q.squared_distance(leaf) >= at_leaf * at_leaf && q.squared_distance(foot) >= at_foot * at_foot &&
           !q.segment_hits(foot, leaf);
}

// Each flat piece cut into as few pieces as the printer bridges, each on the tip at the middle of
// its foot: pieces shorter than twice what `check` finds long (the bridge from foot to foot, and
// twice the overhang past a row's end foot, stay under that), and at least that long (or left whole
// where it is short). Each foot is a tip of the tree, an island on every layer down to where it
// merges: the G-code of the validation parts spends most of its support minutes on those islands
// (shelf_bracket's arm: 57 in one layer under its pieces). Pieces whose tip does not fit are not built.
std::vector<CeilingWall> cut_at_feet(const ModelQuery& q, const std::vector<CeilingWall>& pieces, const Params& p) {
    std::vector<CeilingWall> out;
    for (const CeilingWall& w : pieces) {
        const double length = horizontal_distance(w.from, w.to);
        const double shortest = kSurelyLong * long_top(p, w.thickness);
        const int n = static_cast<int>(std::floor(length / (2 * shortest))) + 1;
        for (int k = 0; k < n; ++k) {
            CeilingWall c = w;
            c.from = w.from + (w.to - w.from) * (double(k) / n);
            c.to = w.from + (w.to - w.from) * (double(k + 1) / n);
            c.on_tree = true;
            if (tip_fits(q, feet_of({c}).front(), p)) out.push_back(c);
        }
    }
    return out;
}

}  // namespace

std::optional<double> hybrid_floor(const ModelQuery& q, const Vec3& x, const Params& p) {
    const double foot = x.z - p.gap - p.hybrid_height;
    auto hit = q.first_hit(x - Vec3{0, 0, 1e-3}, {0, 0, -1});
    const double below = hit ? hit->point.z : 0.0;
    const double room = p.tip_length + kStrutsUnderFoot * p.d_min + p.model_clearance + p.gap;
    if (foot - below < room) return std::nullopt;
    return foot;
}

std::vector<Vec3> feet_of(const std::vector<CeilingWall>& pieces) {
    std::vector<Vec3> feet;
    for (const CeilingWall& w : pieces) feet.push_back({0.5 * (w.from.x + w.to.x), 0.5 * (w.from.y + w.to.y), w.bottom});
    return feet;
}

Ceilings without_feet(const ModelQuery& q, const std::vector<Sample>& samples, const std::vector<char>& stay,
                      const Ceilings& h, const std::vector<Vec3>& lost, const Params& p) {
    std::vector<CeilingWall> kept;
    for (const CeilingWall& w : h.walls) {
        const Vec3 foot = feet_of({w}).front();
        if (std::none_of(lost.begin(), lost.end(), [&](const Vec3& f) { return distance(f, foot) < 1e-9; })) kept.push_back(w);
    }
    Ceilings out = carried_by(q, samples, stay, std::move(kept), p);
    out.feet = feet_of(out.walls);
    out.regions = out.walls.empty() ? 0 : h.regions;
    return out;
}

Ceilings support_hybrid(const ModelQuery& q, const std::vector<Sample>& samples, const Params& p,
                        const FeetTreeCounter& tree_count, const std::vector<Box3>& blockers, const TipAt& tip_at,
                        const std::vector<char>& stay, bool rows_across) {
    if (p.hybrid_height <= 0) {
        Ceilings none;
        none.rest = samples, none.stay = stay;
        return none;
    }
    Ceilings out = lay_out_ceilings(
        q, samples, p, [&](std::vector<CeilingWall> pieces) { return cut_at_feet(q, pieces, p); },
        [&](const std::vector<Sample>& s, const std::vector<CeilingWall>& pieces) {
            return s.empty() && pieces.empty() ? TreeCount{} : tree_count(s, feet_of(pieces));
        },
        blockers, kMostLeftToPrice, tip_at, stay, {}, rows_across);
    out.feet = feet_of(out.walls);
    return out;
}

}  // namespace cs

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

// The cuts of n equal pieces, as fractions (hybrid_piece_cuts).
std::vector<double> equal_cuts(int n) {
    std::vector<double> cuts;
    for (int k = 0; k <= n; ++k) cuts.push_back(double(k) / n);
    return cuts;
}

// Each flat piece cut where hybrid_piece_cuts says: the end pieces under twice what `check` finds long
// (each overhangs its foot by under a long top), at least that long (or left whole where it is
// short). Each foot is a tip of the tree, an island on every layer down to where it merges: the
// G-code of the validation parts spends most of its support minutes on those islands
// (shelf_bracket's arm: 57 in one layer under its pieces). Pieces whose tip does not fit are not built.
std::vector<CeilingWall> cut_at_feet(const ModelQuery& q, const std::vector<CeilingWall>& pieces, const Params& p) {
    std::vector<CeilingWall> out;
    // The pieces of `w` between `cuts` whose tip fits, and how many do not.
    struct Cut {
        std::vector<CeilingWall> built;
        std::size_t lost = 0;
    };
    auto cut = [&](const CeilingWall& w, const std::vector<double>& cuts) {
        Cut kept;
        for (std::size_t k = 0; k + 1 < cuts.size(); ++k) {
            CeilingWall c = w;
            c.from = w.from + (w.to - w.from) * cuts[k];
            c.to = w.from + (w.to - w.from) * cuts[k + 1];
            c.on_tree = true;
            if (tip_fits(q, feet_of({c}).front(), p)) kept.built.push_back(c);
            else ++kept.lost;
        }
        return kept;
    };
    for (const CeilingWall& w : pieces) {
        const double length = horizontal_distance(w.from, w.to);
        const double end_most = 2 * kSurelyLong * long_top(p, w.thickness);
        auto kept = cut(w, hybrid_piece_cuts(length, end_most, p.hybrid_bridge));
        // Longer pieces move the feet: where one then has no room for its tip (a post beside it),
        // equal pieces as short as the end ones, if they lose fewer.
        if (kept.lost > 0 && p.hybrid_bridge > end_most) {
            Cut equal = cut(w, hybrid_piece_cuts(length, end_most, 0));
            if (equal.lost < kept.lost) kept = std::move(equal);
        }
        out.insert(out.end(), kept.built.begin(), kept.built.end());
    }
    return out;
}

}  // namespace

// Each piece stands on the tip at the middle of its foot (`check` grounds a solid by its foot's
// middle), so a row's end piece overhangs its foot by half its length on the side with no foot, and
// between two feet the row's bottom bridges from tip to tip, half of each piece.
std::vector<double> hybrid_piece_cuts(double length, double end_most, double bridge) {
    const int equal = static_cast<int>(std::floor(length / end_most)) + 1;  // each piece under end_most
    if (bridge <= end_most) return equal_cuts(equal);
    // n pieces: two ends e (under end_most) and n - 2 pieces r e between them (r = bridge / end_most).
    const double r = bridge / end_most;
    auto end_piece = [&](int n) { return length / (2 + (n - 2) * r); };
    int n = 3;
    while (end_piece(n) >= end_most) ++n;
    // As many feet either way (always so for two or fewer): equal pieces, whose bridges are the shorter.
    if (n >= equal) return equal_cuts(equal);
    const double e = end_piece(n);
    std::vector<double> cuts{0.0};
    for (int k = 1; k < n; ++k) cuts.push_back((e + (k - 1) * r * e) / length);
    cuts.push_back(1.0);
    return cuts;
}

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

#include "tree/clearance.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "core/rules.hpp"
#include "query/model_query.hpp"
#include "tree/candidates.hpp"
#include "tree/placement.hpp"
#include "tree/tuning.hpp"
#include "tree/verdicts.hpp"

namespace cs {

namespace {

// strut_is_clear's verdict, asked of the model every time.
bool strut_is_clear_now(const ModelQuery& model, const Vec3& a, double wa, const Vec3& b, double wb, double clearance,
                        bool onto_model, double joint_reach) {
    // The strut's own edges, and the same pushed out by the clearance (a bump of the model can
    // slip between the outer lines and still cut the strut, so both are asked), then its axis.
    // The verdict is all of them; the outer edges first, as the likeliest to meet the model.
    for (double c : {clearance, 0.0}) {
        if (c == clearance && clearance == 0.0) continue;  // asked once, as the strut's own
        double ra = 0.5 * wa + c, rb = 0.5 * wb + c;
        // The built strut reaches past b into its joint: onto the model, that end must stay clear too.
        const Vec3 b_end = onto_model && c == 0.0 ? b + normalized(b - a) * joint_reach : b;
        for (auto [sx, sy] : {std::pair{1, 1}, {1, -1}, {-1, 1}, {-1, -1}}) {
            Vec3 ea = a + Vec3{sx * ra, sy * ra, 0}, eb = b_end + Vec3{sx * rb, sy * rb, 0};
            if (model.segment_hits(ea, eb)) return false;
        }
    }
    if (model.segment_hits(a, b)) return false;
    if (onto_model) {
        // The strut's foot hangs a tip's length above the model: a ridge of the model can rise
        // between its edges into the foot's square. Spokes across the square catch it.
        const Vec3 foot = b + normalized(b - a) * joint_reach;
        const double r = 0.5 * wb;
        for (auto [sx, sy] : {std::pair{1, 1}, {1, -1}, {-1, 1}, {-1, -1}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}})
            if (model.segment_hits(foot, foot + Vec3{sx * r, sy * r, 0})) return false;
    }
    // The edges miss a bump of the model that pokes between them: also keep a ball around the
    // axis, as wide as the strut's square (half-diagonal), free of the model.
    double len = distance(a, b);
    // Balls of radius r spaced r apart cover the axis with overlap: no gap for a bump to hide in.
    double r_min = 0.5 * std::min(wa, wb) * std::sqrt(2.0);
    int steps = std::max(1, static_cast<int>(std::ceil(len / std::clamp(r_min, 0.35, 2.0))));
    // A strut onto the model ends a tip's length above it: near that end the balls shrink so they
    // stay clear of the contact itself (they still catch a bump between the edges).
    double end_room = onto_model ? 0.9 * std::sqrt(model.squared_distance(b)) : INFINITY;
    // The distance to the model changes no faster than the point moves: a point whose ball the
    // last measured distance already keeps clear (by more than a rounding margin) needs no query.
    // Same answer as asking at every point; far from the model most points are skipped.
    double known = -INFINITY;
    Vec3 known_at = a;
    for (int i = 0; i <= steps; ++i) {
        double t = double(i) / steps;
        double r = std::min((0.5 * (wa + (wb - wa) * t)) * std::sqrt(2.0), (1 - t) * len + end_room);
        const Vec3 q = a + (b - a) * t;
        if (known - distance(q, known_at) >= r + kTreeTuning.distance_bound_margin) continue;
        const double d2 = model.squared_distance(q);
        if (d2 < r * r) return false;
        known = std::sqrt(d2), known_at = q;
    }
    return true;
}

}  // namespace

bool strut_is_clear(const ModelQuery& model, const Vec3& a, double wa, const Vec3& b, double wb, double clearance,
                    bool onto_model, double joint_reach) {
    const auto question = tree_question(TreeVerdict::strut, {a.x, a.y, a.z, wa, b.x, b.y, b.z, wb, clearance, onto_model ? 1.0 : 0.0, joint_reach});
    return model.verdict(question, [&] { return strut_is_clear_now(model, a, wa, b, wb, clearance, onto_model, joint_reach); });
}

bool contact_tip_is_clear(const ModelQuery& model, const Params& p, const Vec3& node, const Vec3& contact, double width) {
    const auto bottom = contact_tip_bottom(contact_under_tip(model, contact, node.z, p), node, p);
    if (!bottom) return true;
    const TipEnds t = contact_tip(p, *bottom, node, width);
    return prism_is_clear(model, t.bottom, t.bottom_width, t.top, t.top_width);
}

bool enters_support_blocker(const Params& p, const std::vector<Box3>& support_blockers, const Vec3& a, const Vec3& b,
                            double wb) {
    if (support_blockers.empty()) return false;
    const double reach = joint_overlap(p);
    if (sweep_meets_boxes(a, b, wb, reach, support_blockers)) return true;
    return b.z < 1e-6 && p.feet &&
           sweep_meets_boxes(b, b + Vec3{0, 0, p.foot_height}, wb + 2 * p.foot_extra, 0, support_blockers);
}

bool can_escape(const ModelQuery& model, const Params& p, const ConeFan& fan, const Vec3& a, double w) {
    for (const auto& d : fan.dirs) {
        double len = std::min(kTreeTuning.escape_length, a.z / -d.z);
        Vec3 to = a + d * len;
        double wb = std::max(w, eqn1_width(p, len, angle_from_vertical_deg(a, to)));
        if (strut_is_clear(model, a, w, to, wb, p.gap)) return true;
    }
    return false;
}

Vec3 leaf_position(const ModelQuery& model, const Params& p, double tan_c, const Vec3& below) {
    // The strut is square: its corners stand half a diagonal from its axis, whichever way the wall is.
    const double need = 0.5 * std::sqrt(2.0) * p.d_min + p.model_clearance + 0.05;
    double d = std::sqrt(model.squared_distance(below));
    if (d >= need) return below;
    Vec3 away = below - model.closest_point(below);
    away.z = 0;
    if (norm(away) < 1e-9) return below;
    double limit = std::min(0.5 * p.sampling_distance, p.tip_length * tan_c * 0.9);
    Vec3 moved = below + normalized(away) * std::min(need - d, limit);
    // In a slot narrower than a strut, moving off one wall meets the other: stay put.
    if (model.segment_hits(below, moved) || model.inside(moved)) return below;
    return moved;
}

}  // namespace cs

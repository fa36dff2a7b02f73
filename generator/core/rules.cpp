#include "core/rules.hpp"

#include <algorithm>
#include <cmath>

namespace cs {

EndWidths strut_end_widths(const Params& p, double node_width, double run_length, double run_angle_deg, double length,
                           double angle_deg) {
    EndWidths w;
    w.top = std::clamp(std::max(node_width, strength_width(p, run_length, run_angle_deg)), p.d_min, p.d_max);
    w.bottom = std::max(w.top, eqn1_width(p, length, angle_deg));
    return w;
}

double min_n_width(const Params& p) { return 3 * p.wall_thickness; }

double joint_overlap(const Params& p) { return 0.5 * p.layer_height; }

TipEnds leaf_tip(const Params& p, const Vec3& node, const Vec3& tip_top, double strut_width) {
    return {node - Vec3{0, 0, joint_overlap(p)}, tip_top, strut_width, p.tip_diameter};
}

TipEnds contact_tip(const Params& p, const Vec3& tip_bottom, const Vec3& node, double strut_width) {
    return {tip_bottom, node, p.tip_diameter, strut_width};
}

double touching_space(const Params& p) { return 2 * p.gap + p.layer_height; }

double contact_tolerance(const Params& p) {
    double steepest = std::tan(deg_to_rad(90 - p.critical_angle));  // slope of the steepest overhang
    return p.gap + 0.5 * p.tip_diameter * steepest + 0.05;
}

}  // namespace cs

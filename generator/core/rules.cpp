#include "core/rules.hpp"

#include <algorithm>
#include <cmath>

namespace cs {
namespace {

// The paper's Table 1: 1 mm struts are safe to 30 mm at <= 30 deg; 1.5 mm struts to 60 mm at
// <= 50 deg. A safe length growing with d^2 (stiffness of a thin column against the nozzle's push)
// matches both points: 30 * 1.5^2 * 0.85 = 57 mm at 50 deg. Steeper struts lose 15% per 20 deg.
double angle_factor(double angle_deg) {
    double a = std::max(0.0, angle_deg - 30.0);
    return std::max(0.3, 1.0 - 0.15 * a / 20.0);
}

}  // namespace

double safe_length(const Params& p, double d, double angle_deg) {
    return p.strength_length * d * d * angle_factor(angle_deg);
}

double strength_width(const Params& p, double length, double angle_deg) {
    return std::sqrt(std::max(0.0, length) / (p.strength_length * angle_factor(angle_deg)));
}

double eqn1_width(const Params& p, double length, double angle_deg) {
    return std::clamp(p.k * length * angle_deg, p.d_min, p.d_max);
}

double merged_width(const Params& p, const std::vector<double>& widths) {
    double cubes = 0, widest = 0;
    for (double w : widths) cubes += w * w * w, widest = std::max(widest, w);
    return std::clamp(std::max(std::cbrt(cubes), widest), p.d_min, p.d_max);
}

EndWidths strut_end_widths(const Params& p, double node_width, double run_length, double run_angle_deg, double length,
                           double angle_deg) {
    EndWidths w;
    w.top = std::clamp(std::max(node_width, strength_width(p, run_length, run_angle_deg)), p.d_min, p.d_max);
    w.bottom = std::max(w.top, eqn1_width(p, length, angle_deg));
    return w;
}

double overhang_normal_z_limit(double critical_angle_deg) {
    return -std::sin(deg_to_rad(critical_angle_deg)) - kCriticalRounding;
}

double min_n_width(const Params& p) { return 3 * p.wall_thickness; }

double joint_overlap(const Params& p) { return 0.5 * p.layer_height; }

TipEnds leaf_tip(const Params& p, const Vec3& node, const Vec3& tip_top, double strut_width) {
    return {node - Vec3{0, 0, joint_overlap(p)}, tip_top, strut_width, p.tip_diameter};
}

TipEnds contact_tip(const Params& p, const Vec3& tip_bottom, const Vec3& node, double strut_width) {
    return {tip_bottom, node, p.tip_diameter, strut_width};
}

std::optional<Vec3> contact_tip_bottom(const Vec3& contact, const Vec3& node, const Params& p) {
    const Vec3 bottom = contact + Vec3{0, 0, p.gap};
    if (node.z - bottom.z <= kShortestContactTip) return std::nullopt;
    return bottom;
}

double surface_rise(double run, double critical_angle_deg) { return run * std::tan(deg_to_rad(90 - critical_angle_deg)); }

double touching_space(const Params& p) { return 2 * p.gap + p.layer_height; }

bool rests_at(double air, double space) { return air <= space - kHeightRounding; }

double tip_side_clearance(const Params& p) { return 0.5 * p.line_width; }

double contact_tolerance(const Params& p) {
    double steepest = std::tan(deg_to_rad(90 - p.critical_angle));  // slope of the steepest overhang
    return p.gap + 0.5 * p.tip_diameter * steepest + 0.05;
}

}  // namespace cs

#include "core/slicer_time.hpp"

#include <algorithm>
#include <cmath>

namespace cs {

double tree_route_seconds(const SlicerRoute& r, double island_layers, double outline_mm, double hop_mm) {
    return r.island_s * island_layers + r.outline_s_per_mm * outline_mm + r.hop_s_per_mm * hop_mm;
}

double stroke_seconds(double mm, double end_speed, double speed, double acceleration) {
    if (mm <= 0) return 0;
    const double v0 = std::min(end_speed, speed);
    const double ramp = (speed * speed - v0 * v0) / (2 * acceleration);  // to full speed, and back
    if (2 * ramp <= mm) return 2 * (speed - v0) / acceleration + (mm - 2 * ramp) / speed;
    const double peak = std::sqrt(v0 * v0 + acceleration * mm);  // never reaches full speed
    return 2 * (peak - v0) / acceleration;
}

double line_route_seconds(const SlicerRoute& r, double mm, double width) {
    // A wider wall gets a pass more per extra line width (both slicers fill it with lines).
    const double passes = r.passes * std::max(1.0, std::ceil(width / r.one_pass_width - 1e-9));
    return passes * stroke_seconds(mm, r.turn_speed, r.print_speed, r.acceleration);
}

double outline_route_seconds(const SlicerRoute& r, double length, double width) {
    return 2 * (stroke_seconds(length, r.turn_speed, r.print_speed, r.acceleration) +
                stroke_seconds(width, r.turn_speed, r.print_speed, r.acceleration));
}

}  // namespace cs

#include "job/job.hpp"
#include "job/result.hpp"

#include <cmath>
#include <fmt/format.h>

namespace cs {

bool is_scad_input(const std::string& path) { return path.size() > 5 && path.substr(path.size() - 5) == ".scad"; }

std::string pose_in_words(const Placement& pl) {
    const Vec3 a = euler_deg_from_rotation(pl.rotation);
    auto tidy = [](double v) { return std::abs(v) < 5e-4 ? 0.0 : v; };  // no "-0.0"
    return fmt::format("scaled {:g}, rotated {:.1f} deg about X, then {:.1f} about Y, then {:.1f} about Z, then moved by "
                       "({:.2f}, {:.2f}, {:.2f}) mm",
                       pl.scale, tidy(a.x), tidy(a.y), tidy(a.z), tidy(pl.translation.x), tidy(pl.translation.y),
                       tidy(pl.translation.z));
}

std::string pose_mapping(const Placement& pl) {
    const Vec3 a = euler_deg_from_rotation(pl.rotation);
    auto tidy = [](double v) { return std::abs(v) < 5e-4 ? 0.0 : v; };
    return fmt::format("placed = translate([{:.4g}, {:.4g}, {:.4g}]) rotate([{:.4g}, {:.4g}, {:.4g}]) scale({:g}) design: "
                       "multiply the design point by the scale, rotate it about the origin by the angles (X, then Y, "
                       "then Z, as OpenSCAD's rotate), then add the offset. --block, --support-point and the .scad's "
                       "edits take placed coordinates (those of <name>.model.stl)",
                       tidy(pl.translation.x), tidy(pl.translation.y), tidy(pl.translation.z), tidy(a.x), tidy(a.y),
                       tidy(a.z), pl.scale);
}

std::vector<double> pose_numbers(const Placement& pl) {
    std::vector<double> v{pl.scale};
    for (const auto& row : pl.rotation) v.insert(v.end(), row, row + 3);
    v.insert(v.end(), {pl.translation.x, pl.translation.y, pl.translation.z});
    return v;
}

}  // namespace cs

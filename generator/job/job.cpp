#include "job/job.hpp"
#include "job/result.hpp"

namespace cs {

bool is_scad_input(const std::string& path) { return path.size() > 5 && path.substr(path.size() - 5) == ".scad"; }

std::vector<double> pose_numbers(const Placement& pl) {
    std::vector<double> v{pl.scale};
    for (const auto& row : pl.rotation) v.insert(v.end(), row, row + 3);
    v.insert(v.end(), {pl.translation.x, pl.translation.y, pl.translation.z});
    return v;
}

}  // namespace cs

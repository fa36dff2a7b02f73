// A user's own preset: the JSON of `--config FILE`, read and checked whole before anything uses it.
// Every key is either a parameter under its flag name without dashes (core/param_table.hpp), of
// that row's type, or one of
//   "preset"         a preset name (a string)
//   "description"    free text (a string)
//   "support-blocker" a list of support blockers, each [x0, y0, z0, x1, y1, z1] (mm); "block"
//                    is its old name
//   "support-point"  a list of points to support, each [x, y, z] (mm)
// Anything else, or any value of the wrong type, is a ParameterError naming `where` and the key
// (exit 2), never a JSON library exception.
//
// Example:
//   ConfigFile c = parse_config(R"({"preset": "prusa-mk4-pla", "sampling": 2})", "--config my.json");
//   Params p = preset_params(c.preset.value_or("generic-0.4"));
//   apply_config(c.values, p, "--config my.json");
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/geometry.hpp"

namespace cs {

struct ConfigFile {
    std::optional<std::string> preset;  // the preset it names, if any
    nlohmann::json values;              // the whole object, every value of its key's type
    std::vector<Box3> blockers;         // "support-blocker" and "block"
    std::vector<Vec3> support_points;   // "support-point"
};

// `where` starts every message ("--config my.json").
ConfigFile parse_config(std::string_view text, const std::string& where);

}  // namespace cs

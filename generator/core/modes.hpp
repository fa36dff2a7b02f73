// The two choices that used to travel as strings: the support strategy and the orientation mode.
// Each is parsed from, and formatted to, its external spelling here and nowhere else; the rest of
// the code compares enum values.
#pragma once

#include <array>
#include <string>

namespace cs {

// What grows under the overhangs: the tree (the paper's method) or the vertical-columns baseline
// the report compares it with.
enum class Strategy { tree, columns };

// "tree" | "columns" (the spelling of --strategy, the config file, the report and cs_strategy).
const char* to_string(Strategy s);
// Throws ParameterError "strategy must be 'tree' or 'columns', not '<text>'".
Strategy parse_strategy(const std::string& text);

// How the model is turned before it is placed on the bed.
enum class OrientMode {
    automatic,  // the pose that needs the least support ("auto")
    keep,       // the input as it is
    euler,      // rotations about x, y, z given in degrees
};

// "auto" | "keep" | "euler" (the report's placement.orientation and the summary line).
const char* to_string(OrientMode m);

// An --orient value: the mode, and for `euler` its three angles.
struct OrientRequest {
    OrientMode mode = OrientMode::automatic;
    std::array<double, 3> degrees{0, 0, 0};
};

// Parses "auto", "keep" or "RX,RY,RZ" (degrees); throws ParameterError naming --orient otherwise.
OrientRequest parse_orient(const std::string& text);

}  // namespace cs

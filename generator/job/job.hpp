// One run of the generator as the user asked for it: the input, how to place it, the user's edits
// to the supports and the parameters. A plain struct the pipeline reads, output/ records (report,
// .scad) and edit/ reads back from an edited .scad; it depends on nothing but core/.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"

namespace cs {

// A user's edits to the supports: a generated .scad's [Manual edits] section, or --block and
// --support-point on the command line. Coordinates are the placed model's (as in <name>.model.stl).
struct ManualEdits {
    std::vector<Box3> blockers;        // no support solid inside; overhangs inside are not sampled
    std::vector<Vec3> support_points;  // extra points to support, on the model's underside
    std::vector<int> omit_struts;      // struts of the grown tree left out, with what hangs from them
    int highlight_strut = -1;          // shown in colour in the .scad; no effect on the supports

    bool empty() const { return blockers.empty() && support_points.empty() && omit_struts.empty(); }
};

struct Job {
    std::string input;           // mesh file, or an OpenSCAD part (.scad) rendered first
    std::string input_name;      // how the report and the .scad name the input (default: input)
    std::vector<std::string> defines;  // name=value for a .scad input (OpenSCAD -D)
    ManualEdits edits;
    double scale = 1;            // applied first
    std::optional<double> fit;   // then scale so the largest side is this (mm)
    std::string orient = "auto"; // auto | keep | RX,RY,RZ
    bool self_intersection_check = true;
    bool timings = true;          // stage times in the report (the only part that differs run to run)
    Params params;

    const std::string& shown_input() const { return input_name.empty() ? input : input_name; }
};

// Is `path` an OpenSCAD part (rendered to a mesh first) rather than a mesh file?
bool is_scad_input(const std::string& path);

}  // namespace cs

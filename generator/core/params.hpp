// Printer and algorithm parameters: one struct, one preset per printer.
// Units: millimetres and degrees. See README "Parameters" for the meaning of each, and
// core/param_table.hpp for how each is named and checked outside.
#pragma once

#include <string>
#include <vector>

#include "core/geometry.hpp"
#include "core/modes.hpp"

namespace cs {

struct Params {
    std::string preset = "generic-0.4";

    // Printer.
    double critical_angle = 50;   // steepest printable angle, from vertical
    double layer_height = 0.2;
    double line_width = 0.4;      // nozzle extrusion width (informative; walls use wall_thickness)
    double wall_thickness = 0.5;  // wall of the N-profile: slicers drop 0.4 mm walls (CuraEngine kept 9-16 % of
                                  // such struts, all of them at 0.5 mm; measured with bench/slicers/)
    double filament_density = 1.24;  // g/cm^3 of the preset's material (PLA 1.24, PETG 1.27): the summary's grams

    // Sampling and contacts.
    double sampling_distance = 2.5;  // overhang sample spacing on the global XY lattice (chosen by bench)
    double tip_length = 1.0;         // tapered tip at every model contact
    double tip_diameter = 0.8;       // tip end width at the model
    double gap = 0.2;                // z air gap between a tip and the model (one layer)

    // Strut sizing (Eqn 1: d = k * l * alpha, clamped; never narrowing downward).
    double k = 0.0015;
    double d_min = 1.0;
    double d_max = 4.0;
    // Strength rule: a strut (or unbranched run) of width d and angle a is safe up to
    // safe_length = strength_length * (d / 1 mm)^2 * angle_factor(a). See README "Strength".
    double strength_length = 30.0;

    // Feet on the bed.
    bool feet = true;
    double foot_height = 1.0;
    double foot_extra = 1.5;  // a foot is the strut width plus this on each side

    // Tree growth.
    bool supports_on_model = true;       // false = --buildplate-only
    Strategy strategy = Strategy::tree;
    double model_clearance = 0.3;        // extra air kept between a strut and the model
    // Walls under ceilings that fall freely to the bed (ceilings/ceilings.hpp): rows at most this
    // far apart, joined into a meander; 0: trees everywhere. At most 1.4 x sampling_distance, so
    // every point between two rows is within check's lattice reach of one. Every preset turns
    // them off (params.cpp): on the validation set they cost Cura minutes (README).
    double ceiling_span = 3.4;
    // The hybrid (ceilings/hybrid.hpp): where the walls are not chosen, short walls this tall (mm)
    // hang under the ceiling in the walls' rows (ceiling_span apart), their feet carried by the
    // tree; 0: off. Chosen on the tuning set (u_overhang: 1 mm fastest of 1-6), confirmed on the
    // validation set (README). Off wherever ceiling_span is 0 (every preset but generic-0.4).
    double hybrid_height = 1;
    // The hybrid's rows stand on feet (tips of the tree) that their bottom bridges between: the
    // longest such bridge from one foot's tip to the next, mm. A row's end pieces still overhang
    // their foot by less than check's long top, as every piece did before (0 here: every piece under
    // twice the long top, about 7.5 mm at the default sampling). 10: Bambu Studio's default maximum
    // bridge length; measured against 0 on the validation set and the examples (README).
    double hybrid_bridge = 10;
    // Holes and slots the print bridges (every point of their overhang within reach of an inside
    // corner, a wall going down from it) get no support unless this is true (overhang.hpp).
    bool support_bridges = false;
    // A user's edits to one job (support blockers, support points, omitted struts) are no
    // parameters: they travel in the Job (job/job.hpp).
    // Flags, config keys, valid ranges, report keys and .scad names of these: core/param_table.hpp.
};

struct Preset {
    std::string name;
    std::string description;
    Params params;
    std::string sources;  // where the values come from
};

// All built-in presets; the first is the default.
const std::vector<Preset>& presets();
// Throws ParameterError naming the known presets when `name` is unknown.
Params preset_params(const std::string& name);

}  // namespace cs

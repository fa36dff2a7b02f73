#include "core/param_table.hpp"

#include <cmath>

#include <algorithm>
#include <fmt/format.h>

#include "core/errors.hpp"

namespace cs {

const std::vector<ParamRow>& param_table() {
    using P = ScadPlace;
    static const std::vector<ParamRow> rows = {
        {"--critical-angle", &Params::critical_angle, "critical_angle_deg", "degrees", {.min = 5, .max = 80},
         "Steepest printable overhang, degrees from vertical",
         {"critical_angle", P::regrow, "Steepest overhang printed without support (degrees from vertical)", "[5:1:80]"}},
        {"--layer-height", &Params::layer_height, "layer_height_mm", "mm", {.min = 0.01, .max = 2, .min_open = true},
         "Layer height, mm", {"cs_layer_height", P::hidden}},
        // Informative only (walls use --wall); the range just keeps nonsense out of the report.
        {"--line-width", &Params::line_width, "line_width_mm", "mm", {.min = 0, .max = 5, .min_open = true},
         "Extrusion width, mm", {"cs_line_width", P::hidden}},
        {"--filament-density", &Params::filament_density, "filament_density_g_cm3", "g/cm^3",
         {.min = 0.5, .max = 3}, "Filament density, g/cm^3: the summary's support grams (PLA 1.24)",
         {"cs_filament_density", P::hidden}},
        {"--wall", &Params::wall_thickness, "wall_thickness_mm", "mm", {.min = 0.05, .max = 5, .min_open = true},
         "N-profile wall thickness, mm",
         {"wall", P::walls_and_tips, "Wall thickness of the N-profile (mm); slicers drop walls of one line width (0.4)",
          "[0.3:0.05:2]"}},
        {"--sampling", &Params::sampling_distance, "sampling_distance_mm", "mm", {.min = 0.05, .max = 50},
         "Overhang sample spacing, mm",
         {"sampling", P::regrow, "Spacing of the supported points under overhangs (mm)", "[0.25:0.25:10]"}},
        {"--tip-length", &Params::tip_length, "tip_length_mm", "mm", {.min = 0, .max = 20}, "Tapered tip length, mm",
         {"tip_length", P::regrow, "Length of the tapered tips (mm): the tree places its nodes by it", "[0.2:0.1:5]"}},
        {"--tip-diameter", &Params::tip_diameter, "tip_diameter_mm", "mm", {.min = 0, .max = 10, .min_open = true},
         "Tip width at the model, mm",
         {"tip_diameter", P::walls_and_tips, "Width of a tip where it meets the model (mm)", "[0.2:0.05:3]"}},
        {"--gap", &Params::gap, "gap_mm", "mm", {.min = 0, .max = 5}, "Z gap between tips and the model, mm",
         {"gap", P::regrow, "Air between a tip and the model (mm)", "[0:0.05:1]"}},
        {"--k", &Params::k, "k", "mm per (mm*degree)", {.min = 0, .max = 1},
         "Eqn (1) coefficient: d = k * length[mm] * angle[deg]",
         {"k", P::strut_sizing,
          "Eqn (1) coefficient k in d = k * length * angle (mm per mm-degree): larger makes slanted struts thicker",
          "[0:0.0005:0.02]"}},
        {"--d-min", &Params::d_min, "d_min_mm", "mm", {.min = 0, .max = 50, .min_open = true}, "Thinnest strut, mm",
         {"d_min", P::strut_sizing, "Thinnest strut (mm)", "[0.3:0.1:5]"}},
        {"--d-max", &Params::d_max, "d_max_mm", "mm", {.max = 100, .at_least = &Params::d_min}, "Thickest strut, mm",
         {"d_max", P::strut_sizing, "Thickest strut (mm)", "[1:0.1:10]"}},
        {"--strength-length", &Params::strength_length, "strength_length_mm", "mm", {.min = 0, .min_open = true},
         "Safe length of a 1 mm strut at <= 30 deg, mm",
         {"strength_length", P::strut_sizing,
          "Strength rule: a 1 mm strut stays safe this long (mm) at <= 30 deg; safe length grows with width^2",
          "[5:1:120]"}},
        {"--feet", &Params::feet, "feet", "", {}, "Feet on the bed (true/false)",
         {"feet", P::feet, "Widen every strut where it stands on the bed"}},
        {"--foot-height", &Params::foot_height, "foot_height_mm", "mm", {.min = 0, .max = 20}, "Foot height, mm",
         {"foot_height", P::feet, "Height of a foot (mm)", "[0:0.1:5]"}},
        {"--foot-extra", &Params::foot_extra, "foot_extra_mm", "mm", {.min = 0, .max = 20},
         "Foot overhang beyond the strut on each side, mm",
         {"foot_extra", P::feet, "How much wider than its strut a foot is on each side (mm)", "[0:0.1:5]"}},
        {"--clearance", &Params::model_clearance, "model_clearance_mm", "mm", {.min = 0, .max = 10},
         "Air kept between struts and the model, mm",
         {"clearance", P::regrow, "Air kept between struts and the model (mm)", "[0:0.05:2]"}},
        {"--support-bridges", &Params::support_bridges, "support_bridges", "", {},
         "Support holes and slots the print bridges too (true/false; default false)",
         {"support_bridges", P::regrow, "Support holes and slots the print bridges too (the printer bridges them)"}},
        {"--ceiling-span", &Params::ceiling_span, "ceiling_span_mm", "mm", {.min = 0, .max = 50},
         "Rows of walls under ceilings low over the bed at most this far apart, mm (0: trees only)",
         {"ceiling_span", P::regrow, "Walls under low ceilings: rows at most this far apart (mm); 0: trees only",
          "[0:0.1:5]"}},
        {"--hybrid-height", &Params::hybrid_height, "hybrid_height_mm", "mm", {.min = 0, .max = 20},
         "Short walls this tall under ceilings high over the model, their feet on the tree, mm (0: off)",
         {"hybrid_height", P::regrow, "Hybrid under high ceilings: walls this tall on the tree (mm); 0: off",
          "[0:0.5:10]"}},
        {"--hybrid-bridge", &Params::hybrid_bridge, "hybrid_bridge_mm", "mm", {.min = 0, .max = 30},
         "Longest bridge of a hybrid row from one foot to the next, mm (0: pieces under twice check's long top)",
         {"hybrid_bridge", P::regrow, "Hybrid: longest bridge of a row from one foot to the next (mm); 0: short pieces",
          "[0:0.5:20]"}},
        {"--buildplate-only", Negated{&Params::supports_on_model}, "buildplate_only", "", {},
         "Supports stand on the bed only, routed around the model",
         {"buildplate_only", P::regrow, "Supports stand on the bed only, routed around the model"}},
        {"--strategy", &Params::strategy, "strategy", "", {}, "tree (default) or columns (the vertical-columns baseline)",
         {"cs_strategy", P::hidden}},
    };
    return rows;
}

std::string_view config_key(const ParamRow& row) { return std::string_view(row.flag).substr(2); }

const ParamRow* find_param(std::string_view flag_or_key) {
    for (const auto& row : param_table())
        if (flag_or_key == row.flag || flag_or_key == config_key(row)) return &row;
    return nullptr;
}

namespace {

// std::visit over a row's member, with the overloads spelled out once.
template <class... F>
struct Overload : F... {
    using F::operator()...;
};
// Spelled out for clang 14 (the fuzz build), which does not deduce an aggregate's arguments.
template <class... F>
Overload(F...) -> Overload<F...>;

}  // namespace

ParamValue get_param(const ParamRow& row, const Params& p) {
    return std::visit(Overload{[&](double Params::*m) -> ParamValue { return p.*m; },
                               [&](bool Params::*m) -> ParamValue { return p.*m; },
                               [&](Negated n) -> ParamValue { return !(p.*n.member); },
                               [&](Strategy Params::*m) -> ParamValue { return std::string(to_string(p.*m)); }},
                      row.member);
}

void set_param(const ParamRow& row, const ParamValue& value, Params& p) {
    std::visit(Overload{[&](double Params::*m) { p.*m = std::get<double>(value); },
                        [&](bool Params::*m) { p.*m = std::get<bool>(value); },
                        [&](Negated n) { p.*n.member = !std::get<bool>(value); },
                        [&](Strategy Params::*m) { p.*m = parse_strategy(std::get<std::string>(value)); }},
               row.member);
}

ParamValue param_value_from_json(const ParamRow& row, const nlohmann::json& value, const std::string& where) {
    const std::string what = where + ": \"" + std::string(config_key(row)) + "\"";
    return std::visit(Overload{[&](double Params::*) -> ParamValue {
                                   if (!value.is_number() || !std::isfinite(value.get<double>()))
                                       throw ParameterError(what + " must be a number");
                                   return value.get<double>();
                               },
                               [&](auto yes_no) -> ParamValue {  // bool Params::* or Negated
                                   if (!value.is_boolean()) throw ParameterError(what + " must be true or false");
                                   return value.get<bool>();
                               },
                               [&](Strategy Params::*) -> ParamValue {
                                   if (!value.is_string()) throw ParameterError(what + " must be \"tree\" or \"columns\"");
                                   return value.get<std::string>();
                               }},
                      row.member);
}

nlohmann::ordered_json param_value_json(const ParamRow& row, const Params& p) {
    return std::visit([](const auto& v) { return nlohmann::ordered_json(v); }, get_param(row, p));
}

void apply_config(const nlohmann::json& config, Params& p, const std::string& where) {
    for (const auto& [key, value] : config.items()) {
        if (key == "preset" || key == "description" || key == "support-blocker" || key == "block" ||
            key == "support-point")
            continue;  // the user's edits (cli/param_flags.cpp edits_from); "block" is their old name
        const ParamRow* row = find_param(key);
        if (!row || key.rfind("--", 0) == 0)
            throw ParameterError(where + ": \"" + key + "\" is not a parameter (use the flag names, e.g. \"critical-angle\")");
        set_param(*row, param_value_from_json(*row, value, where), p);
    }
}

namespace {

const char* name_of(const ParamRow& row, ParamNaming naming) { return naming == ParamNaming::flag ? row.flag : row.scad.name; }

const ParamRow& row_of(double Params::*member) {
    for (const auto& row : param_table())
        if (auto m = std::get_if<double Params::*>(&row.member); m && *m == member) return row;
    throw std::logic_error("param_table: a range refers to a member without a row");
}

// "5..80 degrees", "> 0 mm", "--d-min..100 mm".
std::string range_text(const ParamRow& row, ParamNaming naming) {
    const ParamRange& r = row.range;
    std::string low = r.at_least ? name_of(row_of(r.at_least), naming) : fmt::format("{}", r.min);
    if (r.max == std::numeric_limits<double>::infinity())
        return fmt::format("{} {} {}", r.min_open ? ">" : ">=", low, row.unit);
    return fmt::format("{}..{} {}", low, r.max, row.unit);
}

bool in_range(const ParamRange& r, double v, const Params& p) {
    bool above_min = r.min_open ? v > r.min : v >= r.min;
    return above_min && v <= r.max && (!r.at_least || v >= p.*r.at_least);
}

}  // namespace

void validate_params(const Params& p, ParamNaming naming) {
    for (const auto& row : param_table()) {
        auto member = std::get_if<double Params::*>(&row.member);
        if (!member || in_range(row.range, p.**member, p)) continue;
        throw ParameterError(fmt::format("{} = {} is out of range ({})", name_of(row, naming), p.**member,
                                         range_text(row, naming)));
    }
}

}  // namespace cs

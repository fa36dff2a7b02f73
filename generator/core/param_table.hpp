// One home for every parameter: the table below has one row per parameter of `Params`, and every
// layer that names parameters is generated from it:
//   cli/param_flags     the command-line flags (`--critical-angle 55`) and the --config file keys
//                       (the flag without its dashes: {"critical-angle": 55}), via set_param
//   validate_params     the valid ranges, with messages naming the flag (or the .scad variable)
//   output/outputs.cpp  the report's "parameters" object (report_key)
//   output/scad.cpp     the Customizer and [Regrow] sections of the generated .scad (scad)
//   edit/edited_scad    reading those values back for `clever-support regrow`
//
// Adding a parameter: add the member to Params (core/params.hpp) with its default, add one row
// to param_table() in param_table.cpp, and use it in the rule it is for. Flags, config key,
// range check, report and .scad follow; tests/unit/test_param_table.cpp checks every row in each
// of them.
#pragma once

#include <limits>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/params.hpp"

namespace cs {

// A yes/no parameter spelled outside as the opposite of its member, and given on the command line
// as a bare flag: `--buildplate-only` (true when present) sets supports_on_model = false.
struct Negated {
    bool Params::*member;
};

// The Params member a row reads and writes: a number, a yes/no (`--feet true|false`), a negated
// yes/no (a bare flag), or the strategy (by its name, core/modes.hpp).
using ParamMember = std::variant<double Params::*, bool Params::*, Negated, Strategy Params::*>;

// A parameter's value as spelled outside (flags, config, report, .scad): negated rows already
// negated, the strategy by its name.
using ParamValue = std::variant<double, bool, std::string>;

// Valid values of a number: min..max, min itself excluded when `min_open`. `at_least` names
// another parameter the value may not fall below (d_max >= d_min).
struct ParamRange {
    double min = -std::numeric_limits<double>::infinity();
    double max = std::numeric_limits<double>::infinity();
    bool min_open = false;
    double Params::*at_least = nullptr;
};

// Where a parameter is in the generated .scad: a Customizer section (takes effect when the .scad
// is rendered), [Regrow] (takes effect with `clever-support regrow`), or [Hidden] (recorded for
// regrow only; output/scad.cpp writes those in its provenance block).
enum class ScadPlace { strut_sizing, walls_and_tips, feet, regrow, hidden };

struct ScadVariable {
    const char* name;         // the OpenSCAD variable, e.g. "critical_angle"
    ScadPlace place;
    const char* why = "";     // the comment line above it in the Customizer
    const char* slider = "";  // the Customizer's range, e.g. "[5:1:80]"; "" for none
};

struct ParamRow {
    const char* flag;        // "--critical-angle"; the --config key is the same without "--"
    ParamMember member;
    const char* report_key;  // in the report's "parameters", e.g. "critical_angle_deg"
    const char* unit;        // as range messages show it: "degrees", "mm", ...; "" for yes/no
    ParamRange range;        // numbers only
    const char* help;        // the flag's --help text
    ScadVariable scad;
};

// Every parameter, in the order of --help and of the .scad sections.
const std::vector<ParamRow>& param_table();

// "critical-angle" for "--critical-angle".
std::string_view config_key(const ParamRow& row);
// The row with that flag or config key, or nullptr.
const ParamRow* find_param(std::string_view flag_or_key);

ParamValue get_param(const ParamRow& row, const Params& p);
// Throws ParameterError for a strategy name that is not one.
void set_param(const ParamRow& row, const ParamValue& value, Params& p);

// A JSON value (a --config file's) as the row's value; throws ParameterError
// "<where>: "<key>" must be ..." when it has the wrong type.
ParamValue param_value_from_json(const ParamRow& row, const nlohmann::json& value, const std::string& where);
// The value for a JSON document (the report).
nlohmann::ordered_json param_value_json(const ParamRow& row, const Params& p);

// Sets every parameter a --config file's object names (keys "preset", "description", "block" and
// "support-point" are not parameters and are left to the caller). Throws ParameterError naming
// `where` and the key for an unknown key or a value of the wrong type.
void apply_config(const nlohmann::json& config, Params& p, const std::string& where);

// How messages name a parameter: by its flag (values from the command line or a config file) or
// by its .scad variable (values from an edited .scad).
enum class ParamNaming { flag, scad };

// Throws ParameterError for the first value out of its range, e.g.
// "--critical-angle = 95 is out of range (5..80 degrees)".
void validate_params(const Params& p, ParamNaming naming = ParamNaming::flag);

}  // namespace cs

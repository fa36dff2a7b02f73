// OpenSCAD's -D name=value as the command line takes them: checked before OpenSCAD sees them, so
// a mistake is named by the define the user typed, not by a line of a file OpenSCAD made up.
//
// Example:
//   check_define("hole_d=");                    // throws ParameterError "-D hole_d=: no value after '='..."
//   unknown_define_warnings({"hole_dd=14"}, "part.scad")
//       -> {"-D hole_dd=14: part.scad has no variable `hole_dd` (did you mean `hole_d`?); ..."}
#pragma once

#include <string>
#include <vector>

namespace cs {

// Throws ParameterError naming the define when it is not `name=value` with an OpenSCAD name and a
// value whose brackets and quotes close.
void check_define(const std::string& define);

// The names a .scad file assigns at its top level (outside modules and functions), in file order.
std::vector<std::string> scad_variable_names(const std::string& text);

// One warning per define whose name the file at `scad` does not assign (OpenSCAD would add it
// and nothing would read it), with the nearest name it does assign. Empty when the file cannot
// be read (the render reports that).
std::vector<std::string> unknown_define_warnings(const std::vector<std::string>& defines, const std::string& scad);

// -D defines for a .scad: each checked (check_define), then a warning on stderr for each name the
// file does not assign (unknown_define_warnings), unless `quiet`.
void check_defines(const std::vector<std::string>& defines, const std::string& scad, bool quiet = false);

struct Params;

// Sets each parameter a define names by its .scad variable (`-D sampling=2`, `-D buildplate_only=true`),
// validated as in an edited .scad. A name that is no parameter: ParameterError with the nearest
// parameter name, unless `others_allowed` (then it is left to OpenSCAD).
void set_scad_params(const std::vector<std::string>& defines, Params& p, bool others_allowed);

// The text of a generated .scad as OpenSCAD reads it with these (checked) defines: each one that
// gives a plain value (a number, true/false, a string, a list) to a name the file assigns one
// (edit/scad_values.hpp) replaces that value; the others are OpenSCAD's alone. `file` names the
// file in errors (InputError when it does not parse).
// Example: with_scad_defines("omit_struts = [];\n", {"omit_struts=[3]"}, "m.scad") -> "omit_struts = [3];\n"
std::string with_scad_defines(std::string text, const std::vector<std::string>& defines, const std::string& file);

}  // namespace cs

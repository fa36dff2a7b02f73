// Reading back the plain values of an OpenSCAD file that clever-support wrote and a person may
// have edited: top-level assignments `name = value;` whose value is a literal (number, true/false,
// string, undef, or a list of those, nested). Comments are skipped; so are assignments whose value
// refers to other names (e.g. `cs_tree_record = [cs_nodes, ...]`). Reading stops at the first
// statement that is not an assignment (`include <...>`, a module call): the data comes before it.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace cs {

struct ScadValue {
    nlohmann::json value;         // numbers, booleans, strings, null (undef), arrays
    int line = 0;                 // where the assignment starts
    std::vector<int> item_lines;  // for a list: the line of each element
    std::size_t begin = 0, end = 0;  // where the value's characters are in the text (end: at the ';')
};

using ScadValues = std::map<std::string, ScadValue>;

// Throws InputError "FILE:LINE: what is wrong" for a malformed value (an unclosed list, a missing
// comma, an expression where a plain value belongs, a name assigned twice).
ScadValues parse_scad_values(const std::string& text, const std::string& file);

// A plain value as OpenSCAD source, the inverse of the parse: numbers shortest (%.10g), strings in
// double quotes, null as undef, lists in brackets. Example: [[1, 2.5, 3]] -> "[[1, 2.5, 3]]".
std::string scad_literal(const nlohmann::json& value);

// `text` with the value of the assignment `name` replaced by `value` (as scad_literal writes it);
// the rest of the file, comments included, stays as it was. Throws InputError "FILE:LINE: ..." when
// the file does not parse, and when it assigns no plain value to `name`.
// Example: with_scad_value("omit_struts = [];\n", "omit_struts", {3, 5}, "m.scad") ->
//          "omit_struts = [3, 5];\n"
std::string with_scad_value(const std::string& text, const std::string& name, const nlohmann::json& value,
                            const std::string& file);

}  // namespace cs

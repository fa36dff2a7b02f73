#include "cli/defines.hpp"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <iterator>
#include <utility>

#include "cli/progress.hpp"
#include "cli/suggest.hpp"
#include "core/errors.hpp"
#include "core/param_table.hpp"
#include "edit/scad_values.hpp"

namespace cs {
namespace {

bool is_name(const std::string& s) {
    if (s.empty() || !(std::isalpha((unsigned char)s[0]) || s[0] == '_' || s[0] == '$')) return false;
    return std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isalnum(c) || c == '_' || c == '$'; });
}

std::string trimmed(const std::string& s) {
    const auto a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
    return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

// A checked define's name and value (check_define), each without the spaces around it.
std::pair<std::string, std::string> name_and_value(const std::string& d) {
    const auto eq = d.find('=');
    return {trimmed(d.substr(0, eq)), trimmed(d.substr(eq + 1))};
}

// "" when every bracket and quote of an OpenSCAD value closes, else what is wrong.
std::string unbalanced(const std::string& value) {
    std::string open;
    for (size_t i = 0; i < value.size(); ++i) {
        const char c = value[i];
        if (c == '"') {
            size_t j = i + 1;
            while (j < value.size() && value[j] != '"') j += value[j] == '\\' ? 2 : 1;
            if (j >= value.size()) return "its string is not closed with \"";
            i = j;
        } else if (c == '[' || c == '(' || c == '{') {
            open.push_back(c);
        } else if (c == ']' || c == ')' || c == '}') {
            const char want = c == ']' ? '[' : c == ')' ? '(' : '{';
            if (open.empty() || open.back() != want) return std::string("its ") + c + " closes nothing";
            open.pop_back();
        }
    }
    return open.empty() ? "" : std::string("its ") + open.back() + " is not closed";
}

}  // namespace

void check_define(const std::string& d) {
    const auto eq = d.find('=');
    const std::string shown = "-D " + d;
    if (eq == std::string::npos) throw ParameterError(shown + ": expected name=value, e.g. -D width=30");
    const std::string name = trimmed(d.substr(0, eq)), value = trimmed(d.substr(eq + 1));
    if (!is_name(name))
        throw ParameterError(shown + ": '" + name + "' is not an OpenSCAD variable name (letters, digits and _, not "
                                                   "starting with a digit)");
    if (value.empty()) throw ParameterError(shown + ": no value after '='; give one, e.g. -D " + name + "=14");
    if (const std::string why = unbalanced(value); !why.empty()) throw ParameterError(shown + ": " + why);
}

std::vector<std::string> scad_variable_names(const std::string& text) {
    std::vector<std::string> names;
    int depth = 0;
    bool line_start = true;
    for (size_t i = 0; i < text.size(); ++i) {
        const char c = text[i];
        if (c == '/' && i + 1 < text.size() && text[i + 1] == '/') {  // line comment
            while (i < text.size() && text[i] != '\n') ++i;
            line_start = true;
            continue;
        }
        if (c == '/' && i + 1 < text.size() && text[i + 1] == '*') {  // block comment
            const auto end = text.find("*/", i + 2);
            i = end == std::string::npos ? text.size() : end + 1;
            continue;
        }
        if (c == '"') {
            while (++i < text.size() && text[i] != '"') i += text[i] == '\\';
            continue;
        }
        if (c == '{') ++depth;
        if (c == '}') depth = std::max(0, depth - 1);
        if (c == '\n' || c == ';') line_start = true;
        if (std::isspace((unsigned char)c) || c == ';') continue;
        if (line_start && depth == 0 && (std::isalpha((unsigned char)c) || c == '_' || c == '$')) {
            size_t j = i;
            while (j < text.size() && (std::isalnum((unsigned char)text[j]) || text[j] == '_' || text[j] == '$')) ++j;
            size_t k = j;
            while (k < text.size() && (text[k] == ' ' || text[k] == '\t')) ++k;
            if (k < text.size() && text[k] == '=' && (k + 1 >= text.size() || text[k + 1] != '=')) {
                const std::string name = text.substr(i, j - i);
                if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
            }
            i = j - 1;
        }
        line_start = false;
    }
    return names;
}

std::vector<std::string> unknown_define_warnings(const std::vector<std::string>& defines, const std::string& scad) {
    std::ifstream in(scad, std::ios::binary);
    if (!in) return {};
    const std::vector<std::string> names =
        scad_variable_names({std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()});
    std::vector<std::string> out;
    for (const auto& d : defines) {
        const std::string name = trimmed(d.substr(0, d.find('=')));
        if (std::find(names.begin(), names.end(), name) != names.end()) continue;
        out.push_back("-D " + d + ": " + scad + " has no variable `" + name + "`" + did_you_mean(name, names) +
                      "; OpenSCAD adds it and nothing reads it");
    }
    return out;
}

void check_defines(const std::vector<std::string>& defines, const std::string& scad, bool quiet) {
    for (const auto& d : defines) check_define(d);
    if (!quiet)
        for (const auto& w : unknown_define_warnings(defines, scad)) warn(w);
}

void set_scad_params(const std::vector<std::string>& defines, Params& p, bool others_allowed) {
    std::vector<std::string> names;
    for (const auto& row : param_table()) names.push_back(row.scad.name);
    for (const auto& d : defines) {
        check_define(d);
        const auto [name, value] = name_and_value(d);
        const ParamRow* row = nullptr;
        for (const auto& r : param_table())
            if (name == r.scad.name) row = &r;
        if (!row) {
            if (others_allowed) continue;
            throw ParameterError("-D " + d + ": `" + name + "` is not a parameter of the .scad" + did_you_mean(name, names) +
                                 "; edit the [Manual edits] section in the file itself");
        }
        nlohmann::json v;
        try {
            v = nlohmann::json::parse(value);
        } catch (const std::exception&) {
            v = value;  // a bare word: the strategy's name
        }
        set_param(*row, param_value_from_json(*row, v, "-D " + d), p);
    }
    validate_params(p, ParamNaming::scad);
}

std::string with_scad_defines(std::string text, const std::vector<std::string>& defines, const std::string& file) {
    const ScadValues values = parse_scad_values(text, file);
    for (const auto& d : defines) {
        const auto [name, value] = name_and_value(d);
        if (!values.count(name)) continue;
        nlohmann::json v;
        try {
            v = nlohmann::json::parse(value);
        } catch (const std::exception&) {
            continue;  // an expression: OpenSCAD's alone
        }
        text = with_scad_value(text, name, v, file);
    }
    return text;
}

}  // namespace cs

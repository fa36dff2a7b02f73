#include "core/config.hpp"

#include <cmath>

#include "core/errors.hpp"
#include "core/param_table.hpp"

namespace cs {
namespace {

// `item` as exactly `count` finite numbers, else a ParameterError naming the key and the form.
std::vector<double> numbers(const nlohmann::json& item, size_t count, const std::string& what, const std::string& form) {
    std::vector<double> v;
    if (item.is_array() && item.size() == count)
        for (const auto& x : item)
            if (x.is_number() && std::isfinite(x.get<double>())) v.push_back(x.get<double>());
    if (v.size() != count) throw ParameterError(what + " must be a list of " + form);
    return v;
}

// A list of number lists: "support-blocker" ("block") and "support-point".
std::vector<std::vector<double>> number_lists(const nlohmann::json& list, size_t count, const std::string& what,
                                              const std::string& form) {
    if (!list.is_array()) throw ParameterError(what + " must be a list of " + form);
    std::vector<std::vector<double>> out;
    for (const auto& item : list) out.push_back(numbers(item, count, what, form));
    return out;
}

std::string text(const nlohmann::json& value, const std::string& what) {
    if (!value.is_string()) throw ParameterError(what + " must be a string");
    return value.get<std::string>();
}

}  // namespace

ConfigFile parse_config(std::string_view text_in, const std::string& where) {
    ConfigFile c;
    try {
        c.values = nlohmann::json::parse(text_in);
    } catch (const nlohmann::json::exception& e) {
        throw ParameterError(where + ": not valid JSON (" + std::string(e.what()) + ")");
    }
    if (!c.values.is_object()) throw ParameterError(where + ": expected a JSON object of parameters");
    auto key = [&](const char* k) { return where + ": \"" + k + "\""; };
    if (c.values.contains("preset")) c.preset = text(c.values["preset"], key("preset"));
    if (c.values.contains("description")) text(c.values["description"], key("description"));
    for (const char* name : {"support-blocker", "block"})  // "block" is the old name
        if (c.values.contains(name))
            for (const auto& v : number_lists(c.values[name], 6, key(name), "[x0, y0, z0, x1, y1, z1]")) {
                Box3 b;
                b.add({v[0], v[1], v[2]});
                b.add({v[3], v[4], v[5]});
                c.blockers.push_back(b);
            }
    if (c.values.contains("support-point"))
        for (const auto& v : number_lists(c.values["support-point"], 3, key("support-point"), "[x, y, z]"))
            c.support_points.push_back({v[0], v[1], v[2]});
    Params scratch;  // every parameter key known and of its row's type, before anyone uses one
    apply_config(c.values, scratch, where);
    return c;
}

}  // namespace cs

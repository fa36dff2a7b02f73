#include "view/view_edit.hpp"

#include <algorithm>
#include <cmath>

#include "core/errors.hpp"
#include "edit/scad_values.hpp"
#include "view/view_state.hpp"

namespace cs {
namespace {

[[noreturn]] void bad_edit(const std::string& what) { throw UsageError("the page sent an edit that cannot be made: " + what); }

nlohmann::json rounded_point(const nlohmann::json& p) {
    if (!p.is_array() || p.size() != 3) bad_edit("a point is not [x, y, z]");
    nlohmann::json out = nlohmann::json::array();
    for (const auto& c : p) {
        if (!c.is_number() || !std::isfinite(c.get<double>())) bad_edit("a coordinate is not a number");
        out.push_back(std::round(c.get<double>() * 100) / 100);
    }
    return out;
}

int index_in(const nlohmann::json& edit, const char* key) {
    if (!edit.contains(key) || !edit[key].is_number_integer()) bad_edit(std::string(key) + " is not a whole number");
    return edit[key].get<int>();
}

nlohmann::json without(nlohmann::json list, int i, const std::string& name) {
    if (i < 0 || i >= static_cast<int>(list.size())) bad_edit(name + " has no item " + std::to_string(i));
    list.erase(list.begin() + i);
    return list;
}

}  // namespace

std::string apply_view_edit(const std::string& text, const nlohmann::json& edit, const std::string& scad_path) {
    if (!edit.is_object() || !edit.contains("op") || !edit["op"].is_string()) bad_edit("no \"op\"");
    const std::string op = edit["op"];
    ScadValues values = parse_scad_values(text, scad_path);
    auto list = [&](const std::string& name) {
        auto it = values.find(name);
        return it != values.end() && it->second.value.is_array() ? it->second.value : nlohmann::json::array();
    };
    std::string name;
    nlohmann::json value;
    if (op == "toggle_strut") {
        name = "omit_struts", value = list(name);
        int e = index_in(edit, "strut");
        auto it = std::find(value.begin(), value.end(), nlohmann::json(e));
        if (it != value.end()) value.erase(it);
        else value.push_back(e);
    } else if (op == "add_point") {
        name = "support_points", value = list(name);
        value.push_back(rounded_point(edit.value("at", nlohmann::json())));
    } else if (op == "remove_point") {
        name = "support_points", value = without(list(name), index_in(edit, "index"), name);
    } else if (op == "add_blocker") {
        const auto box = edit.value("box", nlohmann::json());
        if (!box.is_array() || box.size() != 2) bad_edit("a blocker is not [[x0, y0, z0], [x1, y1, z1]]");
        name = "support_blockers", value = list(name);
        value.push_back({rounded_point(box[0]), rounded_point(box[1])});
    } else if (op == "remove_blocker") {
        name = "support_blockers", value = without(list(name), index_in(edit, "index"), name);
    } else if (op == "set") {
        name = edit.value("name", "");
        bool slider = false;
        const auto state = view_scad_state(text, scad_path);  // kept: the loop walks into it
        for (const auto& s : state["sliders"]) slider = slider || s["name"] == name;
        if (!slider) bad_edit("\"" + name + "\" is not a Customizer value of " + scad_path);
        value = edit.value("value", nlohmann::json());
        if (!value.is_number() || !std::isfinite(value.get<double>())) bad_edit(name + " is not a number");
    } else {
        bad_edit("unknown op \"" + op + "\"");
    }
    std::string out = with_scad_value(text, name, value, scad_path);
    view_scad_state(out, scad_path);  // reads as regrow reads it, or throws its message with the line
    return out;
}

}  // namespace cs

#include "edit/edited_scad.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "core/param_table.hpp"
#include "edit/scad_values.hpp"

namespace cs {
namespace {

class Reader {
public:
    Reader(ScadValues values, std::string file) : v_(std::move(values)), file_(std::move(file)) {}

    bool has(const std::string& name) const { return v_.count(name) > 0; }

    const ScadValue& get(const std::string& name) const {
        auto it = v_.find(name);
        if (it == v_.end())
            throw InputError(file_ + ": " + name + " is missing; it is not a .scad file clever-support wrote, or the line "
                             "assigning " + name + " was removed");
        return it->second;
    }
    [[noreturn]] void fail(int line, const std::string& what) const {
        throw InputError(file_ + ":" + std::to_string(line) + ": " + what);
    }
    double number(const std::string& name) const {
        const auto& x = get(name);
        if (!x.value.is_number()) fail(x.line, name + " must be a number");
        return x.value.get<double>();
    }
    bool boolean(const std::string& name) const {
        const auto& x = get(name);
        if (!x.value.is_boolean()) fail(x.line, name + " must be true or false");
        return x.value.get<bool>();
    }
    std::string text(const std::string& name) const {
        const auto& x = get(name);
        if (!x.value.is_string()) fail(x.line, name + " must be a string in double quotes");
        return x.value.get<std::string>();
    }
    const ScadValue& list(const std::string& name) const {
        const auto& x = get(name);
        if (!x.value.is_array()) fail(x.line, name + " must be a list [ ... ]");
        return x;
    }
    int line_of(const ScadValue& x, size_t i) const { return i < x.item_lines.size() ? x.item_lines[i] : x.line; }

    // Element i of list `x` as an [x, y, z] point.
    Vec3 point(const nlohmann::json& p, int line, const std::string& what) const {
        if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() || !p[2].is_number())
            fail(line, what + " must be a point [x, y, z]");
        return {p[0].get<double>(), p[1].get<double>(), p[2].get<double>()};
    }
    // The range is checked on the number as written: converting first is undefined for a number
    // no int holds (1e300).
    int index(const nlohmann::json& x, int line, const std::string& what, int count) const {
        if (!x.is_number() || !std::isfinite(x.get<double>()) || std::floor(x.get<double>()) != x.get<double>())
            fail(line, what + " must be a whole number");
        const double i = x.get<double>();
        if (i < 0 || i >= count)
            fail(line, fmt::format("{} {} is out of range (0 to {})", what, i, count - 1));
        return static_cast<int>(i);
    }

private:
    ScadValues v_;
    std::string file_;
};

// Parameters added after files were written (2026-11, issue 31): a file without them keeps its
// preset's value, as it was made with.
bool added_later(const std::string& name) {
    return name == "cs_filament_density" || name == "support_bridges" || name == "ceiling_span" ||
           name == "hybrid_height" || name == "hybrid_bridge";
}

// Every parameter under its .scad name (core/param_table.hpp), each read as its row's kind.
Params read_params(const Reader& r) {
    Params p;
    p.preset = r.text("cs_preset");
    for (const auto& pr : presets())
        if (pr.name == p.preset) p = pr.params;
    for (const auto& row : param_table()) {
        const std::string name = row.scad.name;
        if (added_later(name) && !r.has(name)) {
            if (name == "support_bridges") set_param(row, true, p);  // such a file supported bridged holes
            if (name == "ceiling_span") set_param(row, 0.0, p);      // such a file had no walls
            if (name == "hybrid_height") set_param(row, 0.0, p);     // nor a hybrid
            if (name == "hybrid_bridge") set_param(row, 0.0, p);     // its pieces all short (2026-12-07)
            continue;
        }
        ParamValue value;
        if (std::holds_alternative<double Params::*>(row.member)) value = r.number(name);
        else if (std::holds_alternative<Strategy Params::*>(row.member)) value = r.text(name);
        else value = r.boolean(name);
        set_param(row, value, p);
    }
    return p;
}

// The tree lists: every node index in a strut or a leaf in range, every point a point (the
// struts' and pillars' count bounds the edits).
RecordedTree read_tree(const Reader& r) {
    const auto& nodes = r.list("cs_nodes");
    for (size_t i = 0; i < nodes.value.size(); ++i) r.point(nodes.value[i], r.line_of(nodes, i), "node " + std::to_string(i));
    const int n = static_cast<int>(nodes.value.size());
    RecordedTree t;
    const auto& struts = r.list("cs_struts");
    for (size_t e = 0; e < struts.value.size(); ++e) {
        const auto& s = struts.value[e];
        int line = r.line_of(struts, e);
        std::string what = "strut " + std::to_string(e);
        if (!s.is_array() || s.size() != 2) r.fail(line, what + " must be [top node, bottom node]");
        t.struts.push_back({r.index(s[0], line, what + ": top node", n), r.index(s[1], line, what + ": bottom node", n)});
    }
    const auto& leaves = r.list("cs_leaves");
    for (size_t i = 0; i < leaves.value.size(); ++i) {
        const auto& l = leaves.value[i];
        int line = r.line_of(leaves, i);
        if (!l.is_array() || l.size() != 3) r.fail(line, "cs_leaves: each must be [leaf node, [x, y, z] sample, [x, y, z] tip top]");
        t.tips.push_back({r.index(l[0], line, "cs_leaves: leaf node", n), r.point(l[2], line, "cs_leaves: tip top")});
    }
    const auto& pillars = r.list("cs_pillars");
    for (size_t i = 0; i < pillars.value.size(); ++i) {
        const auto& pl = pillars.value[i];
        int line = r.line_of(pillars, i);
        if (!pl.is_array() || pl.size() != 2) r.fail(line, "cs_pillars: each must be [[x, y, z] top, [x, y, z] bottom]");
        t.pillar_tops.push_back(r.point(pl[0], line, "cs_pillars: top"));
        r.point(pl[1], line, "cs_pillars: bottom");
    }
    if (!r.has("cs_walls")) return t;  // a run without walls writes none
    const auto& walls = r.list("cs_walls");
    for (size_t i = 0; i < walls.value.size(); ++i) {
        const auto& w = walls.value[i];
        const int line = r.line_of(walls, i);
        const std::string what = "cs_walls: each must be [[x, y] from, [x, y] to, z of the foot, z of the top, thickness]";
        auto xy = [&](const nlohmann::json& p) {
            if (!p.is_array() || p.size() != 2 || !p[0].is_number() || !p[1].is_number()) r.fail(line, what);
            return Vec3{p[0].get<double>(), p[1].get<double>(), 0};
        };
        if (!w.is_array() || w.size() < 5 || !w[2].is_number() || !w[3].is_number() || !w[4].is_number()) r.fail(line, what);
        const Vec3 from = xy(w[0]), to = xy(w[1]);
        const double foot = w[2].get<double>(), top = w[3].get<double>();
        if (foot > 0)
            t.walls_off_bed.push_back({{0.5 * (from.x + to.x), 0.5 * (from.y + to.y), foot}, {from.x, from.y, top}, {to.x, to.y, top}});
    }
    return t;
}

ManualEdits read_edits(const Reader& r, int struts) {
    ManualEdits e;
    const auto& blockers = r.list("support_blockers");
    for (size_t i = 0; i < blockers.value.size(); ++i) {
        const auto& b = blockers.value[i];
        int line = r.line_of(blockers, i);
        std::string what = "support_blockers[" + std::to_string(i) + "]";
        if (!b.is_array() || b.size() != 2) r.fail(line, what + " must be a box [[x0, y0, z0], [x1, y1, z1]]");
        Vec3 a = r.point(b[0], line, what + " corner"), c = r.point(b[1], line, what + " corner");
        Box3 box;
        box.add(a);
        box.add(c);
        e.support_blockers.push_back(box);
    }
    const auto& points = r.list("support_points");
    for (size_t i = 0; i < points.value.size(); ++i)
        e.support_points.push_back(r.point(points.value[i], r.line_of(points, i), "support_points[" + std::to_string(i) + "]"));
    const auto& omit = r.list("omit_struts");
    for (size_t i = 0; i < omit.value.size(); ++i)
        e.omit_struts.push_back(r.index(omit.value[i], r.line_of(omit, i), "omit_struts: strut or pillar", struts));
    const auto& hl = r.get("highlight_strut");
    if (!(hl.value.is_number() && hl.value.get<double>() == -1))
        e.highlight_strut = r.index(hl.value, hl.line, "highlight_strut: strut", struts);
    return e;
}

}  // namespace

EditedScad read_edited_scad(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw InputError(path + ": cannot open it. Give the .scad file clever-support wrote.");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return read_edited_scad_text(text, path);
}

EditedScad read_edited_scad_text(const std::string& text, const std::string& path) {
    Reader r(parse_scad_values(text, path), path);

    EditedScad out;
    Job& job = out.job;
    job.input = r.text("cs_input_path");
    job.input_name = r.text("cs_input");
    const auto& defines = r.list("cs_defines");
    for (size_t i = 0; i < defines.value.size(); ++i) {
        if (!defines.value[i].is_string()) r.fail(r.line_of(defines, i), "cs_defines must be a list of \"name=value\" strings");
        job.defines.push_back(defines.value[i].get<std::string>());
    }
    job.orient = r.text("cs_orient");
    job.scale = r.number("cs_scale");
    if (double fit = r.number("cs_fit"); fit > 0) job.fit = fit;
    job.self_intersection_check = r.boolean("cs_self_intersection_check");
    job.timings = r.boolean("cs_timings");
    try {  // a strategy that is none, or a value out of range
        job.params = read_params(r);
        validate_params(job.params, ParamNaming::scad);
    } catch (const ParameterError& e) {
        // "d_max = 4 is out of range (...)" starts with the value's .scad name: name its line too.
        const std::string what = e.what(), name = what.substr(0, what.find(" = "));
        if (r.has(name)) throw ParameterError(path + ":" + std::to_string(r.get(name).line) + ": " + what);
        throw ParameterError(path + ": " + what);
    }
    out.tree = read_tree(r);
    job.edits = read_edits(r, static_cast<int>(out.tree.struts.size() + out.tree.pillar_tops.size()));  // pillars after struts
    out.input_sha256 = r.text("cs_input_sha256");
    const auto& pose = r.list("cs_pose");
    for (size_t i = 0; i < pose.value.size(); ++i) {
        if (!pose.value[i].is_number()) r.fail(pose.line, "cs_pose must be a list of numbers");
        out.pose.push_back(pose.value[i].get<double>());
    }
    auto folder = std::filesystem::path(path).parent_path();
    out.folder = folder.empty() ? "." : folder.string();
    return out;
}

}  // namespace cs

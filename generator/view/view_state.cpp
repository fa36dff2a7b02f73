#include "view/view_state.hpp"

#include <filesystem>
#include <regex>
#include <sstream>

#include "check/check.hpp"
#include "core/errors.hpp"
#include "edit/edited_scad.hpp"
#include "mesh/mesh_io.hpp"
#include "pipeline/pipeline.hpp"
#include "struts/struts.hpp"
#include "view/view_tree.hpp"

namespace fs = std::filesystem;

namespace cs {
namespace {

nlohmann::json xyz(const Vec3& p) { return {p.x, p.y, p.z}; }

// The Customizer's numeric values above [Manual edits] (`name = 1; // [min:step:max]`): what
// re-sizes the tree in OpenSCAD without a regrow.
nlohmann::json customizer_sliders(const std::string& text) {
    static const std::regex slider(R"(^([a-z_]+) = ([-0-9.e]+); // \[([-0-9.e]+):([-0-9.e]+):([-0-9.e]+)\])");
    nlohmann::json out = nlohmann::json::array();
    std::istringstream in(text);
    std::string line, comment;
    for (int no = 1; std::getline(in, line); ++no) {
        if (line.rfind("/* [Manual edits]", 0) == 0) break;
        std::smatch m;
        if (std::regex_search(line, m, slider))
            out.push_back({{"name", m[1].str()}, {"value", std::stod(m[2])}, {"min", std::stod(m[3])},
                           {"step", std::stod(m[4])}, {"max", std::stod(m[5])}, {"line", no}, {"about", comment}});
        comment = line.rfind("// ", 0) == 0 ? line.substr(3) : "";
    }
    return out;
}

nlohmann::json edits_json(const ManualEdits& e) {
    nlohmann::json blockers = nlohmann::json::array(), points = nlohmann::json::array();
    for (const auto& b : e.support_blockers) blockers.push_back({xyz(b.min), xyz(b.max)});
    for (const auto& p : e.support_points) points.push_back(xyz(p));
    return {{"support_blockers", blockers}, {"support_points", points}, {"omit_struts", e.omit_struts}};
}

// Every strut of the file; those omit_struts takes out drawn thin, the rest sized as the
// generator sizes the pruned tree (prune_struts keeps the kept struts in order).
nlohmann::json struts_json(const ScadTree& st, const SizedTree& sized, const Params& p) {
    nlohmann::json out = nlohmann::json::array();
    const auto& all = st.tree.struts;
    size_t j = 0;
    for (size_t e = 0; e < all.size(); ++e) {
        const Vec3 &a = st.tree.nodes[all[e].top].p, &b = st.tree.nodes[all[e].bottom].p;
        bool kept = j < sized.tree.struts.size() && sized.tree.struts[j].top == all[e].top &&
                    sized.tree.struts[j].bottom == all[e].bottom;
        double wt = kept ? sized.struts[j].top_width : p.d_min, wb = kept ? sized.struts[j].bottom_width : p.d_min;
        out.push_back({xyz(a), xyz(b), wt, wb, "onto " + st.node_kind[all[e].bottom], distance(a, b), !kept});
        if (kept) ++j;
    }
    return out;
}

// Tips under the overhang samples and above model contacts, and pillars, of the kept tree.
nlohmann::json tips_json(const SizedTree& sized, const Params& p) {
    nlohmann::json out = nlohmann::json::array();
    const auto& nodes = sized.tree.nodes;
    for (size_t v = 0; v < nodes.size(); ++v) {
        if (sized.out_strut[v] < 0 && sized.in_struts[v].empty()) continue;  // pruned or unused
        if (nodes[v].kind == NodeKind::Leaf) out.push_back({xyz(nodes[v].tip), xyz(nodes[v].p), p.tip_diameter, sized.node_width[v]});
        if (nodes[v].kind == NodeKind::ModelContact)
            out.push_back({xyz(nodes[v].p), xyz(nodes[v].contact), sized.node_width[v], p.tip_diameter});
    }
    for (const auto& pl : sized.tree.pillars) out.push_back({xyz(pl.top), xyz(pl.bottom), p.tip_diameter, p.d_min});
    return out;
}

}  // namespace

ViewFolder find_view_folder(const std::string& target) {
    fs::path t(target);
    std::error_code ec;
    if (fs::is_regular_file(t, ec)) {
        if (t.extension() != ".scad")
            throw InputError(target + ": not a .scad file. Give an output folder (out/m/) or the .scad clever-support wrote in it.");
        auto folder = t.parent_path();
        return {folder.empty() ? "." : folder.string(), t.stem().string()};
    }
    if (!fs::is_directory(t, ec))
        throw InputError(target + ": no such folder or file. Give an output folder (out/m/) or its .scad.");
    std::vector<std::string> stems;
    for (const auto& e : fs::directory_iterator(t, ec))
        if (e.path().extension() == ".scad" && e.path().filename() != "clever_support.scad") stems.push_back(e.path().stem());
    if (stems.size() != 1)
        throw InputError(target + (stems.empty() ? ": holds no .scad that clever-support wrote" : ": holds several .scad files") +
                         ". Give the .scad itself, e.g. clever-support view " + target + "/NAME.scad");
    std::string folder = t.string();
    while (folder.size() > 1 && folder.back() == '/') folder.pop_back();
    return {folder, stems[0]};
}

nlohmann::json view_scad_state(const std::string& text, const std::string& scad_path) {
    EditedScad e = read_edited_scad_text(text, scad_path);  // regrow's reading: same errors, same lines
    const Params& p = e.job.params;
    ScadTree st = tree_from_scad(parse_scad_values(text, scad_path));
    SizedTree sized = size_struts(prune_struts(st.tree, e.job.edits.omit_struts), p);
    return {{"sliders", customizer_sliders(text)},
            {"edits", edits_json(e.job.edits)},
            {"struts", struts_json(st, sized, p)},
            {"tips", tips_json(sized, p)},
            {"sampling", p.sampling_distance}};
}

// Judged as `clever-support check FOLDER` judges it: the model as written, the file's settings,
// its blockers and omitted struts left out on purpose.
nlohmann::json view_check(const ViewFolder& f, const std::string& scad_text) {
    const EditedScad e = read_edited_scad_text(scad_text, f.scad());
    CheckOptions o;
    o.left_out = e.job.edits.support_blockers;
    o.tree = e.tree;
    o.omitted_struts = e.job.edits.omit_struts;
    CheckResult c = check_supports(read_mesh(f.file(".model.stl")), read_mesh(f.file(".supports.stl"), true), e.job.params, o);
    nlohmann::json uncovered = nlohmann::json::array(), flagged = nlohmann::json::array();
    for (const auto& u : c.uncovered) uncovered.push_back(xyz(u));
    if (!c.coverage_ok()) uncovered.push_back(xyz(c.largest_gap_at));
    for (const auto& fl : c.flagged) flagged.push_back({{"what", fl.what}, {"at", xyz(fl.at)}});
    if (!c.gap_ok()) flagged.push_back({{"what", "fused contact: air gap " + std::to_string(c.min_air_gap) + " mm"}, {"at", xyz(c.min_air_gap_at)}});
    if (c.penetrating_bodies) flagged.push_back({{"what", "deepest penetration"}, {"at", xyz(c.max_penetration_at)}});
    return {{"ok", c.ok()}, {"coverage_ok", c.coverage_ok()}, {"summary", c.summary()}, {"uncovered", uncovered},
            {"uncovered_area_mm2", c.uncovered_area}, {"left_out_area_mm2", c.left_out_area + c.omitted_area},
            {"largest_gap", c.largest_gap}, {"reach", c.reach},
            {"flagged", flagged}};
}

}  // namespace cs

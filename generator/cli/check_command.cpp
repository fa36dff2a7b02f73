#include "cli/check_command.hpp"

#include <cstdio>
#include <nlohmann/json.hpp>

#include "cli/run_files.hpp"
#include "core/errors.hpp"
#include "edit/edited_scad.hpp"
#include "mesh/mesh_io.hpp"

namespace cs {
namespace {

// What check judges and with what: the meshes, the settings and the regions left out on purpose.
struct Judged {
    std::string model, supports;
    Params params;
    std::vector<Box3> left_out;
    RecordedTree tree;                // the run's tree as recorded, and
    std::vector<int> omitted_struts;  // the struts the user left out of it
    std::string settings_from;  // where the settings come from, for the printed line
};

Judged judged_run(const CheckArgs& c) {
    Judged j;
    if (!c.run.empty()) {
        const std::string scad = run_scad(c.run);
        EditedScad edited = read_edited_scad(scad);
        const std::string stem = edited.folder + "/" + stem_of(scad);
        j.model = stem + ".model.stl";
        j.supports = stem + ".supports.stl";
        j.params = c.params.resolve_over(edited.job.params);
        j.left_out = edited.job.edits.support_blockers;
        j.tree = edited.tree;
        j.omitted_struts = edited.job.edits.omit_struts;
        j.settings_from = c.params.preset_given || !c.params.config.empty() ? "as given" : "read from " + scad;
        if (!c.params.given.empty() && j.settings_from != "as given") j.settings_from += ", flags on top";
    } else {
        if (c.model.empty() || c.supports.empty())
            throw UsageError("check needs a run: `clever-support check out/m/` (its folder or its .scad), or both --model "
                             "and --supports");
        j.params = c.params.resolve(c.params.load_config());
        j.settings_from = c.params.preset_given || !c.params.config.empty() || !c.params.given.empty()
                              ? "as given"
                              : "the default preset: give the run's folder, or the --preset it was made with";
    }
    if (!c.model.empty()) j.model = c.model;
    if (!c.supports.empty()) j.supports = c.supports;
    for (const auto& b : edits_from({}, c.blocks, {}).support_blockers) j.left_out.push_back(b);
    return j;
}

// The settings check judged with, as one line (always printed: a verdict means little without them).
std::string settings_line(const Judged& j, const CheckResult& r) {
    const Params& p = j.params;
    char b[512];
    std::snprintf(b, sizeof b,
                  "judged with preset %s (%s): critical angle %g deg, layer %g mm, sampling %g mm (reach %.2f mm), "
                  "gap %g mm, tip %g mm wide, %g mm long; %zu region%s left out on purpose",
                  p.preset.c_str(), j.settings_from.c_str(), p.critical_angle, p.layer_height, p.sampling_distance, r.reach,
                  p.gap, p.tip_diameter, p.tip_length, j.left_out.size(), j.left_out.size() == 1 ? "" : "s");
    std::string line = b;
    if (!j.omitted_struts.empty()) {
        line += ", and what omit_struts [";
        for (size_t i = 0; i < j.omitted_struts.size(); ++i) line += (i ? ", " : "") + std::to_string(j.omitted_struts[i]);
        line += "] took out";
    }
    return line + "\n";
}

nlohmann::ordered_json settings_json(const Judged& j, const CheckResult& r) {
    const Params& p = j.params;
    nlohmann::ordered_json boxes = nlohmann::ordered_json::array();
    for (const auto& b : j.left_out) boxes.push_back({{b.min.x, b.min.y, b.min.z}, {b.max.x, b.max.y, b.max.z}});
    return {{"preset", p.preset}, {"from", j.settings_from}, {"model", j.model}, {"supports", j.supports},
            {"critical_angle_deg", p.critical_angle}, {"layer_height_mm", p.layer_height},
            {"sampling_distance_mm", p.sampling_distance}, {"reach_mm", r.reach}, {"gap_mm", p.gap},
            {"tip_diameter_mm", p.tip_diameter}, {"tip_length_mm", p.tip_length}, {"left_out", boxes},
            {"omit_struts", j.omitted_struts}};
}

}  // namespace

std::vector<std::string> meshes_checked(const CheckArgs& c) {
    const Judged j = judged_run(c);
    return {j.model, j.supports};
}

int cmd_check(const CheckArgs& c) {
    const Judged j = judged_run(c);
    Mesh model = read_mesh(j.model);  // judged as written (check/check.hpp)
    Mesh sup = read_mesh(j.supports, /*allow_empty=*/true);
    CheckOptions options = c.options;
    options.left_out = j.left_out;
    options.tree = j.tree;
    options.omitted_struts = j.omitted_struts;
    auto res = check_supports(model, sup, j.params, options);
    if (c.as_json) {
        auto out = nlohmann::ordered_json::parse(res.json());
        out["settings"] = settings_json(j, res);
        std::printf("%s\n", out.dump(2).c_str());
    } else {
        std::printf("%s%s", settings_line(j, res).c_str(), res.summary().c_str());
    }
    return res.ok() ? kExitOk : kExitCheckFailed;
}

}  // namespace cs

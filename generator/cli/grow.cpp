#include "cli/grow.hpp"

#include <unistd.h>

#include <cstdio>

#include "cli/compare.hpp"
#include "cli/defines.hpp"
#include "core/errors.hpp"
#include "edit/edited_scad.hpp"
#include "output/outputs.hpp"
#include "pipeline/pipeline.hpp"
#include "render/render.hpp"

namespace cs {
namespace {

// The requested extras after the outputs are written: the rendered union and the pictures.
void render_extras(const std::string& stem, const RunOptions& o) {
    if (o.render) {
        RenderOptions ro;
        ro.scad = stem + ".scad";
        auto rr = render_scad(ro);
        if (!o.quiet && !o.as_json) std::printf("  rendered    %s in %.1f s\n", rr.output.c_str(), rr.seconds);
    }
    if (o.preview) {
        render_previews(stem + ".scad", stem);
        if (!o.quiet && !o.as_json) std::printf("  pictures    %s-front.png, -back.png, -side.png\n", stem.c_str());
    }
}

// Warnings, the outputs (into `dir`, default out/<name>), the report or summary, then the extras.
int finish_run(const Result& r, const Job& job, std::string dir, const RunOptions& o) {
    if (!o.quiet)
        for (const auto& w : r.warnings) warn(w);
    if (dir.empty()) dir = "out/" + r.name;
    write_outputs(dir, output_files(r, job, CS_VERSION));
    if (o.as_json) std::printf("%s", report_json(r, job).c_str());
    else if (!o.quiet) std::printf("%s", human_summary(r, job, dir).c_str());
    render_extras(dir + "/" + r.name, o);
    return kExitOk;
}

}  // namespace

int cmd_generate(const GenerateArgs& g, const RunOptions& o) {
    if (g.input.empty()) throw UsageError("no input mesh given. Example: clever-support model.stl (see --help)");
    if (is_scad_input(g.input)) check_defines(g.part_defines, g.input, o.quiet);
    Job job;
    job.input = g.input;
    job.defines = g.part_defines;
    job.scale = g.scale;
    job.fit = g.fit;
    job.orient = g.orient;
    job.self_intersection_check = !g.no_self_intersection_check;
    job.timings = !g.no_timings;
    const ConfigFile config = g.params.load_config();  // read once: parameters and edits
    job.params = g.params.resolve(config);
    job.edits = edits_from(config, g.support_blockers, g.support_points);
    const Result r = run_showing_progress(job, o);
    const std::string dir = g.out_dir.empty() ? "out/" + r.name : g.out_dir;
    const int code = finish_run(r, job, dir, o);
    if (g.show_pose && !o.as_json) std::printf("  design -> placed: %s\n", pose_mapping(r.placement).c_str());
    if (!g.compare.empty()) {
        if (!o.quiet && !o.as_json && isatty(2)) std::fprintf(stderr, "  slicing with %s for --compare...\n", g.compare.c_str());
        const SlicerComparison c = compare_with_slicer(g.compare, dir, r.name, job.params);
        if (!c.done) warn("--compare " + g.compare + ": " + comparison_line(c));
        else if (!o.as_json && !o.quiet) std::printf("  compare     %s\n", comparison_line(c).c_str());
    }
    return code;
}

std::string regrown_input(const RegrowArgs& a) { return read_edited_scad(a.scad).job.input; }

int cmd_regrow(const RegrowArgs& a, const RunOptions& o) {
    const std::string& file = a.scad;
    EditedScad edited = read_edited_scad(file);
    set_scad_params(a.defines, edited.job.params, /*others_allowed=*/false);
    const Job& job = edited.job;
    Result r = run_showing_progress(job, o);
    // The run hashed the input as it read it: no second read of a big mesh for this note.
    if (!o.quiet && r.input_sha256 != edited.input_sha256)
        std::fprintf(stderr, "clever-support: note: %s changed since %s was written; the supports follow it as it is now\n",
                     job.input.c_str(), file.c_str());
    bool placed_edits = !job.edits.support_blockers.empty() || !job.edits.support_points.empty();
    if (placed_edits && pose_numbers(r.placement) != edited.pose)
        r.warnings.push_back("the model is placed differently than when " + file +
                             " was written (the part, its scale or the orientation changed): check that the support "
                             "blockers and points still sit where you meant them");
    return finish_run(r, job, a.out_dir.empty() ? edited.folder : a.out_dir, o);
}

}  // namespace cs

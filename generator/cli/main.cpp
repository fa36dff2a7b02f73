// clever-support command line: generate (default), regrow, check, render, presets; one function
// per subcommand, and exit_code_for(), the one place errors become messages and exit codes.
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <CLI/CLI.hpp>
#include <cstdio>
#include <exception>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <cmath>
#include <optional>
#include <type_traits>
#include <tbb/global_control.h>

#include "check/check.hpp"
#include "core/errors.hpp"
#include "core/param_table.hpp"
#include "edit/edited_scad.hpp"
#include "mesh/mesh_io.hpp"
#include "output/outputs.hpp"
#include "render/render.hpp"
#include "pipeline/pipeline.hpp"
#include "view/view_cli.hpp"

#ifndef CS_VERSION
#define CS_VERSION "0.1.0"
#endif

namespace {

using namespace cs;

// The parameters of a command: --preset, --config and one flag per row of the parameter table
// (core/param_table.hpp). Flags not given leave the preset's and the config file's values alone.
struct ParamFlags {
    std::string preset = "generic-0.4";
    bool preset_given = false;
    std::string config;  // a user's own preset: JSON of flag names and values
    std::vector<std::pair<const ParamRow*, ParamValue>> given;  // flags, in the order given

    // One option per row: numbers take a number, yes/no rows true/false, negated rows are bare
    // flags (--buildplate-only), the strategy its name.
    void add_to(CLI::App& app) {
        app.add_option("--preset", preset, "Printer preset (see `clever-support presets`)")
            ->capture_default_str()
            ->each([this](const std::string&) { preset_given = true; });
        app.add_option("--config", config, "A JSON file with your own preset: {\"preset\": ..., \"sampling\": 2, ...}");
        for (const ParamRow& row : param_table()) add_flag_for(app, row)->group("Parameters (override the preset)");
    }

    CLI::Option* add_flag_for(CLI::App& app, const ParamRow& row) {
        auto remember = [this, &row](ParamValue v) { given.emplace_back(&row, std::move(v)); };
        return std::visit(
            [&](auto member) -> CLI::Option* {
                using M = decltype(member);
                if constexpr (std::is_same_v<M, double Params::*>)
                    return app.add_option_function<double>(row.flag, [=](const double& v) { remember(v); }, row.help);
                else if constexpr (std::is_same_v<M, bool Params::*>)
                    return app.add_option_function<bool>(row.flag, [=](const bool& v) { remember(v); }, row.help);
                else if constexpr (std::is_same_v<M, Negated>)
                    return app.add_flag_callback(row.flag, [=] { remember(true); }, row.help);
                else
                    return app.add_option_function<std::string>(row.flag, [=](const std::string& v) { remember(v); },
                                                                row.help);
            },
            row.member);
    }

    nlohmann::json load_config() const {
        nlohmann::json cfg;
        if (config.empty()) return cfg;
        std::ifstream in(config);
        if (!in) throw ParameterError("--config " + config + ": cannot read it");
        try {
            cfg = nlohmann::json::parse(in);
        } catch (const std::exception& e) {
            throw ParameterError("--config " + config + ": not valid JSON (" + std::string(e.what()) + ")");
        }
        if (!cfg.is_object()) throw ParameterError("--config " + config + ": expected a JSON object of parameters");
        return cfg;
    }

    // preset, then the config file, then flags: later wins.
    Params resolve() const {
        std::string base = preset;
        nlohmann::json cfg = load_config();
        if (cfg.contains("preset") && !preset_given) base = cfg["preset"].get<std::string>();
        Params p = preset_params(base);
        if (!cfg.is_null()) {
            apply_config(cfg, p, "--config " + config);
            p.preset = cfg.value("preset", p.preset) + " + " + config;
        }
        for (const auto& [row, value] : given) set_param(*row, value, p);
        validate_params(p);
        return p;
    }
};

// "a,b,c" -> numbers; ParameterError naming the flag unless there are exactly `count` of them.
std::vector<double> numbers_in(const std::string& text, size_t count, const std::string& flag, const std::string& form) {
    std::vector<double> v;
    std::istringstream in(text);
    std::string part;
    while (std::getline(in, part, ',')) {
        char* end = nullptr;
        double x = std::strtod(part.c_str(), &end);
        if (part.empty() || *end != '\0' || !std::isfinite(x)) throw ParameterError(flag + " " + text + ": expected " + form);
        v.push_back(x);
    }
    if (v.size() != count) throw ParameterError(flag + " " + text + ": expected " + form);
    return v;
}

Box3 box_of(const std::vector<double>& v) {
    Box3 b;
    b.add({v[0], v[1], v[2]});
    b.add({v[3], v[4], v[5]});
    return b;
}

// Support blockers and points: the --config file's "block" / "support-point" lists first, then
// the flags.
ManualEdits edits_from(const nlohmann::json& cfg, const std::string& config, const std::vector<std::string>& blocks,
                       const std::vector<std::string>& points) {
    ManualEdits e;
    auto numbers = [&](const nlohmann::json& item, size_t count, const std::string& key, const std::string& form) {
        std::vector<double> v;
        if (item.is_array())
            for (const auto& x : item)
                if (x.is_number()) v.push_back(x.get<double>());
        if (!item.is_array() || v.size() != count || item.size() != count)
            throw ParameterError("--config " + config + ": \"" + key + "\" must hold lists of " + form);
        return v;
    };
    if (cfg.contains("block"))
        for (const auto& b : cfg["block"]) e.blockers.push_back(box_of(numbers(b, 6, "block", "[x0, y0, z0, x1, y1, z1]")));
    if (cfg.contains("support-point"))
        for (const auto& q : cfg["support-point"]) {
            auto v = numbers(q, 3, "support-point", "[x, y, z]");
            e.support_points.push_back({v[0], v[1], v[2]});
        }
    for (const auto& b : blocks) e.blockers.push_back(box_of(numbers_in(b, 6, "--block", "x0,y0,z0,x1,y1,z1 in mm")));
    for (const auto& q : points) {
        auto v = numbers_in(q, 3, "--support-point", "x,y,z in mm");
        e.support_points.push_back({v[0], v[1], v[2]});
    }
    return e;
}

void print_error(const std::string& msg) { std::fprintf(stderr, "clever-support: error: %s\n", msg.c_str()); }

// The one place where an error becomes a message on stderr and an exit code (README "Exit codes").
int exit_code_for(const std::exception_ptr& error) {
    try {
        std::rethrow_exception(error);
    } catch (const CLI::ParseError& e) {
        print_error(std::string(e.what()) + ". Run `clever-support --help` for usage.");
        return kExitUsage;
    } catch (const ParameterError& e) {
        print_error(std::string(e.what()) + ".");
        return kExitUsage;
    } catch (const UsageError& e) {
        print_error(e.what());
        return kExitUsage;
    } catch (const InputError& e) {
        print_error(e.what());
        return kExitBadInput;
    } catch (const ExternalToolError& e) {
        print_error(e.what());
        if (!e.log.empty()) std::fprintf(stderr, "%s", e.log.c_str());
        return kExitRenderFailed;
    } catch (const OutputError& e) {
        print_error(e.what());
        return kExitOutputFailed;
    } catch (const std::bad_alloc&) {
        print_error("out of memory. Try a larger --sampling or a smaller model.");
        return kExitInternal;
    } catch (const std::exception& e) {
        print_error(std::string("internal error: ") + e.what() + ". Please report this with the input file.");
        return kExitInternal;
    }
}

// How a run that grows supports (generate, regrow) talks and what it does after writing.
struct RunOptions {
    bool render = false, preview = false, quiet = false, verbose = false, as_json = false;
    int threads = 0;  // 0: all cores
};

// The default command's own inputs (the parameters are in `params`).
struct GenerateArgs {
    std::string input, out_dir, orient = "auto";
    double scale = 1;
    std::optional<double> fit;
    bool no_self_intersection_check = false, no_timings = false;
    std::vector<std::string> part_defines, blocks, support_points;
    ParamFlags params;
};

struct CheckArgs {
    std::string model, supports;
    CheckOptions options;
    bool as_json = false;
    ParamFlags params;
};

// Everything the command line can say; each subcommand's pointer tells whether it was chosen.
struct CommandLine {
    GenerateArgs generate;
    RunOptions run;
    std::string regrow_file;
    CheckArgs check;
    RenderOptions render;
    CLI::App *regrow_cmd = nullptr, *check_cmd = nullptr, *render_cmd = nullptr, *presets_cmd = nullptr;
    ViewArgs view;
    CLI::App* view_cmd = nullptr;
};

void add_run_flags(CLI::App& app, RunOptions& o, bool regrow) {
    app.add_flag("--render", o.render,
                 regrow ? "Also render the .scad with OpenSCAD into <name>.union.stl"
                        : "Also render <name>.scad with OpenSCAD into <name>.union.stl");
    app.add_flag("--preview", o.preview,
                 regrow ? "Also draw <name>-front/back/side.png"
                        : "Also draw <name>-front/back/side.png (model grey, supports orange)");
}

void add_talk_flags(CLI::App& app, RunOptions& o, bool regrow) {
    app.add_flag("-q,--quiet", o.quiet, "Print errors only");
    app.add_flag("-v,--verbose", o.verbose, "Print every stage as it starts");
    app.add_flag("--json", o.as_json, "Print the report JSON on stdout instead of the summary");
    app.add_option("--threads", o.threads,
                   regrow ? "Worker threads for orientation (0: all cores)"
                          : "Worker threads for orientation (0: all cores); output is the same for any count")
        ->check(CLI::Range(0, 1024));
}

void add_generate(CLI::App& app, GenerateArgs& g, RunOptions& o) {
    app.add_option("input", g.input, "Mesh file (" + mesh_formats_text() + "; STL ASCII or binary) or OpenSCAD part (.scad)");
    app.add_option("--out", g.out_dir, "Output directory (default out/<name>)");
    app.add_option("--scale", g.scale, "Scale factor applied first (e.g. 25.4 for inches)");
    app.add_option("--fit", g.fit, "Then scale so the largest side is this many mm");
    app.add_option("--orient", g.orient, "auto (least support), keep, or RX,RY,RZ in degrees")->capture_default_str();
    add_run_flags(app, o, false);
    app.add_flag("--no-self-intersection-check", g.no_self_intersection_check, "Skip counting self-intersections of the input");
    app.add_flag("--no-timings", g.no_timings, "Leave stage times out of the report: byte-identical reports run to run");
    add_talk_flags(app, o, false);
    g.params.add_to(app);
    app.add_option("-D", g.part_defines, "For a .scad input: OpenSCAD's -D name=value, passed when rendering the part (repeatable)")
        ->allow_extra_args(false);
    auto edits_group = "Manual edits (coordinates of <name>.model.stl)";
    app.add_option("--block", g.blocks, "No support inside this box: x0,y0,z0,x1,y1,z1 (repeatable)")
        ->allow_extra_args(false)
        ->group(edits_group);
    app.add_option("--support-point", g.support_points, "Also support this point of the model's underside: x,y,z (repeatable)")
        ->allow_extra_args(false)
        ->group(edits_group);
}

CLI::App* add_regrow(CLI::App& app, std::string& file, RunOptions& o) {
    auto* cmd = app.add_subcommand("regrow", "Grow the supports again from a generated .scad that you edited: its\n"
                                             "parameters, [Manual edits] and [Regrow] values; rewrites every output beside it.\n"
                                             "Example: clever-support regrow out/m/m.scad");
    cmd->add_option("scad", file, "The generated .scad file")->required();
    add_run_flags(*cmd, o, true);
    add_talk_flags(*cmd, o, true);
    return cmd;
}

CLI::App* add_check(CLI::App& app, CheckArgs& c) {
    auto* cmd = app.add_subcommand("check", "Verify supports: coverage, penetration, grounding, closed solids, angles.\n"
                                            "Example: clever-support check --model m.model.stl --supports m.supports.stl");
    cmd->add_option("--model", c.model, "Placed model STL")->required();
    cmd->add_option("--supports", c.supports, "Support STL (separate closed solids)")->required();
    cmd->add_option("--reach", c.options.reach,
                    "Max distance from an overhang point to a contact, mm (default: 0.71 x sampling, the "
                    "largest gap a square lattice of contacts leaves)");
    cmd->add_option("--penetration-tolerance", c.options.penetration_tolerance,
                    "How deep a solid may reach into the model outside its contact ends, mm (default: half the gap)");
    cmd->add_option("--gap-tolerance", c.options.gap_tolerance, "How far an air gap may fall short of --gap, mm")
        ->capture_default_str();
    cmd->add_flag("--json", c.as_json, "Print results as JSON");
    c.params.add_to(*cmd);
    return cmd;
}

CLI::App* add_render(CLI::App& app, RenderOptions& r) {
    auto* cmd = app.add_subcommand("render", "Render a generated .scad with OpenSCAD into <name>.union.stl.\n"
                                             "Example: clever-support render out/m/m.scad -D k=0.003");
    cmd->add_option("scad", r.scad, "Generated .scad file")->required();
    cmd->add_option("-o,--output", r.output, "Output file (default <name>.union.stl)");
    cmd->add_option("-D", r.defines, "Override a parameter: name=value (repeatable)");
    cmd->add_option("--openscad", r.openscad, "OpenSCAD command to use");
    cmd->add_option("--export-format", r.format, "binstl, asciistl or png")->capture_default_str();
    return cmd;
}

void describe_app(CLI::App& app) {
    app.footer("Which file to print (in --out):\n"
               "  Cura:         <name>.3mf        supports marked \"print as support\"; import\n"
               "                                  clever_support.curaprofile once (on an Ender 3/5 or CR-10:\n"
               "                                  clever_support_creality.curaprofile; README, \"Printing in Cura\")\n"
               "  PrusaSlicer:  <name>.prusa.3mf  supports as a part with support-like settings\n"
               "  Other:        <name>.supported.stl with the slicer's own supports off");
    app.set_version_flag("--version", CS_VERSION);
    app.require_subcommand(0, 1);
}

void add_commands(CLI::App& app, CommandLine& cl) {
    describe_app(app);
    add_generate(app, cl.generate, cl.run);
    cl.regrow_cmd = add_regrow(app, cl.regrow_file, cl.run);
    cl.check_cmd = add_check(app, cl.check);
    cl.render_cmd = add_render(app, cl.render);
    cl.presets_cmd = app.add_subcommand("presets", "List the printer presets, their values and where those come from.\n"
                                                   "Your own: --config my.json with {\"preset\": \"generic-0.4\", \"sampling\": 2}");
    cl.view_cmd = add_view_command(app, cl.view);
}

int cmd_presets() {
    for (const auto& pr : presets()) {
        const Params& p = pr.params;
        std::printf("%-16s %s\n", pr.name.c_str(), pr.description.c_str());
        std::printf("%-16s critical angle %g deg, layer %g mm, wall %g mm, sampling %g mm, tip %g x %g mm, gap %g mm, "
                    "k %g, d %g..%g mm\n",
                    "", p.critical_angle, p.layer_height, p.wall_thickness, p.sampling_distance, p.tip_length,
                    p.tip_diameter, p.gap, p.k, p.d_min, p.d_max);
        std::printf("%-16s sources: %s\n\n", "", pr.sources.c_str());
    }
    return kExitOk;
}

int cmd_render(const RenderOptions& o) {
    auto r = render_scad(o);
    std::printf("rendered %s in %.1f s\n", r.output.c_str(), r.seconds);
    return kExitOk;
}

int cmd_check(const CheckArgs& c) {
    Params p = c.params.resolve();
    RepairReport rr;
    Mesh model = repair_mesh(read_mesh(c.model), c.model, rr);
    Mesh sup = read_mesh(c.supports, /*allow_empty=*/true);
    auto res = check_supports(model, sup, p, c.options);
    std::printf("%s", c.as_json ? (res.json() + "\n").c_str() : res.summary().c_str());
    return res.ok() ? kExitOk : kExitCheckFailed;
}

// run_job with the stages shown as they start: every one with -v, a one-line progress on a
// terminal, nothing when stderr is a pipe or a file.
Result run_showing_progress(const Job& job, const RunOptions& o) {
    const int total_stages = 9;
    int stage_no = 0;
    auto progress = [&](const std::string& stage) {
        int pct = 100 * stage_no++ / total_stages;
        if (o.verbose) std::fprintf(stderr, "  [%3d%%] %s...\n", pct, stage.c_str());
        else if (!o.quiet && isatty(2)) std::fprintf(stderr, "\r\033[K  [%3d%%] %s...", pct, stage.c_str());
    };
    // Scoped to the run: the library itself keeps no global state.
    std::optional<tbb::global_control> limit;
    if (o.threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(o.threads));
    Result r = run_job(job, progress);
    if (!o.quiet && !o.verbose && isatty(2)) std::fprintf(stderr, "\r\033[K");
    return r;
}

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
        for (const auto& w : r.warnings) std::fprintf(stderr, "clever-support: warning: %s\n", w.c_str());
    if (dir.empty()) dir = "out/" + r.name;
    write_outputs(dir, output_files(r, job, CS_VERSION));
    if (o.as_json) std::printf("%s", report_json(r, job).c_str());
    else if (!o.quiet) std::printf("%s", human_summary(r, dir).c_str());
    render_extras(dir + "/" + r.name, o);
    return kExitOk;
}

int cmd_generate(const GenerateArgs& g, const RunOptions& o) {
    if (g.input.empty()) throw UsageError("no input mesh given. Example: clever-support model.stl (see --help)");
    Job job;
    job.input = g.input;
    job.defines = g.part_defines;
    job.scale = g.scale;
    job.fit = g.fit;
    job.orient = g.orient;
    job.self_intersection_check = !g.no_self_intersection_check;
    job.timings = !g.no_timings;
    job.params = g.params.resolve();
    job.edits = edits_from(g.params.load_config(), g.params.config, g.blocks, g.support_points);
    return finish_run(run_showing_progress(job, o), job, g.out_dir, o);
}

int cmd_regrow(const std::string& file, const RunOptions& o) {
    EditedScad edited = read_edited_scad(file);
    const Job& job = edited.job;
    Result r = run_showing_progress(job, o);
    // The run hashed the input as it read it: no second read of a big mesh for this note.
    if (!o.quiet && r.input_sha256 != edited.input_sha256)
        std::fprintf(stderr, "clever-support: note: %s changed since %s was written; the supports follow it as it is now\n",
                     job.input.c_str(), file.c_str());
    bool placed_edits = !job.edits.blockers.empty() || !job.edits.support_points.empty();
    if (placed_edits && pose_numbers(r.placement) != edited.pose)
        r.warnings.push_back("the model is placed differently than when " + file +
                             " was written (the part, its scale or the orientation changed): check that the support "
                             "blockers and points still sit where you meant them");
    return finish_run(r, job, edited.folder, o);
}

int run_command(const CommandLine& cl) {
    if (cl.presets_cmd->parsed()) return cmd_presets();
    if (cl.render_cmd->parsed()) return cmd_render(cl.render);
    if (cl.check_cmd->parsed()) return cmd_check(cl.check);
    if (cl.regrow_cmd->parsed()) return cmd_regrow(cl.regrow_file, cl.run);
    if (cl.view_cmd->parsed()) return run_view_command(cl.view);
    return cmd_generate(cl.generate, cl.run);
}

// One run builds and drops many buffers of megabytes (the mesh, its index, the 3MF XML and its
// deflated package, the STLs). glibc maps each one above 128 KB fresh from the kernel and unmaps it
// on free, so every run pays the page faults again, and it hands the top of the heap back as soon
// as 128 KB are free there. Keeping buffers up to 32 MB on the heap and freed memory up to 512 MB:
// igea (270k triangles) 2.5 -> 2.0 CPU-s, peak memory +9 %. A process setting, hence here in main.
void tune_allocator() {
#if defined(__GLIBC__)
    mallopt(M_MMAP_THRESHOLD, 32 << 20);
    mallopt(M_TRIM_THRESHOLD, 512 << 20);
#endif
}

}  // namespace

int main(int argc, char** argv) {
    tune_allocator();
    CLI::App app{"clever-support: tree supports for FDM prints, as printable STL and parametric OpenSCAD.\n"
                 "Examples:\n"
                 "  clever-support model.stl                       # supports into out/model/\n"
                 "  clever-support --fit 80 --render scan.obj      # scale to 80 mm, render the SCAD too\n"
                 "  clever-support --preset replicator2-pla --orient keep part.stl\n"
                 "  clever-support check --model out/m/m.model.stl --supports out/m/m.supports.stl\n"
                 "  clever-support render out/m/m.scad -D k=0.003\n"
                 "  clever-support part.scad -D width=30 --block 0,0,0,10,10,20\n"
                 "  clever-support regrow out/m/m.scad              # after editing it\n",
                 "clever-support"};
    CommandLine cl;
    add_commands(app, cl);
    try {
        app.parse(argc, argv);
        return run_command(cl);
    } catch (const CLI::Success& e) {  // --help, --version
        return app.exit(e);
    } catch (...) {
        return exit_code_for(std::current_exception());
    }
}

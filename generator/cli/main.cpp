// clever-support command line: generate (default), regrow, check, render, apply, presets; one
// function per subcommand, and exit_code_for(), the one place errors become messages and exit codes.
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
#include <algorithm>
#include <filesystem>

#include "check/check.hpp"
#include "cli/compare.hpp"
#include "cli/defines.hpp"
#include "cli/suggest.hpp"
#include "core/config.hpp"
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

    // The --config file, read and checked whole (core/config.hpp); empty without --config.
    ConfigFile load_config() const {
        if (config.empty()) return {};
        std::ifstream in(config, std::ios::binary);
        if (!in) throw ParameterError("--config " + config + ": cannot read it");
        const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
        return parse_config(text, "--config " + config);
    }

    // preset, then the config file (`cfg`: load_config), then flags: later wins.
    Params resolve(const ConfigFile& cfg) const {
        Params p = known_preset(cfg.preset && !preset_given ? *cfg.preset : preset);
        if (!config.empty()) {
            apply_config(cfg.values, p, "--config " + config);
            p.preset = cfg.preset.value_or(p.preset) + " + " + config;
        }
        for (const auto& [row, value] : given) set_param(*row, value, p);
        validate_params(p);
        return p;
    }

    // The settings of a run (`base`, read from its .scad) with the flags given on top; a --preset
    // or --config given replaces them as in resolve().
    Params resolve_over(Params base) const {
        if (preset_given || !config.empty()) return resolve(load_config());
        for (const auto& [row, value] : given) set_param(*row, value, base);
        validate_params(base);
        return base;
    }

    // preset_params, with the nearest preset name suggested for a slip.
    static Params known_preset(const std::string& name) {
        std::vector<std::string> names;
        for (const auto& pr : presets()) names.push_back(pr.name);
        if (std::find(names.begin(), names.end(), name) == names.end()) {
            std::string known;
            for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
            throw ParameterError("unknown preset '" + name + "'" + did_you_mean(name, names) + "; known presets: " + known);
        }
        return preset_params(name);
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

// Support blockers and points: the --config file's "support-blocker" (or, as before, "block") /
// "support-point" lists first, then the flags.
ManualEdits edits_from(const ConfigFile& cfg, const std::vector<std::string>& blockers, const std::vector<std::string>& points) {
    ManualEdits e;
    e.support_blockers = cfg.blockers;
    e.support_points = cfg.support_points;
    for (const auto& b : blockers)
        e.support_blockers.push_back(box_of(numbers_in(b, 6, "--support-blocker", "x0,y0,z0,x1,y1,z1 in mm")));
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
    std::vector<std::string> part_defines, support_blockers, support_points;
    std::string compare;  // "", cura or prusa
    bool show_pose = false;
    ParamFlags params;
};

struct CheckArgs {
    std::string run;  // a run's folder or .scad: meshes, settings and blockers from there
    std::string model, supports;
    std::vector<std::string> blocks;
    CheckOptions options;
    bool as_json = false;
    ParamFlags params;
};

struct RegrowArgs {
    std::string scad, out_dir;
    std::vector<std::string> defines;  // the .scad's parameters, by their .scad names
};

// `apply`: the supports rendered from an edited .scad into the slicer files beside it.
struct ApplyArgs {
    std::string scad, openscad;
    std::vector<std::string> defines;
    bool quiet = false;
};

// Everything the command line can say; each subcommand's pointer tells whether it was chosen.
struct CommandLine {
    GenerateArgs generate;
    RunOptions run;
    RegrowArgs regrow;
    CheckArgs check;
    RenderOptions render;
    ApplyArgs apply;
    CLI::App *regrow_cmd = nullptr, *check_cmd = nullptr, *render_cmd = nullptr, *apply_cmd = nullptr,
             *presets_cmd = nullptr;
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
    app.add_option("--compare", g.compare,
                   "cura or prusa: also slice the model with that slicer's own supports and with ours, in a temporary "
                   "folder, and print both (grams, minutes)")
        ->check(CLI::IsMember({"cura", "prusa"}));
    app.add_flag("--show-pose", g.show_pose, "Print how a point of the input maps to the placed model's coordinates");
    app.add_option("-D", g.part_defines, "For a .scad input: OpenSCAD's -D name=value, passed when rendering the part (repeatable)")
        ->allow_extra_args(false);
    auto edits_group = "Manual edits (coordinates of <name>.model.stl)";
    app.add_option("--support-blocker,--block", g.support_blockers,
                   "No support inside this box: x0,y0,z0,x1,y1,z1 (repeatable)")
        ->allow_extra_args(false)
        ->group(edits_group);
    app.add_option("--support-point", g.support_points, "Also support this point of the model's underside: x,y,z (repeatable)")
        ->allow_extra_args(false)
        ->group(edits_group);
}

CLI::App* add_regrow(CLI::App& app, RegrowArgs& r, RunOptions& o) {
    auto* cmd = app.add_subcommand("regrow", "Grow the supports again from a generated .scad that you edited: its\n"
                                             "parameters, [Manual edits] and [Regrow] values; rewrites every output beside it.\n"
                                             "Example: clever-support regrow out/m/m.scad -D sampling=2 --out out/m-try");
    cmd->add_option("scad", r.scad, "The generated .scad file")->required();
    cmd->add_option("-D", r.defines, "Override a parameter of the .scad: name=value, e.g. -D sampling=2 (repeatable)")
        ->allow_extra_args(false);
    cmd->add_option("--out", r.out_dir, "Write the outputs here instead of beside the .scad");
    add_run_flags(*cmd, o, true);
    add_talk_flags(*cmd, o, true);
    return cmd;
}

CLI::App* add_check(CLI::App& app, CheckArgs& c) {
    auto* cmd = app.add_subcommand("check", "Verify supports: coverage, penetration, grounding, closed solids, angles.\n"
                                            "Example: clever-support check out/m/   (the run's meshes, settings and blockers)\n"
                                            "         clever-support check --model m.model.stl --supports m.supports.stl");
    cmd->add_option("run", c.run,
                    "A run's output folder or its .scad (out/m/ or out/m/m.scad): judges its meshes with the settings "
                    "and support blockers it was made with");
    cmd->add_option("--model", c.model, "Placed model STL (default: the run's <name>.model.stl)");
    cmd->add_option("--supports", c.supports, "Support STL, separate closed solids (default: the run's <name>.supports.stl)");
    cmd->add_option("--block", c.blocks,
                    "A region left out on purpose: x0,y0,z0,x1,y1,z1 (repeatable; the run's support_blockers count too)")
        ->allow_extra_args(false);
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

CLI::App* add_apply(CLI::App& app, ApplyArgs& a) {
    auto* cmd = app.add_subcommand("apply", "Render the supports of an edited .scad (a Customizer tweak, omit_struts) and\n"
                                            "rewrite <name>.supports.stl, .supported.stl, .3mf and .prusa.3mf beside it.\n"
                                            "Example: clever-support apply out/m/m.scad -D k=0.003");
    cmd->add_option("scad", a.scad, "Generated .scad file")->required();
    cmd->add_option("-D", a.defines, "Override a value of the .scad: name=value (repeatable)")->allow_extra_args(false);
    cmd->add_option("--openscad", a.openscad, "OpenSCAD command to use");
    cmd->add_flag("-q,--quiet", a.quiet, "Print errors only");
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
    cl.regrow_cmd = add_regrow(app, cl.regrow, cl.run);
    cl.check_cmd = add_check(app, cl.check);
    cl.render_cmd = add_render(app, cl.render);
    cl.apply_cmd = add_apply(app, cl.apply);
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

void warn(const std::string& w) { std::fprintf(stderr, "clever-support: warning: %s\n", w.c_str()); }

// -D defines for a .scad: each checked (a mistake names the define), a warning for each name the
// file does not assign (unless `quiet`).
void check_defines(const std::vector<std::string>& defines, const std::string& scad, bool quiet = false) {
    for (const auto& d : defines) check_define(d);
    if (!quiet)
        for (const auto& w : unknown_define_warnings(defines, scad)) warn(w);
}

int cmd_render(const RenderOptions& o) {
    check_defines(o.defines, o.scad);
    auto r = render_scad(o);
    std::printf("rendered %s in %.1f s\n", r.output.c_str(), r.seconds);
    std::printf("  (the supports STLs and 3MFs are unchanged: `clever-support apply %s` rewrites them from this .scad)\n",
                o.scad.c_str());
    return kExitOk;
}

std::string stem_of(const std::string& path) { return std::filesystem::path(path).stem().string(); }

// The supports of an edited .scad, rendered without the model, into the four files that carry
// them. Parameters given with -D also set the PrusaSlicer volume's settings.
int cmd_apply(const ApplyArgs& a) {
    check_defines(a.defines, a.scad, a.quiet);
    EditedScad edited = read_edited_scad(a.scad);
    Params p = edited.job.params;
    set_scad_params(a.defines, p, /*others_allowed=*/true);
    const std::string name = stem_of(a.scad), dir = edited.folder;
    const std::string model_file = dir + "/" + name + ".model.stl";
    Mesh model = read_mesh(model_file);
    RenderOptions ro;
    ro.scad = a.scad;
    ro.output = dir + "/." + name + ".apply.stl";
    ro.defines = a.defines;
    ro.defines.insert(ro.defines.end(), {"show_model=false", "show_supports=true"});
    ro.openscad = a.openscad;
    RenderResult rr;
    Mesh supports;  // empty when every solid was left out (OpenSCAD then renders nothing)
    try {
        rr = render_scad(ro);
        supports = read_mesh(ro.output, /*allow_empty=*/true);
    } catch (const ExternalToolError& e) {
        std::remove(ro.output.c_str());
        if ((std::string(e.what()) + e.log).find("top level object is empty") == std::string::npos) throw;
    } catch (...) {
        std::remove(ro.output.c_str());
        throw;
    }
    std::remove(ro.output.c_str());
    // The render is one union, not bodies: the .prusa.3mf gets one supports volume.
    write_outputs(dir, support_mesh_files(name, model, supports, /*built=*/nullptr, p));
    if (!a.quiet) {
        std::printf("applied %s (rendered in %.1f s): rewrote %s/%s.supports.stl, .supported.stl, .3mf, .prusa.3mf\n",
                    a.scad.c_str(), rr.seconds, dir.c_str(), name.c_str());
        std::printf("  supports now %.2f g (%.0f mm^3); the report still describes the supports as grown, and\n"
                    "  solids that touch are one solid now (as check judges them)\n",
                    signed_volume(supports) / 1000.0 * p.filament_density, signed_volume(supports));
    }
    return kExitOk;
}

// A run's generated .scad: `path` itself, or the one in the folder `path`.
std::string run_scad(const std::string& path) {
    namespace fs = std::filesystem;
    std::error_code ec;
    if (!fs::is_directory(path, ec)) {
        if (!is_scad_input(path))
            throw UsageError("check " + path + ": give a run's output folder or its .scad (e.g. check out/m/ or check "
                             "out/m/m.scad), or --model and --supports");
        return path;
    }
    std::vector<std::string> found;
    for (const auto& e : fs::directory_iterator(path, ec))
        if (e.path().extension() == ".scad" && e.path().filename() != "clever_support.scad") found.push_back(e.path().string());
    std::sort(found.begin(), found.end());
    if (found.size() == 1) return found[0];
    if (found.empty())
        throw UsageError("check " + path + ": no generated .scad in this folder; give the folder a run wrote (out/<name>/)");
    std::string list;
    for (const auto& f : found) list += " " + f;
    throw UsageError("check " + path + ": several .scad files here; give one of them:" + list);
}

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

// run_job with the stages shown as they start: every one with -v, a one-line progress on a
// terminal, nothing when stderr is a pipe or a file.
Result run_showing_progress(const Job& job, const RunOptions& o) {
    const int total_stages = static_cast<int>(job_stages(job).size());
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
        for (const auto& w : r.warnings) warn(w);
    if (dir.empty()) dir = "out/" + r.name;
    write_outputs(dir, output_files(r, job, CS_VERSION));
    if (o.as_json) std::printf("%s", report_json(r, job).c_str());
    else if (!o.quiet) std::printf("%s", human_summary(r, job, dir).c_str());
    render_extras(dir + "/" + r.name, o);
    return kExitOk;
}

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

int run_command(const CommandLine& cl) {
    if (cl.presets_cmd->parsed()) return cmd_presets();
    if (cl.render_cmd->parsed()) return cmd_render(cl.render);
    if (cl.apply_cmd->parsed()) return cmd_apply(cl.apply);
    if (cl.check_cmd->parsed()) return cmd_check(cl.check);
    if (cl.regrow_cmd->parsed()) return cmd_regrow(cl.regrow, cl.run);
    if (cl.view_cmd->parsed()) return run_view_command(cl.view);
    return cmd_generate(cl.generate, cl.run);
}

std::vector<std::string> subcommand_names(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::App* s : app.get_subcommands([](const CLI::App*) { return true; })) names.push_back(s->get_name());
    return names;
}

// A first word that is no file and looks like no file name is a subcommand mistyped
// (`clever-support chek --model ...`), not a mesh to read.
void reject_unknown_subcommand(const CLI::App& app, int argc, char** argv) {
    if (argc < 2) return;
    const std::string first = argv[1];
    std::error_code ec;
    if (first.empty() || first[0] == '-' || first.find_first_of("./") != std::string::npos ||
        std::filesystem::exists(first, ec))
        return;
    const auto names = subcommand_names(app);
    if (std::find(names.begin(), names.end(), first) != names.end()) return;
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    throw UsageError("unknown subcommand '" + first + "'" + did_you_mean(first, names) + ". The subcommands are " + list +
                     "; to grow supports, give a model file (" + mesh_formats_text() + " or .scad). Run `clever-support --help` "
                     "for usage.");
}

// The options a command takes, as typed: --long and -s.
std::vector<std::string> option_names(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::Option* opt : app.get_options()) {
        for (const auto& l : opt->get_lnames()) names.push_back("--" + l);
        for (const auto& s : opt->get_snames()) names.push_back("-" + s);
    }
    return names;
}

// Arguments nobody took, in the order typed, with the nearest option for each unknown --flag.
std::string unexpected_arguments(const CLI::App& app) {
    const CLI::App* cmd = &app;
    for (const CLI::App* s : app.get_subcommands()) cmd = s;
    const auto known = option_names(*cmd);
    std::vector<std::string> extras = app.remaining(true);
    std::string msg;
    for (const auto& a : extras) {
        if (a.size() > 1 && a[0] == '-') {
            const std::string flag = a.substr(0, a.find('='));
            msg += (msg.empty() ? "" : "; ") + ("unknown option " + flag + did_you_mean(flag, known));
        }
    }
    if (msg.empty()) {
        for (const auto& a : extras) msg += (msg.empty() ? "" : " ") + a;
        msg = "not expected: " + msg;
    }
    return msg + ". Run `clever-support " + (cmd == &app ? "" : cmd->get_name() + " ") + "--help` for usage.";
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
                 "  clever-support check out/m/                     # the run's meshes, settings and blockers\n"
                 "  clever-support apply out/m/m.scad -D k=0.003    # a tweak into the STLs and 3MFs\n"
                 "  clever-support --compare prusa part.stl         # and PrusaSlicer's own supports beside ours\n"
                 "  clever-support part.scad -D width=30 --support-blocker 0,0,0,10,10,20\n"
                 "  clever-support regrow out/m/m.scad              # after editing it\n",
                 "clever-support"};
    CommandLine cl;
    add_commands(app, cl);
    try {
        reject_unknown_subcommand(app, argc, argv);
        try {
            app.parse(argc, argv);
        } catch (const CLI::ExtrasError&) {
            throw UsageError(unexpected_arguments(app));
        }
        return run_command(cl);
    } catch (const CLI::Success& e) {  // --help, --version
        return app.exit(e);
    } catch (...) {
        return exit_code_for(std::current_exception());
    }
}

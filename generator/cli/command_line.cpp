#include "cli/command_line.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <vector>

#include "cli/suggest.hpp"
#include "core/errors.hpp"
#include "mesh/mesh_io.hpp"

namespace cs {
namespace {

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
               "  PrusaSlicer:  <name>.prusa.3mf  supports as two parts with support-like settings\n"
               "  Other:        <name>.supported.stl with the slicer's own supports off");
    app.set_version_flag("--version", CS_VERSION);
    app.require_subcommand(0, 1);
}

}  // namespace

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

namespace {

std::vector<std::string> subcommand_names(const CLI::App& app) {
    std::vector<std::string> names;
    for (const CLI::App* s : app.get_subcommands([](const CLI::App*) { return true; })) names.push_back(s->get_name());
    return names;
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

}  // namespace

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

}  // namespace cs

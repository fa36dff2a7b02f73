// clever-support command line: parses the words (cli/command_line.hpp) and runs the one command
// they choose: generate (the default, cli/grow.hpp), regrow, check, render, apply, presets, view.
// Every error any of them throws becomes a message and an exit code in one place (cli/exit_code.hpp).
#include <CLI/CLI.hpp>
#include <exception>

#include "cli/command_line.hpp"
#include "cli/exit_code.hpp"
#include "cli/huge_pages.hpp"
#include "core/errors.hpp"

namespace {

using namespace cs;

int run_command(const CommandLine& cl, char** argv) {
    if (cl.presets_cmd->parsed()) return cmd_presets();
    if (cl.render_cmd->parsed()) return cmd_render(cl.render);
    if (cl.apply_cmd->parsed()) return cmd_apply(cl.apply);
    // A large mesh: the whole run on huge pages, run again before it prints anything.
    if (cl.check_cmd->parsed()) {
        rerun_on_huge_pages(meshes_checked(cl.check), argv);
        return cmd_check(cl.check);
    }
    if (cl.regrow_cmd->parsed()) {
        rerun_on_huge_pages({regrown_input(cl.regrow)}, argv);
        return cmd_regrow(cl.regrow, cl.run);
    }
    if (cl.view_cmd->parsed()) return run_view_command(cl.view);
    rerun_on_huge_pages({cl.generate.input}, argv);
    return cmd_generate(cl.generate, cl.run);
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
        return run_command(cl, argv);
    } catch (const CLI::Success& e) {  // --help, --version
        return app.exit(e);
    } catch (...) {
        return exit_code_for(std::current_exception());
    }
}

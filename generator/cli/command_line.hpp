// The command line's words: every subcommand with its options and help (CLI11), filled into one
// CommandLine, and the messages for words nobody takes (a mistyped subcommand or option, with the
// nearest one suggested). main.cpp parses with these and hands the chosen command its arguments.
//
// Example:
//   CLI::App app{"clever-support: ...", "clever-support"};
//   CommandLine cl;
//   add_commands(app, cl);
//   reject_unknown_subcommand(app, argc, argv);  // `clever-support chek` -> UsageError "... did you mean `check`?"
//   app.parse(argc, argv);                       // CLI::ExtrasError -> UsageError(unexpected_arguments(app))
//   if (cl.check_cmd->parsed()) return cmd_check(cl.check);
#pragma once

#include <string>

#include "cli/apply.hpp"
#include "cli/check_command.hpp"
#include "cli/grow.hpp"
#include "view/view_cli.hpp"

namespace CLI {
class App;
}

namespace cs {

// Everything the command line can say; each subcommand's pointer tells whether it was chosen
// (none: the default command, generate).
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

// The default command's options, every subcommand, the footer (which file to print in which
// slicer) and --version, on `app`, writing into `cl`; `cl` must outlive the parse.
void add_commands(CLI::App& app, CommandLine& cl);

// A first word that is no file and looks like no file name is a subcommand mistyped
// (`clever-support chek --model ...`), not a mesh to read: UsageError naming the subcommands.
void reject_unknown_subcommand(const CLI::App& app, int argc, char** argv);

// After a parse left arguments over: those nobody took, in the order typed, with the nearest
// option for each unknown --flag, and where to find the usage.
std::string unexpected_arguments(const CLI::App& app);

}  // namespace cs

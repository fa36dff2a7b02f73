// The two commands that grow supports and write every output of a run (output/outputs.hpp):
//   generate  the default command: a mesh or an OpenSCAD part, with the parameters and the manual
//             edits the flags and --config give, into --out (default out/<name>)
//   regrow    a generated .scad a person edited (its parameters, [Manual edits] and [Regrow]
//             values, -D on top), grown again into the folder beside it or --out
// Both print the run's warnings and then its summary (or with --json its report) on stdout, and
// render the .scad (--render) and draw its pictures (--preview) after writing.
//
// Example (`clever-support --fit 80 scan.obj`):
//   GenerateArgs g;
//   g.input = "scan.obj";
//   g.fit = 80;
//   int code = cmd_generate(g, RunOptions{});  // writes out/scan/, returns kExitOk
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "cli/param_flags.hpp"
#include "cli/progress.hpp"

namespace cs {

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

struct RegrowArgs {
    std::string scad, out_dir;
    std::vector<std::string> defines;  // the .scad's parameters, by their .scad names
};

// Throws UsageError without an input, and what run_job and write_outputs throw.
int cmd_generate(const GenerateArgs& g, const RunOptions& o);

// Throws InputError for a .scad that cannot be read back, ParameterError for a bad -D.
int cmd_regrow(const RegrowArgs& a, const RunOptions& o);

// The mesh or part cmd_regrow reads (the .scad's cs_input_path), for cli/huge_pages.hpp. Throws
// what cmd_regrow throws for a .scad it cannot read back.
std::string regrown_input(const RegrowArgs& a);

}  // namespace cs

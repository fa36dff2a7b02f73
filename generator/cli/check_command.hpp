// `clever-support check`: judges a run's supports (check/check.hpp) with the settings, support
// blockers and omitted struts the run was made with, read from its .scad, or two meshes with the
// settings given. Prints the settings it judged with, then the verdict (or both as JSON).
//
// Example:
//   CheckArgs a;
//   a.run = "out/m/";        // or a.model = "m.model.stl", a.supports = "m.supports.stl"
//   int code = cmd_check(a); // kExitOk, or kExitCheckFailed when a rule fails
#pragma once

#include <string>
#include <vector>

#include "check/check.hpp"
#include "cli/param_flags.hpp"

namespace cs {

struct CheckArgs {
    std::string run;  // a run's folder or .scad: meshes, settings and blockers from there
    std::string model, supports;
    std::vector<std::string> blocks;
    CheckOptions options;
    bool as_json = false;
    ParamFlags params;
};

// Throws UsageError without a run or both meshes, InputError for a mesh or .scad that cannot be
// read, ParameterError for a bad setting.
int cmd_check(const CheckArgs& c);

// The two meshes cmd_check reads (the model, the supports), for cli/huge_pages.hpp. Throws what
// cmd_check throws for a run it cannot find.
std::vector<std::string> meshes_checked(const CheckArgs& c);

}  // namespace cs

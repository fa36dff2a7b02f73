// The parameters of a command as the command line gives them: --preset, --config and one flag per
// row of the parameter table (core/param_table.hpp), resolved into Params (preset, then the config
// file, then the flags: later wins); and the manual edits (support blockers and points) from the
// config file and the flags. And `clever-support presets`, which lists the presets.
//
// Example (`clever-support --preset replicator2-pla --sampling 2 m.stl`):
//   ParamFlags flags;
//   flags.add_to(app);                                 // before app.parse
//   const ConfigFile cfg = flags.load_config();        // after it: {} without --config
//   Params p = flags.resolve(cfg);                     // replicator2-pla with sampling_distance 2
//   ManualEdits e = edits_from(cfg, {"0,0,0,10,10,20"}, {});  // one support blocker
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/config.hpp"
#include "core/param_table.hpp"
#include "core/params.hpp"
#include "job/job.hpp"

namespace CLI {
class App;
class Option;
}  // namespace CLI

namespace cs {

struct ParamFlags {
    std::string preset = "generic-0.4";
    bool preset_given = false;
    std::string config;  // a user's own preset: JSON of flag names and values
    std::vector<std::pair<const ParamRow*, ParamValue>> given;  // flags, in the order given

    // One option per row: numbers take a number, yes/no rows true/false, negated rows are bare
    // flags (--buildplate-only), the strategy its name. Flags not given leave the preset's and the
    // config file's values alone.
    void add_to(CLI::App& app);

    // The --config file, read and checked whole (core/config.hpp); empty without --config.
    // Throws ParameterError when it cannot be read.
    ConfigFile load_config() const;

    // preset, then the config file (`cfg`: load_config), then flags: later wins. Validated.
    Params resolve(const ConfigFile& cfg) const;

    // The settings of a run (`base`, read from its .scad) with the flags given on top; a --preset
    // or --config given replaces them as in resolve().
    Params resolve_over(Params base) const;

    // preset_params, with the nearest preset name suggested for a slip (ParameterError).
    static Params known_preset(const std::string& name);

private:
    CLI::Option* add_flag_for(CLI::App& app, const ParamRow& row);
};

// Support blockers ("x0,y0,z0,x1,y1,z1") and points ("x,y,z"): the --config file's
// "support-blocker" (or, as before, "block") / "support-point" lists first, then the flags.
// Throws ParameterError naming the flag for a value that is not so many numbers.
ManualEdits edits_from(const ConfigFile& cfg, const std::vector<std::string>& blockers, const std::vector<std::string>& points);

// `clever-support presets`: every preset, its values and where they come from, on stdout. kExitOk.
int cmd_presets();

}  // namespace cs

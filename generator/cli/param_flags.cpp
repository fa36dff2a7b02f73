#include "cli/param_flags.hpp"

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <sstream>
#include <type_traits>

#include "cli/suggest.hpp"
#include "core/errors.hpp"

namespace cs {

void ParamFlags::add_to(CLI::App& app) {
    app.add_option("--preset", preset, "Printer preset (see `clever-support presets`)")
        ->capture_default_str()
        ->each([this](const std::string&) { preset_given = true; });
    app.add_option("--config", config, "A JSON file with your own preset: {\"preset\": ..., \"sampling\": 2, ...}");
    for (const ParamRow& row : param_table()) add_flag_for(app, row)->group("Parameters (override the preset)");
}

CLI::Option* ParamFlags::add_flag_for(CLI::App& app, const ParamRow& row) {
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

ConfigFile ParamFlags::load_config() const {
    if (config.empty()) return {};
    std::ifstream in(config, std::ios::binary);
    if (!in) throw ParameterError("--config " + config + ": cannot read it");
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    return parse_config(text, "--config " + config);
}

Params ParamFlags::resolve(const ConfigFile& cfg) const {
    Params p = known_preset(cfg.preset && !preset_given ? *cfg.preset : preset);
    if (!config.empty()) {
        apply_config(cfg.values, p, "--config " + config);
        p.preset = cfg.preset.value_or(p.preset) + " + " + config;
    }
    for (const auto& [row, value] : given) set_param(*row, value, p);
    validate_params(p);
    return p;
}

Params ParamFlags::resolve_over(Params base) const {
    if (preset_given || !config.empty()) return resolve(load_config());
    for (const auto& [row, value] : given) set_param(*row, value, base);
    validate_params(base);
    return base;
}

Params ParamFlags::known_preset(const std::string& name) {
    std::vector<std::string> names;
    for (const auto& pr : presets()) names.push_back(pr.name);
    if (std::find(names.begin(), names.end(), name) == names.end()) {
        std::string known;
        for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
        throw ParameterError("unknown preset '" + name + "'" + did_you_mean(name, names) + "; known presets: " + known);
    }
    return preset_params(name);
}

namespace {

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

}  // namespace

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

}  // namespace cs

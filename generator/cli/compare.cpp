#include "cli/compare.hpp"

#include "render/render.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace cs {
namespace {

std::string quoted(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// A command on PATH (or an absolute path) that exists.
bool on_path(const std::string& command) {
    return std::system(("command -v " + quoted(command) + " >/dev/null 2>&1").c_str()) == 0;
}

// The harness: $CLEVER_SUPPORT_SLICE_PY, else the installed copy of bench/slicers/slice.py
// (data_dir() + "/slicers", found from the binary's own place like the OpenSCAD runner; in the build
// tree a configure-time link to bench/slicers). Never a path compiled in: an installed tool must not
// depend on where it was built.
std::string slice_py() {
    if (const char* e = std::getenv("CLEVER_SUPPORT_SLICE_PY"); e && *e) return e;
    return data_dir() + "/slicers/slice.py";
}

// One slice through slice.py --json; nullopt-like: throws std::runtime_error with its message.
SlicedPrint slice(const std::string& args) {
    const std::string cmd = "python3 " + quoted(slice_py()) + " --json --timeout 600 " + args + " 2>&1";
    FILE* pipe = popen(cmd.c_str(), "r");
    if (!pipe) throw std::runtime_error("cannot start python3");
    std::string out;
    char buf[4096];
    while (size_t n = fread(buf, 1, sizeof buf, pipe)) out.append(buf, n);
    const int status = pclose(pipe);
    const auto brace = out.rfind("\n{");
    const std::string json_text = out.substr(brace == std::string::npos ? 0 : brace + 1);
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(json_text);
    } catch (const std::exception&) {
        throw std::runtime_error("slice.py failed (exit " + std::to_string(WEXITSTATUS(status)) + "): " +
                                 out.substr(out.size() > 300 ? out.size() - 300 : 0));
    }
    return {j.value("grams", 0.0), j.value("print_time_s", 0.0)};
}

}  // namespace

SlicerComparison compare_with_slicer(const std::string& slicer, const std::string& dir, const std::string& name,
                                     const Params& p) {
    SlicerComparison c;
    const bool prusa = slicer == "prusa";
    c.slicer_name = prusa ? "PrusaSlicer" : "CuraEngine";
    c.own_supports = prusa ? "grid" : "normal";
    const char* env = std::getenv(prusa ? "PRUSA_SLICER" : "CURA_ENGINE");
    const std::string bin = env && *env ? env : prusa ? "prusa-slicer" : "CuraEngine";
    if (!on_path(bin)) {
        c.why_not = c.slicer_name + " (" + bin + ") is not installed";
        return c;
    }
    if (!std::filesystem::exists(slice_py())) {
        c.why_not = "the slicing harness " + slice_py() + " is missing (set CLEVER_SUPPORT_SLICE_PY to bench/slicers/slice.py)";
        return c;
    }
    if (!on_path("python3")) {
        c.why_not = "python3 is not installed (bench/slicers/slice.py runs on it)";
        return c;
    }
    // The run's support angle and z gap, spelled in each slicer's keys (bench/slicers/README.md).
    const std::string sets =
        prusa ? fmt::format("--set support_material_threshold={:g} --set support_material_contact_distance={:g} ",
                            90 - p.critical_angle, p.gap)
              : fmt::format("--set support_angle={:g} --set support_z_distance={:g} ", p.critical_angle, p.gap);
    const std::string stem = dir + "/" + name, model = quoted(stem + ".model.stl");
    const std::string head = "--slicer " + slicer + " " + sets;
    try {
        c.bare = slice(head + "--support none " + model);
        c.own = slice(head + "--support " + c.own_supports + " " + model);
        c.ours = prusa ? slice("--slicer prusa --support none " + quoted(stem + ".prusa.3mf"))
                       : slice(head + "--support mesh --support-mesh " + quoted(stem + ".supports.stl") + " " + model);
        c.done = true;
    } catch (const std::exception& e) {
        c.why_not = e.what();
    }
    return c;
}

std::string comparison_line(const SlicerComparison& c) {
    if (!c.done) return "no comparison: " + c.why_not;
    auto added = [&](const SlicedPrint& s) {
        return fmt::format("{:.1f} g, {:.1f} min", s.grams - c.bare.grams, (s.seconds - c.bare.seconds) / 60);
    };
    return fmt::format("your slicer's own supports ({} {}): {}; ours: {} (each over the print without supports: "
                       "{:.1f} g, {:.1f} min; sliced in a temporary folder with bench/slicers/profile.json)",
                       c.slicer_name, c.own_supports, added(c.own), added(c.ours), c.bare.grams, c.bare.seconds / 60);
}

}  // namespace cs

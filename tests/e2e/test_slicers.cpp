// The hand-off to real slicers: what the generator writes for Cura and PrusaSlicer prints the struts
// AS SUPPORT there. Each test skips with a message when its slicer is not installed
// (scripts/install-deps.sh installs both).
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <regex>

#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "mesh/mesh_io.hpp"
#include "output/threemf.hpp"
#include "support.hpp"

namespace cs::test {
namespace {

// Filament length (mm) extruded per ";TYPE:" section, how much of it ran slower than
// `slow_mm_per_min`, and how much of it in the first layer (the lowest z that extrudes). Handles
// absolute (M82) and relative (M83) extrusion.
struct GcodeExtrusion {
    std::map<std::string, double> by_type, slow_by_type, first_layer_by_type;
    double total() const {
        double t = 0;
        for (const auto& [type, mm] : by_type) t += mm;
        return t;
    }
    double of(const std::string& type) const { return by_type.count(type) ? by_type.at(type) : 0; }
    double slow_of(const std::string& type) const { return slow_by_type.count(type) ? slow_by_type.at(type) : 0; }
    double first_layer_of(const std::string& type) const {
        return first_layer_by_type.count(type) ? first_layer_by_type.at(type) : 0;
    }
};

double word(const std::string& line, char w, double otherwise) {
    for (size_t at = line.find(' '); at != std::string::npos; at = line.find(' ', at + 1))
        if (at + 1 < line.size() && line[at + 1] == w) return std::stod(line.substr(at + 2));
    return otherwise;
}

GcodeExtrusion extrusion_by_type(const std::string& path, double slow_mm_per_min) {
    GcodeExtrusion g;
    std::ifstream in(path);
    std::string line, type = "none";
    bool relative = false;
    double e = 0, feed = 0, z = 0, first_z = -1;
    while (std::getline(in, line)) {
        if (line.rfind(";TYPE:", 0) == 0) type = line.substr(6);
        line = line.substr(0, line.find(';'));
        if (line.rfind("M82", 0) == 0) relative = false;
        if (line.rfind("M83", 0) == 0) relative = true;
        if (line.rfind("G92", 0) == 0) e = word(line, 'E', e);
        if (line.rfind("G1 ", 0) != 0 && line.rfind("G0 ", 0) != 0) continue;
        feed = word(line, 'F', feed);
        z = word(line, 'Z', z);
        double ne = word(line, 'E', relative ? 0 : e);
        double de = relative ? ne : ne - e;
        if (!relative) e = ne;
        bool moves = line.find(" X") != std::string::npos || line.find(" Y") != std::string::npos;
        if (de <= 0 || !moves) continue;
        g.by_type[type] += de;
        if (feed <= slow_mm_per_min) g.slow_by_type[type] += de;
        if (first_z < 0) first_z = z;
        if (z == first_z) g.first_layer_by_type[type] += de;
    }
    return g;
}

// A T standing on its stem, its plate overhanging on both sides: the generator's supports under it.
struct Tee {
    TempDir dir;
    std::string stem = dir / "tee";
    Tee() {
        Mesh t = box({-3, -3, 0}, {3, 3, 12});
        append(t, box({-14, -5, 12}, {14, 5, 15}));
        write_stl(dir / "tee.stl", t);
        auto r = run(quote(cli()) + " " + quote(dir / "tee.stl") + " --orient keep -q --out " + quote(dir.path));
        EXPECT_EQ(r.code, 0) << r.out;
    }
};

bool have(const std::string& command) { return run("command -v " + command).code == 0; }

// ---------------------------------------------------------------------------------------------
// PrusaSlicer 2.5: <name>.prusa.3mf, one object whose supports volumes have support-like settings.

struct PrusaSlice {
    bool ok = false;
    GcodeExtrusion extrusion;
    double seconds = 0;
};

double prusa_time_s(const std::string& gcode) {
    std::ifstream in(gcode);
    std::string line, prefix = "; estimated printing time (normal mode) = ";
    double s = -1;
    while (std::getline(in, line))
        if (line.rfind(prefix, 0) == 0) {
            s = 0;
            std::istringstream t(line.substr(prefix.size()));
            double v;
            char unit;
            while (t >> v >> unit) s += v * (unit == 'd' ? 86400 : unit == 'h' ? 3600 : unit == 'm' ? 60 : 1);
        }
    return s;
}

// PrusaSlicer's built-in defaults (an empty private --datadir) except what the test needs to see,
// and `options` (command-line options, e.g. "--perimeter-generator classic").
PrusaSlice prusa_slice(const TempDir& d, const std::string& input, const std::string& tag, const std::string& options = "") {
    std::string gcode = d / (tag + ".gcode");
    auto r = run("prusa-slicer --datadir " + quote(d / "prusa-datadir") + " --loglevel 1 " + options + " --export-gcode -o " +
                 quote(gcode) + " " + quote(input));
    PrusaSlice s;
    EXPECT_EQ(r.code, 0) << tag << ": " << r.out;
    if (r.code != 0) return s;
    s.ok = true;
    // Its default small_perimeter_speed is 15 mm/s: slower than 16 mm/s = the small loops.
    s.extrusion = extrusion_by_type(gcode, 16 * 60);
    s.seconds = prusa_time_s(gcode);
    return s;
}

// bench/slicers/printed_bodies.py on a G-code: the layers of every shell of `bodies` (an STL of
// separate closed solids) and how many of those cross-sections have no extrusion inside them, with
// the object centred at (bed_x, 200) / 2 as PrusaSlicer centres it on its default bed.
nlohmann::json printed_bodies(const std::string& gcode, const std::string& bodies, const std::string& model, double bed_x) {
    auto r = run("python3 " + quote(source_dir() + "/bench/slicers/printed_bodies.py") + " " + quote(gcode) + " " +
                 quote(bodies) + " " + quote(model) + " " + std::to_string(bed_x) + " 200");
    EXPECT_EQ(r.code, 0) << r.out;
    return r.code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json::object();
}

TEST(Slicers, PrusaSlicerPrintsTheSupportsVolumeLikeSupport) {
    if (!have("prusa-slicer")) CS_SKIP_OR_FAIL_IN_CI("prusa-slicer is not installed (scripts/install-deps.sh installs it)");
    Tee tee;
    Mesh model = read_mesh(tee.stem + ".model.stl"), supports = read_mesh(tee.stem + ".supports.stl");
    ASSERT_FALSE(supports.faces.empty());
    // The same 3MF without the per-volume settings: what the settings change.
    {
        std::ofstream f(tee.dir / "plain.3mf", std::ios::binary);
        f << encode_3mf_prusa("tee", {{"tee model", model, {}}, {"tee supports", supports, {}}});
    }
    auto alone = prusa_slice(tee.dir, tee.stem + ".model.stl", "alone");
    auto plain = prusa_slice(tee.dir, tee.dir / "plain.3mf", "plain");
    auto ours = prusa_slice(tee.dir, tee.stem + ".prusa.3mf", "ours");
    ASSERT_TRUE(alone.ok && plain.ok && ours.ok);

    // The supports are printed (not dropped as a separate object or skipped): as perimeters.
    EXPECT_GT(ours.extrusion.of("External perimeter"), alone.extrusion.of("External perimeter") * 1.5);
    // With the settings the supports get one perimeter and no infill above the first layer: inner
    // perimeters and every kind of infill there extrude what the model alone does. Without them the
    // struts add inner perimeters.
    auto infill = [](const GcodeExtrusion& g) {
        return g.of("Internal infill") + g.of("Solid infill") + g.of("Top solid infill") + g.of("Bridge infill");
    };
    auto first_solid = [](const GcodeExtrusion& g) { return g.first_layer_of("Solid infill"); };
    double perimeters_alone = alone.extrusion.of("Perimeter");
    double infill_alone = infill(alone.extrusion) - first_solid(alone.extrusion);
    EXPECT_NEAR(ours.extrusion.of("Perimeter"), perimeters_alone, 0.01 * perimeters_alone);
    EXPECT_NEAR(infill(ours.extrusion) - first_solid(ours.extrusion), infill_alone, 0.01 * infill_alone);
    // The feet meet the bed solid (bottom_solid_layers=1): the first layer gets solid infill beyond
    // the model's own, and nearly as much as with PrusaSlicer's defaults (plain), which fill it too.
    EXPECT_GT(first_solid(ours.extrusion), first_solid(alone.extrusion) + 2);
    EXPECT_GT(first_solid(ours.extrusion), 0.8 * first_solid(plain.extrusion));
    EXPECT_GT(plain.extrusion.of("Perimeter"), perimeters_alone * 1.03);
    // ... and their loops run at the support speed, not the 15 mm/s of small perimeters.
    double slow_alone = alone.extrusion.slow_of("External perimeter");
    EXPECT_NEAR(ours.extrusion.slow_of("External perimeter"), slow_alone, 0.02 * slow_alone + 1);
    EXPECT_GT(plain.extrusion.slow_of("External perimeter"), slow_alone + 20);
    EXPECT_LT(ours.seconds, plain.seconds);

    // No strut vanishes: bench/slicers/printed_bodies.py finds an extrusion inside every body's
    // cross-section on every layer it spans (PrusaSlicer centres the object on its default
    // 200 x 200 mm bed). Placed 1.5 mm off, most cross-sections come out empty: the count is not
    // vacuous.
    if (!have("python3")) CS_SKIP_OR_FAIL_IN_CI("python3 is needed for bench/slicers/printed_bodies.py");
    auto printed = [&](double bed_x, const std::string& tag) {
        return printed_bodies(tee.dir / (tag + ".gcode"), tee.stem + ".supports.stl", tee.stem + ".model.stl", bed_x);
    };
    auto placed = printed(200, "ours"), shifted = printed(203, "ours");
    ASSERT_TRUE(placed.contains("body_layers") && shifted.contains("body_layers"));
    EXPECT_GT(placed["body_layers"].get<int>(), 20);
    EXPECT_EQ(placed["dropped"].get<int>(), 0) << placed.dump();
    EXPECT_GT(shifted["dropped"].get<int>(), placed["body_layers"].get<int>() / 4) << shifted.dump();

    // #32: the same under PrusaSlicer's classic perimeter generator, which many users pick, with
    // thin walls detected (its default) and not (Prusa's own presets). Before the supports came
    // as two volumes, each with its own thin_walls, classic left out the top layers of the tips
    // (0.8 mm squares) with thin walls on, and the N-profile struts' walls with them off.
    for (const char* thin_walls : {"--thin-walls", "--no-thin-walls"}) {
        const std::string tag = std::string("classic") + thin_walls;
        ASSERT_TRUE(prusa_slice(tee.dir, tee.stem + ".prusa.3mf", tag, std::string("--perimeter-generator classic ") + thin_walls).ok);
        auto classic = printed(200, tag);
        ASSERT_TRUE(classic.contains("body_layers")) << thin_walls;
        EXPECT_EQ(classic["body_layers"], placed["body_layers"]) << thin_walls;
        EXPECT_EQ(classic["dropped"].get<int>(), 0) << thin_walls << ": " << classic.dump();
    }
}

// #32 for `clever-support apply`: the supports of an edited .scad reach PrusaSlicer as a run's do,
// as two volumes each with its thin_walls, so the classic perimeter generator prints every body
// layer of them too. (apply wrote one volume with thin walls on before: classic left out the top
// layers of the tips.)
TEST(Slicers, PrusaSlicerPrintsTheSupportsAnApplyWroteUnderClassicToo) {
    if (!have("prusa-slicer")) CS_SKIP_OR_FAIL_IN_CI("prusa-slicer is not installed (scripts/install-deps.sh installs it)");
    if (!have_openscad()) CS_SKIP_OR_FAIL_IN_CI("no OpenSCAD (scripts/install-deps.sh installs it)");
    if (!have("python3")) CS_SKIP_OR_FAIL_IN_CI("python3 is needed for bench/slicers/printed_bodies.py");
    Tee tee;
    // The run's bodies, one shell each, for printed_bodies.py: apply keeps the tree, and a .scad
    // applied without -D renders the same bodies (to the file's 4 decimals).
    const std::string bodies = tee.dir / "bodies.stl";
    std::filesystem::copy_file(tee.stem + ".supports.stl", bodies);
    auto applied = run(quote(cli()) + " apply -q " + quote(tee.stem + ".scad"));
    ASSERT_EQ(applied.code, 0) << applied.out;
    for (const char* thin_walls : {"--thin-walls", "--no-thin-walls"}) {
        const std::string tag = std::string("applied-classic") + thin_walls;
        ASSERT_TRUE(prusa_slice(tee.dir, tee.stem + ".prusa.3mf", tag, std::string("--perimeter-generator classic ") + thin_walls).ok);
        auto classic = printed_bodies(tee.dir / (tag + ".gcode"), bodies, tee.stem + ".model.stl", 200);
        ASSERT_TRUE(classic.contains("body_layers")) << thin_walls;
        EXPECT_GT(classic["body_layers"].get<int>(), 20) << thin_walls;
        EXPECT_EQ(classic["dropped"].get<int>(), 0) << thin_walls << ": " << classic.dump();
    }
}

// #32 on a real part: the wheel example at 80 mm (kept pose, as bench/prusa_classic.py runs it),
// sliced under classic with 0.2 mm layers (bench/slicers/profile.json's). Its walls' rows end in
// 0.5 mm pieces where the ceiling rises to a rim; two of them stood alone above their neighbours on
// a layer, which classic printed nothing of (2 of 3687 body layers left out, on the code before
// 2026-11-28; none under Arachne). Their tops now come down to where the row prints
// (ceilings.hpp, printable_tops).
TEST(Slicers, PrusaSlicerClassicPrintsEveryLayerOfTheWheelsWalls) {
    if (!have("prusa-slicer")) CS_SKIP_OR_FAIL_IN_CI("prusa-slicer is not installed (scripts/install-deps.sh installs it)");
    if (!have("python3")) CS_SKIP_OR_FAIL_IN_CI("python3 is needed for bench/slicers/printed_bodies.py");
    TempDir dir;
    auto r = run(quote(cli()) + " " + quote(source_dir() + "/examples/models/wheel.stl") + " --fit 80 --orient keep -q --out " +
                 quote(dir.path));
    ASSERT_EQ(r.code, 0) << r.out;
    const std::string stem = dir / "wheel";
    ASSERT_TRUE(prusa_slice(dir, stem + ".prusa.3mf", "classic", "--perimeter-generator classic --layer-height 0.2 --first-layer-height 0.2").ok);
    auto classic = printed_bodies(dir / "classic.gcode", stem + ".supports.stl", stem + ".model.stl", 200);
    ASSERT_TRUE(classic.contains("body_layers"));
    EXPECT_GT(classic["body_layers"].get<int>(), 3000);
    EXPECT_EQ(classic["dropped"].get<int>(), 0) << classic.dump();
}

// ---------------------------------------------------------------------------------------------
// Cura 4.13: what the generator writes for Cura (<name>.3mf and the .curaprofile files), read by
// Cura's own code and sliced as a user's Cura slices it on the printers people own. Cura's code,
// definitions, qualities and materials come from Debian's packages, unpacked by
// scripts/install-deps.sh (bench/slicers/fetch_cura_defs.sh); the tests only look for them.

const std::string kPython = "/usr/bin/python3";  // Debian's, where python3-savitar is

std::string bench(const std::string& script) { return kPython + " " + quote(source_dir() + "/bench/slicers/" + script); }

bool have_cura_413() { return run(quote(source_dir() + "/bench/slicers/fetch_cura_defs.sh") + " --no-fetch").code == 0; }

// The generator's Cura files for the tee; `plain.3mf` is the same group without the supports'
// minimum_support_area (what the printer's definition then deletes), `alone.3mf` the model only.
struct CuraTee : Tee {
    Mesh model = read_mesh(stem + ".model.stl"), supports = read_mesh(stem + ".supports.stl");
    CuraTee() {
        Settings plain_settings = cura_support_mesh_settings();
        std::erase_if(plain_settings, [](const auto& kv) { return kv.first == "minimum_support_area"; });
        write("plain.3mf", encode_3mf_cura("tee", {{"tee model", model, {}}, {"tee supports", supports, plain_settings}}));
        write("alone.3mf", encode_3mf_cura("tee", {{"tee model", model, {}}}));
        write("as_model.3mf", encode_3mf_cura("tee", {{"tee model", model, {}}, {"tee supports", supports, {}}}));
    }
    void write(const std::string& name, const std::string& bytes) const {
        std::ofstream(dir / name, std::ios::binary) << bytes;
    }
};

// Slices a Cura 3MF with a profile on a Cura printer (bench/slicers/slice.py --printer).
GcodeExtrusion cura_slice(const TempDir& d, const std::string& tag, const std::string& threemf,
                          const std::string& printer, const std::string& profile) {
    auto r = run(bench("slice.py") + " --slicer cura --support mesh --printer " + printer + " --cura-profile " +
                 quote(profile) + " --out-dir " + quote(d / tag) + " " + quote(threemf));
    EXPECT_EQ(r.code, 0) << tag << ": " << r.out;
    return extrusion_by_type(d / tag + "/out.gcode", 0);
}

// Skips outside CI when a tool is missing; in CI (CI=true) scripts/install-deps.sh installed it, so
// a missing one fails instead (issue #29: a green CI means the suite ran).
#define CURA_TOOLS_OR_SKIP()                                                                              \
    do {                                                                                                 \
        std::string missing = !have("CuraEngine")           ? "CuraEngine"                               \
                              : !have(kPython)              ? kPython                                    \
                              : !have_cura_413()            ? "Cura 4.13 (definitions and code)"         \
                              : run(kPython + " -c 'import Savitar'").code != 0 ? "python3-savitar" : ""; \
        if (missing.empty()) break;                                                                      \
        CS_SKIP_OR_FAIL_IN_CI(missing << " is missing (scripts/install-deps.sh installs it)");          \
    } while (0)

// Cura's own code reads the 3MF (python3-savitar) and judges each profile on an Ender 3, a Prusa
// i3 MK3 and an Ultimaker S5 with their default nozzle and material, as its import does
// (bench/slicers/cura_check.py).
TEST(Slicers, CurasOwnCodeImportsAProfileOnEachPrinterAtOurLayerHeight) {
    CURA_TOOLS_OR_SKIP();
    Tee tee;
    std::string generic = tee.dir / "clever_support.curaprofile", creality = tee.dir / "clever_support_creality.curaprofile";
    // Its JSON to a file: Uranium's imports warn on stderr.
    auto r = run("(" + bench("cura_check.py") + " --3mf " + quote(tee.stem + ".3mf") + " --profile " + quote(generic) +
                 " --profile " + quote(creality) + " --printer creality_ender3 --printer prusa_i3_mk3 --printer ultimaker_s5" +
                 " > " + quote(tee.dir / "check.json") + ")");
    ASSERT_EQ(r.code, 0) << r.out;
    auto check = nlohmann::json::parse(std::ifstream(tee.dir / "check.json"));

    // Savitar reads one group of two objects; the supports carry their three settings.
    const auto& scene = check.at("3mf");
    ASSERT_EQ(scene.size(), 1u);
    ASSERT_EQ(scene[0].at("children").size(), 2u);
    EXPECT_TRUE(scene[0].at("children")[0].at("settings").empty());
    EXPECT_EQ(scene[0].at("children")[1].at("settings"),
              (nlohmann::json{{"support_mesh", "True"}, {"support_mesh_drop_down", "False"}, {"minimum_support_area", "0"}}));

    std::map<std::string, std::string> profile_for = {{"creality_ender3", "clever_support_creality.curaprofile"},
                                                      {"prusa_i3_mk3", "clever_support.curaprofile"},
                                                      {"ultimaker_s5", "clever_support.curaprofile"}};
    for (const auto& printer : check.at("printers")) {
        const std::string name = printer.at("printer");
        SCOPED_TRACE(name);
        // Cura's 3MF reader keeps all three per-object settings on this printer.
        EXPECT_EQ(printer.at("3mf_settings_kept").size(), 3u) << printer.dump();
        EXPECT_TRUE(printer.at("3mf_settings_dropped").empty());
        // The printer's profile imports, visible, named after its file, and choosing it leaves the
        // printer at our 0.2 mm layers: the quality a newly added printer of this kind starts on,
        // or Cura's 0.2 mm quality where that one is finer.
        const auto& ours = printer.at("profiles").at(profile_for.at(name));
        EXPECT_EQ(ours.at("import"), "ok") << ours.dump();
        EXPECT_EQ(ours.at("name_in_cura"), profile_for.at(name).substr(0, profile_for.at(name).find('.')));
        EXPECT_NEAR(ours.at("layer_height").get<double>(), Params{}.layer_height, 1e-9) << ours.dump();
        EXPECT_NEAR(ours.at("quality_layer_height").get<double>(), Params{}.layer_height, 1e-9) << ours.dump();
        for (const auto& [file, profile] : printer.at("profiles").items())
            EXPECT_TRUE(profile.at("unknown_keys").empty()) << file << ": " << profile.dump();
    }
    // Where the other family's profile lands: Creality's qualities are not the generic ones, so each
    // profile is for its own printers (Cura rejects or hides it elsewhere, as it did "normal").
    const auto& ender = check.at("printers")[0];
    EXPECT_EQ(ender.at("profiles").at("clever_support_creality.curaprofile").at("quality_type"), ender.at("preferred_quality_type"));
    EXPECT_NE(ender.at("profiles").at("clever_support.curaprofile").at("import"), "ok");
    EXPECT_EQ(ender.at("minimum_support_area"), "=2");  // why the 3MF sets it per object
    EXPECT_EQ(check.at("printers")[1].at("profiles").at("clever_support_creality.curaprofile").at("import"), "error");
}

// CuraEngine slices the generated 3MF and Creality profile on an Ender 3 (its definition, its
// Standard quality, the profile above them, the objects' own settings): the struts print as
// support, the model as it does alone, and no strut or tip is lost on any layer although the
// Ender 3 deletes support areas under 2 mm2 (without the 3MF's per-object 0 it drops a third).
TEST(Slicers, CuraEnginePrintsOurThreeMfOnAnEnder3WithoutLosingATip) {
    CURA_TOOLS_OR_SKIP();
    CuraTee tee;
    const std::string profile = tee.dir / "clever_support_creality.curaprofile";
    auto ours = cura_slice(tee.dir, "ours", tee.stem + ".3mf", "creality_ender3", profile);
    auto alone = cura_slice(tee.dir, "alone", tee.dir / "alone.3mf", "creality_ender3", profile);
    auto as_model = cura_slice(tee.dir, "as_model", tee.dir / "as_model.3mf", "creality_ender3", profile);
    cura_slice(tee.dir, "plain", tee.dir / "plain.3mf", "creality_ender3", profile);
    ASSERT_GT(alone.total(), 0);
    // Sliced as geometry, nothing is support; as a support mesh, the struts are support sections
    // and the model prints exactly as it does alone (the brim, SKIRT, goes round both).
    auto body = [](const GcodeExtrusion& g) { return g.total() - g.of("SUPPORT") - g.of("SKIRT"); };
    EXPECT_EQ(as_model.of("SUPPORT"), 0);
    EXPECT_GT(body(as_model), body(alone) * 1.02);
    EXPECT_GT(ours.of("SUPPORT"), 0.02 * alone.total());
    EXPECT_NEAR(body(ours), body(alone), 0.01 * body(alone));

    // bench/slicers/printed_bodies.py finds an extrusion inside every body's cross-section on every
    // layer it spans (slice.py centres the group on the Ender 3's 235 x 235 mm bed). Placed 1.5 mm
    // off, most cross-sections come out empty: the count is not vacuous.
    auto printed = [&](const std::string& tag, double bed_x) {
        auto r = run(bench("printed_bodies.py") + " " + quote(tee.dir / tag + "/out.gcode") + " " +
                     quote(tee.stem + ".supports.stl") + " " + quote(tee.stem + ".model.stl") + " " +
                     std::to_string(bed_x) + " 235");
        EXPECT_EQ(r.code, 0) << r.out;
        return r.code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json::object();
    };
    auto placed = printed("ours", 235), shifted = printed("ours", 238), plain = printed("plain", 235);
    ASSERT_TRUE(placed.contains("body_layers") && shifted.contains("body_layers") && plain.contains("body_layers"));
    EXPECT_GT(placed["body_layers"].get<int>(), 20);
    EXPECT_EQ(placed["dropped"].get<int>(), 0) << placed.dump();
    EXPECT_GT(shifted["dropped"].get<int>(), placed["body_layers"].get<int>() / 4) << shifted.dump();
    EXPECT_GT(plain["dropped"].get<int>(), placed["body_layers"].get<int>() / 10) << plain.dump();
}

// ---------------------------------------------------------------------------------------------
// --compare (issue 31): the summary's measured line, from a real slice of each kind.

TEST(Slicers, CompareSlicesTheSlicersOwnSupportsAndOurs) {
    for (const std::string slicer : {"prusa", "cura"}) {
        if (!have(slicer == "prusa" ? "prusa-slicer" : "CuraEngine")) {
            std::cout << "[ SKIPPED  ] --compare " << slicer << ": the slicer is not installed\n";
            continue;
        }
        TempDir d;
        Mesh t = box({-3, -3, 0}, {3, 3, 12});
        append(t, box({-14, -5, 12}, {14, 5, 15}));
        write_stl(d / "tee.stl", t);
        auto r = run(quote(cli()) + " " + quote(d / "tee.stl") + " --orient keep --compare " + slicer + " --out " +
                     quote(d / "out"));
        ASSERT_EQ(r.code, 0) << r.out;
        std::smatch m;
        ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(your slicer's own supports \((PrusaSlicer grid|CuraEngine normal)\): ([0-9.-]+) g, ([0-9.-]+) min; ours: ([0-9.-]+) g, ([0-9.-]+) min)")))
            << r.out;
        // Both add material and time to the print without supports.
        for (int i = 2; i <= 5; ++i) EXPECT_GT(std::stod(m[i]), 0) << slicer << ": " << m[0];
    }
}

}  // namespace
}  // namespace cs::test

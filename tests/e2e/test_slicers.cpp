// The hand-off to real slicers: what the generator writes for Cura and PrusaSlicer prints the struts
// AS SUPPORT there. Each test skips with a message when its slicer is not installed
// (scripts/install-deps.sh installs both).
#include <gtest/gtest.h>

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
// PrusaSlicer 2.5: <name>.prusa.3mf, one object whose supports volume has support-like settings.

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

// PrusaSlicer's built-in defaults (an empty private --datadir) except what the test needs to see.
PrusaSlice prusa_slice(const TempDir& d, const std::string& input, const std::string& tag) {
    std::string gcode = d / (tag + ".gcode");
    auto r = run("prusa-slicer --datadir " + quote(d / "prusa-datadir") + " --loglevel 1 --export-gcode -o " +
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
    auto printed = [&](double bed_x) {
        auto r = run("python3 " + quote(source_dir() + "/bench/slicers/printed_bodies.py") + " " +
                     quote(tee.dir / "ours.gcode") + " " + quote(tee.stem + ".supports.stl") + " " +
                     quote(tee.stem + ".model.stl") + " " + std::to_string(bed_x) + " 200");
        EXPECT_EQ(r.code, 0) << r.out;
        return r.code == 0 ? nlohmann::json::parse(r.out) : nlohmann::json::object();
    };
    auto placed = printed(200), shifted = printed(203);
    ASSERT_TRUE(placed.contains("body_layers") && shifted.contains("body_layers"));
    EXPECT_GT(placed["body_layers"].get<int>(), 20);
    EXPECT_EQ(placed["dropped"].get<int>(), 0) << placed.dump();
    EXPECT_GT(shifted["dropped"].get<int>(), placed["body_layers"].get<int>() / 4) << shifted.dump();
}

// ---------------------------------------------------------------------------------------------
// CuraEngine 4.13: model + supports, the supports as a support mesh (per-mesh support_mesh=true,
// support_mesh_drop_down=false), what Cura's GUI does with <name>.3mf. The engine's CLI cannot read
// 3MF, and it needs Cura's machine definitions, which bench/slicers fetches and resolves.

std::string cura_defs_dir() {
    auto r = run(quote(source_dir() + "/bench/slicers/fetch_cura_defs.sh"));
    if (r.code != 0) return "";
    std::string out = r.out;
    while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
    return out.substr(out.rfind('\n') == std::string::npos ? 0 : out.rfind('\n') + 1);
}

GcodeExtrusion cura_slice(const TempDir& d, const std::string& tag, const std::string& support,
                          const std::string& inputs) {
    std::string out = d / tag;
    auto r = run("python3 " + quote(source_dir() + "/bench/slicers/slice.py") + " --slicer cura --support " + support +
                 " --out-dir " + quote(out) + " " + inputs);
    EXPECT_EQ(r.code, 0) << tag << ": " << r.out;
    return extrusion_by_type(out + "/out.gcode", 0);
}

TEST(Slicers, CuraEnginePrintsTheSupportMeshAsSupport) {
    if (!have("CuraEngine")) CS_SKIP_OR_FAIL_IN_CI("CuraEngine is not installed (scripts/install-deps.sh installs it)");
    if (!have("python3")) CS_SKIP_OR_FAIL_IN_CI("python3 is needed for bench/slicers/slice.py");
    if (cura_defs_dir().empty()) CS_SKIP_OR_FAIL_IN_CI("Cura's machine definitions are not available (bench/slicers/fetch_cura_defs.sh)");
    Tee tee;
    std::string model = quote(tee.stem + ".model.stl"), supports = quote(tee.stem + ".supports.stl");
    auto alone = cura_slice(tee.dir, "alone", "none", model);
    auto as_model = cura_slice(tee.dir, "as_model", "none", quote(tee.stem + ".supported.stl"));
    auto as_support = cura_slice(tee.dir, "as_support", "mesh", "--support-mesh " + supports + " " + model);
    ASSERT_GT(alone.total(), 0);
    // Sliced as geometry, nothing is support; as a support mesh, the struts are support sections
    // and the model prints exactly as it does alone.
    EXPECT_EQ(as_model.of("SUPPORT"), 0);
    EXPECT_GT(as_model.total(), alone.total() * 1.02);
    EXPECT_GT(as_support.of("SUPPORT"), 0.02 * alone.total());
    EXPECT_NEAR(as_support.total() - as_support.of("SUPPORT"), alone.total(), 0.01 * alone.total());
}

}  // namespace
}  // namespace cs::test

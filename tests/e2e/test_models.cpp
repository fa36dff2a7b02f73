// End to end: the CLI on the shared benchmark meshes (skipped where ../shared/models is absent)
// and on the bundled examples, judged by the independent `check` and the report.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>

#include "check/check.hpp"
#include "core/params.hpp"
#include "mesh/mesh_io.hpp"
#include "support.hpp"

namespace cs::test {
namespace {

struct Model {
    std::string file;
    double scale;
};

double benchmark_scale(const std::string& file) {
    std::ifstream in(shared_models() + "/benchmark.json");
    auto j = nlohmann::json::parse(in);
    for (const auto& m : j["models"])
        if (m["file"] == file) return m["scale"].get<double>();
    return 1.0;
}

std::string slurp(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

struct Generated {
    std::string dir, name;
    nlohmann::json report;
    CheckResult check;
};

Generated generate(const std::string& input, double scale, const std::string& out, const std::string& extra = "",
                   const std::string& orient = "keep") {
    Generated g;
    g.dir = out;
    g.name = std::filesystem::path(input).stem().string();
    auto r = run(quote(cli()) + " " + quote(input) + " --orient " + orient + " --scale " + std::to_string(scale) + " --out " +
                 quote(out) + " -q " + extra);
    EXPECT_EQ(r.code, 0) << r.out;
    g.report = nlohmann::json::parse(slurp(out + "/" + g.name + ".report.json"));
    Mesh model = read_mesh(out + "/" + g.name + ".model.stl");
    Mesh supports = read_mesh(out + "/" + g.name + ".supports.stl", true);
    Params p;
    g.check = check_supports(model, supports, p, {});
    return g;
}

// What the strict check still finds in today's supports, per model (issue 15). Each count is a
// ceiling, measured: the generator may only get better (lower it when it does); everything else
// the judge asks must hold outright. Since no strut or tip is built nearer the model than the z
// gap (a leaf that finds no such way down is given up, and counted in the dropped samples), no
// model has a fused or penetrating solid. (The bird's chosen pose had 4 points 0.08 mm beyond
// reach, where no tip's square fitted under a slope running diagonally to it; such a tip may now
// drop as far as the square's corner needs, tree/placement.cpp place_tip_top.) (nefertiti's 3 points behind the headdress were a scanner's folded sliver, a
// hanging keel no tip fits under; repair now unfolds it, mesh/unfold_caps.hpp.) With
// --buildplate-only a dead end sends its leaves down again, merging only among themselves, then
// one by one, so the dropped branches counted there are single leaves that found no way to the
// bed (menger: 50 of 2021 samples; 56 before the hybrid took rows across flat crowns, 2026-12-06).
struct KnownShortfall {
    std::size_t fused = 0, penetrating = 0, dropped_samples = 0, dropped_branches = 0, uncovered = 0;
};

KnownShortfall known_shortfall(const std::string& file, bool buildplate_only) {
    static const std::map<std::string, std::pair<KnownShortfall, KnownShortfall>> known = {
        // file: {default: fused, penetrating, dropped samples, dropped branches, uncovered points},
        //       {the same with --buildplate-only (coverage not asked)}
        {"bridge.stl", {{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}}},
        {"u_overhang.stl", {{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}}},
        {"extruder_idler.stl", {{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}}},
        {"spot.stl", {{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}}},
        {"fandisk.stl", {{0, 0, 1, 0, 0}, {0, 0, 1, 0, 0}}},
        {"rocker_arm.stl", {{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}}},
        {"menger_sponge3.stl", {{0, 0, 0, 0, 0}, {0, 0, 50, 50, 0}}},
        {"armadillo.stl", {{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}}},
        {"beast.stl", {{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}}},
        {"stanford_bunny.stl", {{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}}},
        {"nefertiti.stl", {{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}}},
        {"igea.stl", {{0, 0, 0, 0, 0}, {0, 0, 0, 0, 0}}},
        {"example:tree", {{0, 0, 1, 0, 0}, {}}},
        {"auto:tree", {{0, 0, 1, 0, 0}, {}}},
        {"example:molecule", {{0, 0, 0, 0, 0}, {}}},
        {"auto:molecule", {{0, 0, 0, 0, 0}, {}}},
        {"example:arches", {{0, 0, 0, 0, 0}, {}}},
        {"auto:arches", {{0, 0, 0, 0, 0}, {}}},
        {"example:wheel", {{0, 0, 0, 0, 0}, {}}},
        {"auto:wheel", {{0, 0, 0, 0, 0}, {}}},
        {"example:bird", {{0, 0, 2, 0, 0}, {}}},
        {"auto:bird", {{0, 0, 3, 2, 0}, {}}},
        // bench/validation: parts the generator is never tuned on (issue 32).
        {"validation:bearing_block", {{0, 0, 0, 0, 0}, {}}},
        {"validation:cable_clip", {{0, 0, 0, 0, 0}, {}}},
        {"validation:enclosure_lid", {{0, 0, 0, 0, 0}, {}}},
        {"validation:ledges_low_roof", {{0, 0, 0, 0, 0}, {}}},
        {"validation:pipe_tee", {{0, 0, 0, 0, 0}, {}}},
        {"validation:propeller", {{0, 0, 0, 0, 0}, {}}},
        {"validation:shelf_bracket", {{0, 0, 0, 0, 0}, {}}},
        {"validation:shelter_roof", {{0, 0, 0, 0, 0}, {}}},
        {"validation:wall_rack", {{0, 0, 0, 0, 0}, {}}},
        // fan (added 2026-12-06): 4 samples the tree drops (as before the tails), their
        // overhang held by others: check passes with full coverage.
        {"validation:fan", {{0, 0, 4, 0, 0}, {}}},
        {"validation:delta_wing", {{0, 0, 0, 0, 0}, {}}},
        {"validation:wedge_ledge", {{0, 0, 0, 0, 0}, {}}}
    };
    auto it = known.find(file);
    if (it == known.end()) return {};
    return buildplate_only ? it->second.second : it->second.first;
}

// The ratchet: a ceiling above what the run measures is slack, and a later regression could hide
// in it. Margin: none. The outputs are deterministic (byte-identical run to run and for any
// thread count: the Determinism tests), so a count measured once is the count; when a change
// lowers one, the ceiling comes down with it and the improvement is locked in.
constexpr std::size_t kRatchetMargin = 0;

KnownShortfall measured_shortfall(const CheckResult& c, const nlohmann::json& report) {
    KnownShortfall m;
    m.fused = c.fused_contacts;
    m.penetrating = c.penetrating_bodies;
    m.dropped_samples = report["supports"]["dropped_samples"].get<std::size_t>();
    m.dropped_branches = report["supports"]["dropped_branches"].get<std::size_t>();
    m.uncovered = c.overhang_points - c.covered - c.exempt;
    return m;
}

// Fails naming the one number to lower (and to what) for each ceiling of `key` that the run
// came in under. Coverage is not asked with --buildplate-only, so its ceiling is not either.
void expect_no_slack(const std::string& key, bool buildplate_only, const KnownShortfall& measured) {
    const KnownShortfall ceiling = known_shortfall(key, buildplate_only);
    const std::pair<const char*, std::pair<std::size_t, std::size_t>> numbers[] = {
        {"fused", {ceiling.fused, measured.fused}},
        {"penetrating", {ceiling.penetrating, measured.penetrating}},
        {"dropped samples", {ceiling.dropped_samples, measured.dropped_samples}},
        {"dropped branches", {ceiling.dropped_branches, measured.dropped_branches}},
        {"uncovered points", {buildplate_only ? 0 : ceiling.uncovered, buildplate_only ? 0 : measured.uncovered}}};
    for (const auto& [what, cm] : numbers)
        EXPECT_LE(cm.first, cm.second + kRatchetMargin)
            << "ratchet: tests/e2e/test_models.cpp, known_shortfall(\"" << key << "\"), "
            << (buildplate_only ? "--buildplate-only" : "default") << " row: the ceiling for " << what << " is "
            << cm.first << " but this run measured " << cm.second << ". The generator got better here: lower that "
            << "number to " << cm.second << " so the improvement is locked in.";
}

// Everything but coverage (not every overhang can reach the bed with --buildplate-only) holds
// outright; air gap and penetration within the known shortfall; something is built.
void expect_sound(const Generated& g, const KnownShortfall& k, const std::string& file) {
    const CheckResult& c = g.check;
    EXPECT_GT(c.bodies, 0u) << file << ": nothing was built";
    EXPECT_GT(c.contacts, 0u) << file << ": no solid touches the model from below";
    EXPECT_EQ(c.ungrounded_bodies, 0u) << c.summary();
    EXPECT_EQ(c.buried_bottoms, 0u) << c.summary();
    EXPECT_EQ(c.open_bodies + c.inward_bodies, 0u) << c.summary();
    EXPECT_EQ(c.steep_bodies, 0u) << c.summary();
    EXPECT_EQ(c.weak_bodies, 0u) << c.summary();
    EXPECT_LE(c.fused_contacts, k.fused) << file << ": more fused contacts than known\n" << c.summary();
    EXPECT_LE(c.penetrating_bodies, k.penetrating) << file << ": more penetrating solids than known\n" << c.summary();
    const auto& s = g.report["supports"];
    EXPECT_EQ(s["strength_violations"].get<std::size_t>(), 0u) << file;
    EXPECT_LE(s["dropped_samples"].get<std::size_t>(), k.dropped_samples) << file << ": " << s.dump();
    EXPECT_LE(s["dropped_branches"].get<std::size_t>(), k.dropped_branches) << file << ": " << s.dump();
}

class SharedModel : public ::testing::TestWithParam<std::string> {};

TEST_P(SharedModel, StrictCheckPassesWithFullCoverageAndTreeBeatsColumns) {
    if (!have_shared_models()) CS_SKIP_OR_FAIL_IN_CI("../shared/models is absent");
    TempDir tmp;
    const std::string file = GetParam();
    auto g = generate(shared_models() + "/" + file, benchmark_scale(file), tmp.path);
    const KnownShortfall k = known_shortfall(file, false);
    const auto& c = g.check;
    EXPECT_LE(c.overhang_points - c.covered - c.exempt, k.uncovered) << file << ": more uncovered points than known\n"
                                                                     << c.summary();
    if (k.uncovered == 0) EXPECT_LE(c.largest_gap, c.reach) << c.summary();
    EXPECT_GT(c.overhang_points, 0u);
    expect_sound(g, k, file);
    if (k.fused == 0 && k.penetrating == 0 && k.uncovered == 0) EXPECT_TRUE(c.ok()) << c.summary();
    expect_no_slack(file, false, measured_shortfall(c, g.report));
    // What is printed: the slabs' bridges are hollow in both slicers' files (ceilings/slabs.hpp).
    double tree = g.report["supports"]["support_volume_mm3"].get<double>() - g.report["supports"]["bridges_volume_mm3"].get<double>(),
           columns = g.report["columns_baseline"]["support_volume_mm3"];
    EXPECT_GT(tree, 0);
    EXPECT_LT(tree, columns) << "tree support should use less material than plain columns";
}

TEST_P(SharedModel, BuildplateOnlyPutsNoContactOnTheModel) {
    if (!have_shared_models()) CS_SKIP_OR_FAIL_IN_CI("../shared/models is absent");
    TempDir tmp;
    const std::string file = GetParam();
    auto g = generate(shared_models() + "/" + file, benchmark_scale(file), tmp.path, "--buildplate-only");
    EXPECT_EQ(g.report["supports"]["model_contacts"], 0) << g.report["supports"].dump();
    EXPECT_EQ(g.report["supports"]["ceiling_walls_on_model"], 0) << g.report["supports"].dump();
    // On the bed: trunks, or walls under a ceiling low over it (bridge: walls only).
    EXPECT_GT(g.report["supports"]["bed_contacts"].get<std::size_t>() + g.report["supports"]["ceiling_walls"].get<std::size_t>(), 0u)
        << g.report["supports"].dump();
    // Coverage is not asked: an overhang enclosed by the model (the U's ceiling) cannot reach the
    // bed at all. Everything that is built must still be sound.
    expect_sound(g, known_shortfall(file, true), file);
    expect_no_slack(file, true, measured_shortfall(g.check, g.report));
}

INSTANTIATE_TEST_SUITE_P(Benchmark, SharedModel,
                         ::testing::Values("bridge.stl", "u_overhang.stl", "extruder_idler.stl", "spot.stl",
                                           "fandisk.stl", "rocker_arm.stl", "menger_sponge3.stl", "armadillo.stl",
                                           "beast.stl", "stanford_bunny.stl", "nefertiti.stl", "igea.stl"),
                         [](const auto& info) { return std::filesystem::path(info.param).stem().string(); });

TEST(Determinism, SameInputSameBytes) {
    std::string input = have_shared_models() ? shared_models() + "/spot.stl" : source_dir() + "/examples/models/tree.stl";
    double scale = have_shared_models() ? benchmark_scale("spot.stl") : 1.0;
    TempDir a, b;
    auto ga = generate(input, scale, a.path);
    auto gb = generate(input, scale, b.path);
    for (const auto& f : std::filesystem::directory_iterator(a.path)) {
        std::string name = f.path().filename().string();
        if (name.ends_with(".report.json")) continue;  // holds timings
        EXPECT_EQ(slurp(a / name), slurp(b / name)) << name << " differs between two runs";
    }
    auto ra = ga.report, rb = gb.report;
    ra.erase("seconds"), rb.erase("seconds"), ra.erase("seconds_total"), rb.erase("seconds_total");
    EXPECT_EQ(ra.dump(), rb.dump());
}

// The whole CLI with the orientation search on: one worker thread or all, same bytes.
TEST(Determinism, AnyThreadCountSameBytes) {
    const std::string input = source_dir() + "/examples/models/bird.stl";
    TempDir one, all;
    for (auto [dir, threads] : {std::pair{&one, "1"}, std::pair{&all, "0"}}) {
        auto r = run(quote(cli()) + " " + quote(input) + " --orient auto --no-timings -q --threads " + threads +
                     " --out " + quote(dir->path));
        ASSERT_EQ(r.code, 0) << r.out;
    }
    size_t files = 0;
    for (const auto& f : std::filesystem::directory_iterator(one.path)) {
        std::string name = f.path().filename().string();
        EXPECT_EQ(slurp(one / name), slurp(all / name)) << name << " differs between 1 thread and all";
        ++files;
    }
    EXPECT_GE(files, 5u);
}

class Example : public ::testing::TestWithParam<std::string> {};

TEST_P(Example, ChecksPass) {
    TempDir tmp;
    auto g = generate(source_dir() + "/examples/models/" + GetParam() + ".stl", 1.0, tmp.path);
    const KnownShortfall k = known_shortfall("example:" + GetParam(), false);
    EXPECT_LE(g.check.overhang_points - g.check.covered - g.check.exempt, k.uncovered) << g.check.summary();
    expect_sound(g, k, GetParam());
    expect_no_slack("example:" + GetParam(), false, measured_shortfall(g.check, g.report));
    EXPECT_LT(g.report["supports"]["support_volume_mm3"].get<double>(),
              g.report["columns_baseline"]["support_volume_mm3"].get<double>());
}

INSTANTIATE_TEST_SUITE_P(Bundled, Example, ::testing::Values("tree", "molecule", "arches", "wheel", "bird"));

// A user's size, not the bundled one (issue 32: unseen models and scales). At 120 mm a leaf under
// the bird's wing and one under a molecule's ball found no way down in the sweep and were lost,
// leaving 0.28 and 0.21 mm2 beyond reach; the samples beside a lost leaf now get leaves of their own.
class ExampleAt120 : public ::testing::TestWithParam<std::string> {};

TEST_P(ExampleAt120, CoverageIsFull) {
    TempDir tmp;
    auto g = generate(source_dir() + "/examples/models/" + GetParam() + ".stl", 1.0, tmp.path, "--fit 120");
    EXPECT_TRUE(g.check.coverage_ok()) << g.check.summary();
    EXPECT_EQ(g.check.overhang_points - g.check.covered - g.check.exempt, 0u) << g.check.summary();
    EXPECT_TRUE(g.check.ok()) << g.check.summary();
}

INSTANTIATE_TEST_SUITE_P(Bundled, ExampleAt120, ::testing::Values("bird", "molecule"));

// The validation set (bench/validation: OpenSCAD parts with their STLs, issue 32), as the bench
// runs it (default preset, orientation kept): `check` passes on every part, coverage included.
class ValidationPart : public ::testing::TestWithParam<std::string> {};

TEST_P(ValidationPart, ChecksPass) {
    TempDir tmp;
    auto g = generate(source_dir() + "/bench/validation/" + GetParam() + ".stl", 1.0, tmp.path);
    const std::string key = "validation:" + GetParam();
    const KnownShortfall k = known_shortfall(key, false);
    EXPECT_LE(g.check.overhang_points - g.check.covered - g.check.exempt, k.uncovered) << g.check.summary();
    EXPECT_TRUE(g.check.ok() || k.uncovered + k.fused + k.penetrating > 0) << g.check.summary();
    expect_sound(g, k, GetParam());
    expect_no_slack(key, false, measured_shortfall(g.check, g.report));
}

INSTANTIATE_TEST_SUITE_P(Bench, ValidationPart,
                         ::testing::Values("bearing_block", "cable_clip", "enclosure_lid", "ledges_low_roof", "pipe_tee",
                                           "propeller", "shelf_bracket", "shelter_roof", "wall_rack", "fan", "delta_wing",
                                           "wedge_ledge"));

// The validation parts in the pose a user gets by default (--orient auto): every check passes
// there too. wall_rack's auto pose lost the keyholes' rim leaves, their only landing a shelf top
// 0.1 deg steeper than a tip stands on by choice (GrowTree.ALeafWhoseOnlyLandingIs...): 22
// points beyond reach. enclosure_lid is left out: its pose search alone takes 30 s.
class ValidationPartAuto : public ::testing::TestWithParam<std::string> {};

TEST_P(ValidationPartAuto, ChecksPassInTheChosenPose) {
    TempDir tmp;
    auto g = generate(source_dir() + "/bench/validation/" + GetParam() + ".stl", 1.0, tmp.path, "", "auto");
    EXPECT_TRUE(g.check.ok()) << g.check.summary();
}

INSTANTIATE_TEST_SUITE_P(Bench, ValidationPartAuto,
                         ::testing::Values("bearing_block", "cable_clip", "ledges_low_roof", "pipe_tee", "propeller",
                                           "shelf_bracket", "shelter_roof", "wall_rack", "fan", "delta_wing", "wedge_ledge"));

// The validation parts at sizes no bench uses (issue 32: a user's size), where `check` failed on
// the generator's own output:
// - bearing_block at 60 mm (either pose): a rim sample where the block's outer wall rises from
//   the counterbore's crown, the wall's lowest corner a hair (1e-4 mm) below the rim; the tree's
//   ray down started inside that wall's plane and met it at once: "resting", no tip, and the
//   top-up counted the sample as holding its neighbours (3 points, gap 1.85 mm);
// - wall_rack at 60 mm (auto): the top-up's sample on a knife edge took no tip, as its neighbour
//   had not (2.06 mm);
// - wall_rack at 120 mm (auto): a hook's ridge 20 mm over a 45.1 degree slope; each leaf, gone
//   down alone, followed its bends into a pocket and was lost there, though it could stand on the
//   slope right under it (36 points, gap 11.6 mm);
// - propeller at 120 mm (auto): the same on a blade's edge (9 points, gap 2.03 mm).
// Not here: propeller at 80 mm (auto) still fails by `check`'s sampling: a blade edge point 1.89 mm
// from check's nearest point resting on material, 1.76 mm from the nearest resting point of the
// overhang (the generator's finer demand): held as check holds it (a sample there costs the same
// edge at the bundled size a strut of its own, +2.4 min in Cura). Left to the lead (robust3.md).
struct Sized {
    std::string part;
    int fit;
    std::string pose;
};
void PrintTo(const Sized& s, std::ostream* os) { *os << s.part << " at " << s.fit << " mm, " << s.pose; }

class ValidationPartAtAnotherSize : public ::testing::TestWithParam<Sized> {};

TEST_P(ValidationPartAtAnotherSize, ChecksPass) {
    TempDir tmp;
    const Sized& s = GetParam();
    auto g = generate(source_dir() + "/bench/validation/" + s.part + ".stl", 1.0, tmp.path,
                      "--fit " + std::to_string(s.fit), s.pose);
    EXPECT_TRUE(g.check.ok()) << g.check.summary();
}

INSTANTIATE_TEST_SUITE_P(Bench, ValidationPartAtAnotherSize,
                         ::testing::Values(Sized{"bearing_block", 60, "keep"}, Sized{"bearing_block", 60, "auto"},
                                           Sized{"wall_rack", 60, "auto"}, Sized{"wall_rack", 120, "auto"},
                                           Sized{"propeller", 120, "auto"}),
                         [](const auto& info) {
                             return info.param.part + "_" + std::to_string(info.param.fit) + "_" + info.param.pose;
                         });

// Sizes and presets the bench never uses, in the pose the orientation search picks, where `check`
// failed on the generator's own output (docs/experiments/check-sweep.md):
// - molecule at 1.5x: a zero-area face along a stick, classed an overhang by its rounded normal,
//   made an inside corner whose anchors held the overhang beside it (0.21 mm2 beyond reach);
// - wedge_ledge at 0.8x under ender3-pla, shelter_roof at 1.3x under prusa-mk4-petg: the pose put
//   a 45 degree face at exactly the preset's critical angle, printable, which the judge read from
//   the float32 model.stl a hair past it (33 and 200 mm2);
// - molecule under prusa-mk4-petg: an inside corner beside a face that rises from the edge, which
//   carries nothing (0.16 mm2);
// - bearing_block at 0.6x: its flange's lowest line exactly 2 gaps + 1 layer (0.6 mm) over the bed,
//   which the generator let rest there and the judge, reading 0.6000000238 from the float32 file,
//   did not (1.04 mm2).
struct PresetRun {
    std::string input;  // under the source tree
    double scale;
    std::string preset;
};
void PrintTo(const PresetRun& r, std::ostream* os) { *os << r.input << " at " << r.scale << "x, " << r.preset; }

class AtAnotherSizeAndPreset : public ::testing::TestWithParam<PresetRun> {};

TEST_P(AtAnotherSizeAndPreset, CheckPassesInTheChosenPose) {
    TempDir tmp;
    const PresetRun& s = GetParam();
    auto g = run(quote(cli()) + " " + quote(source_dir() + "/" + s.input) + " --scale " + std::to_string(s.scale) +
                 " --preset " + s.preset + " --out " + quote(tmp.path) + " -q");
    ASSERT_EQ(g.code, 0) << g.out;
    auto c = run(quote(cli()) + " check " + quote(tmp.path));  // judged with the run's own settings
    EXPECT_EQ(c.code, 0) << c.out;
}

INSTANTIATE_TEST_SUITE_P(Bench, AtAnotherSizeAndPreset,
                         ::testing::Values(PresetRun{"examples/models/molecule.stl", 1.5, "generic-0.4"},
                                           PresetRun{"bench/validation/wedge_ledge.stl", 0.8, "ender3-pla"},
                                           PresetRun{"bench/validation/shelter_roof.stl", 1.3, "prusa-mk4-petg"},
                                           PresetRun{"examples/models/molecule.stl", 1.0, "prusa-mk4-petg"},
                                           PresetRun{"bench/validation/bearing_block.stl", 0.6, "generic-0.4"}),
                         [](const auto& info) {
                             std::string name = std::filesystem::path(info.param.input).stem().string() + "_" +
                                                std::to_string(static_cast<int>(info.param.scale * 10)) + "_" + info.param.preset;
                             for (char& ch : name)
                                 if (!std::isalnum(static_cast<unsigned char>(ch))) ch = '_';
                             return name;
                         });

// A benchmark model at another size, in its default pose: extruder_idler at 80 mm. A ridge's tip
// found no top straight under it (a corner in the model) and took the first that fitted, half a
// millimetre aside, where the model over all of its top is 0.66 mm higher than the ridge: no
// contact for check (3 ridge points beyond reach) though a top a little lower, on the diagonal,
// holds it (placement: tops away from the overhang are the last resort).
TEST(SharedModelAt80, ExtruderIdlerInItsAutoPoseHoldsItsRidges) {
    if (!have_shared_models()) CS_SKIP_OR_FAIL_IN_CI("../shared/models is absent");
    TempDir tmp;
    auto g = generate(shared_models() + "/extruder_idler.stl", 1.0, tmp.path, "--fit 80", "auto");
    EXPECT_TRUE(g.check.ok()) << g.check.summary();
}

// beast at the benchmark's size in its default pose: the bottom edge of a fold in the scan, whose
// upper end takes no tip (its square dips into the fold wherever it goes) and whose lower end
// does. The sample given up held its neighbours by itself, so the coverage top-up added none
// there: 3 ridge points beyond reach (gap 14.2 mm).
TEST(SharedModelAuto, BeastHoldsTheBottomEdgeOfAFold) {
    if (!have_shared_models()) CS_SKIP_OR_FAIL_IN_CI("../shared/models is absent");
    TempDir tmp;
    auto g = generate(shared_models() + "/beast.stl", benchmark_scale("beast.stl"), tmp.path, "", "auto");
    EXPECT_TRUE(g.check.ok()) << g.check.summary();
}

// The default run turns each example to its least-support pose; there too every check passes
// (the wheel's auto pose once put a strut's foot 0.29 mm into a ridge of the rim).
class ExampleAuto : public ::testing::TestWithParam<std::string> {};

TEST_P(ExampleAuto, ChecksPassInTheChosenPose) {
    TempDir tmp;
    const std::string name = GetParam();
    auto r = run(quote(cli()) + " " + quote(source_dir() + "/examples/models/" + name + ".stl") + " --out " +
                 quote(tmp.path) + " -q");
    ASSERT_EQ(r.code, 0) << r.out;
    Mesh model = read_mesh(tmp / (name + ".model.stl"));
    Mesh supports = read_mesh(tmp / (name + ".supports.stl"), true);
    Params p;
    CheckResult c = check_supports(model, supports, p, {});
    const KnownShortfall k = known_shortfall("auto:" + name, false);
    std::ifstream report_file(tmp / (name + ".report.json"));
    expect_no_slack("auto:" + name, false, measured_shortfall(c, nlohmann::json::parse(report_file)));
    EXPECT_LE(c.overhang_points - c.covered - c.exempt, k.uncovered) << c.summary();
    EXPECT_EQ(c.ungrounded_bodies + c.buried_bottoms + c.open_bodies + c.inward_bodies + c.steep_bodies + c.weak_bodies, 0u) << c.summary();
    EXPECT_LE(c.fused_contacts, k.fused) << c.summary();
    EXPECT_LE(c.penetrating_bodies, k.penetrating) << c.summary();
    // The chosen pose either needs support, and then it is there, or needs none at all.
    if (c.overhang_points == c.exempt) EXPECT_EQ(c.bodies, 0u) << name << ": supports built for a pose that needs none";
    else EXPECT_GT(c.contacts, 0u) << c.summary();
}

INSTANTIATE_TEST_SUITE_P(Bundled, ExampleAuto, ::testing::Values("tree", "molecule", "arches", "wheel", "bird"));

}  // namespace
}  // namespace cs::test

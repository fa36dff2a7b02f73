// End to end: the CLI on the shared benchmark meshes (skipped where ../shared/models is absent)
// and on the bundled examples, judged by the independent `check` and the report.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "check/check.hpp"
#include "core/params.hpp"
#include "mesh/mesh_io.hpp"
#include "mesh/repair.hpp"
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

Generated generate(const std::string& input, double scale, const std::string& out, const std::string& extra = "") {
    Generated g;
    g.dir = out;
    g.name = std::filesystem::path(input).stem().string();
    auto r = run(quote(cli()) + " " + quote(input) + " --orient keep --scale " + std::to_string(scale) + " --out " +
                 quote(out) + " -q " + extra);
    EXPECT_EQ(r.code, 0) << r.out;
    g.report = nlohmann::json::parse(slurp(out + "/" + g.name + ".report.json"));
    RepairReport rr;
    Mesh model = read_mesh(out + "/" + g.name + ".model.stl");
    Mesh supports = read_mesh(out + "/" + g.name + ".supports.stl", true);
    Params p;
    g.check = check_supports(model, supports, p, {});
    return g;
}

class SharedModel : public ::testing::TestWithParam<std::string> {};

TEST_P(SharedModel, ChecksPassWithFullCoverageAndTreeBeatsColumns) {
    if (!have_shared_models()) GTEST_SKIP() << "../shared/models is absent";
    TempDir tmp;
    const std::string file = GetParam();
    auto g = generate(shared_models() + "/" + file, benchmark_scale(file), tmp.path);
    EXPECT_TRUE(g.check.ok()) << g.check.summary();
    EXPECT_TRUE(g.check.coverage_ok()) << g.check.summary();
    EXPECT_GT(g.check.overhang_points, 0u);
    double tree = g.report["supports"]["support_volume_mm3"], columns = g.report["columns_baseline"]["support_volume_mm3"];
    EXPECT_GT(tree, 0);
    EXPECT_LT(tree, columns) << "tree support should use less material than plain columns";
}

TEST_P(SharedModel, BuildplateOnlyPutsNoContactOnTheModel) {
    if (!have_shared_models()) GTEST_SKIP() << "../shared/models is absent";
    TempDir tmp;
    const std::string file = GetParam();
    auto g = generate(shared_models() + "/" + file, benchmark_scale(file), tmp.path, "--buildplate-only");
    EXPECT_EQ(g.report["supports"]["model_contacts"], 0) << g.report["supports"].dump();
    // Coverage is not asked: an overhang enclosed by the model (the U's ceiling) cannot reach the
    // bed at all. Everything that is built must still be sound.
    EXPECT_EQ(g.check.penetrating_bodies, 0u) << g.check.summary();
    EXPECT_EQ(g.check.ungrounded_bodies, 0u) << g.check.summary();
    EXPECT_EQ(g.check.open_bodies + g.check.inward_bodies, 0u) << g.check.summary();
    EXPECT_EQ(g.check.steep_bodies, 0u) << g.check.summary();
}

INSTANTIATE_TEST_SUITE_P(Benchmark, SharedModel,
                         ::testing::Values("bridge.stl", "u_overhang.stl", "extruder_idler.stl", "spot.stl",
                                           "armadillo.stl"),
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
    EXPECT_TRUE(g.check.ok()) << g.check.summary();
    EXPECT_LT(g.report["supports"]["support_volume_mm3"].get<double>(),
              g.report["columns_baseline"]["support_volume_mm3"].get<double>());
}

INSTANTIATE_TEST_SUITE_P(Bundled, Example, ::testing::Values("tree", "molecule", "arches", "wheel", "bird"));

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
    EXPECT_TRUE(c.ok()) << c.summary();
}

INSTANTIATE_TEST_SUITE_P(Bundled, ExampleAuto, ::testing::Values("tree", "molecule", "arches", "wheel", "bird"));

}  // namespace
}  // namespace cs::test

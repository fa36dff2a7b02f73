// A user's own preset in a JSON config file: preset, then config, then flags.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "mesh/mesh_io.hpp"
#include "support.hpp"

namespace cs::test {
namespace {

nlohmann::json run_with(const TempDir& d, const std::string& config_json, const std::string& flags, int& code) {
    Mesh t = box({-3, -3, 0}, {3, 3, 10});
    append(t, box({-12, -4, 10}, {12, 4, 13}));
    write_stl(d / "tee.stl", t);
    std::ofstream(d / "my.json") << config_json;
    auto r = run(quote(cli()) + " " + quote(d / "tee.stl") + " --orient keep --json --out " + quote(d / "out") +
                 " --config " + quote(d / "my.json") + " " + flags);
    code = r.code;
    if (r.code != 0) return nlohmann::json{{"error", r.out}};
    std::ifstream in(d / "out/tee.report.json");
    return nlohmann::json::parse(in);
}

TEST(Config, FileOverridesThePresetAndFlagsOverrideTheFile) {
    TempDir d;
    int code = 0;
    auto r = run_with(d, R"({"preset": "prusa-mk4-pla", "sampling": 2.5, "feet": false, "gap": 0.3})", "--gap 0.25", code);
    ASSERT_EQ(code, 0) << r.dump();
    const auto& p = r["parameters"];
    EXPECT_EQ(p["critical_angle_deg"], 55.0);  // from the preset named in the file
    EXPECT_EQ(p["sampling_distance_mm"], 2.5);  // from the file
    EXPECT_EQ(p["feet"], false);
    EXPECT_EQ(p["gap_mm"], 0.25);               // the flag wins
}

TEST(Config, UnknownKeyIsAUsageErrorNamingIt) {
    TempDir d;
    int code = 0;
    auto r = run_with(d, R"({"samplin": 2})", "", code);
    EXPECT_EQ(code, 2);
    EXPECT_NE(r["error"].get<std::string>().find("samplin"), std::string::npos);
}

TEST(Config, WrongTypeAndBrokenJsonAreUsageErrors) {
    TempDir d;
    int code = 0;
    run_with(d, R"({"sampling": "fine"})", "", code);
    EXPECT_EQ(code, 2);
    run_with(d, R"({"sampling": 2)", "", code);
    EXPECT_EQ(code, 2);
}

TEST(Config, PresetsListSaysWhereValuesComeFrom) {
    auto r = run(quote(cli()) + " presets");
    EXPECT_EQ(r.code, 0);
    for (const char* name : {"generic-0.4", "replicator2-pla", "prusa-mk4-pla", "prusa-mk4-petg", "ender3-pla"})
        EXPECT_NE(r.out.find(name), std::string::npos) << name;
    EXPECT_NE(r.out.find("sources:"), std::string::npos);
}

}  // namespace
}  // namespace cs::test

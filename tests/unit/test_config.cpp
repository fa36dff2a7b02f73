// A user's own preset in a JSON config file: preset, then config, then flags.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "core/param_table.hpp"
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

// The JSON types a key accepts: a number, a yes/no, a string (preset, description, strategy), or
// a list of number lists (block, support-point).
enum class Want { number, boolean, text, lists };

std::vector<std::pair<std::string, Want>> every_config_key() {
    std::vector<std::pair<std::string, Want>> keys = {
        {"preset", Want::text}, {"description", Want::text}, {"block", Want::lists}, {"support-blocker", Want::lists},
        {"support-point", Want::lists}};
    for (const ParamRow& row : param_table()) {
        Want w = std::holds_alternative<double Params::*>(row.member)     ? Want::number
                 : std::holds_alternative<Strategy Params::*>(row.member) ? Want::text
                                                                          : Want::boolean;
        keys.emplace_back(std::string(config_key(row)), w);
    }
    return keys;
}

// Every key given a value of every other JSON type ({"preset": 5}, {"sampling": "fine"},
// {"block": {}} ...) is a parameter error naming the key (exit 2), never an internal error.
TEST(Config, EveryWrongTypedValueIsAParameterErrorNamingTheKey) {
    TempDir d;
    // One value of each JSON type; each key's own type's value is left out. None is a list of
    // number lists of the right length.
    const std::vector<std::pair<std::string, Want>> values = {
        {"5", Want::number},   {"\"x\"", Want::text}, {"true", Want::boolean},  {"{}", Want::lists},
        {"null", Want::lists}, {"[[1, 2]]", Want::lists}, {"[5]", Want::lists}};
    int runs = 0;
    for (const auto& [key, want] : every_config_key())
        for (const auto& [value, type] : values) {
            if (type == want && want != Want::lists) continue;
            std::ofstream(d / "bad.json") << "{\"" << key << "\": " << value << "}";
            auto r = run(quote(cli()) + " " + quote(d / "none.stl") + " --config " + quote(d / "bad.json"));
            ++runs;
            EXPECT_EQ(r.code, 2) << key << ": " << value << " -> " << r.out;
            EXPECT_NE(r.out.find("\"" + key + "\""), std::string::npos) << key << ": " << value << " -> " << r.out;
            EXPECT_EQ(r.out.find("internal error"), std::string::npos) << key << ": " << value << " -> " << r.out;
        }
    EXPECT_GT(runs, 100);
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

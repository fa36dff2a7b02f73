// The parameter table (core/param_table.hpp) pinned row by row: every parameter has a flag in
// --help, a --config key, a report key and a .scad variable, and validate_params enforces its range
// with a message naming the flag. A row added to the table is checked here without a new test.
#include <gtest/gtest.h>

#include <cmath>
#include <fmt/format.h>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>

#include "core/errors.hpp"
#include "core/param_table.hpp"
#include "mesh/mesh_io.hpp"
#include "output/scad.hpp"
#include "support.hpp"

namespace cs::test {
namespace {

bool contains(const std::string& hay, const std::string& needle) { return hay.find(needle) != std::string::npos; }

// A value unlike the generic preset's, inside every range: numbers 10% larger, yes/no flipped,
// the other strategy.
ParamValue changed(const ParamRow& row) {
    ParamValue v = get_param(row, Params{});
    if (auto* d = std::get_if<double>(&v)) return *d * 1.1;
    if (auto* b = std::get_if<bool>(&v)) return !*b;
    return std::string(std::get<std::string>(v) == "tree" ? "columns" : "tree");
}

std::string as_scad(const ParamValue& v) {
    if (auto* d = std::get_if<double>(&v)) return scad_number(*d);
    if (auto* b = std::get_if<bool>(&v)) return *b ? "true" : "false";
    return scad_string(std::get<std::string>(v));
}

nlohmann::json as_json(const ParamValue& v) {
    return std::visit([](const auto& x) { return nlohmann::json(x); }, v);
}

// Runs the CLI on a small T (overhangs on both sides) and returns its report; `args` sets values.
nlohmann::json report_of(const TempDir& d, const std::string& args) {
    Mesh t = box({-3, -3, 0}, {3, 3, 10});
    append(t, box({-12, -4, 10}, {12, 4, 13}));
    write_stl(d / "tee.stl", t);
    auto r = run(quote(cli()) + " " + quote(d / "tee.stl") + " --orient keep -q --out " + quote(d / "out") + " " + args);
    EXPECT_EQ(r.code, 0) << r.out;
    std::ifstream in(d / "out/tee.report.json");
    return r.code == 0 ? nlohmann::json::parse(in) : nlohmann::json::object();
}


// Every row's report key holds the changed value, and its .scad variable is assigned it.
void expect_changed_everywhere(const TempDir& d, const nlohmann::json& report) {
    const std::string scad = read_text(d / "out/tee.scad");
    for (const auto& row : param_table()) {
        SCOPED_TRACE(row.flag);
        ASSERT_TRUE(report["parameters"].contains(row.report_key)) << row.report_key;
        EXPECT_EQ(report["parameters"][row.report_key], as_json(changed(row)));
        EXPECT_TRUE(contains(scad, "\n" + std::string(row.scad.name) + " = " + as_scad(changed(row)) + ";"))
            << row.scad.name << " is not assigned its value in the .scad";
    }
}

TEST(ParamTable, NamesAreUniqueInEveryLayer) {
    std::set<std::string> flags, reports, scads;
    for (const auto& row : param_table()) {
        EXPECT_EQ(std::string(row.flag).rfind("--", 0), 0u) << row.flag;
        EXPECT_TRUE(flags.insert(row.flag).second) << row.flag;
        EXPECT_TRUE(reports.insert(row.report_key).second) << row.report_key;
        EXPECT_TRUE(scads.insert(row.scad.name).second) << row.scad.name;
        EXPECT_EQ(find_param(config_key(row)), &row);
        EXPECT_FALSE(std::string(row.help).empty()) << row.flag;
    }
}

TEST(ParamTable, EveryRowHasAFlagInHelp) {
    for (const std::string command : {"", "check "}) {
        auto r = run(quote(cli()) + " " + command + "--help");
        ASSERT_EQ(r.code, 0) << r.out;
        for (const auto& row : param_table())
            EXPECT_TRUE(contains(r.out, "  " + std::string(row.flag) + " ")) << command << "--help lacks " << row.flag;
    }
}

TEST(ParamTable, EveryFlagSetsItsParameter) {
    TempDir d;
    std::string args;
    for (const auto& row : param_table()) {
        ParamValue v = changed(row);
        if (std::holds_alternative<Negated>(row.member)) args += std::string(" ") + row.flag;  // a bare flag
        else if (auto* x = std::get_if<double>(&v)) args += fmt::format(" {} {}", row.flag, *x);
        else if (auto* b = std::get_if<bool>(&v)) args += fmt::format(" {} {}", row.flag, *b ? "true" : "false");
        else args += fmt::format(" {} {}", row.flag, std::get<std::string>(v));
    }
    expect_changed_everywhere(d, report_of(d, args));
}

TEST(ParamTable, EveryConfigKeySetsItsParameter) {
    TempDir d;
    nlohmann::json config = nlohmann::json::object();
    for (const auto& row : param_table()) config[std::string(config_key(row))] = as_json(changed(row));
    std::ofstream(d / "my.json") << config.dump();
    expect_changed_everywhere(d, report_of(d, "--config " + quote(d / "my.json")));
}

TEST(ParamTable, ConfigValuesOfTheWrongTypeNameTheKey) {
    for (const auto& row : param_table()) {
        SCOPED_TRACE(row.flag);
        Params p;
        nlohmann::json wrong = {{std::string(config_key(row)), std::holds_alternative<double Params::*>(row.member)
                                                                   ? nlohmann::json("text")
                                                                   : nlohmann::json(1.5)}};
        try {
            apply_config(wrong, p, "--config my.json");
            ADD_FAILURE() << "accepted " << wrong.dump();
        } catch (const ParameterError& e) {
            EXPECT_TRUE(contains(e.what(), "--config my.json: \"" + std::string(config_key(row)) + "\" must be")) << e.what();
        }
    }
    Params p;
    EXPECT_THROW(apply_config({{"samplin", 2}}, p, "--config my.json"), ParameterError);
}

// A value just past `bound`, on the side the range excludes.
double just_outside(double bound, bool open, double direction) {
    return open ? bound : std::nextafter(bound, direction * INFINITY);
}

void expect_rejected(const ParamRow& row, double value, const Params& base) {
    SCOPED_TRACE(fmt::format("{} = {}", row.flag, value));
    Params p = base;
    p.*std::get<double Params::*>(row.member) = value;
    for (auto [naming, name] : {std::pair{ParamNaming::flag, row.flag}, std::pair{ParamNaming::scad, row.scad.name}}) {
        try {
            validate_params(p, naming);
            ADD_FAILURE() << "accepted";
        } catch (const ParameterError& e) {
            EXPECT_EQ(std::string(e.what()).rfind(std::string(name) + " = ", 0), 0u) << e.what();
            EXPECT_TRUE(contains(e.what(), "out of range")) << e.what();
        }
    }
}

TEST(ParamTable, ValidateEnforcesEveryRangeNamingTheFlag) {
    Params generic;
    EXPECT_NO_THROW(validate_params(generic));
    for (const auto& row : param_table()) {
        if (!std::holds_alternative<double Params::*>(row.member)) continue;  // yes/no and strategy: no range
        const ParamRange& r = row.range;
        EXPECT_TRUE(std::isfinite(r.min) || r.at_least) << row.flag << " has no lower bound";
        if (std::isfinite(r.min)) expect_rejected(row, just_outside(r.min, r.min_open, -1), generic);
        if (std::isfinite(r.max)) expect_rejected(row, just_outside(r.max, false, +1), generic);
        if (r.at_least) expect_rejected(row, std::nextafter(generic.*r.at_least, -INFINITY), generic);
        expect_rejected(row, NAN, generic);
    }
}

TEST(ParamTable, EveryFlagIsInTheReadmeParameterTable) {
    const std::string readme = read_text(source_dir() + "/README.md");
    const auto from = readme.find("### Parameters"), to = readme.find("**Adding a parameter.**");
    ASSERT_TRUE(from != std::string::npos && to != std::string::npos && from < to) << "README's Parameters section moved";
    const std::string section = readme.substr(from, to - from);
    for (const auto& row : param_table())
        EXPECT_TRUE(contains(section, "`" + std::string(row.flag) + "`")) << row.flag << " is not in README's Parameters table";
}

TEST(ParamTable, NegatedRowIsTheBuildplateOnlySwitch) {
    const ParamRow* row = find_param("buildplate-only");
    ASSERT_NE(row, nullptr);
    Params p;
    set_param(*row, true, p);
    EXPECT_FALSE(p.supports_on_model);
    EXPECT_EQ(std::get<bool>(get_param(*row, p)), true);
    EXPECT_THROW(set_param(*find_param("strategy"), std::string("bush"), p), ParameterError);
}

}  // namespace
}  // namespace cs::test

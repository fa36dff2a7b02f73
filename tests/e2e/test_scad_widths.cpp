// The strut widths of the C++ struts stage and of the OpenSCAD template are two implementations
// of the same rules (core/rules.hpp, scad_templates/clever_support.scad): per strut, on the tree
// a generated .scad carries, they must agree. The template's widths come out through echo().
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/rules.hpp"
#include "edit/scad_values.hpp"
#include "struts/struts.hpp"
#include "support.hpp"

namespace cs::test {
namespace {



// The tree as the .scad holds it: nodes, struts, and which nodes are leaves (the template tells
// bends from leaves by cs_leaves; the struts stage by the node kind).
SupportTree tree_of(const ScadValues& v) {
    SupportTree t;
    for (const auto& n : v.at("cs_nodes").value) t.nodes.push_back({{n[0], n[1], n[2]}, NodeKind::Merge});
    for (const auto& s : v.at("cs_struts").value) t.struts.push_back({s[0].get<int>(), s[1].get<int>()});
    for (const auto& l : v.at("cs_leaves").value) t.nodes[l[0].get<int>()].kind = NodeKind::Leaf;
    return t;
}

// [[upper, lower], ...] from the template, evaluated by OpenSCAD on the generated data.
std::vector<std::array<double, 2>> template_widths(const std::string& dir, const std::string& scad) {
    std::string text = read_text(scad);
    text = text.substr(0, text.find("include <clever_support.scad>"));
    const std::string driver = dir + "/widths.scad";
    std::ofstream(driver) << text << "include <clever_support.scad>\n"
                          << "echo(cs_widths = cs_derive(cs_tree_record, omit_struts, k, d_min, d_max, strength_length)[4]);\n";
    auto r = run("openscad -o " + quote(dir + "/widths.echo") + " " + quote(driver));
    EXPECT_EQ(r.code, 0) << r.out;
    std::string echo = read_text(dir + "/widths.echo");
    // The list from "cs_widths = [" to the end of its line. Plain string search: std::regex
    // recurses once per character and overflows the stack on a long list under ASan.
    const std::string key = "cs_widths = ";
    const auto at = echo.find(key);
    EXPECT_NE(at, std::string::npos) << echo;
    std::vector<std::array<double, 2>> out;
    if (at == std::string::npos) return out;
    const auto from = at + key.size(), end = echo.find_first_of("\r\n", from);
    std::string list = echo.substr(from, end == std::string::npos ? std::string::npos : end - from);
    while (!list.empty() && list.back() != ']') list.pop_back();  // an echo line may end in a quote
    for (const auto& w : nlohmann::json::parse(list)) out.push_back({w[0], w[1]});
    return out;
}

void expect_same_widths(const std::string& model, const std::string& extra) {
    if (!have_native_openscad()) CS_SKIP_OR_FAIL_IN_CI("no OpenSCAD");
    TempDir dir;
    auto r = run(quote(cli()) + " " + quote(model) + " --orient keep -q --out " + quote(dir.path) + " " + extra);
    ASSERT_EQ(r.code, 0) << r.out;
    const std::string name = std::filesystem::path(model).stem().string();
    const std::string scad = dir / (name + ".scad");
    const ScadValues v = parse_scad_values(read_text(scad), scad);
    Params p;
    p.k = v.at("k").value;
    p.d_min = v.at("d_min").value;
    p.d_max = v.at("d_max").value;
    p.strength_length = v.at("strength_length").value;
    const SizedTree sized = size_struts(tree_of(v), p);
    const auto widths = template_widths(dir.path, scad);
    ASSERT_EQ(widths.size(), sized.struts.size());
    ASSERT_GT(widths.size(), 0u);
    for (size_t e = 0; e < widths.size(); ++e) {
        // Both size the same decimal data; echo() prints six significant digits (widths < 10 mm).
        EXPECT_NEAR(widths[e][0], sized.struts[e].top_width, 2e-5) << "strut " << e << " upper width";
        EXPECT_NEAR(widths[e][1], sized.struts[e].bottom_width, 2e-5) << "strut " << e << " lower width";
    }
}

// The narrowest N-profile strut: the template's cs_min_n_width and the struts stage's rule
// (core/rules.hpp min_n_width) for walls a Customizer may set.
TEST(ScadWidths, NarrowestNProfileIsTheStrutsStages) {
    if (!have_native_openscad()) GTEST_SKIP() << "no OpenSCAD";
    TempDir dir;
    const std::vector<double> walls = {0.4, 0.5, 0.8, 1.2};
    const std::string driver = dir / "min_n.scad";
    {
        std::ofstream out(driver);
        out << "include <" << source_dir() << "/scad_templates/clever_support.scad>\n"
            << "echo(cs_min_n = [";
        for (size_t i = 0; i < walls.size(); ++i) out << (i ? ", " : "") << "cs_min_n_width(" << walls[i] << ")";
        out << "]);\n";
    }
    auto r = run("openscad -o " + quote(dir / "min_n.echo") + " " + quote(driver));
    ASSERT_EQ(r.code, 0) << r.out;
    const std::string echo = read_text(dir / "min_n.echo"), key = "cs_min_n = ";
    const auto at = echo.find(key);
    ASSERT_NE(at, std::string::npos) << echo;
    std::string list = echo.substr(at + key.size(), echo.find_first_of("\r\n", at) - at - key.size());
    while (!list.empty() && list.back() != ']') list.pop_back();
    const auto got = nlohmann::json::parse(list);
    ASSERT_EQ(got.size(), walls.size()) << echo;
    for (size_t i = 0; i < walls.size(); ++i) {
        Params p;
        p.wall_thickness = walls[i];
        EXPECT_NEAR(got[i].get<double>(), min_n_width(p), 1e-9) << "wall " << walls[i];
    }
}

TEST(ScadWidths, TemplateSizesEveryStrutAsTheStrutsStage) {
    expect_same_widths(source_dir() + "/examples/models/arches.stl", "");
}

TEST(ScadWidths, AgreeWithStifferStrutsAndSteeperEqn1) {
    // A larger k and a shorter safe length make Eqn 1 and the strength rule decide more struts.
    expect_same_widths(source_dir() + "/examples/models/tree.stl", "--k 0.004 --strength-length 12");
}

}  // namespace
}  // namespace cs::test

// The command line's helpers for mistakes (cli/suggest.hpp, cli/defines.hpp): which word a slip
// meant, and what is wrong with a -D define.
#include <gtest/gtest.h>

#include "cli/defines.hpp"
#include "cli/suggest.hpp"
#include "core/errors.hpp"
#include "core/params.hpp"

using namespace cs;

TEST(Suggest, EditDistanceCountsSwapsAsOne) {
    EXPECT_EQ(edit_distance("check", "check"), 0);
    EXPECT_EQ(edit_distance("chek", "check"), 1);
    EXPECT_EQ(edit_distance("chcek", "check"), 1);  // two letters swapped
    EXPECT_EQ(edit_distance("Check", "check"), 0);
    EXPECT_EQ(edit_distance("", "abc"), 3);
}

TEST(Suggest, NearestWordForASlip) {
    const std::vector<std::string> subcommands = {"regrow", "check", "render", "apply", "presets"};
    EXPECT_EQ(closest_word("chek", subcommands), "check");
    EXPECT_EQ(closest_word("rendr", subcommands), "render");
    EXPECT_EQ(closest_word("zebra", subcommands), "");  // not a slip of any of them
    EXPECT_EQ(did_you_mean("chek", subcommands), " (did you mean `check`?)");
    EXPECT_EQ(did_you_mean("zebra", subcommands), "");
}

TEST(Suggest, AFlagThatStartsAsOneDoes) {
    const std::vector<std::string> flags = {"--scale", "--sampling", "--support-point", "--strategy"};
    EXPECT_EQ(closest_word("--sampel", flags), "--sampling");  // four edits, but it starts as --sampling
    EXPECT_EQ(closest_word("--samplng", flags), "--sampling");
    EXPECT_EQ(closest_word("--zoom", flags), "");
    EXPECT_EQ(closest_word("--s", flags), "");  // too short to tell
}

TEST(Defines, ASyntaxErrorNamesTheDefine) {
    EXPECT_NO_THROW(check_define("hole_d=14"));
    EXPECT_NO_THROW(check_define("pts=[[1, 2], [3, 4]]"));
    EXPECT_NO_THROW(check_define("label=\"a]b\""));
    auto message = [](const std::string& d) {
        try {
            check_define(d);
        } catch (const ParameterError& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_EQ(message("hole_d="), "-D hole_d=: no value after '='; give one, e.g. -D hole_d=14");
    EXPECT_NE(message("hole_d").find("-D hole_d: expected name=value"), std::string::npos);
    EXPECT_NE(message("3d=1").find("'3d' is not an OpenSCAD variable name"), std::string::npos);
    EXPECT_NE(message("pts=[1, 2").find("-D pts=[1, 2: its [ is not closed"), std::string::npos);
    EXPECT_NE(message("s=\"abc").find("string is not closed"), std::string::npos);
}

TEST(Defines, TopLevelNamesOnly) {
    const std::string text = "// width = 3;\nhole_d = 3.4; /* depth = 2; */\nwidth=30;\n"
                             "module ear(r) { inner = 2; cube(r); }\nx == 1;\n$fn = 48;\nlabel = \"a = b\";\n";
    EXPECT_EQ(scad_variable_names(text), (std::vector<std::string>{"hole_d", "width", "$fn", "label"}));
}

TEST(Defines, ScadParametersByTheirScadNames) {
    Params p;
    set_scad_params({"sampling=2", "buildplate_only=true", "k=0.003"}, p, false);
    EXPECT_EQ(p.sampling_distance, 2);
    EXPECT_FALSE(p.supports_on_model);
    EXPECT_EQ(p.k, 0.003);
    EXPECT_THROW(set_scad_params({"samplin=2"}, p, false), ParameterError);
    EXPECT_NO_THROW(set_scad_params({"show_model=false"}, p, true));  // left to OpenSCAD
    EXPECT_THROW(set_scad_params({"sampling=-1"}, p, false), ParameterError);  // out of range
    try {
        set_scad_params({"samplin=2"}, p, false);
    } catch (const ParameterError& e) {
        EXPECT_NE(std::string(e.what()).find("did you mean `sampling`"), std::string::npos) << e.what();
    }
}

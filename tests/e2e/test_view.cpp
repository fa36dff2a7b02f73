// `clever-support view` without a browser: the edits the page sends land in the .scad's lists and
// read back as regrow reads them (a bad one fails with regrow's message and line), the tree is
// re-sized by Customizer values without a regrow, and the server's guard (token, Host). The page
// itself, in Chromium: tests/browser/view_test.mjs (ctest ViewInBrowser).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/errors.hpp"
#include "edit/scad_values.hpp"
#include "support.hpp"
#include "view/view_cli.hpp"
#include "view/view_edit.hpp"
#include "view/view_server.hpp"
#include "view/view_state.hpp"

using namespace cs;
using namespace cs::test;

namespace {

std::string read_all(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// examples/models/arches.stl supported into a scratch folder (about a second).
struct Arches {
    TempDir dir;
    std::string scad = dir / "a/arches.scad";
    std::string text;
    Arches() {
        auto r = run(quote(cli()) + " " + quote(source_dir() + "/examples/models/arches.stl") + " --orient keep --no-timings -q --out " +
                     quote(dir / "a"));
        EXPECT_EQ(r.code, 0) << r.out;
        text = read_all(scad);
    }
    std::string edit(const std::string& t, const nlohmann::json& e) const { return apply_view_edit(t, e, scad); }
    nlohmann::json value(const std::string& t, const std::string& name) const { return parse_scad_values(t, scad).at(name).value; }
};

std::string error_of(const Arches& a, const nlohmann::json& e) {
    try {
        a.edit(a.text, e);
    } catch (const std::exception& x) {
        return x.what();
    }
    return "";
}

}  // namespace

TEST(ViewEdit, EachEditLandsInItsManualEditsListAndReadsBackAsRegrowReadsIt) {
    Arches a;
    std::string t = a.edit(a.text, {{"op", "toggle_strut"}, {"strut", 5}});
    EXPECT_EQ(a.value(t, "omit_struts"), nlohmann::json({5}));
    EXPECT_NE(t.find("omit_struts = [5];"), std::string::npos);
    EXPECT_EQ(a.edit(t, {{"op", "toggle_strut"}, {"strut", 5}}), a.text) << "a second click undoes it, byte for byte";
    t = a.edit(a.text, {{"op", "add_point"}, {"at", {1.234, -5.678, 37.8}}});
    EXPECT_EQ(a.value(t, "support_points"), nlohmann::json::parse("[[1.23, -5.68, 37.8]]"));
    t = a.edit(t, {{"op", "add_blocker"}, {"box", {{-10, -8, -1}, {0, 8, 38.3}}}});
    EXPECT_NE(t.find("support_blockers = [[[-10, -8, -1], [0, 8, 38.3]]];"), std::string::npos);
    t = a.edit(t, {{"op", "remove_point"}, {"index", 0}});
    EXPECT_TRUE(a.value(t, "support_points").empty());
    // Everything else in the file is as it was: the edit replaced the values only.
    std::string back = a.edit(t, {{"op", "remove_blocker"}, {"index", 0}});
    EXPECT_EQ(back, a.text);
}

TEST(ViewEdit, OmittedStrutTakesItsBranchAndCustomizerValuesResizeWithoutRegrow) {
    Arches a;
    auto before = view_scad_state(a.text, a.scad);
    const auto& struts = before["struts"];
    ASSERT_GT(struts.size(), 100u);
    // The strut to the bed carrying the most: omitting it takes every strut above it.
    int trunk = -1;
    double widest = 0;
    for (size_t e = 0; e < struts.size(); ++e)
        if (struts[e][4] == "onto bed" && struts[e][3].get<double>() > widest) widest = struts[e][3], trunk = static_cast<int>(e);
    ASSERT_GE(trunk, 0);
    auto omitted = view_scad_state(a.edit(a.text, {{"op", "toggle_strut"}, {"strut", trunk}}), a.scad);
    int gone = 0;
    for (const auto& s : omitted["struts"]) gone += s[6].get<bool>();
    EXPECT_GT(gone, 1) << "the branch above the trunk goes with it";
    EXPECT_TRUE(omitted["struts"][trunk][6].get<bool>());
    EXPECT_LT(omitted["tips"].size(), before["tips"].size());
    // k: the Customizer's slider; slanted struts get thicker, nothing regrows (same struts).
    std::string thicker = a.edit(a.text, {{"op", "set"}, {"name", "k"}, {"value", 0.01}});
    EXPECT_NE(thicker.find("k = 0.01; // [0:0.0005:0.02]"), std::string::npos) << "the range comment stays";
    auto resized = view_scad_state(thicker, a.scad);
    ASSERT_EQ(resized["struts"].size(), struts.size());
    double grown = 0;
    for (size_t e = 0; e < struts.size(); ++e) {
        EXPECT_EQ(resized["struts"][e][0], struts[e][0]);
        grown = std::max(grown, resized["struts"][e][3].get<double>() - struts[e][3].get<double>());
    }
    EXPECT_GT(grown, 0.5);
    bool has_k = false;
    for (const auto& s : before["sliders"]) has_k = has_k || (s["name"] == "k" && s["max"] == 0.02);
    EXPECT_TRUE(has_k);
}

TEST(ViewEdit, AFailingEditGivesRegrowsMessageWithItsLineAndChangesNothing) {
    Arches a;
    std::string e = error_of(a, {{"op", "toggle_strut"}, {"strut", 99999}});
    EXPECT_NE(e.find(a.scad + ":"), std::string::npos) << e;
    EXPECT_NE(e.find("omit_struts: strut or pillar 99999 is out of range"), std::string::npos) << e;
    e = error_of(a, {{"op", "set"}, {"name", "d_min"}, {"value", 50}});
    EXPECT_NE(e.find(a.scad), std::string::npos) << e;
    EXPECT_NE(error_of(a, {{"op", "set"}, {"name", "../../etc/x"}, {"value", 1}}).find("not a Customizer value"), std::string::npos);
    EXPECT_NE(error_of(a, {{"op", "set"}, {"name", "cs_input_path"}, {"value", 1}}).find("not a Customizer value"), std::string::npos);
    EXPECT_NE(error_of(a, {{"op", "add_point"}, {"at", {1, 2}}}).find("not [x, y, z]"), std::string::npos);
    EXPECT_NE(error_of(a, {{"op", "write"}, {"path", "/etc/passwd"}}).find("unknown op"), std::string::npos);
    EXPECT_EQ(read_all(a.scad), a.text);
}

TEST(ViewServer, AnswersOnlyItsTokenAndItsOwnHost) {
    EXPECT_TRUE(view_request_allowed("127.0.0.1:8080", "/ab12/", "ab12", 8080));
    EXPECT_TRUE(view_request_allowed("localhost:8080", "/ab12/files/model.stl", "ab12", 8080));
    EXPECT_FALSE(view_request_allowed("127.0.0.1:8080", "/ab12", "ab12", 8080)) << "the token is a whole segment";
    EXPECT_FALSE(view_request_allowed("127.0.0.1:8080", "/ab13/", "ab12", 8080));
    EXPECT_FALSE(view_request_allowed("127.0.0.1:8080", "/", "ab12", 8080));
    EXPECT_FALSE(view_request_allowed("127.0.0.1:8080", "/ab12/", "", 8080));
    EXPECT_FALSE(view_request_allowed("evil.example:8080", "/ab12/", "ab12", 8080)) << "DNS rebinding";
    EXPECT_FALSE(view_request_allowed("127.0.0.1:8081", "/ab12/", "ab12", 8080));
    EXPECT_FALSE(view_request_allowed("127.0.0.1", "/ab12/", "ab12", 8080));
    EXPECT_FALSE(view_request_allowed("", "/ab12/", "ab12", 8080));
}

TEST(ViewFolder, FindsTheOneScadOfAnOutputFolderOrSaysWhatToGive) {
    Arches a;
    auto f = find_view_folder(a.dir / "a/");
    EXPECT_EQ(f.scad(), a.scad);
    EXPECT_EQ(find_view_folder(a.scad).file(".model.stl"), a.dir / "a/arches.model.stl");
    EXPECT_THROW(find_view_folder(a.dir / "missing"), InputError);
    EXPECT_THROW(find_view_folder(a.dir / "a/arches.model.stl"), InputError);
    EXPECT_THROW(find_view_folder(a.dir.path), InputError) << "no .scad in it";
    auto r = run(quote(cli()) + " view " + quote(a.dir / "nothing"));
    EXPECT_EQ(r.code, 3) << r.out;
    EXPECT_NE(r.out.find("Give an output folder"), std::string::npos) << r.out;
}

// `view` runs in an executable of its own (view_cli.hpp): the server's command line reads back
// as what `view` gave it, and nothing else is one.
TEST(ViewServer, ItsCommandLineCarriesTheFolderTheCliAndThePage) {
    const ViewOptions o{"out/m/", "/opt/cs/bin/clever-support", "/opt/cs/share/clever-support/view"};
    const std::vector<std::string> args = view_server_args(o);
    ASSERT_EQ(args.size(), 4u);
    EXPECT_EQ(args[0], kViewServer);
    std::vector<const char*> argv;
    for (const std::string& a : args) argv.push_back(a.c_str());
    const auto back = view_options_from_args(static_cast<int>(argv.size()), argv.data());
    ASSERT_TRUE(back);
    EXPECT_EQ(back->target, o.target);
    EXPECT_EQ(back->cli, o.cli);
    EXPECT_EQ(back->page_dir, o.page_dir);
    EXPECT_FALSE(view_options_from_args(2, argv.data()));
    // Started by hand, the server says what to run instead.
    const std::string server = (std::filesystem::path(cli()).parent_path() / kViewServer).string();
    auto r = run(quote(server) + " out/m/");
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("clever-support view FOLDER"), std::string::npos) << r.out;
}

// Every run but `view` starts without the web server's libraries (cpp-httplib, libssl, libcrypto;
// libcrypto also came with libzip until the 3MFs were packed with minizip, and loading it cost
// every run about 3 ms): the loader's own log of a run names none of them. `view` becomes its server: its errors are the
// server's (ViewFolder's test above), and without the server beside it, it says so.
TEST(ViewServer, OnlyViewLoadsTheWebServer) {
    TempDir tmp;
    const std::string log = tmp / "loader";
    auto r = run("LD_DEBUG=files LD_DEBUG_OUTPUT=" + quote(log) + " " + quote(cli()) + " --version");
    ASSERT_EQ(r.code, 0) << r.out;
    std::string loaded;
    for (const auto& e : std::filesystem::directory_iterator(tmp.path)) loaded += read_all(e.path().string());
    EXPECT_NE(loaded.find("libstdc++"), std::string::npos) << "the loader's log was not read";
    for (const char* lib : {"libcpp-httplib", "libssl", "libcrypto", "libbrotli"})
        EXPECT_EQ(loaded.find(lib), std::string::npos) << lib << " is loaded by every run";
    const std::string alone = tmp / "clever-support";
    std::filesystem::copy_file(cli(), alone);
    std::filesystem::permissions(alone, std::filesystem::perms::owner_exec, std::filesystem::perm_options::add);
    auto v = run(quote(alone) + " view " + quote(tmp / "nothing"));
    EXPECT_EQ(v.code, 5) << v.out;
    EXPECT_NE(v.out.find("cannot start the page's server"), std::string::npos) << v.out;
}

// The page's check judges a folder as `clever-support check FOLDER` does: after omitting a strut
// and regrowing, the overhang the omitted tips held is left out on purpose and both pass; with
// the omission undone in the file only, both fail on that overhang. The strut is one whose tips
// hold the print itself (22 since 2026-12-06, when the hybrid under the arches' flat crowns took
// rows across them and the tree was renumbered; 102 before): omitting a strut under a hybrid
// piece's foot leaves the piece resting on nothing, which `check` fails (known, not yet fixed).
TEST(ViewCheck, JudgesTheFolderAsCheckDoesWithTheUsersOmissions) {
    Arches a;
    std::string t = a.edit(a.text, {{"op", "toggle_strut"}, {"strut", 22}});
    std::ofstream(a.scad, std::ios::binary) << t;
    auto regrow = run(quote(cli()) + " regrow -q " + quote(a.scad));
    ASSERT_EQ(regrow.code, 0) << regrow.out;
    const ViewFolder f = find_view_folder(a.scad);
    t = read_all(a.scad);
    nlohmann::json c = view_check(f, t);
    EXPECT_EQ(c["ok"], true) << c["summary"];
    EXPECT_GT(c["left_out_area_mm2"].get<double>(), 0) << c["summary"];
    EXPECT_NE(c["summary"].get<std::string>().find("left out on purpose by the user's edit"), std::string::npos);
    EXPECT_EQ(run(quote(cli()) + " check " + quote(f.folder)).code, 0);
    const std::string undone = a.edit(t, {{"op", "toggle_strut"}, {"strut", 22}});
    std::ofstream(a.scad, std::ios::binary) << undone;
    c = view_check(f, undone);
    EXPECT_EQ(c["coverage_ok"], false) << c["summary"];
    EXPECT_FALSE(c["uncovered"].empty());
    EXPECT_EQ(run(quote(cli()) + " check " + quote(f.folder)).code, 4);
}

// The built CLI (support.hpp run()/cli()): exit codes, messages, outputs, the bad-input corpus.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "cli/huge_pages.hpp"
#include "core/errors.hpp"
#include "mesh/mesh_io.hpp"
#include "mesh/repair.hpp"
#include "pipeline/pipeline.hpp"
#include "shapes.hpp"
#include "support.hpp"
#include "zip_read.hpp"

namespace fs = std::filesystem;
using namespace cs;
using cs::test::quote;
using CliRun = cs::test::Run;
using cs::test::TempDir;
using cs::test::elements;
using cs::test::unzip;
using cs::test::read_text;

namespace {

CliRun cli(const std::string& args) { return cs::test::run(quote(cs::test::cli()) + " " + args); }

std::string bad_dir() { return cs::test::source_dir() + "/tests/data/bad"; }


// Every entry of a directory, hidden ones included; empty when it does not exist.
std::set<std::string> entries(const std::string& dir) {
    std::set<std::string> names;
    std::error_code ec;
    if (!fs::exists(dir, ec)) return names;
    for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
    return names;
}

std::set<std::string> six_outputs(const std::string& stem) {  // and the 3MFs since issues 7 and 11
    return {stem + ".supported.stl", stem + ".supports.stl", stem + ".model.stl", stem + ".report.json",
            stem + ".scad",          "clever_support.scad", stem + ".3mf",         stem + ".prusa.3mf",
            "clever_support.curaprofile", "clever_support_creality.curaprofile"};
}

std::string stem_of(const std::string& file) { return fs::path(file).stem().string(); }

bool contains(const std::string& hay, const std::string& needle) { return hay.find(needle) != std::string::npos; }

// The run exited with `code` and its output says every one of `words`; on failure, the code, the
// words it did not say and all it printed.
testing::AssertionResult exits_saying(const CliRun& r, int code, const std::vector<std::string>& words) {
    std::string missing;
    for (const auto& w : words)
        if (!contains(r.out, w)) missing += "\n  does not say: " + w;
    if (r.code == code && missing.empty()) return testing::AssertionSuccess();
    return testing::AssertionFailure() << "exit code " << r.code << " (expected " << code << ")" << missing << "\n"
                                       << r.out;
}

// A T (stem and a cantilevered plate): a small good mesh with overhangs. Run it with
// --orient keep: upside down (plate on the bed, which auto orientation picks) it needs no support.
std::string write_good_mesh(const TempDir& dir, const std::string& name = "tee.stl") {
    std::string path = dir / name;
    write_stl(path, cs::test::t_shape());
    return path;
}

struct ExpectedRow {
    std::string file;
    int code;
    std::string phrase;
};
void PrintTo(const ExpectedRow& r, std::ostream* os) { *os << r.file << " -> exit " << r.code << ", '" << r.phrase << "'"; }

// The first line where two texts differ, for short failure messages.
std::string first_difference(const std::string& a, const std::string& b) {
    std::stringstream sa(a), sb(b);
    std::string la, lb;
    for (int n = 1;; ++n) {
        bool ga = static_cast<bool>(std::getline(sa, la)), gb = static_cast<bool>(std::getline(sb, lb));
        if (!ga && !gb) return "identical";
        if (!ga || !gb || la != lb) return "line " + std::to_string(n) + ": '" + la + "' vs '" + lb + "'";
    }
}

// The first table of tests/data/bad/EXPECTED.md: | file | exit | key phrase | what it is |
std::vector<ExpectedRow> expected_rows() {
    std::ifstream in(bad_dir() + "/EXPECTED.md");
    std::vector<ExpectedRow> rows;
    std::string line;
    bool in_table = false;
    while (std::getline(in, line)) {
        if (line.rfind("| file |", 0) == 0) {
            in_table = true;
            continue;
        }
        if (!in_table) continue;
        if (line.rfind("|---", 0) == 0) continue;
        if (line.empty() || line[0] != '|') break;  // end of the first table
        std::vector<std::string> cells;
        std::stringstream ss(line.substr(1));
        std::string cell;
        while (std::getline(ss, cell, '|')) {
            auto b = cell.find_first_not_of(' '), e = cell.find_last_not_of(' ');
            cells.push_back(b == std::string::npos ? "" : cell.substr(b, e - b + 1));
        }
        if (cells.size() < 3) continue;
        rows.push_back({cells[0], std::stoi(cells[1]), cells[2]});
    }
    return rows;
}

// Runs the CLI on `input` with --out in a fresh folder and checks code, phrase and outputs.
void expect_outcome(const std::string& input, int code, const std::string& phrase) {
    TempDir tmp;
    std::string out = tmp / "out";
    CliRun r = cli(quote(input) + " --out " + quote(out));
    EXPECT_EQ(r.code, code) << r.out;
    std::string where = r.out;
    if (code == 0) where += read_text(out + "/" + stem_of(input) + ".report.json");
    EXPECT_TRUE(contains(where, phrase)) << "missing '" << phrase << "' in:\n" << r.out;
    if (code != 0) {
        EXPECT_TRUE(contains(r.out, "clever-support: error: ")) << r.out;
        EXPECT_TRUE(contains(r.out, input)) << "the message does not name the file:\n" << r.out;
        auto left = entries(out);
        EXPECT_TRUE(left.empty()) << "a failed run left " << (left.empty() ? "" : *left.begin()) << " in --out";
        EXPECT_TRUE(entries(tmp.path).size() <= 1u);  // at most the (empty) out folder
    } else {
        EXPECT_EQ(entries(out), six_outputs(stem_of(input)));
    }
}

}  // namespace

// ---------------------------------------------------------------- the bad-input corpus

TEST(BadCorpus, ExpectedTableCoversEveryFile) {
    auto rows = expected_rows();
    ASSERT_GE(rows.size(), 17u) << "tests/data/bad/EXPECTED.md table not found or short";
    std::set<std::string> listed;
    for (const auto& r : rows) listed.insert(r.file);
    for (const auto& e : fs::directory_iterator(bad_dir())) {
        std::string name = e.path().filename().string();
        if (name == "EXPECTED.md") continue;
        EXPECT_TRUE(listed.count(name)) << name << " has no row in EXPECTED.md";
    }
    for (const auto& f : listed) EXPECT_TRUE(fs::exists(bad_dir() + "/" + f)) << f << " is listed but missing";
}

// One test per row of EXPECTED.md (BadCorpus/File.HasItsExpectedOutcome/<file>).
class File : public ::testing::TestWithParam<ExpectedRow> {};

TEST_P(File, HasItsExpectedOutcome) {
    const ExpectedRow& row = GetParam();
    expect_outcome(bad_dir() + "/" + row.file, row.code, row.phrase);
}

INSTANTIATE_TEST_SUITE_P(BadCorpus, File, ::testing::ValuesIn(expected_rows()),
                         [](const ::testing::TestParamInfo<ExpectedRow>& info) {
                             std::string name = info.param.file;
                             for (auto& c : name)
                                 if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                             return name;
                         });

TEST(BadCorpus, DirectoryAsInput) {
    TempDir tmp;
    fs::create_directory(tmp / "dir.stl");
    expect_outcome(tmp / "dir.stl", kExitBadInput, "is a directory, not a mesh file");
}

TEST(BadCorpus, UnreadableFile) {
    if (geteuid() == 0) GTEST_SKIP() << "root can read chmod 000 files";
    TempDir tmp;
    std::string path = tmp / "unreadable.stl";
    write_stl(path, cs::test::t_shape());
    fs::permissions(path, fs::perms::none);
    expect_outcome(path, kExitBadInput, "cannot read");
}

TEST(BadCorpus, MissingFile) {
    TempDir tmp;
    expect_outcome(tmp / "nope.stl", kExitBadInput, "cannot open: No such file or directory");
}

// ---------------------------------------------------------------- a good run

TEST(Cli, GoodMeshWritesExactlyTheSixOutputs) {
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    std::string out = tmp / "out";
    // Without the hybrid (on its plate 10 mm up the time model prices the hybrid cheaper than
    // walls on both routes): walls, whose rows pair into slabs.
    CliRun r = cli(quote(input) + " --orient keep --hybrid-height 0 --out " + quote(out));
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(entries(out), six_outputs("tee"));
    EXPECT_FALSE(contains(r.out, "warning")) << r.out;
    // The outputs are what they say they are.
    Mesh model = read_mesh(out + "/tee.model.stl");
    Mesh supports = read_mesh(out + "/tee.supports.stl");
    Mesh supported = read_mesh(out + "/tee.supported.stl");
    EXPECT_EQ(model.faces.size(), cs::test::t_shape().faces.size());
    EXPECT_FALSE(supports.faces.empty());
    // The model and the supports, but the slabs' bridges (12 triangles each), which printed as
    // model geometry would be filled (ceilings/slabs.hpp).
    const auto rep = nlohmann::json::parse(read_text(out + "/tee.report.json"));
    const std::size_t bridges = rep["supports"]["ceiling_bridges"];
    EXPECT_GT(bridges, 0u) << "the tee's arms are roofs low over the bed: walls, in slabs";
    EXPECT_EQ(supported.faces.size(), model.faces.size() + supports.faces.size() - 12 * bridges);
    EXPECT_NEAR(bounding_box(model).min.z, 0, 1e-6);
    std::string report = read_text(out + "/tee.report.json");
    EXPECT_TRUE(contains(report, "\"tool\": \"clever-support\"")) << report.substr(0, 300);
    EXPECT_TRUE(contains(read_text(out + "/tee.scad"), "clever_support.scad"));
}

TEST(Cli, GeneratedSupportsPassTheCheckCommand) {
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    std::string out = tmp / "out";
    ASSERT_EQ(cli(quote(input) + " --orient keep --out " + quote(out)).code, 0);
    CliRun r = cli("check --model " + quote(out + "/tee.model.stl") + " --supports " + quote(out + "/tee.supports.stl"));
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_FALSE(contains(r.out, "FAIL")) << r.out;
}

TEST(Cli, TwoRunsWriteByteIdenticalMeshesAndScad) {
    // The T as it is (supports under the plate), and a corpus file whose pose auto orientation picks.
    TempDir tmp;
    std::string tee = write_good_mesh(tmp);
    std::string disjoint = bad_dir() + "/disjoint_shells.stl";
    for (const auto& [input, flags] : {std::pair{tee, std::string(" --orient keep")}, std::pair{disjoint, std::string()}}) {
        SCOPED_TRACE(input);
        std::string stem = stem_of(input);
        std::string a = tmp / (stem + "-a"), b = tmp / (stem + "-b");
        ASSERT_EQ(cli(quote(input) + flags + " --out " + quote(a)).code, 0);
        ASSERT_EQ(cli(quote(input) + flags + " --out " + quote(b)).code, 0);
        EXPECT_GT(fs::file_size(a + "/" + stem + ".supports.stl"), 84u) << "no supports: a weak test";
        for (const auto& f : six_outputs(stem)) {
            if (f == stem + ".report.json") continue;  // see TwoRunsWriteByteIdenticalReports
            std::string x = read_text(a + "/" + f), y = read_text(b + "/" + f);
            EXPECT_FALSE(x.empty()) << f;
            EXPECT_TRUE(x == y) << f << " differs between two runs";
        }
    }
}

TEST(Cli, TwoRunsWriteIdenticalReportsApartFromTimings) {
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    ASSERT_EQ(cli(quote(input) + " --orient keep --out " + quote(tmp / "a")).code, 0);
    ASSERT_EQ(cli(quote(input) + " --orient keep --out " + quote(tmp / "b")).code, 0);
    // Drop the wall-clock lines ("seconds" block and "seconds_total").
    auto strip = [](const std::string& s) {
        std::stringstream in(s);
        std::string line, out;
        bool in_seconds = false;
        while (std::getline(in, line)) {
            if (contains(line, "\"seconds\": {")) in_seconds = true;
            bool skip = in_seconds || contains(line, "\"seconds_total\"");
            if (in_seconds && contains(line, "}")) in_seconds = false;
            if (!skip) out += line + "\n";
        }
        return out;
    };
    std::string a = read_text(tmp / "a/tee.report.json"), b = read_text(tmp / "b/tee.report.json");
    ASSERT_FALSE(a.empty());
    EXPECT_TRUE(strip(a) == strip(b)) << first_difference(strip(a), strip(b));
}

TEST(Cli, TwoRunsWriteByteIdenticalReports) {
    // algorithm.md 3 (d): same input, same output, byte for byte: every file, the report included.
    // The report's stage times (issue 2 asks for them) are the one part that cannot repeat:
    // --no-timings leaves them out for pipelines that diff reports.
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    ASSERT_EQ(cli(quote(input) + " --orient keep --no-timings --out " + quote(tmp / "a")).code, 0);
    ASSERT_EQ(cli(quote(input) + " --orient keep --no-timings --out " + quote(tmp / "b")).code, 0);
    std::string a = read_text(tmp / "a/tee.report.json"), b = read_text(tmp / "b/tee.report.json");
    ASSERT_FALSE(a.empty());
    EXPECT_TRUE(a == b) << "tee.report.json differs between two identical runs, first at " << first_difference(a, b);
}

TEST(Cli, ModelNeedingNoSupportStillChecksClean) {
    // A cube: an empty supports STL is written, and `check` accepts the pair.
    TempDir tmp;
    std::string input = tmp / "cube.stl";
    write_stl(input, cs::test::box({0, 0, 0}, {20, 20, 10}));
    std::string out = tmp / "out";
    CliRun r = cli(quote(input) + " --out " + quote(out));
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(entries(out), six_outputs("cube"));
    EXPECT_EQ(fs::file_size(out + "/cube.supports.stl"), 84u);
    CliRun c = cli("check --model " + quote(out + "/cube.model.stl") + " --supports " + quote(out + "/cube.supports.stl"));
    EXPECT_EQ(c.code, 0) << c.out;
}

TEST(Cli, RerunIntoTheSameDirectoryReplacesTheOutputs) {
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    std::string out = tmp / "out";
    ASSERT_EQ(cli(quote(input) + " --out " + quote(out)).code, 0);
    ASSERT_EQ(cli(quote(input) + " --out " + quote(out)).code, 0);
    EXPECT_EQ(entries(out), six_outputs("tee"));  // no temporaries left over
}

TEST(Cli, VerboseProgressCountsEveryStageOfTheRun) {
    // -v names each stage with how far the run is: the i-th of n stages at 100 * i / n percent, the
    // stages those run_job goes through (job_stages), with and without the self-intersection count.
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    for (bool intersections : {true, false}) {
        SCOPED_TRACE(intersections);
        CliRun r = cli(quote(input) + " -v --orient keep --out " + quote(tmp / "out") +
                       (intersections ? "" : " --no-self-intersection-check"));
        ASSERT_EQ(r.code, 0) << r.out;
        std::vector<std::string> names;
        std::vector<int> percents;
        const std::regex line(R"(\[ *([0-9]+)%\] ([a-z -]+)\.\.\.)");
        for (auto it = std::sregex_iterator(r.out.begin(), r.out.end(), line); it != std::sregex_iterator(); ++it) {
            percents.push_back(std::stoi((*it)[1]));
            names.push_back((*it)[2]);
        }
        Job job;
        job.self_intersection_check = intersections;
        EXPECT_EQ(names, job_stages(job)) << r.out;
        for (size_t i = 0; i < percents.size(); ++i)
            EXPECT_EQ(percents[i], static_cast<int>(100 * i / percents.size())) << names[i] << " in\n" << r.out;
    }
}

// ---------------------------------------------------------------- output failures

TEST(Cli, OutUnderDevFullFailsWithExitSix) {
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    CliRun r = cli(quote(input) + " --out /dev/full/x");
    EXPECT_EQ(r.code, kExitOutputFailed) << r.out;
    EXPECT_TRUE(contains(r.out, "/dev/full")) << r.out;
    EXPECT_TRUE(contains(r.out, "not a directory")) << r.out;
    EXPECT_TRUE(contains(r.out, "--out")) << "the message should say what to do:\n" << r.out;
    EXPECT_FALSE(fs::exists("/dev/full/x"));
}

TEST(Cli, ReadOnlyOutputDirectoryFailsWithExitSix) {
    if (geteuid() == 0) GTEST_SKIP() << "root writes into read-only directories (see UnwritableOutputDirectory)";
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    std::string ro = tmp / "ro";
    fs::create_directory(ro);
    fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
    CliRun r = cli(quote(input) + " --out " + quote(ro));
    fs::permissions(ro, fs::perms::owner_all);
    EXPECT_EQ(r.code, kExitOutputFailed) << r.out;
    EXPECT_TRUE(contains(r.out, "Permission denied")) << r.out;
    EXPECT_TRUE(entries(ro).empty()) << "a failed run left files behind";
}

TEST(Cli, UnwritableOutputDirectoryFailsWithExitSix) {
    // /proc accepts no new directories, not even from root.
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    EXPECT_TRUE(exits_saying(cli(quote(input) + " --out /proc/clever-support-test-out"), kExitOutputFailed,
                             {"cannot create the output directory"}));
    EXPECT_FALSE(fs::exists("/proc/clever-support-test-out"));
}

TEST(Cli, ThreeMfThatFailsToEncodeLeavesNothingAndExitsSix) {
    // minizip fails to pack (tests/fault/failing_zip.cpp, preloaded): the STLs before the 3MF were
    // already written to temporaries; none may be left, and the failure is an output error.
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    std::string out = tmp / "out";
    CliRun r = cs::test::run("LD_PRELOAD=" + quote(CS_FAILING_ZIP) + " ASAN_OPTIONS=verify_asan_link_order=0 " +
                             quote(cs::test::cli()) + " " + quote(input) + " --orient keep --out " + quote(out));
    EXPECT_EQ(r.code, kExitOutputFailed) << r.out;
    EXPECT_TRUE(contains(r.out, "tee.3mf")) << r.out;
    EXPECT_TRUE(contains(r.out, "3MF packaging failed")) << r.out;
    EXPECT_TRUE(entries(out).empty()) << "a failed run left files behind";
}

TEST(Cli, OutputSetIsAllOrNothingWhenOneRenameFails) {
    // One output's name is taken by a directory: the run fails (exit 6) and must not leave the
    // other outputs in place (outputs.hpp: "a failure leaves no half-written output behind"; a
    // partial set next to an older run's files would mix two runs).
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    std::string out = tmp / "out";
    fs::create_directories(out + "/tee.report.json");
    EXPECT_TRUE(
        exits_saying(cli(quote(input) + " --orient keep --out " + quote(out)), kExitOutputFailed, {"tee.report.json"}));
    EXPECT_EQ(entries(out), std::set<std::string>{"tee.report.json"}) << "outputs left behind by a failed run";
}

TEST(Cli, OutputPathThatIsAFileFailsWithExitSix) {
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    std::ofstream(tmp / "afile") << "x";
    EXPECT_TRUE(
        exits_saying(cli(quote(input) + " --out " + quote(tmp / "afile")), kExitOutputFailed, {"not a directory"}));
    EXPECT_EQ(read_text(tmp / "afile"), "x");
}

// ---------------------------------------------------------------- usage

TEST(Cli, UnknownPresetIsAUsageError) {
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    CliRun r = cli(quote(input) + " --preset nope --out " + quote(tmp / "out"));
    EXPECT_EQ(r.code, kExitUsage) << r.out;
    EXPECT_TRUE(contains(r.out, "unknown preset 'nope'")) << r.out;
    EXPECT_TRUE(contains(r.out, "generic-0.4")) << "should list the known presets:\n" << r.out;
    EXPECT_TRUE(entries(tmp / "out").empty());
}

TEST(Cli, NegativeKIsAUsageError) {
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    EXPECT_TRUE(exits_saying(cli(quote(input) + " --k -1 --out " + quote(tmp / "out")), kExitUsage,
                             {"k = -1", "out of range"}));
    EXPECT_TRUE(entries(tmp / "out").empty());
}

TEST(Cli, OtherBadParametersAreUsageErrors) {
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    for (const char* bad : {"--critical-angle 95", "--sampling 0", "--d-min 3 --d-max 2", "--strategy bush",
                            "--scale 0", "--no-such-flag", "--k abc"}) {
        SCOPED_TRACE(bad);
        EXPECT_TRUE(exits_saying(cli(quote(input) + " " + bad + " --out " + quote(tmp / "out")), kExitUsage,
                                 {"clever-support: error: "}));
    }
    EXPECT_TRUE(entries(tmp / "out").empty());
}

TEST(Cli, NoInputIsAUsageError) {
    EXPECT_TRUE(exits_saying(cli(""), kExitUsage, {"no input mesh"}));
}

TEST(Cli, PresetsListsTheBuiltInPresets) {
    EXPECT_TRUE(exits_saying(cli("presets"), 0, {"generic-0.4", "replicator2-pla"}));
}

TEST(Cli, HelpExitsZeroWithExamples) {
    EXPECT_TRUE(exits_saying(cli("--help"), 0, {"Example", "--out"}));
}

// ---------------------------------------------------------------- check

TEST(Cli, CheckOnABrokenPairExitsFour) {
    TempDir tmp;
    std::string model = tmp / "model.stl", supports = tmp / "supports.stl";
    write_stl(model, cs::test::t_shape());
    write_stl(supports, cs::test::box({30, 0, 5}, {32, 2, 7}));  // floating, covering nothing
    EXPECT_TRUE(exits_saying(cli("check --model " + quote(model) + " --supports " + quote(supports)), kExitCheckFailed,
                             {"FAIL coverage", "FAIL grounding"}));
    EXPECT_TRUE(exits_saying(cli("check --json --model " + quote(model) + " --supports " + quote(supports)),
                             kExitCheckFailed, {"\"ok\": false"}));
}

TEST(Cli, CheckWithABadModelFileExitsThree) {
    TempDir tmp;
    std::string supports = tmp / "supports.stl";
    write_stl(supports, cs::test::box({0, 0, 0}, {1, 1, 1}));
    EXPECT_TRUE(
        exits_saying(cli("check --model " + quote(bad_dir() + "/truncated.stl") + " --supports " + quote(supports)),
                     kExitBadInput, {"truncated binary STL"}));
}

TEST(Cli, CheckWithoutArgumentsIsAUsageError) {
    CliRun r = cli("check");
    EXPECT_EQ(r.code, kExitUsage) << r.out;
}

// ---------------------------------------------------------------- the first hour (issue 31)
// What a new user meets, typed as they type it: the summary's grams and minutes, check on a run's
// folder, bridged holes, edits, warnings, words for mistakes, the pose.

namespace {

// A 12 x 10 x 6 block with a tunnel `width` mm wide through it along y (floor z 2, ceiling z 4):
// a horizontal slot the printer bridges. With --orient keep.
std::string write_tunnel(const TempDir& dir, double width = 2) {
    const double w = width / 2;
    cs::test::CellGrid g({-6, -w, w, 6}, {-5, 5}, {0, 2, 4, 6});
    g.fill({-6, -5, 0}, {6, 5, 2});
    g.fill({-6, -5, 4}, {6, 5, 6});
    g.fill({-6, -5, 2}, {-w, 5, 4});
    g.fill({w, -5, 2}, {6, 5, 4});
    std::string path = dir / "tunnel.stl";
    write_stl(path, g.mesh());
    return path;
}

nlohmann::json report_of(const std::string& out, const std::string& stem) {
    return nlohmann::json::parse(read_text(out + "/" + stem + ".report.json"));
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
    auto at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    return at == std::string::npos ? text : text.replace(at, from.size(), to);
}

}  // namespace

TEST(FirstHour, SummaryGivesGramsAndMinutesNotColumns) {
    TempDir tmp;
    std::string out = tmp / "out";
    CliRun r = cli(quote(write_good_mesh(tmp)) + " --orient keep --out " + quote(out));
    ASSERT_EQ(r.code, 0) << r.out;
    std::smatch m;
    ASSERT_TRUE(std::regex_search(r.out, m, std::regex(R"(support +([0-9.]+) g of filament \(([0-9]+) mm\^3 at 1.24 g/cm\^3\), about ([0-9.]+) min of printing added)")))
        << r.out;
    auto report = report_of(out, "tee");
    const double volume = report["supports"]["support_volume_mm3"], seconds = report["supports"]["slicer_estimate"]["seconds"];
    // What the slicers print: the slabs' bridges (hollow in both slicers' files) are left out.
    const double printed = volume - report["supports"]["bridges_volume_mm3"].get<double>();
    EXPECT_NEAR(std::stod(m[1]), printed / 1000 * 1.24, 0.006) << r.out;
    EXPECT_NEAR(std::stod(m[2]), printed, 0.51) << r.out;
    EXPECT_NEAR(std::stod(m[3]), seconds / 60, 0.06) << r.out;
    EXPECT_GT(std::stod(m[3]), 0);
    // Each route's estimate beside it (report: slicer_estimate.routes), their mean the one number.
    std::smatch per;
    ASSERT_TRUE(std::regex_search(r.out, per, std::regex(R"(estimate: Cura ([0-9.]+), PrusaSlicer ([0-9.]+)\))"))) << r.out;
    const auto& routes = report["supports"]["slicer_estimate"]["routes"];
    const double cura = routes["cura_support_mesh"]["seconds"], prusa = routes["prusa_3mf"]["seconds"];
    EXPECT_NEAR(std::stod(per[1]), cura / 60, 0.06) << r.out;
    EXPECT_NEAR(std::stod(per[2]), prusa / 60, 0.06) << r.out;
    EXPECT_NEAR(seconds, 0.5 * (cura + prusa), 1e-6);
    EXPECT_FALSE(contains(r.out, "vs columns")) << r.out;  // moved to the report
    EXPECT_TRUE(report["saving_vs_columns"].contains("volume"));
    EXPECT_EQ(report["parameters"]["filament_density_g_cm3"], 1.24);
    // The preset's density: PETG weighs more for the same volume.
    CliRun petg = cli(quote(write_good_mesh(tmp)) + " --orient keep --preset prusa-mk4-petg --out " + quote(tmp / "petg"));
    EXPECT_TRUE(contains(petg.out, "at 1.27 g/cm^3")) << petg.out;
}

TEST(FirstHour, CheckTakesTheRunFolderWithItsPreset) {
    TempDir tmp;
    std::string out = tmp / "out";
    ASSERT_EQ(cli(quote(write_good_mesh(tmp)) + " --orient keep --preset prusa-mk4-pla --out " + quote(out)).code, 0);
    for (const std::string& run : {out, out + "/", out + "/tee.scad"}) {
        CliRun r = cli("check " + quote(run));
        EXPECT_EQ(r.code, 0) << run << "\n" << r.out;
        EXPECT_TRUE(contains(r.out, "judged with preset prusa-mk4-pla (read from " + out + "/tee.scad)")) << r.out;
        EXPECT_TRUE(contains(r.out, "critical angle 55 deg")) << r.out;
    }
    // Both meshes typed: the settings it used are said, and how to give the run's.
    CliRun typed = cli("check --model " + quote(out + "/tee.model.stl") + " --supports " + quote(out + "/tee.supports.stl"));
    EXPECT_TRUE(contains(typed.out, "judged with preset generic-0.4 (the default preset: give the run's folder")) << typed.out;
    CliRun j = cli("check --json " + quote(out));
    auto parsed = nlohmann::json::parse(j.out);
    EXPECT_EQ(parsed["settings"]["preset"], "prusa-mk4-pla");
    EXPECT_EQ(parsed["settings"]["critical_angle_deg"], 55);
    // Not a run.
    EXPECT_TRUE(exits_saying(cli("check " + quote(tmp.path)), kExitUsage, {"no generated .scad in this folder"}));
}

TEST(FirstHour, BlockedRegionsAreLeftOutOnPurpose) {
    TempDir tmp;
    std::string out = tmp / "out", block = "2,-5,0,10,5,10";  // under the plate's right half
    ASSERT_EQ(cli(quote(write_good_mesh(tmp)) + " --orient keep --block " + block + " --out " + quote(out)).code, 0);
    const std::string meshes = " --model " + quote(out + "/tee.model.stl") + " --supports " + quote(out + "/tee.supports.stl");
    EXPECT_TRUE(exits_saying(cli("check " + quote(out)), 0, {"left out on purpose", "1 region left out on purpose"}));
    EXPECT_TRUE(exits_saying(cli("check" + meshes), kExitCheckFailed, {"FAIL coverage"}));
    EXPECT_TRUE(exits_saying(cli("check --block " + block + meshes), 0, {"blocked region: left out on purpose"}));
}

TEST(FirstHour, ASlotThePrinterBridgesGetsNoSupport) {
    TempDir tmp;
    std::string tunnel = write_tunnel(tmp), out = tmp / "out", old = tmp / "old";
    CliRun r = cli(quote(tunnel) + " --orient keep --out " + quote(out));
    ASSERT_EQ(r.code, 0) << r.out;
    auto report = report_of(out, "tunnel");
    EXPECT_GT(report["overhangs"]["area_mm2"].get<double>(), 19.0);  // the ceiling, 2 x 10 mm
    EXPECT_EQ(report["overhangs"]["samples"], 0);
    EXPECT_EQ(report["supports"]["bodies"], 0);
    CliRun judged = cli("check " + quote(out));  // check agrees: the walls carry the ceiling
    EXPECT_EQ(judged.code, 0) << judged.out;
    // The old behaviour, by the parameter.
    ASSERT_EQ(cli(quote(tunnel) + " --orient keep --support-bridges true --out " + quote(old)).code, 0);
    auto supported = report_of(old, "tunnel");
    EXPECT_GT(supported["overhangs"]["samples"].get<int>(), 0);
    EXPECT_GT(supported["supports"]["bodies"].get<int>(), 0);
    EXPECT_EQ(supported["parameters"]["support_bridges"], true);
    EXPECT_TRUE(contains(read_text(old + "/tunnel.scad"), "support_bridges = true;"));
}

TEST(FirstHour, PillarsCanBeLeftOutByIndex) {
    TempDir tmp;
    std::string out = tmp / "out";
    ASSERT_EQ(cli(quote(write_tunnel(tmp)) + " --orient keep --support-bridges true --out " + quote(out)).code, 0);
    auto before = report_of(out, "tunnel");
    ASSERT_EQ(before["supports"]["struts"], 0);  // a part with pillars only
    const int pillars = before["supports"]["pillars"];
    ASSERT_GT(pillars, 0);
    const std::string scad = out + "/tunnel.scad", text = read_text(scad);
    EXPECT_TRUE(contains(text, "/* 0 */ [[")) << "pillars are numbered after the (no) struts";
    std::ofstream(scad) << replaced(text, "omit_struts = [];", "omit_struts = [0];");
    CliRun r = cli("regrow " + quote(scad));
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(report_of(out, "tunnel")["supports"]["pillars"], pillars - 1);
    std::ofstream(scad) << replaced(text, "omit_struts = [];", "omit_struts = [99];");
    CliRun bad = cli("regrow " + quote(scad));
    EXPECT_NE(bad.code, 0) << bad.out;
    EXPECT_TRUE(contains(bad.out, "strut or pillar")) << bad.out;
}

TEST(FirstHour, RegrowTakesDefinesAndOut) {
    TempDir tmp;
    std::string out = tmp / "out", tryout = tmp / "try";
    ASSERT_EQ(cli(quote(write_good_mesh(tmp)) + " --orient keep --out " + quote(out)).code, 0);
    const std::string original = read_text(out + "/tee.scad");
    CliRun r = cli("regrow " + quote(out + "/tee.scad") + " -D sampling=2 --out " + quote(tryout));
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(entries(tryout), six_outputs("tee"));
    EXPECT_TRUE(contains(read_text(tryout + "/tee.scad"), "\nsampling = 2;")) << "the define took effect";
    EXPECT_EQ(report_of(tryout, "tee")["parameters"]["sampling_distance_mm"], 2);
    // Its .prusa.3mf is a run's: the model and the two supports volumes, each with its thin_walls.
    const auto volumes = elements(unzip(read_text(tryout + "/tee.prusa.3mf"))["Metadata/Slic3r_PE_model.config"], "volume");
    ASSERT_EQ(volumes.size(), 3u);
    EXPECT_TRUE(contains(volumes[1], "key=\"name\" value=\"tee supports\"") && contains(volumes[1], "key=\"thin_walls\" value=\"1\""))
        << volumes[1];
    EXPECT_TRUE(contains(volumes[2], "key=\"name\" value=\"tee supports, solid\"") &&
                contains(volumes[2], "key=\"thin_walls\" value=\"0\""))
        << volumes[2];
    EXPECT_EQ(read_text(out + "/tee.scad"), original) << "the folder it came from is left alone";
    EXPECT_TRUE(exits_saying(cli("regrow " + quote(out + "/tee.scad") + " -D samplin=2"), kExitUsage,
                             {"did you mean `sampling`"}));
}

TEST(FirstHour, SaysWhatWasDropped) {
    TempDir tmp;
    // A support point in a slit narrower than a tip: no strut fits under it.
    std::string out = tmp / "out";
    EXPECT_TRUE(
        exits_saying(cli(quote(write_tunnel(tmp, 0.6)) + " --orient keep --support-point 0,0,4 --out " + quote(out)), 0,
                     {"support point [0, 0, 4] (on the model at (0.00, 0.00, 4.00)) got no tip"}));
    // A floating shell.
    EXPECT_TRUE(
        exits_saying(cli(quote(bad_dir() + "/disjoint_shells.stl") + " --orient keep --out " + quote(tmp / "shells")),
                     0, {"floats"}));
    EXPECT_FALSE(contains(cli(quote(write_good_mesh(tmp)) + " --orient keep --out " + quote(tmp / "t")).out, "floats"));
    // Lone struts: a 1 mm post 30 mm tall with an arm to each side, one sample under each arm
    // (at 5 mm sampling), on the bed only: two 28 mm struts, 1 mm wide, that nothing joins.
    cs::test::CellGrid g({-6, -0.5, 0.5, 6}, {-0.5, 0.5}, {0, 29, 30});
    g.fill({-0.5, -0.5, 0}, {0.5, 0.5, 30});
    g.fill({-6, -0.5, 29}, {6, 0.5, 30});
    std::string post = tmp / "post.stl";
    write_stl(post, g.mesh());
    EXPECT_TRUE(
        exits_saying(cli(quote(post) + " --orient keep --buildplate-only --sampling 5 --out " + quote(tmp / "post")), 0,
                     {"a lone strut from", "comfortable range"}));
}

TEST(FirstHour, ClearWordsForMistakes) {
    TempDir tmp;
    std::string tee = write_good_mesh(tmp);
    EXPECT_TRUE(exits_saying(cli(quote(tee) + " --sampel 2"), kExitUsage,
                             {"unknown option --sampel (did you mean `--sampling`?)"}));
    EXPECT_TRUE(exits_saying(cli("chek --model " + quote(tee)), kExitUsage,
                             {"unknown subcommand 'chek' (did you mean `check`?)"}));
    EXPECT_TRUE(
        exits_saying(cli(quote(tee) + " --preset prusa-mk4-pal"), kExitUsage, {"did you mean `prusa-mk4-pla`"}));
    CliRun checkflag = cli("check --blok 0,0,0,1,1,1");
    EXPECT_TRUE(contains(checkflag.out, "did you mean `--block`")) << checkflag.out;
    // A -D with no value is named as typed, before OpenSCAD makes up a line number for it.
    std::string part = tmp / "part.scad";
    std::ofstream(part) << "hole_d = 3;\ncube(10);\n";
    CliRun define = cli(quote(part) + " -D hole_d= --out " + quote(tmp / "p"));
    EXPECT_EQ(define.code, kExitUsage) << define.out;
    EXPECT_TRUE(contains(define.out, "-D hole_d=: no value after '='")) << define.out;
    EXPECT_FALSE(contains(define.out, "line")) << define.out;
    // .scad is an input wherever inputs are listed.
    EXPECT_TRUE(contains(cli("--help").out, ".scad")) << "--help";
    std::string odd = tmp / "model.xyz";
    std::ofstream(odd) << "nothing";
    EXPECT_TRUE(contains(cli(quote(odd)).out, ".scad"));
}

TEST(FirstHour, ThePoseInWords) {
    TempDir tmp;
    std::string out = tmp / "out";
    CliRun r = cli(quote(write_good_mesh(tmp)) + " --orient 90,0,30 --show-pose --out " + quote(out));
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "pose        scaled 1, rotated 90.0 deg about X, then 0.0 about Y, then 30.0 about Z, then moved by ("))
        << r.out;
    EXPECT_TRUE(contains(r.out, "design -> placed: placed = translate([")) << r.out;
    EXPECT_TRUE(contains(read_text(out + "/tee.scad"), "// pose: scaled 1, rotated 90.0 deg about X"));
    // The report's angles and offset map the design onto the placed model.
    auto pl = report_of(out, "tee")["placement"];
    EXPECT_TRUE(pl.contains("how_to_map"));
    double r3[3][3];
    rotation_from_euler_deg(pl["rotation_deg"][0], pl["rotation_deg"][1], pl["rotation_deg"][2], r3);
    Mesh design = cs::test::t_shape();
    const Vec3 t{pl["translation_mm"][0], pl["translation_mm"][1], pl["translation_mm"][2]};
    for (auto& v : design.vertices)
        v = Vec3{r3[0][0] * v.x + r3[0][1] * v.y + r3[0][2] * v.z, r3[1][0] * v.x + r3[1][1] * v.y + r3[1][2] * v.z,
                 r3[2][0] * v.x + r3[2][1] * v.y + r3[2][2] * v.z} + t;
    Box3 mapped = bounding_box(design), placed = bounding_box(read_mesh(out + "/tee.model.stl"));
    EXPECT_NEAR(distance(mapped.min, placed.min), 0, 1e-3);
    EXPECT_NEAR(distance(mapped.max, placed.max), 0, 1e-3);
}

// ---------------------------------------------------------------- huge pages (cli/huge_pages.hpp)

TEST(HugePages, OnlyALargeInputRunsAgainAndOnlyWhereTheKernelLeavesItToTheProcess) {
    const std::string madvise = "always [madvise] never\n";
    EXPECT_TRUE(wants_rerun(kRerunFromBytes, madvise, nullptr));
    EXPECT_TRUE(wants_rerun(kRerunFromBytes, madvise, "glibc.malloc.arena_max=2"));
    EXPECT_FALSE(wants_rerun(kRerunFromBytes - 1, madvise, nullptr));  // the heap's huge pages do
    EXPECT_FALSE(wants_rerun(kRerunFromBytes, "[always] madvise never\n", nullptr));
    EXPECT_FALSE(wants_rerun(kRerunFromBytes, "always madvise [never]\n", nullptr));
    EXPECT_FALSE(wants_rerun(kRerunFromBytes, "", nullptr));  // no such kernel file
    // Named already, by the user or by the run that started this one: never again (no loop).
    EXPECT_FALSE(wants_rerun(kRerunFromBytes, madvise, "glibc.malloc.hugetlb=0"));
    EXPECT_FALSE(wants_rerun(kRerunFromBytes, madvise, with_huge_tunable(nullptr).c_str()));
    EXPECT_FALSE(wants_rerun(kRerunFromBytes, madvise, with_huge_tunable("glibc.malloc.arena_max=2").c_str()));
}

TEST(HugePages, TheTunableIsAddedToWhatTheEnvironmentHeld) {
    EXPECT_EQ(with_huge_tunable(nullptr), "glibc.malloc.hugetlb=1");
    EXPECT_EQ(with_huge_tunable(""), "glibc.malloc.hugetlb=1");
    EXPECT_EQ(with_huge_tunable("glibc.malloc.arena_max=2"), "glibc.malloc.arena_max=2:glibc.malloc.hugetlb=1");
}

// A mesh file past kRerunFromBytes (a small part, and blank lines after it: an ASCII STL may end
// so) runs again where the kernel leaves huge pages to the process (the loader, LD_DEBUG=files,
// starts the program twice), with the same arguments: generate, regrow and check each write or say
// what a run that is not run again (the tunable set already) does, byte for byte. A build with
// sanitizers never runs again (kMayRerun).
TEST(HugePages, ALargeInputRunAgainWritesWhatItWouldHave) {
    const bool madvise = contains(read_text("/sys/kernel/mm/transparent_hugepage/enabled"), "[madvise]");
    TempDir tmp;
    const std::string large = tmp / "large.stl";
    {
        const Mesh m = cs::test::t_shape();
        std::ofstream stl(large);
        stl << "solid tee\n";
        for (const Triangle& t : m.faces) {
            stl << "facet normal 0 0 0\nouter loop\n";
            for (int k = 0; k < 3; ++k) {
                const Vec3& v = m.vertices[t[k]];
                stl << "vertex " << v.x << " " << v.y << " " << v.z << "\n";
            }
            stl << "endloop\nendfacet\n";
        }
        stl << "endsolid tee\n";
        const std::string blank(1023, ' ');
        for (std::uintmax_t n = 0; n < kRerunFromBytes / 1024 + 1; ++n) stl << blank << '\n';
    }
    ASSERT_GE(fs::file_size(large), kRerunFromBytes);
    // The command's exit code and output, and how many times the loader started the program (its
    // log apart, in files named <prefix>.<pid>: the one process, run again, appends to its own).
    int calls = 0;
    auto run_counted = [&](const std::string& env, const std::string& args) {
        const std::string prefix = tmp / ("loader" + std::to_string(++calls));
        CliRun r = cs::test::run(env + " LD_DEBUG=files LD_DEBUG_OUTPUT=" + quote(prefix) + " " + quote(cs::test::cli()) + " " + args);
        std::size_t starts = 0;
        for (const auto& e : fs::directory_iterator(tmp.path))
            if (e.path().filename().string().starts_with(fs::path(prefix).filename().string() + ".")) {
                const std::string log = read_text(e.path().string());
                for (std::size_t at = 0; (at = log.find("initialize program:", at)) != std::string::npos; ++at) ++starts;
            }
        return std::tuple{r.code, starts, r.out};
    };
    const std::size_t twice = madvise && kMayRerun ? 2u : 1u;
    const std::string set = "GLIBC_TUNABLES=glibc.malloc.hugetlb=1";
    const std::string args = " --orient keep --no-timings --out ";
    const std::vector<std::string> outputs{"large.scad", "large.supports.stl", "large.model.stl", "large.3mf"};
    {
        const auto [code, starts, said] = run_counted("", quote(large) + args + quote(tmp / "again"));
        ASSERT_EQ(code, 0) << said;
        EXPECT_EQ(starts, twice) << said;
        const auto [code1, starts1, said1] = run_counted(set, quote(large) + args + quote(tmp / "once"));
        ASSERT_EQ(code1, 0) << said1;
        EXPECT_EQ(starts1, 1u) << said1;
        for (const std::string& file : outputs)
            EXPECT_EQ(read_text(tmp / "again" + "/" + file), read_text(tmp / "once" + "/" + file)) << file;
    }
    {  // regrow reads the .scad's input, the large file
        const auto [code, starts, said] = run_counted("", "regrow " + quote(tmp / "again" + "/large.scad") + " --out " + quote(tmp / "regrown"));
        ASSERT_EQ(code, 0) << said;
        EXPECT_EQ(starts, twice) << said;
        for (const std::string& file : outputs)
            EXPECT_EQ(read_text(tmp / "regrown" + "/" + file), read_text(tmp / "once" + "/" + file)) << file;
    }
    {  // check reads the large file as the model
        const std::string args = "check --model " + quote(large) + " --supports " + quote(tmp / "once" + "/large.supports.stl");
        const auto [code, starts, said] = run_counted("", args);
        const auto [code1, starts1, said1] = run_counted(set, args);
        EXPECT_EQ(starts, twice) << said;
        EXPECT_EQ(starts1, 1u) << said1;
        EXPECT_EQ(code, code1);
        EXPECT_EQ(said, said1);
        EXPECT_TRUE(contains(said, "coverage")) << said;
    }
}

// The built CLI (support.hpp run()/cli()): exit codes, messages, outputs, the bad-input corpus.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "core/errors.hpp"
#include "mesh/mesh_io.hpp"
#include "shapes.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using namespace cs;
using cs::test::quote;
using CliRun = cs::test::Run;
using cs::test::TempDir;

namespace {

CliRun cli(const std::string& args) { return cs::test::run(quote(cs::test::cli()) + " " + args); }

std::string bad_dir() { return cs::test::source_dir() + "/tests/data/bad"; }

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

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
    if (code == 0) where += read_file(out + "/" + stem_of(input) + ".report.json");
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
    CliRun r = cli(quote(input) + " --orient keep --out " + quote(out));
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(entries(out), six_outputs("tee"));
    EXPECT_FALSE(contains(r.out, "warning")) << r.out;
    // The outputs are what they say they are.
    Mesh model = read_mesh(out + "/tee.model.stl");
    Mesh supports = read_mesh(out + "/tee.supports.stl");
    Mesh supported = read_mesh(out + "/tee.supported.stl");
    EXPECT_EQ(model.faces.size(), cs::test::t_shape().faces.size());
    EXPECT_FALSE(supports.faces.empty());
    EXPECT_EQ(supported.faces.size(), model.faces.size() + supports.faces.size());
    EXPECT_NEAR(bounding_box(model).min.z, 0, 1e-6);
    std::string report = read_file(out + "/tee.report.json");
    EXPECT_TRUE(contains(report, "\"tool\": \"clever-support\"")) << report.substr(0, 300);
    EXPECT_TRUE(contains(read_file(out + "/tee.scad"), "clever_support.scad"));
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
            std::string x = read_file(a + "/" + f), y = read_file(b + "/" + f);
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
    std::string a = read_file(tmp / "a/tee.report.json"), b = read_file(tmp / "b/tee.report.json");
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
    std::string a = read_file(tmp / "a/tee.report.json"), b = read_file(tmp / "b/tee.report.json");
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
    CliRun r = cli(quote(input) + " --out /proc/clever-support-test-out");
    EXPECT_EQ(r.code, kExitOutputFailed) << r.out;
    EXPECT_TRUE(contains(r.out, "cannot create the output directory")) << r.out;
    EXPECT_FALSE(fs::exists("/proc/clever-support-test-out"));
}

TEST(Cli, OutputSetIsAllOrNothingWhenOneRenameFails) {
    // One output's name is taken by a directory: the run fails (exit 6) and must not leave the
    // other outputs in place (outputs.hpp: "a failure leaves no half-written output behind"; a
    // partial set next to an older run's files would mix two runs).
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    std::string out = tmp / "out";
    fs::create_directories(out + "/tee.report.json");
    CliRun r = cli(quote(input) + " --orient keep --out " + quote(out));
    EXPECT_EQ(r.code, kExitOutputFailed) << r.out;
    EXPECT_TRUE(contains(r.out, "tee.report.json")) << r.out;
    EXPECT_EQ(entries(out), std::set<std::string>{"tee.report.json"}) << "outputs left behind by a failed run";
}

TEST(Cli, OutputPathThatIsAFileFailsWithExitSix) {
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    std::ofstream(tmp / "afile") << "x";
    CliRun r = cli(quote(input) + " --out " + quote(tmp / "afile"));
    EXPECT_EQ(r.code, kExitOutputFailed) << r.out;
    EXPECT_TRUE(contains(r.out, "not a directory")) << r.out;
    EXPECT_EQ(read_file(tmp / "afile"), "x");
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
    CliRun r = cli(quote(input) + " --k -1 --out " + quote(tmp / "out"));
    EXPECT_EQ(r.code, kExitUsage) << r.out;
    EXPECT_TRUE(contains(r.out, "k = -1")) << r.out;
    EXPECT_TRUE(contains(r.out, "out of range")) << r.out;
    EXPECT_TRUE(entries(tmp / "out").empty());
}

TEST(Cli, OtherBadParametersAreUsageErrors) {
    TempDir tmp;
    std::string input = write_good_mesh(tmp);
    for (const char* bad : {"--critical-angle 95", "--sampling 0", "--d-min 3 --d-max 2", "--strategy bush",
                            "--scale 0", "--no-such-flag", "--k abc"}) {
        SCOPED_TRACE(bad);
        CliRun r = cli(quote(input) + " " + bad + " --out " + quote(tmp / "out"));
        EXPECT_EQ(r.code, kExitUsage) << r.out;
        EXPECT_TRUE(contains(r.out, "clever-support: error: ")) << r.out;
    }
    EXPECT_TRUE(entries(tmp / "out").empty());
}

TEST(Cli, NoInputIsAUsageError) {
    CliRun r = cli("");
    EXPECT_EQ(r.code, kExitUsage) << r.out;
    EXPECT_TRUE(contains(r.out, "no input mesh")) << r.out;
}

TEST(Cli, PresetsListsTheBuiltInPresets) {
    CliRun r = cli("presets");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "generic-0.4")) << r.out;
    EXPECT_TRUE(contains(r.out, "replicator2-pla")) << r.out;
}

TEST(Cli, HelpExitsZeroWithExamples) {
    CliRun r = cli("--help");
    EXPECT_EQ(r.code, 0) << r.out;
    EXPECT_TRUE(contains(r.out, "Example")) << r.out;
    EXPECT_TRUE(contains(r.out, "--out")) << r.out;
}

// ---------------------------------------------------------------- check

TEST(Cli, CheckOnABrokenPairExitsFour) {
    TempDir tmp;
    std::string model = tmp / "model.stl", supports = tmp / "supports.stl";
    write_stl(model, cs::test::t_shape());
    write_stl(supports, cs::test::box({30, 0, 5}, {32, 2, 7}));  // floating, covering nothing
    CliRun r = cli("check --model " + quote(model) + " --supports " + quote(supports));
    EXPECT_EQ(r.code, kExitCheckFailed) << r.out;
    EXPECT_TRUE(contains(r.out, "FAIL coverage")) << r.out;
    EXPECT_TRUE(contains(r.out, "FAIL grounding")) << r.out;
    CliRun j = cli("check --json --model " + quote(model) + " --supports " + quote(supports));
    EXPECT_EQ(j.code, kExitCheckFailed) << j.out;
    EXPECT_TRUE(contains(j.out, "\"ok\": false")) << j.out;
}

TEST(Cli, CheckWithABadModelFileExitsThree) {
    TempDir tmp;
    std::string supports = tmp / "supports.stl";
    write_stl(supports, cs::test::box({0, 0, 0}, {1, 1, 1}));
    CliRun r = cli("check --model " + quote(bad_dir() + "/truncated.stl") + " --supports " + quote(supports));
    EXPECT_EQ(r.code, kExitBadInput) << r.out;
    EXPECT_TRUE(contains(r.out, "truncated binary STL")) << r.out;
}

TEST(Cli, CheckWithoutArgumentsIsAUsageError) {
    CliRun r = cli("check");
    EXPECT_EQ(r.code, kExitUsage) << r.out;
}

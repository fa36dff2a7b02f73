// Replays the fuzz corpora (tests/data/fuzz/<format>/: seeds and the reproducers scripts/fuzz.sh
// found) through parse_mesh and, when that succeeds, repair_mesh, in the normal build without
// libFuzzer. Each file must parse (and repair) or be rejected with InputError; any other exception
// fails its test, and a crash kills the test binary, which fails it too. Seeds named seed-* are
// valid meshes and must be accepted. One test per file: FuzzCorpus/Replay.AcceptsOrRejectsWithInputError/<format>_<file>.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <exception>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <ostream>
#include <string>
#include <typeinfo>
#include <vector>

#include "core/errors.hpp"
#include "mesh/mesh_io.hpp"
#include "mesh/repair.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using namespace cs;

namespace {

const std::vector<std::string> kFormats = {"stl", "obj", "off", "ply", "3mf"};

std::string corpus_dir() { return cs::test::source_dir() + "/tests/data/fuzz"; }

struct CorpusFile {
    std::string format;  // the folder, which is also the format the fuzzer parsed it as
    std::string name;    // file name within the folder
    std::string path() const { return corpus_dir() + "/" + format + "/" + name; }
};

// Keeps test names readable (gtest_discover_tests shows the parameter): "stl/crash-<sha1>".
void PrintTo(const CorpusFile& f, std::ostream* os) { *os << f.format << "/" << f.name; }

std::vector<CorpusFile> corpus_files() {
    std::vector<CorpusFile> files;
    for (const auto& format : kFormats) {
        std::vector<std::string> names;
        std::error_code ec;
        for (const auto& e : fs::directory_iterator(corpus_dir() + "/" + format, ec))
            if (e.is_regular_file()) names.push_back(e.path().filename().string());
        std::sort(names.begin(), names.end());
        for (auto& n : names) files.push_back({format, n});
    }
    return files;
}

std::string test_name(const ::testing::TestParamInfo<CorpusFile>& info) {
    std::string s = info.param.format + "_" + info.param.name;
    for (char& c : s)
        if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
    return s;
}

bool starts_with(const std::string& s, const std::string& prefix) { return s.rfind(prefix, 0) == 0; }

class Replay : public ::testing::TestWithParam<CorpusFile> {};

TEST_P(Replay, AcceptsOrRejectsWithInputError) {
    const CorpusFile& f = GetParam();
    if (!fs::exists(f.path())) GTEST_SKIP() << f.path() << " is gone (rebuild to refresh the test list)";
    std::ifstream in(f.path(), std::ios::binary);
    ASSERT_TRUE(in) << "cannot read " << f.path();
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string name = f.format + "/" + f.name;
    std::string rejected;  // the InputError message, if any
    try {
        Mesh raw = parse_mesh(bytes, f.format, name);
        RepairReport report;
        Mesh repaired = repair_mesh(raw, name, report);
        EXPECT_FALSE(repaired.faces.empty()) << name << ": repair_mesh returned no triangles without an InputError";
    } catch (const InputError& e) {
        rejected = e.what();
        EXPECT_FALSE(rejected.empty()) << name << ": InputError without a message";
    } catch (const std::exception& e) {
        ADD_FAILURE() << name << ": threw " << typeid(e).name() << " (not InputError): " << e.what();
    } catch (...) {
        ADD_FAILURE() << name << ": threw something that is not a std::exception";
    }
    if (starts_with(f.name, "seed-"))
        EXPECT_EQ(rejected, "") << name << " is a valid seed mesh and must be accepted";
}

INSTANTIATE_TEST_SUITE_P(FuzzCorpus, Replay, ::testing::ValuesIn(corpus_files()), test_name);

TEST(FuzzCorpus, EveryFormatHasValidAndBrokenSeeds) {
    auto files = corpus_files();
    for (const auto& format : kFormats) {
        size_t valid = 0, other = 0;
        for (const auto& f : files)
            if (f.format == format) (starts_with(f.name, "seed-") ? valid : other)++;
        EXPECT_GT(valid, 0u) << "tests/data/fuzz/" << format << "/ has no seed-* file";
        EXPECT_GT(other, 0u) << "tests/data/fuzz/" << format << "/ has no broken (bad-*) file";
    }
}

}  // namespace

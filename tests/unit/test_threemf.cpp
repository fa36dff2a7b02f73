// 3MF output: a valid ZIP package with the model and its supports as two objects of one build,
// and PrusaSlicer (when installed) slices it like the STL of the same print.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>

#include "mesh/mesh_io.hpp"
#include "output/threemf.hpp"
#include "support.hpp"

namespace cs::test {
namespace {

std::uint32_t get32(const std::string& s, size_t at) {
    std::uint32_t v = 0;
    for (int i = 3; i >= 0; --i) v = (v << 8) | std::uint8_t(s[at + i]);
    return v;
}

// Reads back a stored ZIP (what encode_zip writes) by its central directory.
std::map<std::string, std::string> unzip(const std::string& z) {
    std::map<std::string, std::string> out;
    size_t eocd = z.rfind(std::string("PK\x05\x06", 4));
    EXPECT_NE(eocd, std::string::npos);
    size_t n = std::uint8_t(z[eocd + 10]) | (std::uint8_t(z[eocd + 11]) << 8);
    size_t at = get32(z, eocd + 16);
    for (size_t i = 0; i < n; ++i) {
        EXPECT_EQ(get32(z, at), 0x02014b50u);
        std::uint32_t size = get32(z, at + 20);
        size_t name_len = std::uint8_t(z[at + 28]) | (std::uint8_t(z[at + 29]) << 8);
        std::string name = z.substr(at + 46, name_len);
        size_t local = get32(z, at + 42);
        EXPECT_EQ(get32(z, local), 0x04034b50u);
        size_t local_name = std::uint8_t(z[local + 26]) | (std::uint8_t(z[local + 27]) << 8);
        out[name] = z.substr(local + 30 + local_name, size);
        at += 46 + name_len;
    }
    return out;
}

TEST(ThreeMF, PackageHoldsModelAndSupportsAsTwoObjects) {
    Mesh model = box({0, 0, 0}, {10, 10, 10});
    Mesh supports = box({2, 2, 0}, {3, 3, 5});
    auto files = unzip(encode_3mf({{"part", model}, {"part supports", supports}}));
    ASSERT_EQ(files.size(), 3u);
    ASSERT_TRUE(files.count("[Content_Types].xml") && files.count("_rels/.rels") && files.count("3D/3dmodel.model"));
    const std::string& xml = files["3D/3dmodel.model"];
    auto count = [&](const std::string& what) {
        long n = 0;
        for (size_t at = xml.find(what); at != std::string::npos; at = xml.find(what, at + 1)) ++n;
        return n;
    };
    EXPECT_EQ(count("<object "), 2);
    EXPECT_EQ(count("<item objectid="), 2);
    EXPECT_EQ(count("<vertex "), 16);    // shared corners: 8 per box
    EXPECT_EQ(count("<triangle "), 24);
    EXPECT_NE(xml.find("unit=\"millimeter\""), std::string::npos);
}

TEST(ThreeMF, PrusaSlicerSlicesItLikeTheStl) {
    if (run("command -v prusa-slicer").code != 0) GTEST_SKIP() << "prusa-slicer is not installed";
    TempDir d;
    Mesh t = box({-3, -3, 0}, {3, 3, 10});
    append(t, box({-12, -4, 10}, {12, 4, 13}));
    write_stl(d / "tee.stl", t);
    ASSERT_EQ(run(quote(cli()) + " " + quote(d / "tee.stl") + " --orient keep -q --out " + quote(d.path)).code, 0);
    auto slice = [&](const std::string& in, const std::string& out) {
        auto r = run("prusa-slicer --datadir " + quote(d / "prusa") + " --export-gcode -o " + quote(out) + " " + quote(in));
        EXPECT_EQ(r.code, 0) << r.out;
        std::ifstream g(out);
        std::string line;
        double mm = -1;
        while (std::getline(g, line))
            if (line.rfind("; filament used [mm] = ", 0) == 0) mm = std::stod(line.substr(23));
        return mm;
    };
    double from_3mf = slice(d / "tee.3mf", d / "a.gcode"), from_stl = slice(d / "tee.supported.stl", d / "b.gcode");
    ASSERT_GT(from_3mf, 0);
    EXPECT_NEAR(from_3mf, from_stl, 0.02 * from_stl) << "the 3MF's parts must stay where the generator put them";
}

}  // namespace
}  // namespace cs::test

// Reading 3MF models (mesh/read_3mf.hpp): our own .3mf and .prusa.3mf outputs read back to the
// model they were written from; build items, transforms, components, p:path parts and units place
// the triangles where the file says; every way a 3MF goes wrong is an InputError that says which.
// The corpus files of tests/data/fuzz/3mf/ (made by tests/data/fuzz/make_3mf_seeds.py) are replayed
// by test_fuzz_replay.cpp; the CLI's exit code for them is pinned here.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "core/errors.hpp"
#include "core/params.hpp"
#include "mesh/mesh_io.hpp"
#include "mesh/read_3mf.hpp"
#include "output/threemf.hpp"
#include "support.hpp"

namespace cs::test {
namespace {

using Corner = std::array<long long, 3>;
using Tri = std::array<Corner, 3>;

// Every triangle as its three corners (in units of 1e-5 mm, after `shift`), rotated to start at
// its smallest corner so that the winding is kept, sorted: equal for two meshes with the same
// triangles in any vertex order or numbering.
std::vector<Tri> triangles_of(const Mesh& m, Vec3 shift = {}) {
    std::vector<Tri> out;
    for (const auto& f : m.faces) {
        Tri t;
        for (int k = 0; k < 3; ++k) {
            Vec3 p = m.vertices[f[k]] - shift;
            t[k] = {std::llround(p.x * 1e5), std::llround(p.y * 1e5), std::llround(p.z * 1e5)};
        }
        std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
        out.push_back(t);
    }
    std::sort(out.begin(), out.end());
    return out;
}

Mesh joined(const Mesh& a, const Mesh& b) {
    Mesh m = a;
    const auto n = static_cast<std::uint32_t>(m.vertices.size());
    m.vertices.insert(m.vertices.end(), b.vertices.begin(), b.vertices.end());
    for (auto f : b.faces) m.faces.push_back({f[0] + n, f[1] + n, f[2] + n});
    return m;
}

std::string read_file(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string corpus(const std::string& name) { return source_dir() + "/tests/data/fuzz/3mf/" + name; }

// A 3MF package around one model part's XML (and any further parts), packed by our own writer.
std::string package(const std::string& model, std::vector<std::pair<std::string, std::string>> more = {}) {
    more.emplace_back("3D/3dmodel.model", model);
    return encode_zip(std::move(more));
}

const char* kCore = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02";

std::string tet_object(int id) {
    return "<object id=\"" + std::to_string(id) +
           "\" type=\"model\"><mesh><vertices><vertex x=\"0\" y=\"0\" z=\"0\"/><vertex x=\"10\" y=\"0\" z=\"0\"/>"
           "<vertex x=\"0\" y=\"10\" z=\"0\"/><vertex x=\"0\" y=\"0\" z=\"10\"/></vertices><triangles>"
           "<triangle v1=\"0\" v2=\"2\" v3=\"1\"/><triangle v1=\"0\" v2=\"1\" v3=\"3\"/>"
           "<triangle v1=\"0\" v2=\"3\" v3=\"2\"/><triangle v1=\"1\" v2=\"2\" v3=\"3\"/></triangles></mesh></object>";
}

// Object 2: a group of the given <component> elements.
std::string group_object(const std::string& components) {
    return "<object id=\"2\" type=\"model\"><components>" + components + "</components></object>";
}

std::string model_xml(const std::string& resources, const std::string& build, const std::string& unit = "millimeter") {
    return std::string("<?xml version=\"1.0\"?><model unit=\"") + unit + "\" xmlns=\"" + kCore + "\"><resources>" +
           resources + "</resources><build>" + build + "</build></model>";
}

// The InputError message of parsing `bytes`, or "" when it parses.
std::string error_of(const std::string& bytes, std::size_t limit = kMax3mfUnpackedBytes) {
    try {
        parse_3mf(bytes, "t.3mf", nullptr, limit);
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

TEST(Read3mf, OurCuraOutputReadsBackToTheSameModelAndSupports) {
    const Mesh model = box({0, 0, 0}, {20, 10, 8});
    const Mesh supports = box({2, 2, -5}, {4, 4, -1});
    const std::string bytes = encode_3mf_cura("part", {{"part", model, {}}, {"supports", supports, cura_support_mesh_settings()}});
    ThreeMfContents what;
    const Mesh back = parse_3mf(bytes, "part.3mf", &what);
    // The build item shifts the group onto the plate (threemf.cpp): the same shift for every vertex.
    const Mesh both = joined(model, supports);
    const Vec3 shift = bounding_box(back).min - bounding_box(both).min;
    EXPECT_NEAR(shift.z, 0, 1e-9);
    EXPECT_EQ(triangles_of(back, shift), triangles_of(both));
    EXPECT_EQ(what.build_items, 1);
    EXPECT_EQ(what.mesh_objects, 2);
    EXPECT_EQ(what.component_objects, 1);
    EXPECT_EQ(what.components, 2);
    EXPECT_EQ(what.triangles, 24u);
    EXPECT_EQ(what.summary(),
              "3MF: 1 build item of 3 objects (2 meshes, 1 group of 2 components), read as one model of 24 triangles, "
              "unit millimeter");
}

TEST(Read3mf, OurPrusaOutputReadsBackToTheSameModelAndSupports) {
    const Mesh model = box({-5, -5, 0}, {5, 15, 30});
    const Mesh supports = box({0, 0, -3}, {1, 1, -0.5});
    const std::string bytes = encode_3mf_prusa("part", {{"part", model, {}}, {"supports", supports, {}}});
    ThreeMfContents what;
    const Mesh back = parse_3mf(bytes, "part.prusa.3mf", &what);
    const Mesh both = joined(model, supports);
    const Vec3 shift = bounding_box(back).min - bounding_box(both).min;
    EXPECT_EQ(triangles_of(back, shift), triangles_of(both));
    EXPECT_EQ(what.build_items, 1);
    EXPECT_EQ(what.mesh_objects, 1);
    EXPECT_EQ(what.model_parts, 1);
}

TEST(Read3mf, BuildItemsTransformsAndComponentsPlaceEveryTriangle) {
    // Object 1 (a tetrahedron) is used three times: in group 2 as is and moved by (100, 0, 0), and
    // by a build item that mirrors it in x and lifts it by 5.
    const std::string xml = model_xml(tet_object(1) + group_object("<component objectid=\"1\"/><component objectid=\"1\" "
                                                                   "transform=\"1 0 0 0 1 0 0 0 1 100 0 0\"/>"),
                                      "<item objectid=\"2\" transform=\"1 0 0 0 1 0 0 0 1 0 20 0\"/>"
                                      "<item objectid=\"1\" transform=\"-1 0 0 0 1 0 0 0 1 0 0 5\"/>");
    ThreeMfContents what;
    const Mesh m = parse_3mf(package(xml), "t.3mf", &what);
    ASSERT_EQ(m.faces.size(), 12u);
    const Box3 b = bounding_box(m);
    EXPECT_NEAR(b.min.x, -10, 1e-12);  // the mirrored copy
    EXPECT_NEAR(b.max.x, 110, 1e-12);  // the moved one
    EXPECT_NEAR(b.min.y, 0, 1e-12);
    EXPECT_NEAR(b.max.y, 30, 1e-12);   // the group's item moves it by 20
    EXPECT_NEAR(b.max.z, 15, 1e-12);   // the mirrored one is lifted by 5
    // Every copy still encloses the tetrahedron's volume outward: the mirror's winding is turned.
    EXPECT_NEAR(signed_volume(m), 3 * 1000.0 / 6, 1e-9);
    EXPECT_EQ(what.build_items, 2);
    EXPECT_EQ(what.components, 2);
}

TEST(Read3mf, NestedTransformsComposeInnerFirst) {
    // A component turned 90 degrees about z inside a group moved by (0, 0, 7): the corner (10,0,0)
    // turns to (0,10,0) and then rises to (0,10,7).
    const std::string xml =
        model_xml(tet_object(1) + group_object("<component objectid=\"1\" transform=\"0 1 0 -1 0 0 0 0 1 0 0 0\"/>"),
                  "<item objectid=\"2\" transform=\"1 0 0 0 1 0 0 0 1 0 0 7\"/>");
    const Mesh m = parse_3mf(package(xml), "t.3mf");
    ASSERT_EQ(m.vertices.size(), 4u);
    EXPECT_NEAR(m.vertices[1].x, 0, 1e-12);
    EXPECT_NEAR(m.vertices[1].y, 10, 1e-12);
    EXPECT_NEAR(m.vertices[1].z, 7, 1e-12);
}

TEST(Read3mf, UnitsBecomeMillimetres) {
    const Mesh m = parse_3mf(package(model_xml(tet_object(1), "<item objectid=\"1\"/>", "inch")), "t.3mf");
    EXPECT_NEAR(bounding_box(m).max.x, 254, 1e-9);
    const Mesh c = parse_3mf(package(model_xml(tet_object(1), "<item objectid=\"1\"/>", "centimeter")), "t.3mf");
    EXPECT_NEAR(bounding_box(c).max.z, 100, 1e-9);
}

TEST(Read3mf, SupportObjectsAreLeftOutAndSaidSo) {
    std::string support = tet_object(2);
    support.replace(support.find("type=\"model\""), 12, "type=\"support\"");
    ThreeMfContents what;
    const Mesh m = parse_3mf(package(model_xml(tet_object(1) + support, "<item objectid=\"1\"/><item objectid=\"2\"/>")),
                             "t.3mf", &what);
    EXPECT_EQ(m.faces.size(), 4u);
    EXPECT_EQ(what.skipped_objects, 1);
    EXPECT_NE(what.summary().find("1 object of type support/other left out"), std::string::npos) << what.summary();
}

TEST(Read3mf, AFileWithoutBuildItemsPlacesItsTopLevelObjects) {
    const std::string xml = model_xml(tet_object(1) + group_object("<component objectid=\"1\"/>"), "");
    const Mesh m = parse_3mf(package(xml), "t.3mf");
    EXPECT_EQ(m.faces.size(), 4u);  // object 2 only; object 1 is its component
}

TEST(Read3mf, CorpusSeedsReadAsTheyAreDescribed) {
    ThreeMfContents what;
    Mesh plate = parse_3mf(read_file(corpus("seed-plate.3mf")), "seed-plate.3mf", &what);
    EXPECT_EQ(plate.faces.size(), 12u + 4u + 4u);
    EXPECT_EQ(what.build_items, 2);
    Mesh production = parse_3mf(read_file(corpus("seed-production.3mf")), "seed-production.3mf", &what);
    EXPECT_EQ(production.faces.size(), 12u);
    EXPECT_EQ(what.model_parts, 2);
    EXPECT_NEAR(bounding_box(production).min.z, 2, 1e-12);
    EXPECT_EQ(parse_3mf(read_file(corpus("seed-no-rels.3mf")), "n.3mf").faces.size(), 12u);
}

TEST(Read3mf, EachWayAFileGoesWrongIsNamed) {
    const std::vector<std::pair<std::string, std::string>> cases = {
        {"bad-not_a_zip.3mf", "not a ZIP"},
        {"bad-no_model_part.3mf", "has no 3D model part"},
        {"bad-broken_xml.3mf", "broken XML in 3D/3dmodel.model at line"},
        {"bad-missing_object.3mf", "refers to object 7, which the file does not define"},
        {"bad-transform_not_a_number.3mf", "that is not 12 numbers"},
        {"bad-transform_11_numbers.3mf", "that is not 12 numbers"},
        {"bad-vertex_index.3mf", "refers to vertex 99"},
        {"bad-vertex_nan.3mf", "not three finite numbers"},
        {"bad-component_loop.3mf", "contains itself"},
        {"bad-unit.3mf", "unit \"furlong\""},
        {"bad-entities.3mf", "DOCTYPE"},
        {"bad-zip_bomb.3mf", "ZIP bomb"},
    };
    for (const auto& [file, words] : cases) {
        const std::string message = error_of(read_file(corpus(file)));
        EXPECT_NE(message.find(words), std::string::npos) << file << ": " << message;
        EXPECT_EQ(message.rfind("t.3mf: ", 0), 0u) << file << " names the file first: " << message;
    }
}

TEST(Read3mf, DecompressionStopsAtTheLimitWhateverTheHeaderSays) {
    // 4 MB of XML that deflates to a few kB: refused under a 1 MB limit, read under the default.
    const std::string xml = model_xml(tet_object(1), "<item objectid=\"1\"/>") + std::string(4 << 20, ' ');
    const std::string bytes = package(xml);
    ASSERT_LT(bytes.size(), 100'000u);
    EXPECT_NE(error_of(bytes, 1 << 20).find("unpacks to more than 1 MB"), std::string::npos) << error_of(bytes, 1 << 20);
    EXPECT_EQ(error_of(bytes), "");
}

TEST(Read3mf, TheCommandLineReadsA3mfSaysWhatItReadAndItsOutputsReadBack) {
    TempDir t;
    const Mesh a = box({0, 0, 0}, {20, 20, 4}), b = box({0, 0, 0}, {6, 6, 12});
    // Two objects on one plate: a slab and, beside it, a block with a slab-wide ledge on top.
    std::string xml = "<?xml version=\"1.0\"?><model unit=\"millimeter\" xmlns=\"" + std::string(kCore) + "\"><resources>";
    auto object = [](int id, const Mesh& m) {
        std::string s = "<object id=\"" + std::to_string(id) + "\" type=\"model\"><mesh><vertices>";
        for (const auto& v : m.vertices)
            s += "<vertex x=\"" + std::to_string(v.x) + "\" y=\"" + std::to_string(v.y) + "\" z=\"" + std::to_string(v.z) + "\"/>";
        s += "</vertices><triangles>";
        for (const auto& f : m.faces)
            s += "<triangle v1=\"" + std::to_string(f[0]) + "\" v2=\"" + std::to_string(f[1]) + "\" v3=\"" +
                 std::to_string(f[2]) + "\"/>";
        return s + "</triangles></mesh></object>";
    };
    xml += object(1, a) + object(2, b) +
           "</resources><build><item objectid=\"2\"/><item objectid=\"1\" transform=\"1 0 0 0 1 0 0 0 1 0 0 12\"/>"
           "</build></model>";
    {
        std::ofstream(t / "plate.3mf", std::ios::binary) << package(xml);
    }
    test::Run r = run(quote(cli()) + " " + quote(t / "plate.3mf") + " --out " + quote(t / "out") + " --orient keep");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_NE(r.out.find("input       3MF: 2 build items of 2 objects (2 meshes), read as one model of 24 triangles"),
              std::string::npos)
        << r.out;
    Mesh placed = read_mesh(t / "out/plate.model.stl");
    EXPECT_NEAR(bounding_box(placed).size().z, 16, 1e-4);
    EXPECT_EQ(placed.faces.size(), 24u);

    // The run's own .3mf and .prusa.3mf read back to its model and supports (the STLs it wrote,
    // float32: compared by size, shape and volume, the 3MF being shifted onto the plate).
    const Mesh written = joined(placed, read_mesh(t / "out/plate.supports.stl", true));
    ASSERT_GT(written.faces.size(), placed.faces.size()) << "the ledge needs supports";
    for (const std::string file : {"plate.3mf", "plate.prusa.3mf"}) {
        std::string contents;
        const Mesh back = read_mesh(t / ("out/" + file), false, &contents);
        EXPECT_EQ(back.faces.size(), written.faces.size()) << file;
        const Box3 a = bounding_box(back), b = bounding_box(written);
        const Vec3 shift = a.min - b.min;
        EXPECT_NEAR(norm(a.max - b.max - shift), 0, 1e-4) << file;
        EXPECT_NEAR(shift.z, 0, 1e-4) << file;
        EXPECT_NEAR(signed_volume(back), signed_volume(written), 1e-3 * signed_volume(written)) << file;
        EXPECT_NE(contents.find("read as one model of " + std::to_string(written.faces.size()) + " triangles"),
                  std::string::npos)
            << contents;
    }
}

TEST(Read3mf, TheCommandLineRefusesBadFilesWithExit3AndNothingWritten) {
    TempDir t;
    for (const std::string file : {"bad-not_a_zip.3mf", "bad-missing_object.3mf", "bad-zip_bomb.3mf"}) {
        test::Run r = run(quote(cli()) + " " + quote(corpus(file)) + " --out " + quote(t / "out"));
        EXPECT_EQ(r.code, 3) << file << ": " << r.out;
        EXPECT_NE(r.out.find(file + ": "), std::string::npos) << r.out;
        EXPECT_FALSE(std::filesystem::exists(t / "out")) << file;
    }
}

}  // namespace
}  // namespace cs::test

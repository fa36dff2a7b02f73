// Reading an edited .scad back (edit/scad_values), the bodies it renders (view/view_tree, what
// `apply` writes for PrusaSlicer), pruning omitted struts and a user's samples (pipeline), and the
// box tests the blockers use (core/geometry).
#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "edit/scad_values.hpp"
#include "mesh/mesh_io.hpp"
#include "output/scad.hpp"
#include "pipeline/pipeline.hpp"
#include "shapes.hpp"
#include "support.hpp"
#include "view/view_tree.hpp"

using namespace cs;

namespace {

std::string error_of(const std::string& text) {
    try {
        parse_scad_values(text, "x.scad");
    } catch (const InputError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST(ScadValues, ReadsPlainValuesSkipsCommentsAndReferencesStopsAtCode) {
    auto v = parse_scad_values("// header\nk = 0.0015; // [0:0.0005:0.02]\nfeet = true;\nname = \"a \\\"b\\\"\";\n"
                               "list = [\n  /* 0 leaf */ [1, -2.5, 3e-1],\n  /* 1 */ [4, 5, 6]\n];\nempty = [];\n"
                               "nothing = undef;\nrecord = [list, empty];\ninclude <lib.scad>\nafter = 1;\n",
                               "x.scad");
    EXPECT_DOUBLE_EQ(v.at("k").value.get<double>(), 0.0015);
    EXPECT_EQ(v.at("feet").value, true);
    EXPECT_EQ(v.at("name").value, "a \"b\"");
    EXPECT_EQ(v.at("list").value.size(), 2u);
    EXPECT_DOUBLE_EQ(v.at("list").value[0][2].get<double>(), 0.3);
    EXPECT_EQ(v.at("list").line, 5);
    EXPECT_EQ(v.at("list").item_lines, (std::vector<int>{6, 7}));
    EXPECT_TRUE(v.at("empty").value.empty());
    EXPECT_TRUE(v.at("nothing").value.is_null());
    EXPECT_FALSE(v.count("record")) << "refers to other names: not data";
    EXPECT_FALSE(v.count("after")) << "after the code starts";
}

TEST(ScadValues, MalformedValuesNameTheLine) {
    EXPECT_NE(error_of("a = 1;\nb = [1, 2;\n").find("x.scad:2: malformed list"), std::string::npos);
    EXPECT_NE(error_of("a = 1;\nb = [1,\n2,\n").find("x.scad:2: a list opened here is never closed"), std::string::npos)
        << error_of("a = 1;\nb = [1,\n2,\n");
    EXPECT_NE(error_of("a = 1\nb = 2;\n").find("x.scad:2: expected a plain value"), std::string::npos)
        << error_of("a = 1\nb = 2;\n");
    EXPECT_NE(error_of("a = \"open;\n").find("x.scad:1: a string is not closed"), std::string::npos);
    EXPECT_NE(error_of("a = 1;\n\na = 2;\n").find("x.scad:3: a is assigned twice"), std::string::npos);
    EXPECT_NE(error_of("a = 1 + 2;\n").find("plain value"), std::string::npos);
}

TEST(ScadValues, EveryStatementBeforeTheCodeThatIsNotAnAssignmentIsAnErrorAtItsLine) {
    // Issue 29: `support_blockers = [` shortened to `[];`, the old entry and `];` left below.
    const std::string stray = "a = 1;\nsupport_blockers = [];\n  [[0, 0, 0], [1, 1, 1]]\n];\ncs_input_path = \"x\";\n";
    EXPECT_NE(error_of(stray).find("x.scad:3: expected an assignment"), std::string::npos) << error_of(stray);
    EXPECT_NE(error_of("a = 1;\n\n];\nb = 2;\n").find("x.scad:3: expected an assignment"), std::string::npos);
    EXPECT_NE(error_of("a = 1;\ncube(1);\ninclude <lib.scad>\n").find("x.scad:2:"), std::string::npos);
    EXPECT_NE(error_of("a = 1;\nb;\n").find("x.scad:2:"), std::string::npos);
    EXPECT_EQ(error_of("a = 1;\ninclude <lib.scad>\ncube(1);\n]];\n"), "") << "after the code starts: OpenSCAD's";
    EXPECT_EQ(error_of("a = 1;\nuse <lib.scad>\ncube(1);\n"), "");
}

TEST(ScadValues, NumbersMustBeFinite) {
    EXPECT_NE(error_of("a = 1;\nb = 1e999;\n").find("x.scad:2: a number must be finite"), std::string::npos)
        << error_of("a = 1;\nb = 1e999;\n");
    EXPECT_NE(error_of("b = [1, -inf];\n").find("x.scad:1: a number must be finite"), std::string::npos);
    EXPECT_NE(error_of("b = +nan;\n").find("finite"), std::string::npos);
}

namespace {

// Two leaves 0, 1 merge at 2, which stands on bed node 4 through bend 3; leaf 5 stands on bed 6.
SupportTree small_tree() {
    SupportTree t;
    auto node = [&](Vec3 p, NodeKind k) { t.nodes.push_back({p, k, {}, {}}); };
    node({0, 0, 10}, NodeKind::Leaf);
    node({2, 0, 10}, NodeKind::Leaf);
    node({1, 0, 8}, NodeKind::Merge);
    node({1, 0, 4}, NodeKind::Bend);
    node({1, 0, 0}, NodeKind::Bed);
    node({5, 0, 10}, NodeKind::Leaf);
    node({5, 0, 0}, NodeKind::Bed);
    t.struts = {{0, 2}, {1, 2}, {2, 3}, {3, 4}, {5, 6}};
    t.stats.bed_contacts = 2;
    return t;
}

}  // namespace

TEST(PruneStruts, AStrutGoesWithEverythingAboveItNodesKeepTheirIndices) {
    auto t = prune_struts(small_tree(), {2});  // 2 -> 3: takes 0 -> 2 and 1 -> 2 along
    ASSERT_EQ(t.struts.size(), 2u);
    EXPECT_EQ(t.struts[0].top, 3);
    EXPECT_EQ(t.struts[1].top, 5);
    EXPECT_EQ(t.nodes.size(), 7u);
    for (int v : {0, 1, 2}) EXPECT_EQ(t.nodes[v].kind, NodeKind::Dropped) << v;
    EXPECT_EQ(t.nodes[3].kind, NodeKind::Bend) << "still carries strut 3 -> 4";
    EXPECT_EQ(t.nodes[5].kind, NodeKind::Leaf);
    auto all = prune_struts(small_tree(), {3, 4});
    EXPECT_TRUE(all.struts.empty());
    EXPECT_EQ(all.stats.bed_contacts, 0u);
    EXPECT_EQ(prune_struts(small_tree(), {}).struts.size(), 5u);
    EXPECT_THROW(prune_struts(small_tree(), {5}), ParameterError);
    EXPECT_THROW(prune_struts(small_tree(), {-1}), ParameterError);
}

// `apply` splits the .prusa.3mf's supports by the bodies the .scad records, since OpenSCAD's
// union cannot tell a tip from a strut: rebuilt from the file, they are the bodies the run built
// (as near as the file writes its numbers), omitted branches left out as the run left them out,
// contact tips ending where the file says, and the file's walls.
TEST(SupportsFromScad, AreTheBodiesAndWallsTheRunBuilt) {
    cs::test::TempDir tmp;
    std::map<BodyKind, int> kinds;
    std::map<Profile, int> profiles;
    // Struts to the bed and onto the box below; a table's struts stand on feet.
    for (const Mesh& shape : {cs::test::cantilever_over_box(), cs::test::table_shape()})
        for (const std::vector<int>& omit : {std::vector<int>{}, std::vector<int>{0, 3}}) {
            const std::string input = tmp / "part.stl";
            write_stl(input, shape);
            Job job;
            job.input = input;
            job.orient = "keep";
            job.params.ceiling_span = 0;  // trees, as the default preset grows them (the wall is added below)
            job.edits.omit_struts = omit;
            Result r = run_job(job);
            Supports run = r.supports;
            run.walls.push_back({{-30, -20, 0}, {-10, -20, 0}, 0, 4.25, false, 0.6});
            run.grown_walls = run.walls;  // as finish_supports records them (no piece on the tree here)
            const ScadMeta meta{"test", r.input_sha256, input, "part.model.stl", pose_numbers(r.placement), ""};
            const std::string text = emit_scad(run, job, meta);
            const Supports back = supports_from_scad(parse_scad_values(text, "part.scad"), omit, job.params);
            ASSERT_EQ(back.bodies.size(), run.bodies.size()) << omit.size();
            for (size_t i = 0; i < run.bodies.size(); ++i) {
                const Body &a = run.bodies[i], &b = back.bodies[i];
                ++kinds[a.kind], ++profiles[a.profile];
                EXPECT_EQ(b.kind, a.kind) << i;
                EXPECT_EQ(b.profile, a.profile) << i;
                EXPECT_LT(distance(b.bottom, a.bottom), 1e-3) << i;
                EXPECT_LT(distance(b.top, a.top), 1e-3) << i;
                EXPECT_NEAR(b.bottom_width, a.bottom_width, 1e-3) << i;
                EXPECT_NEAR(b.top_width, a.top_width, 1e-3) << i;
            }
            ASSERT_EQ(back.walls.size(), run.walls.size());
            for (size_t i = 0; i < run.walls.size(); ++i) {
                const CeilingWall &a = run.walls[i], &b = back.walls[i];
                EXPECT_LT(horizontal_distance(b.from, a.from), 1e-3) << i;
                EXPECT_LT(horizontal_distance(b.to, a.to), 1e-3) << i;
                EXPECT_NEAR(b.bottom, a.bottom, 1e-3) << i;
                EXPECT_NEAR(b.top, a.top, 1e-3) << i;
                EXPECT_NEAR(b.thickness, a.thickness, 1e-3) << i;
            }
        }
    // Not vacuous: the runs had every kind of body the rebuild places, and both profiles.
    for (BodyKind k : {BodyKind::Strut, BodyKind::Tip, BodyKind::ContactTip, BodyKind::Foot})
        EXPECT_GT(kinds[k], 0) << static_cast<int>(k);
    EXPECT_GT(profiles[Profile::N], 0);
    EXPECT_GT(profiles[Profile::Square], 0);
}

TEST(Boxes, SegmentsAndSweptSquaresMeetBoxes) {
    const Box3 b{{0, 0, 0}, {1, 1, 1}};
    EXPECT_TRUE(segment_meets_box({-1, 0.5, 0.5}, {2, 0.5, 0.5}, b));
    EXPECT_TRUE(segment_meets_box({0.5, 0.5, 0.5}, {0.6, 0.6, 0.6}, b)) << "inside";
    EXPECT_FALSE(segment_meets_box({-1, 2, 0.5}, {2, 2, 0.5}, b));
    EXPECT_FALSE(segment_meets_box({2, 2, 2}, {3, 0.5, 0.5}, b));
    EXPECT_TRUE(segment_meets_box({1, 1, 2}, {1, 1, -2}, b)) << "along an edge: the box is closed";
    // A vertical strut 1.2 wide beside the box: its square reaches 0.1 into it.
    EXPECT_TRUE(sweep_meets_boxes({1.5, 0.5, 2}, {1.5, 0.5, -1}, 1.2, 0, {b}));
    EXPECT_FALSE(sweep_meets_boxes({1.7, 0.5, 2}, {1.7, 0.5, -1}, 1.2, 0, {b}));
    EXPECT_FALSE(sweep_meets_boxes({1.5, 0.5, 2}, {1.5, 0.5, -1}, 1.2, 0, {}));
}

// Reading an edited .scad back (edit/scad_values), pruning omitted struts and a user's samples
// (pipeline), and the box tests the blockers use (core/geometry).
#include <gtest/gtest.h>

#include "core/errors.hpp"
#include "edit/scad_values.hpp"
#include "pipeline/pipeline.hpp"

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

#include "view/view_tree.hpp"

#include "pipeline/pipeline.hpp"
#include "struts/struts.hpp"

namespace cs {
namespace {

Vec3 point_of(const nlohmann::json& p) { return {p[0].get<double>(), p[1].get<double>(), p[2].get<double>()}; }

const nlohmann::json& list_of(const ScadValues& values, const std::string& name) {
    static const nlohmann::json empty = nlohmann::json::array();
    auto it = values.find(name);
    return it == values.end() || !it->second.value.is_array() ? empty : it->second.value;
}

}  // namespace

ScadTree tree_from_scad(const ScadValues& values) {
    ScadTree out;
    SupportTree& t = out.tree;
    for (const auto& p : list_of(values, "cs_nodes")) {
        Node node;
        node.p = point_of(p);
        node.kind = NodeKind::Bend;
        t.nodes.push_back(node);
    }
    const int n = static_cast<int>(t.nodes.size());
    std::vector<int> in(n, 0);
    for (const auto& s : list_of(values, "cs_struts")) {
        Strut e{s[0].get<int>(), s[1].get<int>()};
        t.struts.push_back(e);
        ++in[e.bottom];
    }
    out.node_kind.assign(n, "chain");
    for (int v = 0; v < n; ++v)
        if (in[v] > 1) t.nodes[v].kind = NodeKind::Merge, out.node_kind[v] = "merge";
    auto node_at = [&](const nlohmann::json& x) { return x.is_number() && x.get<int>() >= 0 && x.get<int>() < n ? x.get<int>() : -1; };
    for (const auto& l : list_of(values, "cs_leaves"))
        if (int v = node_at(l[0]); v >= 0) {
            t.nodes[v].kind = NodeKind::Leaf, out.node_kind[v] = "leaf";
            t.nodes[v].contact = point_of(l[1]);
            t.nodes[v].tip = point_of(l[2]);
        }
    for (const auto& c : list_of(values, "cs_contacts"))
        if (int v = node_at(c[0]); v >= 0) {
            t.nodes[v].kind = NodeKind::ModelContact, out.node_kind[v] = "contact";
            t.nodes[v].contact = point_of(c[1]);
        }
    for (const auto& b : list_of(values, "cs_beds"))
        if (int v = node_at(b[0]); v >= 0) {
            t.nodes[v].kind = NodeKind::Bed, out.node_kind[v] = "bed";
            t.nodes[v].room = b[1].get<double>();
        }
    for (const auto& p : list_of(values, "cs_pillars")) {
        Pillar pillar;
        pillar.top = point_of(p[0]);
        pillar.bottom = point_of(p[1]);
        t.pillars.push_back(pillar);
    }
    return out;
}

std::vector<CeilingWall> walls_from_scad(const ScadValues& values) {
    std::vector<CeilingWall> walls;
    for (const auto& w : list_of(values, "cs_walls")) {
        CeilingWall wall;
        wall.from = {w[0][0].get<double>(), w[0][1].get<double>(), 0};
        wall.to = {w[1][0].get<double>(), w[1][1].get<double>(), 0};
        wall.bottom = w[2].get<double>();
        wall.top = w[3].get<double>();
        wall.thickness = w[4].get<double>();
        wall.bridge = w.size() > 5 && w[5].is_number() && w[5].get<double>() == 1;  // ceilings/slabs.hpp
        walls.push_back(wall);
    }
    return walls;
}

Supports supports_from_scad(const ScadValues& values, const std::vector<int>& omit, const Params& p) {
    Supports s;
    const SupportTree grown = tree_from_scad(values).tree;
    s.sized = size_struts(prune_struts(grown, omit), p);
    // Where the file says, not where the rules would put them again from its numbers: a contact
    // node's `contact` is already its tip's bottom, and the overlap is the one cs_tree draws with.
    const auto& nodes = s.sized.tree.nodes;
    for (size_t v = 0; v < nodes.size(); ++v)
        if (nodes[v].kind == NodeKind::ModelContact) s.sized.contact_tip[v] = nodes[v].contact;
    if (auto it = values.find("cs_overlap"); it != values.end() && it->second.value.is_number())
        s.sized.overlap = it->second.value.get<double>();
    s.bodies = build_bodies(s.sized, p);
    s.grown_walls = walls_from_scad(values);
    s.walls = omit.empty() ? s.grown_walls : prune_pieces(s.grown_walls, grown, s.sized.tree);
    return s;
}

}  // namespace cs

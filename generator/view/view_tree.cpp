#include "view/view_tree.hpp"

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
        node.kind = NodeKind::Chain;
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

}  // namespace cs

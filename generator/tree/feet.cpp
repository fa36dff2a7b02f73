#include "tree/feet.hpp"

#include <algorithm>
#include <iterator>

namespace cs {
namespace {

bool before(const Vec3& a, const Vec3& b) {
    if (a.z != b.z) return a.z > b.z;
    if (a.x != b.x) return a.x < b.x;
    return a.y < b.y;
}

}  // namespace

SupportTree hang_feet(SupportTree hung, const std::vector<Vec3>& feet, const Params& p) {
    if (feet.empty()) return hung;
    std::vector<Node> leaves;
    for (const Vec3& f : feet) {
        Node n;
        n.p = f - Vec3{0, 0, p.tip_length};
        n.kind = NodeKind::Leaf;
        n.contact = f;
        n.tip = f;
        leaves.push_back(n);
    }
    std::sort(leaves.begin(), leaves.end(), [](const Node& a, const Node& b) { return before(a.contact, b.contact); });
    std::vector<Node> nodes;
    std::merge(hung.nodes.begin(), hung.nodes.end(), leaves.begin(), leaves.end(), std::back_inserter(nodes),
               [](const Node& a, const Node& b) { return before(a.contact, b.contact); });
    hung.nodes = std::move(nodes);
    return hung;
}

std::vector<Vec3> lost_feet(const SupportTree& grown, const std::vector<Vec3>& feet, double within) {
    std::vector<char> below(grown.nodes.size(), 0);
    for (const Strut& s : grown.struts) below[s.top] = 1;
    std::vector<Vec3> lost;
    for (const Vec3& f : feet) {
        const bool held = std::any_of(grown.nodes.begin(), grown.nodes.end(), [&](const Node& n) {
            const std::size_t i = &n - grown.nodes.data();
            return n.kind == NodeKind::Leaf && below[i] && distance(n.tip, f) < within;
        });
        if (!held) lost.push_back(f);
    }
    return lost;
}

bool feet_carried(const SupportTree& grown, const std::vector<Vec3>& feet, double within) {
    return lost_feet(grown, feet, within).empty();
}

}  // namespace cs

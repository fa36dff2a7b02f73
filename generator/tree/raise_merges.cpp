// The pass after the sweep that raises merges of two leaves to meet their leaning tips, and the
// merges below them after (sweep_books.hpp: raise_merges).
#include <algorithm>
#include <utility>

#include "tree/candidates.hpp"
#include "tree/sweep_books.hpp"

namespace cs {
namespace {

// Merge m of nodes hi (the higher) and lo, whose strut goes on down to `below`, rises to where
// their cones meet once they lean; everything stays where it was when anything would not fit.
void raise_merge(SweepBooks& b, int m, int hi, int lo, int below) {
    auto& nodes = b.t_.nodes;
    const Vec3 a = nodes[hi].p, c = nodes[lo].p, old = nodes[m].p;
    const auto leaned = b.leaned_pair(hi, lo);
    const bool leaves = nodes[hi].kind == NodeKind::Leaf && nodes[lo].kind == NodeKind::Leaf;
    if (leaves && !leaned) return;
    const Vec3 a2 = leaned ? leaned->first : a, c2 = leaned ? leaned->second : c;
    const Vec3 m2 = merge_point(a2, c2, b.fan_.tan_c);
    if (m2.z <= old.z + 1e-6 || m2 == c2) return;  // it would not rise (beyond rounding)
    nodes[hi].p = a2, nodes[lo].p = c2, nodes[m].p = m2;
    const Vec3& to = nodes[below].p;
    const bool fits = angle_from_vertical_deg(m2, to) <= b.p_.critical_angle + 1e-9 && b.clear(hi, m2) &&
                      b.clear(lo, m2) && b.clear(m, to, -1, nodes[below].kind == NodeKind::ModelContact) &&
                      b.can_escape(m2, b.books_[m].width);
    if (!fits) nodes[hi].p = a, nodes[lo].p = c, nodes[m].p = old;
}

}  // namespace

void raise_merges(SweepBooks& b) {
    const auto& nodes = b.t_.nodes;
    std::vector<int> merges;
    for (int m = 0; m < static_cast<int>(nodes.size()); ++m)
        if (nodes[m].kind == NodeKind::Merge && b.books_[m].up.size() == 2 && b.books_[m].down >= 0) merges.push_back(m);
    // Top down, so each merge sees where its parents ended up.
    std::stable_sort(merges.begin(), merges.end(), [&](int x, int y) { return nodes[x].p.z > nodes[y].p.z; });
    for (int m : merges) {
        int u = b.books_[m].up[0], v = b.books_[m].up[1];
        if (nodes[u].p.z < nodes[v].p.z) std::swap(u, v);
        raise_merge(b, m, u, v, b.books_[m].down);
    }
}

}  // namespace cs

// The slicer cost model of tree/slicer_cost.hpp: what a slicer spends printing a tree, layer by
// layer. The prices are the slicers' own, fitted to their G-code (core/slicer_time.hpp).
#include "tree/slicer_cost.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "core/slicer_time.hpp"
#include "core/xy_grid.hpp"

namespace cs {
namespace {

// Outline of one layer of a strut of width w: its square. CuraEngine closes the N-profile's narrow
// holes in a support area and walls the outside only (the G-code of four models drew 0.49-0.56 of
// the length that walling the holes too would take).
double outline_per_layer(double w) { return 4 * w; }

// A piece of support between two heights, an island on every layer in between.
struct Upright {
    Vec3 top, bottom;
    double width;
};

std::vector<Upright> uprights(const SupportTree& t, const std::vector<double>& strut_width, const Params& p) {
    std::vector<Upright> out;
    for (size_t i = 0; i < t.struts.size(); ++i)
        out.push_back({t.nodes[t.struts[i].top].p, t.nodes[t.struts[i].bottom].p, strut_width[i]});
    const double tip_width = 0.5 * (p.tip_diameter + p.d_min);
    for (const auto& n : t.nodes) {
        if (n.kind == NodeKind::Leaf) out.push_back({n.tip, n.p, tip_width});
        if (n.kind == NodeKind::ModelContact) out.push_back({n.p, n.contact, tip_width});
    }
    for (const auto& pl : t.pillars) out.push_back({pl.top, pl.bottom, p.d_min});
    return out;
}

// The nearest-next walk over a layer's islands, on a grid. It keeps the array order the plain
// O(n^2) walk would leave (that walk swaps each point it goes to into the next place) so that ties
// go to the same point.
class NearestNextWalk {
public:
    explicit NearestNextWalk(const std::vector<Vec3>& pts)
        : pts_(pts), at_(pts.size()), pos_(pts.size()), taken_(pts.size(), 0) {
        std::iota(at_.begin(), at_.end(), std::size_t{0});
        std::iota(pos_.begin(), pos_.end(), std::size_t{0});
        file(at_);
    }

    double length() {
        double len = 0;
        std::size_t cur = 0;
        take(cur);
        for (std::size_t i = 0; i + 1 < pts_.size(); ++i) {
            const std::size_t b = nearest(pts_[cur]);
            const std::size_t e = at_[i + 1], pb = pos_[b];  // the plain walk's swap of places i + 1 and pb
            at_[pb] = e, pos_[e] = pb, at_[i + 1] = b, pos_[b] = i + 1;
            len += horizontal_distance(pts_[cur], pts_[b]);
            take(b);
            cur = b;
        }
        return len;
    }

private:
    // Files the points in a grid of about one point per cell over their bounding box.
    void file(const std::vector<std::size_t>& ids) {
        double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
        for (std::size_t id : ids) {
            x0 = std::min(x0, pts_[id].x), x1 = std::max(x1, pts_[id].x);
            y0 = std::min(y0, pts_[id].y), y1 = std::max(y1, pts_[id].y);
        }
        const double m = static_cast<double>(ids.size());
        const double cell = std::max({std::sqrt((x1 - x0) * (y1 - y0) / m), std::max(x1 - x0, y1 - y0) / m, 1e-6});
        grid_ = XyGrid<std::size_t>(cell);
        for (std::size_t id : ids) grid_.insert(pts_[id], id);
        i0_ = grid_.index(x0), i1_ = grid_.index(x1), j0_ = grid_.index(y0), j1_ = grid_.index(y1);
        filed_ = alive_ = ids.size();
    }

    void take(std::size_t id) {
        grid_.erase(pts_[id], id);
        taken_[id] = 1;
        // Refile when three quarters are gone, so the rings searched stay about as dense as at first.
        if (--alive_ > 16 && 4 * alive_ < filed_) {
            std::vector<std::size_t> left;
            for (std::size_t k = 0; k < pts_.size(); ++k)
                if (!taken_[k]) left.push_back(k);
            file(left);
        }
    }

    // The nearest point still filed (squared XY distance as the plain walk compares them; a tie
    // goes to the one earliest in its array).
    std::size_t nearest(const Vec3& q) {
        std::size_t best = 0, best_pos = std::numeric_limits<std::size_t>::max();
        double best_d2 = std::numeric_limits<double>::infinity();
        const long ci = grid_.index(q.x), cj = grid_.index(q.y);
        const long rings = std::max({std::abs(ci - i0_), std::abs(ci - i1_), std::abs(cj - j0_), std::abs(cj - j1_)});
        for (long k = 0; k <= rings; ++k) {
            grid_.visit_ring(q, k, [&](std::size_t id) {
                const Vec3& b = pts_[id];
                const double d2 = (q.x - b.x) * (q.x - b.x) + (q.y - b.y) * (q.y - b.y);
                if (d2 < best_d2 || (d2 == best_d2 && pos_[id] < best_pos)) best = id, best_d2 = d2, best_pos = pos_[id];
            });
            // Every point beyond ring k is more than k cells away: once that is farther than the
            // best, none of them can win or tie (a nanometre of margin for rounding).
            const double beyond = k * grid_.cell() - 1e-6;
            if (beyond > 0 && beyond * beyond > best_d2) break;
        }
        return best;
    }

    const std::vector<Vec3>& pts_;
    std::vector<std::size_t> at_, pos_;  // at_[k]: the point in place k of the plain walk's array; pos_ its inverse
    std::vector<char> taken_;            // visited (no longer filed)
    XyGrid<std::size_t> grid_{1.0};
    long i0_ = 0, i1_ = 0, j0_ = 0, j1_ = 0;  // cells spanned by the points filed
    std::size_t filed_ = 0, alive_ = 0;
};

}  // namespace

double nearest_next_path(const std::vector<Vec3>& pts) {
    if (pts.size() < 2) return 0;
    return NearestNextWalk(pts).length();
}

SlicerCost estimate_slicer_cost(const SupportTree& t, const std::vector<double>& strut_width, const Params& p) {
    SlicerCost c;
    auto ups = uprights(t, strut_width, p);
    double top = 0;
    for (const auto& u : ups) top = std::max(top, u.top.z);
    const double h = p.layer_height;
    std::vector<double> zs;  // the middle of each layer, summed up as the slicer steps (same rounding)
    for (double z = 0.5 * h; z < top; z += h) zs.push_back(z);
    // Each upright filed under the layers it spans, in upright order: as many entries as island-layers.
    std::vector<std::vector<std::size_t>> on_layer(zs.size());
    for (std::size_t k = 0; k < ups.size(); ++k) {
        const Upright& u = ups[k];
        if (u.top.z == u.bottom.z) continue;
        const auto first = std::lower_bound(zs.begin(), zs.end(), u.bottom.z);
        const auto last = std::upper_bound(zs.begin(), zs.end(), u.top.z);
        for (auto it = first; it < last; ++it) on_layer[it - zs.begin()].push_back(k);
    }
    std::vector<Vec3> islands;
    for (std::size_t l = 0; l < zs.size(); ++l) {
        const double z = zs[l];
        islands.clear();
        for (std::size_t k : on_layer[l]) {
            const Upright& u = ups[k];
            islands.push_back(u.bottom + (u.top - u.bottom) * ((z - u.bottom.z) / (u.top.z - u.bottom.z)));
            c.outline_mm += outline_per_layer(u.width);
        }
        c.island_layers += islands.size();
        c.most_islands = std::max(c.most_islands, islands.size());
        c.travel_mm += nearest_next_path(islands);
    }
    c.cura_seconds = tree_route_seconds(kCuraRoute, c.island_layers, c.outline_mm, c.travel_mm);
    c.prusa_seconds = tree_route_seconds(kPrusaRoute, c.island_layers, c.outline_mm, c.travel_mm);
    c.seconds = 0.5 * (c.cura_seconds + c.prusa_seconds);
    return c;
}

}  // namespace cs

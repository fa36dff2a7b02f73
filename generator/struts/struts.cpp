#include "struts/struts.hpp"

#include <algorithm>
#include <numeric>

#include "core/rules.hpp"

namespace cs {
namespace {

struct Profile2D {
    std::vector<std::array<double, 2>> ring;  // counter-clockwise seen from +z
    std::vector<std::array<int, 3>> cap;      // triangles of the ring, counter-clockwise
};

// The N (paper Fig. 10) in a d x d square with walls t: left bar, right bar and the diagonal from
// the top-left to the bottom-right corner, as ONE simple polygon of 12 corners. The diagonal band
// is |x + y| <= t / sqrt(2), i.e. t thick. Collinear corners on the bars' inner edges are shared
// by the cap triangles so the caps have no T-junctions.
Profile2D n_profile(double d, double t) {
    const double a = d / 2, c = t / std::sqrt(2.0);
    Profile2D p;
    p.ring = {{-a, -a},         {-a + t, -a},         {-a + t, a - t - c}, {a - t, -a + t - c},
              {a - t, -a},      {a, -a},              {a, a},              {a - t, a},
              {a - t, -a + t + c}, {-a + t, a - t + c}, {-a + t, a},         {-a, a}};
    p.cap = {{0, 1, 2}, {0, 2, 9}, {0, 9, 11}, {9, 10, 11},  // left bar
             {4, 5, 6}, {4, 6, 3}, {3, 6, 8},  {8, 6, 7},    // right bar
             {2, 3, 8}, {2, 8, 9}};                          // diagonal
    return p;
}

Profile2D square_profile(double d) {
    const double a = d / 2;
    return {{{-a, -a}, {a, -a}, {a, a}, {-a, a}}, {{0, 1, 2}, {0, 2, 3}}};
}

Profile2D profile_of(Profile kind, double d, double wall) {
    return kind == Profile::N ? n_profile(d, wall) : square_profile(d);
}

}  // namespace

Vec3 foot_top(const Vec3& bed_point, const Vec3& above, const Params& p) {
    // At most half-way up its strut, so the foot never ends where the strut begins.
    double f = std::min(0.5, p.foot_height / above.z);
    return bed_point + (above - bed_point) * f;
}

double foot_extra(const Params& p, double strut_width, double room) {
    // The foot's corner reaches (w/2 + extra) * sqrt(2) from its centre.
    double fit = room / std::sqrt(2.0) - 0.5 * strut_width - p.model_clearance;
    double extra = std::min(p.foot_extra, fit);
    return extra >= 0.25 ? extra : 0.0;
}

SizedTree size_struts(SupportTree tree, const Params& p) {
    SizedTree s;
    const auto& nodes = tree.nodes;
    const auto& struts = tree.struts;
    const size_t n = nodes.size();
    s.out_strut.assign(n, -1);
    s.in_struts.assign(n, {});
    auto& out = s.out_strut;
    auto& in = s.in_struts;
    for (size_t e = 0; e < struts.size(); ++e) {
        out[struts[e].top] = static_cast<int>(e);
        in[struts[e].bottom].push_back(static_cast<int>(e));
    }
    s.contact_tip.assign(n, std::nullopt);
    for (size_t v = 0; v < n; ++v)
        if (nodes[v].kind == NodeKind::ModelContact) s.contact_tip[v] = contact_tip_bottom(nodes[v].contact, nodes[v].p, p);
    s.overlap = joint_overlap(p);
    s.struts.resize(struts.size());
    for (size_t e = 0; e < struts.size(); ++e) {
        const Vec3 &a = nodes[struts[e].top].p, &b = nodes[struts[e].bottom].p;
        s.struts[e].length = distance(a, b);
        s.struts[e].angle = angle_from_vertical_deg(a, b);
    }
    // Runs: a node with one strut in and one out that is not a leaf is a bend in one column.
    auto is_bend = [&](int v) { return in[v].size() == 1 && out[v] >= 0 && nodes[v].kind != NodeKind::Leaf; };
    for (size_t e = 0; e < struts.size(); ++e) {
        if (is_bend(struts[e].top)) continue;  // not the head of its run
        std::vector<int> run{static_cast<int>(e)};
        while (is_bend(struts[run.back()].bottom)) run.push_back(out[struts[run.back()].bottom]);
        double len = 0, ang = 0;
        for (int r : run) len += s.struts[r].length, ang = std::max(ang, s.struts[r].angle);
        for (int r : run) s.struts[r].run_length = len, s.struts[r].run_angle = ang;
    }

    // Widths, top down: every strut into a node is sized before the node.
    std::vector<int> order(n);
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int x, int y) { return nodes[x].p.z > nodes[y].p.z; });
    s.node_width.assign(n, p.d_min);
    for (int v : order) {
        std::vector<double> carried;
        for (int e : in[v]) carried.push_back(s.struts[e].bottom_width);
        if (carried.size() == 1) s.node_width[v] = carried[0];
        else if (carried.size() > 1) s.node_width[v] = merged_width(p, carried);
        if (out[v] < 0) continue;
        auto& st = s.struts[out[v]];
        double need = strength_width(p, st.run_length, st.run_angle);
        if (need > p.d_max) ++s.strength_violations;
        const EndWidths w = strut_end_widths(p, s.node_width[v], st.run_length, st.run_angle, st.length, st.angle);
        st.top_width = w.top;
        st.bottom_width = w.bottom;
        s.worst_length_to_width = std::max(s.worst_length_to_width, st.run_length / st.top_width);
    }
    s.tree = std::move(tree);
    return s;
}

std::vector<double> mean_strut_widths(const SizedTree& sized) {
    std::vector<double> widths;
    widths.reserve(sized.struts.size());
    for (const auto& z : sized.struts) widths.push_back(0.5 * (z.top_width + z.bottom_width));
    return widths;
}

std::vector<Body> build_bodies(const SizedTree& sized, const Params& p) {
    std::vector<Body> bodies;
    const auto& nodes = sized.tree.nodes;
    const double overlap = sized.overlap;
    auto profile = [&](double w0, double w1) { return std::min(w0, w1) >= min_n_width(p) ? Profile::N : Profile::Square; };
    // The width of the last strut into a node at its bottom, and of the strut out of it at its top.
    auto incoming_width = [&](size_t v) {
        return sized.in_struts[v].empty() ? p.d_min : sized.struts[sized.in_struts[v].back()].bottom_width;
    };
    auto outgoing_width = [&](size_t v) { return sized.out_strut[v] < 0 ? p.d_min : sized.struts[sized.out_strut[v]].top_width; };

    for (size_t e = 0; e < sized.tree.struts.size(); ++e) {
        const auto& st = sized.tree.struts[e];
        const auto& sz = sized.struts[e];
        Vec3 top = nodes[st.top].p, bottom = nodes[st.bottom].p;
        const Node& foot_node = nodes[st.bottom];
        if (foot_node.kind != NodeKind::Bed) {
            bottom = bottom + normalized(bottom - top) * overlap;
        } else if (p.feet && p.foot_height > 0 && foot_extra(p, sz.bottom_width, foot_node.room) > 0) {
            // On a foot, the strut stops just inside the foot's top rather than running through it.
            bottom = foot_top(foot_node.p, top, p) + normalized(bottom - top) * overlap;
        }
        bodies.push_back({BodyKind::Strut, profile(sz.top_width, sz.bottom_width), bottom, top, sz.bottom_width,
                          sz.top_width});
    }
    for (size_t v = 0; v < nodes.size(); ++v) {
        const Node& nd = nodes[v];
        if (nd.kind == NodeKind::Leaf) {
            const TipEnds t = leaf_tip(p, nd.p, nd.tip, outgoing_width(v));
            bodies.push_back({BodyKind::Tip, Profile::Square, t.bottom, t.top, t.bottom_width, t.top_width});
        } else if (nd.kind == NodeKind::ModelContact) {
            if (const auto& bottom = sized.contact_tip[v]) {
                const TipEnds t = contact_tip(p, *bottom, nd.p, incoming_width(v));
                bodies.push_back({BodyKind::ContactTip, Profile::Square, t.bottom, t.top, t.bottom_width, t.top_width});
            }
        } else if (nd.kind == NodeKind::Bed && p.feet && p.foot_height > 0 && !sized.in_struts[v].empty()) {
            const Vec3& above = nodes[sized.tree.struts[sized.in_struts[v].back()].top].p;
            Vec3 top = foot_top(nd.p, above, p);
            double w = incoming_width(v);
            double extra = foot_extra(p, w, nd.room);
            if (extra > 0) bodies.push_back({BodyKind::Foot, Profile::Square, nd.p, top, w + 2 * extra, w});
        }
    }
    for (const auto& pl : sized.tree.pillars)
        bodies.push_back({BodyKind::Pillar, Profile::Square, pl.bottom, pl.top, p.d_min, p.tip_diameter});
    return bodies;
}

Mesh body_mesh(const Body& b, double wall) {
    Profile2D lo = profile_of(b.profile, b.bottom_width, wall);
    Profile2D hi = profile_of(b.profile, b.top_width, wall);
    Mesh m;
    const auto n = static_cast<std::uint32_t>(lo.ring.size());
    for (const auto& q : lo.ring) m.vertices.push_back(b.bottom + Vec3{q[0], q[1], 0});
    for (const auto& q : hi.ring) m.vertices.push_back(b.top + Vec3{q[0], q[1], 0});
    for (const auto& t : lo.cap)  // bottom faces down: reversed
        m.faces.push_back({std::uint32_t(t[0]), std::uint32_t(t[2]), std::uint32_t(t[1])});
    for (const auto& t : hi.cap) m.faces.push_back({n + t[0], n + t[1], n + t[2]});
    for (std::uint32_t i = 0; i < n; ++i) {
        std::uint32_t j = (i + 1) % n;
        m.faces.push_back({i, j, n + j});
        m.faces.push_back({i, n + j, n + i});
    }
    return m;
}

Mesh bodies_mesh(const std::vector<Body>& bodies, double wall) {
    Mesh all;
    for (const auto& b : bodies) append(all, body_mesh(b, wall));
    return all;
}

Mesh bodies_mesh(const std::vector<Body>& bodies, double wall, Profile only) {
    Mesh some;
    for (const auto& b : bodies)
        if (b.profile == only) append(some, body_mesh(b, wall));
    return some;
}

}  // namespace cs

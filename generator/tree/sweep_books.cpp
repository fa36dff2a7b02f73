#include "tree/sweep_books.hpp"

#include <algorithm>

#include "tree/clearance.hpp"

namespace cs {

SweepBooks::SweepBooks(const ModelQuery& model, const Params& p) : model_(model), p_(p), fan_(p.critical_angle) {}

int SweepBooks::add_node(const Vec3& p, NodeKind kind, const Vec3& contact, double width) {
    Node n;
    n.p = p, n.kind = kind, n.contact = contact;
    t_.nodes.push_back(n);
    SweepNode b;
    b.width = width;
    books_.push_back(std::move(b));
    return static_cast<int>(t_.nodes.size()) - 1;
}

void SweepBooks::connect(int top, int bottom) {
    books_[bottom].up.push_back(top);
    books_[top].down = bottom;
    books_[top].made = struts_made_++;
}

std::vector<Strut> SweepBooks::struts() const {
    std::vector<int> tops;
    for (int v = 0; v < static_cast<int>(books_.size()); ++v)
        if (books_[v].down >= 0) tops.push_back(v);
    std::sort(tops.begin(), tops.end(), [&](int a, int b) { return books_[a].made < books_[b].made; });
    std::vector<Strut> out;
    out.reserve(tops.size());
    for (int v : tops) out.push_back({v, books_[v].down});
    return out;
}

EndWidths SweepBooks::widths(int from, const Vec3& to) const {
    const Vec3& a = t_.nodes[from].p;
    const double len = distance(a, to), angle = angle_from_vertical_deg(a, to);
    // A bend continues its run: the strength rule sizes the whole run as one column.
    return strut_end_widths(p_, books_[from].width, books_[from].run + len, angle, len, angle);
}

bool SweepBooks::clear(int from, const Vec3& to, double clearance, bool onto_model) const {
    const double air = clearance < 0 ? p_.model_clearance : clearance;
    return !enters_keep_out(p_, t_.nodes[from].p, to, bottom_width(from, to)) &&
           strut_is_clear(model_, t_.nodes[from].p, top_width(from, to), to, bottom_width(from, to), air, onto_model,
                          joint_overlap(p_)) &&
           run_stays_clear(from, to, std::min(air, p_.gap));
}

// A strut on from a bend lengthens the bend's run, and the strength rule widens the whole run as
// one column (struts/): the struts above in the run must still clear the model at that width by
// the z gap (nearer, they print fused to it).
bool SweepBooks::run_stays_clear(int from, const Vec3& to, double air) const {
    if (t_.nodes[from].kind != NodeKind::Chain) return true;
    const double run = books_[from].run + distance(t_.nodes[from].p, to);
    double angle = angle_from_vertical_deg(t_.nodes[from].p, to);
    std::vector<int> above;  // the tops of the run's struts, bottom up
    for (int v = from; v >= 0 && t_.nodes[v].kind == NodeKind::Chain && books_[v].up.size() == 1;) {
        const int u = books_[v].up[0];
        above.push_back(u);
        angle = std::max(angle, angle_from_vertical_deg(t_.nodes[u].p, t_.nodes[v].p));
        v = u;
    }
    for (int u : above) {
        const Vec3 &a = t_.nodes[u].p, &b = t_.nodes[books_[u].down].p;
        const EndWidths w = strut_end_widths(p_, books_[u].width, run, angle, distance(a, b), angle_from_vertical_deg(a, b));
        if (!strut_is_clear(model_, a, w.top, b, w.bottom, air, false, joint_overlap(p_))) return false;
    }
    return true;
}

bool SweepBooks::can_escape(const Vec3& a, double w) const { return cs::can_escape(model_, p_, fan_, a, w); }

}  // namespace cs

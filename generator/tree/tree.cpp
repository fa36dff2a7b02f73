#include "tree/tree.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <queue>
#include <unordered_map>

#include "core/xy_grid.hpp"
#include "query/model_query.hpp"
#include "struts/placement.hpp"

namespace cs {
namespace {

// Unit directions of the cone fan: the axis, then rings at half and 95% of the critical angle.
// 95% keeps a contact tip (which sits above its model point) inside the cone.
std::vector<Vec3> cone_fan(double critical_angle_deg) {
    std::vector<Vec3> dirs{{0, 0, -1}};
    for (double f : {0.5, 0.95}) {
        double a = deg_to_rad(f * critical_angle_deg);
        for (int i = 0; i < 8; ++i) {
            double phi = i * std::numbers::pi / 4 + (f < 0.9 ? 0 : std::numbers::pi / 8);
            dirs.push_back({std::sin(a) * std::cos(phi), std::sin(a) * std::sin(phi), -std::cos(a)});
        }
    }
    return dirs;
}

// Active nodes in an XY grid, for the "other active points" of the sweep, and as one list.
class ActiveGrid {
public:
    explicit ActiveGrid(double cell) : grid_(cell) {}

    void insert(int id, const Vec3& p) {
        grid_.insert(p, id);
        pos_[id] = list_.size();
        list_.push_back(id);
    }
    void remove(int id, const Vec3& p) {
        grid_.erase(p, id);
        size_t i = pos_[id];
        pos_[list_.back()] = i;
        list_[i] = list_.back();
        list_.pop_back();
        pos_.erase(id);
    }
    size_t size() const { return list_.size(); }

    // Calls visit(id) for active nodes in rings of cells around p until stop(ring_distance) says
    // that nothing farther can matter; falls back to all nodes when rings outgrow the population.
    template <typename Visit, typename Stop>
    void visit_near(const Vec3& p, Visit visit, Stop stop) const {
        for (long k = 0;; ++k) {
            if ((2 * k + 1) * (2 * k + 1) > 4 * static_cast<long>(list_.size()) + 64) {
                for (int id : list_) visit(id);
                return;
            }
            grid_.visit_ring(p, k, visit);
            if (stop(k * grid_.cell())) return;
        }
    }

private:
    XyGrid<int> grid_;
    std::unordered_map<int, size_t> pos_;
    std::vector<int> list_;
};

// SteepModel: a model point too steep to stand on, used only when nothing else fits.
enum class Target { InCone, Merge, Model, Bed, SteepModel };

struct Candidate {
    double dist;     // strut length
    Target type;
    double span = 0; // how far down the node stays an island of its own: what a slicer pays for
    int other = -1;  // the partner node of a merge
    Vec3 point;      // merge point, contact node, or bed point
    Vec3 contact;    // model point below a contact node
};

class Sweep {
public:
    Sweep(const ModelQuery& model, const Params& p)
        : model_(model), p_(p), tan_c_(std::tan(deg_to_rad(p.critical_angle))), fan_(cone_fan(p.critical_angle)),
          grid_(std::max(2.0 * p.sampling_distance, 1.0)) {
        vertical_only_.assign(fan_.size(), 0);
        vertical_only_[0] = 1;
        slanted_only_.assign(fan_.size(), 1);
        slanted_only_[0] = 0;
        fan_cos_min_ = 1;
        for (const auto& d : fan_) fan_cos_min_ = std::min(fan_cos_min_, -d.z);
    }

    SupportTree run(const std::vector<Sample>& samples) {
        hang_leaves(samples);
        while (!heap_.empty()) {
            auto [z, neg_id] = heap_.top();
            heap_.pop();
            int id = -neg_id;
            if (!active_[id]) continue;
            support(id);
        }
        std::erase_if(t_.struts, [](const Strut& s) { return s.top < 0; });  // dropped branches
        return std::move(t_);
    }

private:
    bool tree() const { return p_.strategy == "tree"; }

    int add_node(const Vec3& p, NodeKind kind, const Vec3& contact, double width) {
        t_.nodes.push_back({p, kind, contact});
        width_.push_back(width);
        active_.push_back(0);
        incoming_.push_back(0);
        in_struts_.emplace_back();
        run_.push_back(0);
        retries_.push_back(0);
        banned_.emplace_back();
        return static_cast<int>(t_.nodes.size()) - 1;
    }
    void activate(int id) {
        active_[id] = 1;
        grid_.insert(id, t_.nodes[id].p);
        heap_.push({t_.nodes[id].p.z, -id});
    }
    void retire(int id) {
        active_[id] = 0;
        grid_.remove(id, t_.nodes[id].p);
    }
    void connect(int top, int bottom) {
        in_struts_[bottom].push_back(static_cast<int>(t_.struts.size()));
        t_.struts.push_back({top, bottom});
        ++incoming_[bottom];
    }

    // Widths a strut from node `from` to `to` will have at its ends (estimates for clearance, by
    // the struts stage's rules; a run of several struts may come out a little wider).
    double top_width(int from, const Vec3& to) const {
        const Vec3& a = t_.nodes[from].p;
        // A bend continues its run: the strength rule sizes the whole run as one column.
        double need = strength_width(p_, run_[from] + distance(a, to), angle_from_vertical_deg(a, to));
        return std::clamp(std::max(width_[from], need), p_.d_min, p_.d_max);
    }
    double bottom_width(int from, const Vec3& to) const {
        const Vec3& a = t_.nodes[from].p;
        return std::max(top_width(from, to), eqn1_width(p_, distance(a, to), angle_from_vertical_deg(a, to)));
    }

    void hang_leaves(const std::vector<Sample>& samples) {
        const double tip = p_.gap + p_.tip_length;
        for (const auto& s : samples) {
            // Start just below the sample so the ray does not report the sample's own face.
            const Vec3 start = s.p - Vec3{0, 0, 1e-4};
            // A face with material right below it (overlapping shells) is no overhang.
            if (model_.inside(s.p - Vec3{0, 0, 0.01})) {
                ++t_.stats.internal;
                continue;
            }
            auto hit = model_.first_hit(start, {0, 0, -1});
            double below = hit ? hit->point.z : 0.0;
            double free = s.p.z - below;
            if (free <= touching_space(p_)) {
                ++t_.stats.touching;
                continue;
            }
            if (free < 2 * tip) {
                auto fit = hang_pillar(s.p);
                t_.stats.bridged += fit == PillarFit::TooLow;
                t_.stats.dropped += fit == PillarFit::NoRoom;
                continue;
            }
            const Vec3 top = place_tip_top(model_, s.p, p_);
            Vec3 at = leaf_position({top.x, top.y, s.p.z - tip});
            // A tip that would graze the model beside it moves its foot a little where it is clear.
            if (auto clear = clear_tip_foot(model_, at, top, p_); clear && can_escape(*clear, p_.d_min)) at = *clear;
            // A leaf in a crevice that no strut can leave, or whose tip's foot would lie in the model
            // (a low overhang over a step), is no leaf: a pillar stands there if one fits (a slot too low for a tip and a strut), else
            // the sample is dropped now, before others merge into it.
            const bool stuck = !can_escape(at, p_.d_min) || !square_is_clear(model_, at, p_.d_min);
            if (stuck && free <= safe_length(p_, p_.d_min, 0) && hang_pillar(s.p) == PillarFit::Fits) continue;
            int leaf = add_node(at, stuck ? NodeKind::Dropped : NodeKind::Leaf, s.p, p_.d_min);
            t_.nodes[leaf].tip = top;
            if (stuck) {
                ++t_.stats.dropped;
                continue;
            }
            activate(leaf);
        }
    }

    // Under a low overhang a pillar, placed by its whole footprint (struts/placement.hpp); where
    // none fits the print bridges the slot (too low) or the sample is given up (too tight).
    PillarFit hang_pillar(const Vec3& sample) {
        auto placed = fit_pillar(model_, sample, p_);
        if (placed.fit == PillarFit::Fits && sweep_meets_boxes(placed.pillar.top, placed.pillar.bottom, p_.d_min, 0, p_.keep_out))
            return PillarFit::NoRoom;  // it would stand in a user's blocker
        if (placed.fit == PillarFit::Fits) {
            t_.pillars.push_back(placed.pillar);
            ++t_.stats.pillars;
        }
        return placed.fit;
    }

    // Can a strut of width w leave point a at all: is a short strut along some fan direction
    // clear? Asked of leaves, merge points and bends before they are made, so no node is put
    // where nothing can carry it down.
    bool can_escape(const Vec3& a, double w) const {
        for (const auto& d : fan_) {
            double len = std::min(2.0, a.z / -d.z);
            Vec3 to = a + d * len;
            double wb = std::max(w, eqn1_width(p_, len, angle_from_vertical_deg(a, to)));
            if (strut_is_clear(model_, a, w, to, wb, 0.0)) return true;
        }
        return false;
    }

    // A leaf hangs straight below its sample unless the model is too close beside it (a sample
    // next to a wall): then it moves away from the wall, slanting its tip, so the strut below it
    // keeps its clearance. The shift stays well inside the cone and within half a sample spacing.
    Vec3 leaf_position(const Vec3& below) const {
        const double need = 0.5 * p_.d_min + p_.model_clearance + 0.05;
        double d = std::sqrt(model_.squared_distance(below));
        if (d >= need) return below;
        Vec3 away = below - model_.closest_point(below);
        away.z = 0;
        if (norm(away) < 1e-9) return below;
        double limit = std::min(0.5 * p_.sampling_distance, p_.tip_length * tan_c_ * 0.9);
        Vec3 moved = below + normalized(away) * std::min(need - d, limit);
        // In a slot narrower than a strut, moving off one wall meets the other: stay put.
        if (model_.segment_hits(below, moved) || model_.inside(moved)) return below;
        return moved;
    }

    // The node a strut ends at above model point c, reached from a node at height z_from.
    Vec3 contact_node(const Vec3& c, double z_from) const {
        // Normally a full tip above c; when the node is already close, half-way, so struts still descend.
        double up = std::min(p_.gap + p_.tip_length, 0.5 * std::max(0.0, z_from - c.z));
        return c + Vec3{0, 0, up};
    }

    // A tip can stand on a face that slopes at most 45 degrees; steeper, it would slide off and
    // its tip would dig into the wall.
    bool can_stand_on(std::size_t face) const {
        const Mesh& m = model_.mesh();
        return normalized(face_normal_unnormalized(m, m.faces[face])).z >= std::cos(deg_to_rad(45));
    }

    bool in_cone(const Vec3& apex, const Vec3& q) const {
        return apex.z > q.z && horizontal_distance(apex, q) <= (apex.z - q.z) * tan_c_ * (1 + 1e-9);
    }

    // Model and bed candidates along the fan. With a finite `reach`, slanted rays are first asked
    // whether the model is within that reach at all (a cheap segment test); the directions passed
    // over are marked in `skipped` for a second pass should nothing near be clear.
    void collect_contacts(int id, std::vector<Candidate>& out, double reach, std::vector<char>* skipped,
                          const std::vector<char>* only = nullptr) const {
        const Vec3& a = t_.nodes[id].p;
        bool slanted = tree() || !p_.supports_on_model;
        for (size_t i = 0; i < fan_.size(); ++i) {
            if (i > 0 && !slanted) break;
            if (only && !(*only)[i]) continue;
            const Vec3& d = fan_[i];
            if (i > 0 && std::isfinite(reach) && !model_.segment_hits(a, a + d * reach)) {
                if (skipped) (*skipped)[i] = 1;
                continue;
            }
            auto hit = model_.first_hit(a, d);
            if (hit) {
                if (!p_.supports_on_model) continue;
                if (i > 0 && !tree()) continue;
                Vec3 node = contact_node(hit->point, a.z);
                if (i > 0 && !in_cone(a, node)) continue;
                out.push_back({hit->distance, can_stand_on(hit->face) ? Target::Model : Target::SteepModel, a.z - node.z,
                               -1, node, hit->point});
            } else {
                // The bed along a slanted ray: longer than straight down, so taken only when the
                // vertical is blocked (or, buildplate-only, when the model is in the way).
                double len = a.z / -d.z;
                out.push_back({len, Target::Bed, a.z, -1, a + d * len, {}});
            }
        }
    }

    // Cheapest for the slicer first (island_cost): the fewest layers this node stays an island of
    // its own, so branches join as high as they can and trunks carry them down; then the shorter strut.
    static void by_cost(std::vector<Candidate>& c) {
        std::sort(c.begin(), c.end(), [](const Candidate& x, const Candidate& y) {
            if (x.span != y.span) return x.span < y.span;
            if (x.dist != y.dist) return x.dist < y.dist;
            if (x.type != y.type) return x.type < y.type;
            return x.other < y.other;
        });
    }

    // Takes the first candidate whose strut (and what it joins) fits; false when none does.
    bool take_first_clear(int id, const std::vector<Candidate>& cands) {
        for (const auto& c : cands) {
            if (c.type == Target::SteepModel || !clear(id, c)) continue;
            if (c.type == Target::Merge && (!clear(c.other, c.point) || !can_escape(c.point, merged_estimate(id, c))))
                continue;
            // Joining a node widens it: it must still fit through where it is.
            if (c.type == Target::InCone &&
                !can_escape(c.point, merged_width(p_, {width_[c.other], bottom_width(id, c.point)})))
                continue;
            accept(id, c);
            return true;
        }
        return false;
    }

    void collect_merges(int id, double bound, std::vector<Candidate>& out) {
        const Vec3 a = t_.nodes[id].p;
        // A partner at horizontal distance D meets this node at least D / (2 tan c) lower (both
        // at one height meet half-way; a lower partner meets lower still).
        const double lb = 1.0 / (2 * tan_c_);
        const size_t keep = 6;
        std::vector<Candidate> found;
        auto kth = [&] {
            if (found.size() < keep) return bound;
            std::nth_element(found.begin(), found.begin() + (keep - 1), found.end(),
                             [](const Candidate& x, const Candidate& y) { return x.span < y.span; });
            found.resize(keep);
            return std::min(bound, found.back().span);
        };
        grid_.visit_near(
            a,
            [&](int q) {
                if (q == id || std::find(banned_[id].begin(), banned_[id].end(), q) != banned_[id].end()) return;
                const Vec3& b = t_.nodes[q].p;
                if (b.z > a.z || (b.z == a.z && q < id)) return;  // only nodes the sweep has not passed
                Vec3 s = merge_point(a, b, tan_c_);
                if (s.z < p_.layer_height) return;
                double d = distance(a, s), span = a.z - s.z;
                if (d < 1e-9 || span >= bound) return;
                found.push_back({d, s == b ? Target::InCone : Target::Merge, span, q, s, {}});
            },
            [&](double ring) { return ring * lb >= kth(); });
        for (auto& c : found) out.push_back(c);
    }

    bool clear(int from, const Vec3& to, double clearance = -1, bool onto_model = false) const {
        return !enters_keep_out(from, to) &&
               strut_is_clear(model_, t_.nodes[from].p, top_width(from, to), to, bottom_width(from, to),
                              clearance < 0 ? p_.model_clearance : clearance, onto_model);
    }
    bool clear(int from, const Candidate& c, double clearance = -1) const {
        if (c.type == Target::Model && sweep_meets_boxes(c.point, c.contact, bottom_width(from, c.point), 0, p_.keep_out))
            return false;  // its contact tip would stand in a blocker
        return clear(from, c.point, clearance, c.type == Target::Model);  // a steep face: no relief
    }
    // A user's support blockers: the strut (reaching into its joint) and, on the bed, its foot.
    bool enters_keep_out(int from, const Vec3& to) const {
        if (p_.keep_out.empty()) return false;
        const double w = bottom_width(from, to), reach = 0.5 * p_.layer_height;
        if (sweep_meets_boxes(t_.nodes[from].p, to, w, reach, p_.keep_out)) return true;
        return to.z < 1e-6 && p_.feet &&
               sweep_meets_boxes(to, to + Vec3{0, 0, p_.foot_height}, w + 2 * p_.foot_extra, 0, p_.keep_out);
    }

    void support(int id) {
        std::vector<Candidate> cands;
        collect_contacts(id, cands, INFINITY, nullptr, &vertical_only_);
        // The columns baseline is what plain slicer supports do: straight down to whatever is
        // below, the model or the bed, no questions asked (unless the model is off limits).
        if (!tree() && !cands.empty() && (p_.supports_on_model || cands[0].type == Target::Bed)) {
            accept(id, cands[0]);
            return;
        }
        // Less of a drop than straight down is all that can win: the fan only looks as far as a
        // slanted ray can go within that drop at first.
        double bound = cands.empty() ? INFINITY : cands[0].span;
        std::vector<char> skipped(fan_.size(), 0);
        collect_contacts(id, cands, bound / fan_cos_min_, &skipped, &slanted_only_);
        bound = INFINITY;
        for (const auto& c : cands) bound = std::min(bound, c.span);
        if (tree()) collect_merges(id, bound * (1 + 1e-9), cands);
        by_cost(cands);
        if (take_first_clear(id, cands)) return;
        // Nothing near fits: the farther fan (slanted landings beyond the vertical's reach).
        std::vector<Candidate> far;
        collect_contacts(id, far, INFINITY, nullptr, &skipped);
        by_cost(far);
        if (take_first_clear(id, far)) return;
        cands.insert(cands.end(), far.begin(), far.end());
        by_cost(cands);
        if (step_down(id)) return;
        // In a tight spot, give up the extra air before giving up clearance altogether.
        for (const auto& c : cands) {
            if (!clear(id, c, 0.0)) continue;
            if (c.type == Target::Merge && !clear(c.other, c.point, 0.0)) continue;
            ++t_.stats.tight;
            accept(id, c);
            return;
        }
        if (step_down(id, 0.0)) {
            ++t_.stats.tight;
            return;
        }
        // Nothing fits here. First undo what was joined into this node, so the branches above try
        // again elsewhere (a merge made a node too wide for where it hangs); after that, drop it
        // and the branches above it rather than print supports fused into the model. The report
        // counts the samples lost; `check` judges whether their neighbours still cover them.
        if (undo_joins(id)) return;
        drop_with_branches(id);
    }

    // Detaches the struts ending at `id` and sends the nodes above back to the sweep, barred from
    // joining `id` again. A leaf stays (thin again) and retries; a merge point or bend is dropped.
    bool undo_joins(int id) {
        if (in_struts_[id].empty() || retries_[id] >= 2) return false;
        for (int e : in_struts_[id]) {
            int parent = t_.struts[e].top;
            t_.struts[e] = {-1, -1};
            banned_[parent].push_back(id);
            retries_[parent] = std::max(retries_[parent], retries_[id]) + 1;  // strictly more: it ends
            if (t_.nodes[id].kind != NodeKind::Chain && t_.stats.merges > 0) --t_.stats.merges;
            activate(parent);
        }
        in_struts_[id].clear();
        incoming_[id] = 0;
        if (t_.nodes[id].kind == NodeKind::Leaf) {
            width_[id] = p_.d_min;
            run_[id] = 0;
            ++retries_[id];
            if (active_[id]) retire(id);
            activate(id);
        } else {
            if (active_[id]) retire(id);
            if (t_.nodes[id].kind == NodeKind::Chain && t_.stats.steps > 0) --t_.stats.steps;
            t_.nodes[id].kind = NodeKind::Dropped;
        }
        ++t_.stats.undone;
        return true;
    }

    void drop_with_branches(int id) {
        std::vector<int> stack{id};
        while (!stack.empty()) {
            int v = stack.back();
            stack.pop_back();
            if (active_[v]) retire(v);
            if (t_.nodes[v].kind == NodeKind::Leaf) ++t_.stats.dropped;
            t_.nodes[v].kind = NodeKind::Dropped;
            for (int e : in_struts_[v]) {
                stack.push_back(t_.struts[e].top);
                t_.struts[e] = {-1, -1};
            }
            in_struts_[v].clear();
        }
        ++t_.stats.dropped_branches;
    }

    double merged_estimate(int id, const Candidate& c) const {
        return merged_width(p_, {bottom_width(id, c.point), bottom_width(c.other, c.point)});
    }

    void accept(int id, const Candidate& c) {
        retire(id);
        switch (c.type) {
            case Target::InCone:
                run_[c.other] = 0;  // now a branch point: a new run starts here
                connect(id, c.other);
                width_[c.other] = merged_width(p_, {width_[c.other], bottom_width(id, c.point)});
                ++t_.stats.merges;
                break;
            case Target::Merge: {
                double w = merged_width(p_, {bottom_width(id, c.point), bottom_width(c.other, c.point)});
                retire(c.other);
                int s = add_node(c.point, NodeKind::Merge, {}, w);
                retries_[s] = std::max(retries_[id], retries_[c.other]);
                connect(id, s);
                connect(c.other, s);
                activate(s);
                ++t_.stats.merges;
                break;
            }
            case Target::Model:
            case Target::SteepModel:
                connect(id, add_node(c.point, NodeKind::ModelContact, contact_under_tip(model_, c.contact, c.point.z, p_),
                                     bottom_width(id, c.point)));
                ++t_.stats.model_contacts;
                break;
            case Target::Bed: {
                int b = add_node(c.point, NodeKind::Bed, c.point, bottom_width(id, c.point));
                // Room for a foot: distance to the model from the middle of where a foot would be.
                Vec3 probe = c.point + Vec3{0, 0, 0.5 * p_.foot_height};
                t_.nodes[b].room = std::sqrt(model_.squared_distance(probe));
                connect(id, b);
                ++t_.stats.bed_contacts;
                break;
            }
        }
    }

    // No candidate is clear (a node in a tight spot): step down as far as a clear strut reaches
    // along the fan, and carry on from there. In buildplate-only mode this is how supports find
    // their way around the model to the bed.
    bool step_down(int id, double clearance = -1) {
        const Vec3 a = t_.nodes[id].p;
        double best_drop = 0;
        Vec3 best;
        for (const auto& d : fan_) {
            auto hit = model_.first_hit(a, d);
            double margin = 0.5 * width_[id] + p_.model_clearance + p_.d_min;
            double len = hit ? hit->distance - margin / std::max(0.2, -d.z) : a.z / -d.z;
            for (len = std::min(len, 20.0); len * -d.z > std::max(0.5, best_drop); len *= 0.4) {
                Vec3 to = a + d * len;
                if (clear(id, to, clearance) && (to.z < 1e-6 || can_escape(to, bottom_width(id, to)))) {
                    best_drop = a.z - to.z, best = to;
                    break;
                }
            }
        }
        if (best_drop < 0.5) return false;
        if (best.z < 1e-6) {
            accept(id, {best_drop, Target::Bed, best_drop, -1, {best.x, best.y, 0}, {}});
            return true;
        }
        retire(id);
        int c = add_node(best, NodeKind::Chain, {}, bottom_width(id, best));
        run_[c] = run_[id] + distance(a, best);
        retries_[c] = retries_[id];
        connect(id, c);
        activate(c);
        ++t_.stats.steps;
        return true;
    }

    const ModelQuery& model_;
    const Params& p_;
    double tan_c_;
    std::vector<Vec3> fan_;
    std::vector<char> vertical_only_, slanted_only_;  // masks over fan_
    double fan_cos_min_;                              // cosine of the fan's steepest slant
    SupportTree t_;
    std::vector<double> width_;  // estimated width at each node, for clearance
    std::vector<char> active_;
    std::vector<int> incoming_;
    std::vector<std::vector<int>> in_struts_;
    std::vector<double> run_;  // bends: length of the unbranched run above them
    std::vector<int> retries_;               // how often a node was sent back by undo_joins
    std::vector<std::vector<int>> banned_;   // nodes a node may not join again
    ActiveGrid grid_;
    std::priority_queue<std::pair<double, int>> heap_;  // highest first, then lowest id
};

}  // namespace

double SupportTree::total_length() const {
    double l = 0;
    for (const auto& s : struts) l += distance(nodes[s.top].p, nodes[s.bottom].p);
    return l;
}

double touching_space(const Params& p) { return 2 * p.gap + p.layer_height; }

double contact_tolerance(const Params& p) {
    double steepest = std::tan(deg_to_rad(90 - p.critical_angle));  // slope of the steepest overhang
    return p.gap + 0.5 * p.tip_diameter * steepest + 0.05;
}

Vec3 merge_point(const Vec3& a, const Vec3& b, double tan_c) {
    double D = horizontal_distance(a, b);
    double dz = a.z - b.z;
    if (D <= dz * tan_c) return b;
    double zs = (a.z + b.z - D / tan_c) / 2;
    double h = (a.z - zs) * tan_c;
    return {a.x + (b.x - a.x) / D * h, a.y + (b.y - a.y) / D * h, zs};
}

std::optional<Vec3> first_hit_in_cone(const ModelQuery& model, const Vec3& apex, double critical_angle_deg) {
    std::optional<Vec3> best;
    double best_d = INFINITY;
    for (const auto& d : cone_fan(critical_angle_deg)) {
        auto hit = model.first_hit(apex, d);
        if (hit && hit->distance < best_d) best_d = hit->distance, best = hit->point;
    }
    return best;
}

bool strut_is_clear(const ModelQuery& model, const Vec3& a, double wa, const Vec3& b, double wb, double clearance,
                    bool onto_model) {
    if (model.segment_hits(a, b)) return false;
    // The strut's own edges, and the same pushed out by the clearance (a bump of the model can
    // slip between the outer lines and still cut the strut, so both are asked).
    for (double c : {0.0, clearance}) {
        if (c == clearance && c == 0.0 && clearance != 0.0) continue;
        double ra = 0.5 * wa + c, rb = 0.5 * wb + c;
        // The built strut reaches a little past b into its joint (half a layer; 0.25 mm covers
        // any layer height): onto the model, that end must stay clear too.
        const Vec3 b_end = onto_model && c == 0.0 ? b + normalized(b - a) * 0.25 : b;
        for (auto [sx, sy] : {std::pair{1, 1}, {1, -1}, {-1, 1}, {-1, -1}}) {
            Vec3 ea = a + Vec3{sx * ra, sy * ra, 0}, eb = b_end + Vec3{sx * rb, sy * rb, 0};
            if (model.segment_hits(ea, eb)) return false;
        }
        if (clearance == 0.0) break;
    }
    if (onto_model) {
        // The strut's foot hangs a tip's length above the model: a ridge of the model can rise
        // between its edges into the foot's square. Spokes across the square catch it.
        const Vec3 foot = b + normalized(b - a) * 0.25;
        const double r = 0.5 * wb;
        for (auto [sx, sy] : {std::pair{1, 1}, {1, -1}, {-1, 1}, {-1, -1}, {1, 0}, {-1, 0}, {0, 1}, {0, -1}})
            if (model.segment_hits(foot, foot + Vec3{sx * r, sy * r, 0})) return false;
    }
    // The edges miss a bump of the model that pokes between them: also keep a ball around the
    // axis, as wide as the strut's square (half-diagonal), free of the model.
    double len = distance(a, b);
    // Balls of radius r spaced r apart cover the axis with overlap: no gap for a bump to hide in.
    double r_min = 0.5 * std::min(wa, wb) * std::sqrt(2.0);
    int steps = std::max(1, static_cast<int>(std::ceil(len / std::clamp(r_min, 0.35, 2.0))));
    // A strut onto the model ends a tip's length above it: near that end the balls shrink so they
    // stay clear of the contact itself (they still catch a bump between the edges).
    double end_room = onto_model ? 0.9 * std::sqrt(model.squared_distance(b)) : INFINITY;
    for (int i = 0; i <= steps; ++i) {
        double t = double(i) / steps;
        double r = std::min((0.5 * (wa + (wb - wa) * t)) * std::sqrt(2.0), (1 - t) * len + end_room);
        if (model.squared_distance(a + (b - a) * t) < r * r) return false;
    }
    return true;
}

namespace {

// Prices of the slicer cost model, for CuraEngine 4.13 with the bench profile (0.2 mm layers,
// acceleration 1500 mm/s^2, support as a support mesh with one wall and no infill); checked against
// its G-code in bench/results/tree_shape.md.
// Each island costs a stop and a start: accelerating to and from a hop of a few mm at 1500 mm/s^2
// takes about 2 * sqrt(d / a) = 0.1 s for d = 4 mm, the outline's seam adds its own stop, and some
// hops retract. What the G-code of four models leaves after outline and travel: 0.20-0.26 s.
constexpr double kIslandSeconds = 0.2;
// Outlines of 1 to 4 mm struts are drawn in segments of a few mm: at 1500 mm/s^2 they average well
// below the 60 mm/s support speed.
constexpr double kOutlineMmPerSecond = 30;
// Travel between islands at 150 mm/s, slowed the same way by acceleration over hops of a few mm.
constexpr double kTravelMmPerSecond = 100;

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

// Length of a path through the points, always on to the nearest one not yet visited.
double nearest_next_path(std::vector<Vec3> pts) {
    double len = 0;
    for (size_t i = 0; i + 1 < pts.size(); ++i) {
        size_t best = i + 1;
        for (size_t j = i + 2; j < pts.size(); ++j)
            if (horizontal_distance(pts[i], pts[j]) < horizontal_distance(pts[i], pts[best])) best = j;
        std::swap(pts[i + 1], pts[best]);
        len += horizontal_distance(pts[i], pts[i + 1]);
    }
    return len;
}

}  // namespace

SlicerCost estimate_slicer_cost(const SupportTree& t, const std::vector<double>& strut_width, const Params& p) {
    SlicerCost c;
    auto ups = uprights(t, strut_width, p);
    double top = 0;
    for (const auto& u : ups) top = std::max(top, u.top.z);
    const double h = p.layer_height;
    for (double z = 0.5 * h; z < top; z += h) {
        std::vector<Vec3> islands;
        for (const auto& u : ups) {
            if (u.top.z < z || u.bottom.z > z || u.top.z == u.bottom.z) continue;
            islands.push_back(u.bottom + (u.top - u.bottom) * ((z - u.bottom.z) / (u.top.z - u.bottom.z)));
            c.outline_mm += outline_per_layer(u.width);
        }
        c.island_layers += islands.size();
        c.most_islands = std::max(c.most_islands, islands.size());
        c.travel_mm += nearest_next_path(std::move(islands));
    }
    c.seconds = c.island_layers * kIslandSeconds + c.outline_mm / kOutlineMmPerSecond + c.travel_mm / kTravelMmPerSecond;
    return c;
}

SupportTree grow_tree(const ModelQuery& model, const std::vector<Sample>& samples, const Params& p) {
    return Sweep(model, p).run(samples);
}

}  // namespace cs

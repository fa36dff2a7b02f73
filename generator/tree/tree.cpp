#include "tree/tree.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <map>
#include <optional>
#include <queue>
#include <tuple>
#include <utility>

#include "core/rules.hpp"
#include "query/model_query.hpp"
#include "tree/candidates.hpp"
#include "tree/clearance.hpp"
#include "tree/placement.hpp"
#include "tree/sweep_books.hpp"
#include "tree/tuning.hpp"

namespace cs {
namespace {

// Cell of the sweep's XY grids (active nodes, feet): two sample spacings, so a node's nearest
// neighbours lie in its own cell or the ring around it.
double grid_cell(const Params& p) { return std::max(2.0 * p.sampling_distance, 1.0); }

// The sweep grows the tree top down. Its books (tree/sweep_books.hpp) hold the nodes and struts
// grown so far and one record per node: whether it is active, what it carries (estimated width,
// run length), and who may not join whom again. Where a node may go comes from
// tree/candidates.hpp, whether it fits from tree/clearance.hpp; the sweep takes the first that
// fits, or steps down, or undoes and drops.
class Sweep : SweepBooks {
public:
    Sweep(const ModelQuery& model, const Params& p, const std::vector<Box3>& support_blockers, GrowOptions options = {})
        : SweepBooks(model, p, support_blockers), options_(options), cx_{model, p, fan_, tree()} {}

    SupportTree hang_only(const std::vector<Sample>& samples) {
        hang_leaves(samples);
        count_from_tree();
        return std::move(t_);
    }

    // Grows from leaves hung by hang_only for the same model and parameters: what the sweep
    // would have hung itself, node for node, so the tree is the same as grown from the samples.
    SupportTree run(SupportTree hung) {
        std::vector<int> leaves;
        for (const Node& n : hung.nodes) {
            const int id = add_node(n.p, n.kind, n.contact, p_.d_min);
            t_.nodes[id] = n;
            if (n.kind == NodeKind::Leaf) leaves.push_back(id);
        }
        t_.pillars = std::move(hung.pillars);
        t_.stats = hung.stats;
        start(leaves);
        while (!heap_.empty()) {
            auto [z, neg_id] = heap_.top();
            heap_.pop();
            int id = -neg_id;
            if (!books_[id].active) continue;
            support(id);
        }
        if (tree()) raise_merges(*this);
        t_.grown_with = options_;
        t_.struts = struts();
        space_feet();
        count_from_tree();
        return std::move(t_);
    }

private:
    bool tree() const { return p_.strategy == Strategy::tree; }

    // What the finished tree shows by itself; the other stats count events of the sweep.
    void count_from_tree() {
        auto count = [&](NodeKind k) {
            return static_cast<std::size_t>(std::count_if(t_.nodes.begin(), t_.nodes.end(), [&](const Node& n) { return n.kind == k; }));
        };
        t_.stats.bed_contacts = count(NodeKind::Bed);
        t_.stats.model_contacts = count(NodeKind::ModelContact);
        t_.stats.pillars = t_.pillars.size();
    }

    // Feet of columns on the bed side by side (leaves gone down alone, at the sample spacing) may
    // come near each other but not into each other: a foot's room reaches at most half way to the
    // next, plus the air a foot keeps from the model (struts/foot_extra takes that off again).
    void space_feet() {
        XyGrid<int> beds(grid_cell(p_));
        for (int v = 0; v < static_cast<int>(t_.nodes.size()); ++v)
            if (t_.nodes[v].kind == NodeKind::Bed) beds.insert(t_.nodes[v].p, v);
        const double keep = std::sqrt(2.0) * p_.model_clearance - kTreeTuning.feet_apart;
        for (int v = 0; v < static_cast<int>(t_.nodes.size()); ++v) {
            Node& n = t_.nodes[v];
            if (n.kind != NodeKind::Bed) continue;
            beds.visit_near(n.p, 2, [&](int u) {
                if (u != v) n.room = std::min(n.room, 0.5 * horizontal_distance(n.p, t_.nodes[u].p) + keep);
            });
        }
    }

    void activate(int id) {
        books_[id].active = true;
        if (!books_[id].alone) pool(id).insert(id, t_.nodes[id].p);
        heap_.push({t_.nodes[id].p.z, -id});
    }
    void retire(int id) {
        books_[id].active = false;
        if (!books_[id].alone) pool(id).remove(id, t_.nodes[id].p);
    }
    // Each sample's leaf (its tip placed), pillar, or the reason it has neither; run() starts from these.
    void hang_leaves(const std::vector<Sample>& samples) {
        const double tip = p_.gap + p_.tip_length;
        for (const auto& s : samples) {
            // A face with material right below it (overlapping shells) is no overhang.
            if (material_right_below(model_, s.p)) {
                ++t_.stats.internal;
                continue;
            }
            // The air below it, as the sampling judges what rests on material (overhang.hpp).
            const double free = air_below(model_, s.p);
            if (rests_at(free, touching_space(p_))) {
                ++t_.stats.touching;
                continue;
            }
            if (free < 2 * tip) {
                auto fit = hang_pillar(s.p);
                t_.stats.bridged += fit == PillarFit::TooLow;
                t_.stats.dropped += fit == PillarFit::NoRoom;
                // Bridged or given up, the sample holds nothing up: the print bridges it only
                // where the overhang hangs no more than touching_space above what is below.
                if (fit != PillarFit::Fits) t_.no_pillar.push_back(s.p);
                continue;
            }
            const auto placed_top = place_tip_top(model_, s.p, p_);
            if (!placed_top) {  // no tip fits under it without reaching into the model
                add_node(s.p - Vec3{0, 0, tip}, NodeKind::Dropped, s.p, p_.d_min);
                ++t_.stats.dropped;
                continue;
            }
            const Vec3 top = *placed_top;
            Vec3 at = leaf_position(model_, p_, fan_.tan_c, {top.x, top.y, s.p.z - tip});
            // A tip that would graze the model beside it moves its foot a little where it is clear.
            if (auto clear = clear_tip_foot(model_, at, top, p_); clear && can_escape(*clear, p_.d_min)) at = *clear;
            // A leaf in a crevice that no strut can leave, or whose tip's foot would lie in the model
            // (a low overhang over a step), is no leaf: a pillar stands there if one fits (a slot too low for a tip and a strut), else
            // the sample is dropped now, before others merge into it.
            const bool stuck = !can_escape(at, p_.d_min) || !square_is_clear(model_, at, p_.d_min);
            if (stuck && free <= safe_length(p_, p_.d_min, 0) && hang_pillar(s.p) == PillarFit::Fits) continue;
            int leaf = add_node(at, stuck ? NodeKind::Dropped : NodeKind::Leaf, s.p, p_.d_min);
            t_.nodes[leaf].tip = top;
            t_.stats.dropped += stuck;
        }
    }
    // The sweep starts from the leaves, paired first if asked.
    void start(const std::vector<int>& leaves) {
        if (tree() && options_.pair_leaves_first) lean_tips_in_pairs(*this, leaves, options_.lean_quads);
        for (int leaf : leaves) activate(leaf);
    }

    // Under a low overhang a pillar, placed by its whole footprint (tree/placement.hpp); where
    // none fits the print bridges the slot (too low) or the sample is given up (too tight).
    PillarFit hang_pillar(const Vec3& sample) {
        auto placed = fit_pillar(model_, sample, p_);
        if (placed.fit == PillarFit::Fits && sweep_meets_boxes(placed.pillar.top, placed.pillar.bottom, p_.d_min, 0, support_blockers_))
            return PillarFit::NoRoom;  // it would stand in a user's blocker
        if (placed.fit == PillarFit::Fits) {
            placed.pillar.sample = sample;
            t_.pillars.push_back(placed.pillar);
        }
        return placed.fit;
    }

    // Takes the cheapest clear one (by_cost) of the landings in `cands` and the merges with a span
    // below `bound`. Merge partners are fetched in batches (collect_merges; each twice the last, so
    // a node in a pocket, where every partner is blocked, rescans the active nodes only a few
    // times), and a landing is tried only once no partner left to fetch could be cheaper: the
    // order is the same as with every partner fetched at once. False when none fits; `cands`
    // then holds all of them, in cost order.
    bool take_cheapest_clear(int id, std::vector<Candidate>& cands, double bound) {
        by_cost(cands);
        if (!tree() || books_[id].alone) return take_first_clear(id, cands);
        std::vector<Candidate> landings = std::move(cands), tried;
        std::optional<Candidate> after;
        bool more = true;
        for (std::size_t batch = kTreeTuning.merge_batch; more; batch *= 2) {
            std::vector<Candidate> now;
            collect_merges(cx_, pool(id), t_.nodes, id, books_[id].banned, bound, after ? &*after : nullptr, batch, now);
            more = now.size() == batch;
            if (more) after = *std::max_element(now.begin(), now.end(), cost_less);
            // Landings up to the batch's dearest merge go now; dearer ones wait for the next batch.
            auto wait = std::partition(landings.begin(), landings.end(),
                                       [&](const Candidate& c) { return !more || !cost_less(*after, c); });
            now.insert(now.end(), landings.begin(), wait);
            landings.erase(landings.begin(), wait);
            by_cost(now);
            if (take_first_clear(id, now)) return true;
            tried.insert(tried.end(), now.begin(), now.end());
        }
        cands = std::move(tried);
        return false;
    }

    // Takes the first candidate whose strut (and what it joins) fits; false when none does.
    bool take_first_clear(int id, const std::vector<Candidate>& cands) {
        for (const auto& c : cands) {
            if (too_wide_for_pool(id, c)) continue;
            if (c.type == Target::Merge && options_.lean_merging_leaves && merge_leaning(id, c)) return true;
            if (const int u = strut_alongside(id, c); u >= 0) {
                if (join_strut_alongside(id, u)) return true;
                continue;  // two struts in one column would carry both loads at the width of one
            }
            if (ends_where_a_strut_ends(c)) continue;
            if (c.type == Target::SteepModel || !clear(id, c)) continue;
            if (c.type == Target::Merge && (!clear(c.other, c.point) || !can_escape(c.point, merged_estimate(id, c))))
                continue;
            // Joining a node widens it: it must still fit through where it is.
            if (c.type == Target::InCone &&
                !can_escape(c.point, merged_width(p_, {books_[c.other].width, bottom_width(id, c.point)})))
                continue;
            accept(id, c);
            return true;
        }
        return false;
    }

    // Would the node that merge `c` makes be as wide as the dead end node `id`'s pool came out of
    // (SweepNode::width_cap)? Never for the nodes never released.
    bool too_wide_for_pool(int id, const Candidate& c) const {
        if (!std::isfinite(books_[id].width_cap) || (c.type != Target::Merge && c.type != Target::InCone)) return false;
        const double w = c.type == Target::Merge ? merged_estimate(id, c)
                                                 : merged_width(p_, {books_[c.other].width, bottom_width(id, c.point)});
        return w >= books_[id].width_cap;
    }

    // Would joining node `id` straight into an active node (InCone) lay its strut along a strut
    // already ending there? Coming down one line, the two would share faces and corners (not two
    // closed solids but one torn one: a bend straight above a bend, both 20 mm steps, in the
    // Menger sponge with --buildplate-only), and one column would carry two loads at the width of
    // one. The top of that strut, or -1. So does a landing (on the bed or the model) ending where a
    // strut made before ends, when node `id` lies on that strut (strut_to_the_same_end).
    int strut_alongside(int id, const Candidate& c) const {
        if (c.type != Target::InCone) return strut_to_the_same_end(id, c);
        const Vec3 &a = t_.nodes[id].p, &b = t_.nodes[c.other].p;
        for (int u : books_[c.other].up) {
            const Vec3& top = t_.nodes[u].p;
            // The lower of the two tops lies on the other strut's line (within a joint's overlap).
            if (top.z < a.z ? point_segment_distance(top, a, b) < joint_overlap(p_)
                            : point_segment_distance(a, top, b) < joint_overlap(p_))
                return u;
        }
        return -1;
    }
    // Landings ending where one made before ends (within a joint's overlap): two struts ending at
    // one point give their end caps the same faces, one torn solid, not two closed ones
    // (menger_sponge3 with --buildplate-only: a merge point made later on a column to the bed
    // went straight down to the column's foot). The top of such a strut that node `id` lies on,
    // so that it joins it (split_strut_at), or -1; any other landing there is not taken.
    int strut_to_the_same_end(int id, const Candidate& c) const {
        int along = -1;
        for_landings_ending_at(c, [&](int end) {
            for (int u : books_[end].up)
                if (point_segment_distance(t_.nodes[id].p, t_.nodes[u].p, t_.nodes[end].p) < joint_overlap(p_)) along = u;
        });
        return along;
    }
    bool ends_where_a_strut_ends(const Candidate& c) const {
        bool shared = false;
        for_landings_ending_at(c, [&](int) { shared = true; });
        return shared;
    }
    template <typename Visit>
    void for_landings_ending_at(const Candidate& c, Visit visit) const {
        if (c.type != Target::Bed && c.type != Target::Model && c.type != Target::SteepModel) return;
        ends_.visit_near(c.point, 1, [&](int end) {
            if (distance(t_.nodes[end].p, c.point) < joint_overlap(p_)) visit(end);
        });
    }

    // Node `id` joins the strut down from `top`, which its own strut would run along, where they meet: straight
    // above the strut's top it joins that top; on the strut (a bend landed on another's column)
    // the strut is split there. The strut below carries both, as wide as the merged load needs,
    // if it still clears the model at that width.
    bool join_strut_alongside(int id, int top) {
        if (t_.nodes[top].p.z >= t_.nodes[id].p.z) return split_strut_at(id, top);
        const int below = books_[top].down;
        const Vec3 &at = t_.nodes[top].p, &to = t_.nodes[below].p;
        if (!clear(id, at)) return false;
        const double was_width = books_[top].width, was_run = books_[top].run;
        books_[top].width = merged_width(p_, {books_[top].width, bottom_width(id, at)});
        books_[top].run = 0;  // now a branch point: a new run starts here
        const bool fits = !enters_support_blocker(p_, support_blockers_, at, to, bottom_width(top, to)) &&
                          strut_is_clear(model_, at, top_width(top, to), to, bottom_width(top, to), p_.model_clearance,
                                         false, joint_overlap(p_)) &&
                          can_escape(to, merged_width(p_, {books_[below].width, bottom_width(top, to)})) &&
                          contact_tip_fits(top, below);
        if (!fits) {
            books_[top].width = was_width, books_[top].run = was_run;
            return false;
        }
        retire(id);
        connect(id, top);
        books_[below].width = merged_width(p_, {books_[below].width, bottom_width(top, to)});
        ++t_.stats.merges;
        return true;
    }
    // Node `id` lies on the strut down from `top`: the strut ends at it, and it carries the
    // strut's load on down to where the strut went.
    bool split_strut_at(int id, int top) {
        const int below = books_[top].down;
        const Vec3 &a = t_.nodes[id].p, &to = t_.nodes[below].p;
        const double was_width = books_[id].width, was_run = books_[id].run;
        books_[id].width = merged_width(p_, {books_[id].width, bottom_width(top, a)});
        books_[id].run = 0;  // a branch point: a new run starts here
        if (!clear(id, to) || !can_escape(to, merged_width(p_, {books_[below].width, bottom_width(id, to)})) ||
            !contact_tip_fits(id, below)) {
            books_[id].width = was_width, books_[id].run = was_run;
            return false;
        }
        retire(id);
        books_[top].down = id;  // the same strut, made when it was: it keeps its place in the tree
        books_[id].up.push_back(top);
        std::erase(books_[below].up, top);
        connect(id, below);
        books_[below].width = merged_width(p_, {books_[below].width, bottom_width(id, to)});
        ++t_.stats.merges;
        return true;
    }

    // A strut that comes out wider onto a contact node already made: the contact's tip widens with it.
    bool contact_tip_fits(int from, int below) const {
        const Node& n = t_.nodes[below];
        return n.kind != NodeKind::ModelContact || contact_tip_is_clear(model_, p_, n.p, n.contact, bottom_width(from, n.p));
    }

    // Leaves about to merge lean first (GrowOptions::lean_merging_leaves): they meet a layer or two
    // below their tips instead of a strut's drop further down. False, with nothing changed, when
    // either cannot lean or the nearer merge does not fit.
    bool merge_leaning(int id, const Candidate& c) {
        const int other = c.other;
        const auto leaned = leaned_pair(id, other);
        if (!leaned) return false;
        const Vec3 a = t_.nodes[id].p, b = t_.nodes[other].p;
        const auto [a2, b2] = *leaned;
        const Vec3 m = merge_point(a2, b2, fan_.tan_c);
        if (m.z < p_.layer_height) return false;
        const Candidate c2{distance(a2, m), m == b2 ? Target::InCone : Target::Merge, a2.z - m.z, other, m, {}};
        move_node(id, a2);
        move_node(other, b2);
        const bool fits =
            clear(id, c2) && (c2.type == Target::InCone
                                  ? can_escape(m, merged_width(p_, {books_[other].width, bottom_width(id, m)}))
                                  : clear(other, m) && can_escape(m, merged_estimate(id, c2)));
        if (fits) {
            accept(id, c2);
            return true;
        }
        move_node(id, a);
        move_node(other, b);
        return false;
    }
    void move_node(int v, const Vec3& to) {
        const bool listed = books_[v].active && !books_[v].alone;
        if (listed) pool(v).remove(v, t_.nodes[v].p);
        t_.nodes[v].p = to;
        if (listed) pool(v).insert(v, to);
    }

    using SweepBooks::clear;
    bool clear(int from, const Candidate& c, double clearance = -1) const {
        if (c.type == Target::Model && sweep_meets_boxes(c.point, c.contact, bottom_width(from, c.point), 0, support_blockers_))
            return false;  // its contact tip would stand in a blocker
        if (c.type == Target::Model && !contact_tip_is_clear(model_, p_, c.point, c.contact, bottom_width(from, c.point)))
            return false;  // its contact tip, widening into the strut, would reach into the model
        return clear(from, c.point, clearance, c.type == Target::Model);  // a steep face: no relief
    }
    void support(int id) {
        if (find_way_down(id)) return;
        // Nothing fits here. First undo what was joined into this node, so the branches above try
        // again elsewhere (a merge made a node too wide for where it hangs); after that, break up
        // the branches above it: each leaf goes down again alone. A leaf that cannot get down alone
        // stands on a steep face if its tip fits there, else it is dropped rather than printed
        // fused into the model; the report counts the samples lost and `check` judges whether
        // their neighbours still cover them.
        if (undo_joins(id)) return;
        if (stand_on_steep_face(id)) return;
        release_branches(id);
    }

    // The last way down of a node going down alone (released from a dead end twice): a model face
    // steeper than a tip stands on by choice (kTreeTuning.stand_on_slope_deg), if the contact's
    // tip fits on it as the struts stage builds it (contact_tip_is_clear: its foot on the slope,
    // no corner in the model) and the strut reaches it with the z gap's air, as a tight landing
    // (take_tight) keeps it. Without it a face a fraction of a degree past that slope loses the
    // leaf, and the overhang it holds, though a tip stands there as on the slope itself:
    // wall_rack in its auto pose, a shelf's top and lip 45.1-45.2 deg steep under the keyholes,
    // the lip barring every other way down. Only where the leaf was lost: no other tree changes.
    bool stand_on_steep_face(int id) {
        if (!books_[id].alone) return false;
        std::vector<Candidate> cands;
        collect_contacts(cx_, t_.nodes[id].p, INFINITY, nullptr, nullptr, cands);
        std::erase_if(cands, [](const Candidate& c) { return c.type != Target::SteepModel; });
        by_cost(cands);
        for (const Candidate& c : cands) {
            if (sweep_meets_boxes(c.point, c.contact, bottom_width(id, c.point), 0, support_blockers_) ||
                !contact_tip_is_clear(model_, p_, c.point, c.contact, bottom_width(id, c.point)) ||
                !clear(id, c.point, p_.gap, true))
                continue;
            ++t_.stats.tight;
            accept(id, c);
            return true;
        }
        return false;
    }

    // Takes the cheapest clear strut down from node `id`, a bend, or a tight fit; false if none.
    bool find_way_down(int id) {
        std::vector<Candidate> cands;
        collect_contacts(cx_, t_.nodes[id].p, INFINITY, nullptr, &fan_.vertical_only, cands);
        // The columns baseline is what plain slicer supports do: straight down to whatever is
        // below, the model or the bed, no questions asked (unless the model is off limits).
        if (!tree() && !cands.empty() && (p_.supports_on_model || cands[0].type == Target::Bed)) {
            accept(id, cands[0]);
            return true;
        }
        // Less of a drop than straight down is all that can win: the fan only looks as far as a
        // slanted ray can go within that drop at first.
        double bound = cands.empty() ? INFINITY : cands[0].span;
        std::vector<char> skipped(fan_.dirs.size(), 0);
        collect_contacts(cx_, t_.nodes[id].p, bound / fan_.cos_min, &skipped, &fan_.slanted_only, cands);
        // Merges are searched only as far down as the best other way could win. A steep face (a
        // wall beside the node) can never be stood on, so it bounds nothing: a trunk beside a wall
        // would otherwise never see the neighbour a few mm away and go to the bed alone.
        bound = INFINITY;
        for (const auto& c : cands)
            if (c.type != Target::SteepModel) bound = std::min(bound, c.span);
        if (take_cheapest_clear(id, cands, bound * (1 + 1e-9))) return true;
        // Nothing near fits: the farther fan (slanted landings beyond the vertical's reach).
        std::vector<Candidate> far;
        collect_contacts(cx_, t_.nodes[id].p, INFINITY, nullptr, &skipped, far);
        by_cost(far);
        if (take_first_clear(id, far)) return true;
        cands.insert(cands.end(), far.begin(), far.end());
        by_cost(cands);
        if (step_down(id)) return true;
        // In a tight spot, give up the extra air, down to the z gap: nearer than that, a strut
        // prints fused to the model.
        return take_tight(id, cands, p_.gap);
    }

    // The first candidate, or else a step down, clear with only `air` around the strut.
    bool take_tight(int id, const std::vector<Candidate>& cands, double air) {
        for (const auto& c : cands) {
            if (strut_alongside(id, c) >= 0 || ends_where_a_strut_ends(c) || !clear(id, c, air)) continue;
            if (c.type == Target::Merge && !clear(c.other, c.point, air)) continue;
            ++t_.stats.tight;
            accept(id, c);
            return true;
        }
        if (!step_down(id, air)) return false;
        ++t_.stats.tight;
        return true;
    }

    // Detaches the struts ending at `id` and sends the nodes above back to the sweep, barred from
    // joining `id` again. A leaf stays (thin again) and retries; a merge point or bend is dropped.
    bool undo_joins(int id) {
        if (books_[id].up.empty() || books_[id].retries >= 2) return false;
        for (int parent : books_[id].up) {
            books_[parent].down = -1;
            books_[parent].banned.push_back(id);
            if (t_.nodes[id].kind == NodeKind::Bend) books_[parent].failed_bends.push_back(t_.nodes[id].p);
            books_[parent].retries = std::max(books_[parent].retries, books_[id].retries) + 1;  // strictly more: it ends
            if (t_.nodes[id].kind != NodeKind::Bend && t_.stats.merges > 0) --t_.stats.merges;
            activate(parent);
        }
        books_[id].up.clear();
        if (t_.nodes[id].kind == NodeKind::Leaf) {
            books_[id].width = p_.d_min;
            books_[id].run = 0;
            ++books_[id].retries;
            if (books_[id].active) retire(id);
            activate(id);
        } else {
            if (books_[id].active) retire(id);
            if (t_.nodes[id].kind == NodeKind::Bend && t_.stats.steps > 0) --t_.stats.steps;
            t_.nodes[id].kind = NodeKind::Dropped;
        }
        ++t_.stats.undone;
        return true;
    }

    // Takes apart the dead end `id` and everything joined into it. Each leaf above starts again
    // from its own place, thin. The first time, it merges again, but only with the other leaves
    // released from this dead end and only into nodes thinner than the dead end: a trunk too wide
    // to land where its leaves can (a shelf arm over a 45 degree brace: a 3 mm trunk finds no
    // clear landing on the brace, 1 mm leaves do) need not cost every leaf an island of its own
    // all the way down (there, 33 leaves each 9 mm alone, half the part's island-layers). A leaf
    // from such a second try that ends in a dead end again goes alone: it merges with no one and
    // no one with it. So a dead end costs at most two more descents per leaf, and only the leaves
    // that find no way down even alone are lost.
    void release_branches(int id) {
        const int released_pool = id + 1;
        const double dead_end_width = books_[id].width;
        std::vector<int> stack{id};
        std::size_t lost = 0;
        while (!stack.empty()) {
            int v = stack.back();
            stack.pop_back();
            if (books_[v].active) retire(v);
            for (int u : books_[v].up) {
                stack.push_back(u);
                books_[u].down = -1;
            }
            books_[v].up.clear();
            if (t_.nodes[v].kind == NodeKind::Leaf && !books_[v].alone) {
                if (books_[v].pool == 0)
                    restart_in_pool(v, released_pool, dead_end_width);
                else
                    restart_alone(v);
                continue;
            }
            // A leaf that went down alone and still ends here: a steep face it could have stood on
            // from where it hangs (the pocket its bends led it into may offer none).
            if (t_.nodes[v].kind == NodeKind::Leaf && v != id && stand_on_steep_face(v)) continue;
            if (t_.nodes[v].kind == NodeKind::Leaf) ++lost;
            t_.nodes[v].kind = NodeKind::Dropped;
        }
        t_.stats.dropped += lost;
        t_.stats.dropped_branches += lost > 0;
    }
    void restart_alone(int leaf) {
        books_[leaf].alone = true;
        books_[leaf].width = p_.d_min;
        books_[leaf].run = 0;
        activate(leaf);
    }
    void restart_in_pool(int leaf, int pool, double width_cap) {
        books_[leaf].pool = pool;
        books_[leaf].width_cap = width_cap;
        books_[leaf].width = p_.d_min;
        books_[leaf].run = 0;
        activate(leaf);
    }
    // The active nodes that node `id` may merge with: those of its pool (SweepNode::pool).
    ActiveNodes& pool(int id) { return pools_.try_emplace(books_[id].pool, grid_cell(p_)).first->second; }

    double merged_estimate(int id, const Candidate& c) const {
        return merged_width(p_, {bottom_width(id, c.point), bottom_width(c.other, c.point)});
    }

    void accept(int id, const Candidate& c) {
        retire(id);
        switch (c.type) {
            case Target::InCone:
                books_[c.other].run = 0;  // now a branch point: a new run starts here
                connect(id, c.other);
                books_[c.other].width = merged_width(p_, {books_[c.other].width, bottom_width(id, c.point)});
                ++t_.stats.merges;
                break;
            case Target::Merge: {
                double w = merged_width(p_, {bottom_width(id, c.point), bottom_width(c.other, c.point)});
                retire(c.other);
                int s = add_node(c.point, NodeKind::Merge, {}, w);
                books_[s].retries = std::max(books_[id].retries, books_[c.other].retries);
                books_[s].pool = books_[id].pool;  // partners come from one pool
                books_[s].width_cap = books_[id].width_cap;
                connect(id, s);
                connect(c.other, s);
                activate(s);
                ++t_.stats.merges;
                break;
            }
            case Target::Model:
            case Target::SteepModel: {
                const int m = add_node(c.point, NodeKind::ModelContact, contact_under_tip(model_, c.contact, c.point.z, p_),
                                       bottom_width(id, c.point));
                ends_.insert(c.point, m);
                connect(id, m);
                break;
            }
            case Target::Bed: {
                int b = add_node(c.point, NodeKind::Bed, c.point, bottom_width(id, c.point));
                // Room for a foot: distance to the model from the middle of where a foot would be.
                Vec3 probe = c.point + Vec3{0, 0, 0.5 * p_.foot_height};
                t_.nodes[b].room = std::sqrt(model_.squared_distance(probe));
                ends_.insert(c.point, b);
                connect(id, b);
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
        const TreeTuning& k = kTreeTuning;
        for (const auto& d : fan_.dirs) {
            if (passes_failed_bend(id, a, d)) continue;
            auto hit = model_.first_hit(a, d);
            double margin = 0.5 * books_[id].width + p_.model_clearance + p_.d_min;
            double len = hit ? hit->distance - margin / std::max(k.step_min_cos, -d.z) : a.z / -d.z;
            for (len = std::min(len, k.step_reach); len * -d.z > std::max(k.step_min_drop, best_drop); len *= k.step_shrink) {
                Vec3 to = a + d * len;
                const bool on_bed = to.z < 1e-6;
                if (clear(id, to, clearance) &&
                    (on_bed ? !ends_where_a_strut_ends({0, Target::Bed, 0, -1, {to.x, to.y, 0}, {}})
                            : can_escape(to, bottom_width(id, to))) &&
                    !passes_through_a_node(id, a, to)) {
                    best_drop = a.z - to.z, best = to;
                    break;
                }
            }
        }
        if (best_drop < k.step_min_drop) return false;
        if (best.z < 1e-6) {
            accept(id, {best_drop, Target::Bed, best_drop, -1, {best.x, best.y, 0}, {}});
            return true;
        }
        retire(id);
        int c = add_node(best, NodeKind::Bend, {}, bottom_width(id, best));
        books_[c].alone = books_[id].alone;
        books_[c].pool = books_[id].pool;
        books_[c].width_cap = books_[id].width_cap;
        books_[c].run = books_[id].run + distance(a, best);
        books_[c].retries = books_[id].retries;
        connect(id, c);
        activate(c);
        ++t_.stats.steps;
        return true;
    }

    // Would a bend from `a` to `to` pass through another active node? That node could then only
    // go down inside the bend's strut: two struts along one line (strut_alongside).
    bool passes_through_a_node(int id, const Vec3& a, const Vec3& to) const {
        const Vec3 mid = (a + to) * 0.5;
        const double reach = 0.5 * horizontal_distance(a, to) + grid_cell(p_);
        bool hit = false;
        auto look_in = [&](int k) {
            const auto listed = pools_.find(k);
            if (listed == pools_.end()) return;
            listed->second.visit_near(
                mid,
                [&](int q) {
                    const Vec3& b = t_.nodes[q].p;
                    hit = hit || (q != id && b.z < a.z && b.z > to.z && point_segment_distance(b, a, to) < joint_overlap(p_));
                },
                [&](double ring) { return hit || ring > reach; });
        };
        look_in(0);  // the nodes never released
        if (!hit && books_[id].pool != 0) look_in(books_[id].pool);
        return hit;
    }

    bool passes_failed_bend(int id, const Vec3& a, const Vec3& d) const {
        const Vec3 far = a + d * kTreeTuning.step_reach;
        return std::any_of(books_[id].failed_bends.begin(), books_[id].failed_bends.end(), [&](const Vec3& f) {
            return point_segment_distance(f, a, far) < kTreeTuning.failed_bend_radius;
        });
    }

    GrowOptions options_;
    CandidateContext cx_;
    std::map<int, ActiveNodes> pools_;  // active nodes by SweepNode::pool
    XyGrid<int> ends_{grid_cell(p_)};   // the landings made: bed feet and contact nodes
    std::priority_queue<std::pair<double, int>> heap_;  // highest first, then lowest id
};

}  // namespace

double SupportTree::total_length() const {
    double l = 0;
    for (const auto& s : struts) l += distance(nodes[s.top].p, nodes[s.bottom].p);
    return l;
}

SupportTree grow_tree(const ModelQuery& model, const std::vector<Sample>& samples, const Params& p,
                      GrowOptions options, const std::vector<Box3>& support_blockers) {
    return grow_tree(model, hang_leaves(model, samples, p, support_blockers), p, options, support_blockers);
}

SupportTree grow_tree(const ModelQuery& model, SupportTree hung, const Params& p, GrowOptions options,
                      const std::vector<Box3>& support_blockers) {
    return Sweep(model, p, support_blockers, options).run(std::move(hung));
}

SupportTree hang_leaves(const ModelQuery& model, const std::vector<Sample>& samples, const Params& p,
                        const std::vector<Box3>& support_blockers) {
    return Sweep(model, p, support_blockers).hang_only(samples);
}

SupportTree hang_more_leaves(const ModelQuery& model, SupportTree hung, std::vector<Sample> more, const Params& p,
                             const std::vector<Box3>& support_blockers) {
    // Each sample hangs by itself (its leaf, pillar or reason depends on the model alone) and
    // hung trees list them in sample order: merged by the samples' order (sort_top_down's), the
    // lists are what hanging every sample again would give, node for node.
    sort_top_down(more);
    SupportTree added = hang_leaves(model, more, p, support_blockers);
    auto before = [](const Vec3& a, const Vec3& b) {
        if (a.z != b.z) return a.z > b.z;
        if (a.x != b.x) return a.x < b.x;
        return a.y < b.y;
    };
    SupportTree out;
    std::merge(hung.nodes.begin(), hung.nodes.end(), added.nodes.begin(), added.nodes.end(), std::back_inserter(out.nodes),
               [&](const Node& a, const Node& b) { return before(a.contact, b.contact); });
    std::merge(hung.pillars.begin(), hung.pillars.end(), added.pillars.begin(), added.pillars.end(),
               std::back_inserter(out.pillars), [&](const Pillar& a, const Pillar& b) { return before(a.sample, b.sample); });
    std::merge(hung.no_pillar.begin(), hung.no_pillar.end(), added.no_pillar.begin(), added.no_pillar.end(),
               std::back_inserter(out.no_pillar), before);
    out.stats = hung.stats;
    out.stats.internal += added.stats.internal;
    out.stats.touching += added.stats.touching;
    out.stats.bridged += added.stats.bridged;
    out.stats.dropped += added.stats.dropped;
    out.stats.pillars = out.pillars.size();
    return out;
}

}  // namespace cs

#include "tree/candidates.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "query/model_query.hpp"
#include "tree/tree.hpp"
#include "tree/tuning.hpp"
#include "tree/verdicts.hpp"

namespace cs {
namespace {

// The node a strut ends at above model point c, reached from a node at height z_from.
Vec3 contact_node(const Params& p, const Vec3& c, double z_from) {
    // Normally a full tip above c; when the node is already close, half-way, so struts still descend.
    double up = std::min(p.gap + p.tip_length, 0.5 * std::max(0.0, z_from - c.z));
    return c + Vec3{0, 0, up};
}

// A tip can stand on a face that slopes at most kTreeTuning.stand_on_slope_deg; steeper, it would
// slide off and its tip would dig into the wall.
bool can_stand_on(const ModelQuery& model, std::size_t face) {
    const Mesh& m = model.mesh();
    return normalized(face_normal_unnormalized(m, m.faces[face])).z >= std::cos(deg_to_rad(kTreeTuning.stand_on_slope_deg));
}

bool in_cone(const Vec3& apex, const Vec3& q, double tan_c) {
    return apex.z > q.z && horizontal_distance(apex, q) <= (apex.z - q.z) * tan_c * (1 + 1e-9);
}

}  // namespace

Vec3 merge_point(const Vec3& a, const Vec3& b, double tan_c) {
    double D = horizontal_distance(a, b);
    double dz = a.z - b.z;
    if (D <= dz * tan_c) return b;
    double zs = (a.z + b.z - D / tan_c) / 2;
    double h = (a.z - zs) * tan_c;
    return {a.x + (b.x - a.x) / D * h, a.y + (b.y - a.y) / D * h, zs};
}

std::vector<Vec3> cone_fan(double critical_angle_deg) {
    const int n = kTreeTuning.fan_directions;
    std::vector<Vec3> dirs{{0, 0, -1}};
    for (size_t ring = 0; ring < kTreeTuning.fan_rings.size(); ++ring) {
        double a = deg_to_rad(kTreeTuning.fan_rings[ring] * critical_angle_deg);
        for (int i = 0; i < n; ++i) {
            // Every other ring turned by half a step: the rings interleave.
            double phi = i * 2 * std::numbers::pi / n + (ring % 2 ? std::numbers::pi / n : 0);
            dirs.push_back({std::sin(a) * std::cos(phi), std::sin(a) * std::sin(phi), -std::cos(a)});
        }
    }
    return dirs;
}

ConeFan::ConeFan(double critical_angle_deg)
    : dirs(cone_fan(critical_angle_deg)), tan_c(std::tan(deg_to_rad(critical_angle_deg))) {
    vertical_only.assign(dirs.size(), 0);
    vertical_only[0] = 1;
    slanted_only.assign(dirs.size(), 1);
    slanted_only[0] = 0;
    for (const auto& d : dirs) cos_min = std::min(cos_min, -d.z);
}

namespace {

// segment_hits(a, b) for a fan direction's reach from a node, remembered: the three ways a tree
// grows from the same leaves ask it of the same nodes.
bool reach_hits(const ModelQuery& model, const Vec3& a, const Vec3& b) {
    return model.verdict(tree_question(TreeVerdict::fan_reach, {a.x, a.y, a.z, b.x, b.y, b.z}), [&] { return model.segment_hits(a, b); });
}

}  // namespace

void collect_contacts(const CandidateContext& cx, const Vec3& a, double reach, std::vector<char>* skipped,
                      const std::vector<char>* only, std::vector<Candidate>& out) {
    const auto& fan = cx.fan.dirs;
    const bool slanted = cx.tree || !cx.p.supports_on_model;
    for (size_t i = 0; i < fan.size(); ++i) {
        if (i > 0 && !slanted) break;
        if (only && !(*only)[i]) continue;
        const Vec3& d = fan[i];
        if (i > 0 && std::isfinite(reach) && !reach_hits(cx.model, a, a + d * reach)) {
            if (skipped) (*skipped)[i] = 1;
            continue;
        }
        auto hit = cx.model.first_hit(a, d);
        if (hit) {
            if (!cx.p.supports_on_model) continue;
            if (i > 0 && !cx.tree) continue;
            Vec3 node = contact_node(cx.p, hit->point, a.z);
            if (i > 0 && !in_cone(a, node, cx.fan.tan_c)) continue;
            out.push_back({hit->distance, can_stand_on(cx.model, hit->face) ? Target::Model : Target::SteepModel,
                           a.z - node.z, -1, node, hit->point});
        } else {
            // The bed along a slanted ray: longer than straight down, so taken only when the
            // vertical is blocked (or, buildplate-only, when the model is in the way).
            double len = a.z / -d.z;
            out.push_back({len, Target::Bed, a.z, -1, a + d * len, {}});
        }
    }
}

void ActiveNodes::insert(int id, const Vec3& p) {
    grid_.insert(p, id);
    pos_[id] = list_.size();
    list_.push_back(id);
}

void ActiveNodes::remove(int id, const Vec3& p) {
    grid_.erase(p, id);
    std::size_t i = pos_[id];
    pos_[list_.back()] = i;
    list_[i] = list_.back();
    list_.pop_back();
    pos_.erase(id);
}

void collect_merges(const CandidateContext& cx, const ActiveNodes& active, const std::vector<Node>& nodes, int id,
                    const std::vector<int>& banned, double bound, const Candidate* after, std::size_t keep,
                    std::vector<Candidate>& out) {
    const Vec3 a = nodes[id].p;
    const double tan_c = cx.fan.tan_c;
    // A partner at horizontal distance D meets this node at least D / (2 tan c) lower (both
    // at one height meet half-way; a lower partner meets lower still).
    const double lb = 1.0 / (2 * tan_c);
    std::vector<Candidate> found;
    auto kth = [&] {
        if (found.size() < keep) return bound;
        std::nth_element(found.begin(), found.begin() + (keep - 1), found.end(), cost_less);
        found.resize(keep);
        return std::min(bound, found.back().span);
    };
    active.visit_near(
        a,
        [&](int q) {
            if (q == id || std::find(banned.begin(), banned.end(), q) != banned.end()) return;
            const Vec3& b = nodes[q].p;
            if (b.z > a.z || (b.z == a.z && q < id)) return;  // only nodes the sweep has not passed
            Vec3 s = merge_point(a, b, tan_c);
            if (s.z < cx.p.layer_height) return;
            double d = distance(a, s), span = a.z - s.z;
            if (d < 1e-9 || span >= bound) return;
            const Candidate c{d, s == b ? Target::InCone : Target::Merge, span, q, s, {}};
            if (!after || cost_less(*after, c)) found.push_back(c);
        },
        [&](double ring) { return ring * lb >= kth(); });
    kth();  // the batch: at most `keep`, the cheapest
    for (auto& c : found) out.push_back(c);
}

bool cost_less(const Candidate& x, const Candidate& y) {
    if (x.span != y.span) return x.span < y.span;
    if (x.dist != y.dist) return x.dist < y.dist;
    if (x.type != y.type) return x.type < y.type;
    return x.other < y.other;
}

void by_cost(std::vector<Candidate>& c) { std::sort(c.begin(), c.end(), cost_less); }

}  // namespace cs

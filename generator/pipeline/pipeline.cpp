#include "pipeline/pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <memory>
#include <mutex>
#include <tuple>
#include <unordered_map>

#include <fmt/format.h>
#include <unistd.h>

#include "core/errors.hpp"
#include "core/sha256.hpp"
#include "core/param_table.hpp"
#include "core/rules.hpp"
#include "ceilings/slabs.hpp"
#include "mesh/mesh_io.hpp"
#include "render/render.hpp"
#include "query/model_query.hpp"
#include "struts/solid_volume.hpp"
#include "core/slicer_time.hpp"
#include "tree/slicer_cost.hpp"
#include "tree/feet.hpp"
#include "tree/tree.hpp"

namespace cs {
namespace {

class Stopwatch {
public:
    explicit Stopwatch(std::vector<Stage>& out) : out_(out) {}
    template <typename F>
    auto time(const std::string& name, const std::function<void(const std::string&)>& progress, F f) {
        if (progress) progress(name);
        auto t0 = std::chrono::steady_clock::now();
        if constexpr (std::is_void_v<decltype(f())>) {
            f();
            record(name, t0);
        } else {
            auto r = f();
            record(name, t0);
            return r;
        }
    }

private:
    void record(const std::string& name, std::chrono::steady_clock::time_point t0) {
        double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        out_.push_back({name, s});
    }
    std::vector<Stage>& out_;
};

std::string stem(const std::string& path) {
    auto slash = path.find_last_of('/');
    std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
    auto dot = base.find_last_of('.');
    return dot == std::string::npos || dot == 0 ? base : base.substr(0, dot);
}

// Scales `mesh` by --scale, or to --fit's size, and returns the factor; warns when the size
// suggests the file is not in millimetres.
double scale_to_mm(Mesh& mesh, const Job& job, std::vector<std::string>& warnings) {
    const std::string& input = job.shown_input();
    double scale = job.scale;
    if (job.fit) {
        Vec3 size = bounding_box(mesh).size();
        scale = *job.fit / std::max({size.x, size.y, size.z});
    }
    for (auto& v : mesh.vertices) v = v * scale;
    if (scale < 0)
        for (auto& f : mesh.faces) std::swap(f[1], f[2]);
    Vec3 size = bounding_box(mesh).size();
    double largest = std::max({size.x, size.y, size.z});
    if (largest < 1.0)
        warnings.push_back(input + ": the model is only " + std::to_string(largest) +
                           " mm across; if its units are not millimetres use --scale (e.g. 25.4 for inches) or --fit MM");
    if (largest > 1000.0)
        warnings.push_back(input + ": the model is " + std::to_string(largest) +
                           " mm across (over 1 m); if its units are not millimetres use --scale or --fit MM");
    return scale;
}

// choose_orientation with the support each candidate pose really needs. Candidate poses are
// compared by trees grown from samples twice as sparse: a quarter of the work, and the ranking of
// poses holds (the chosen pose's tree is then grown in full).
// A pose may be judged through one index of the model as given, each question turned into the
// pose, instead of an index of its own: indexing a pose cost more than a quarter of the whole run
// on 50k-100k-triangle scans (CGAL's tree and its distance search tree, built for a few thousand
// questions). Turning rounds, and a question that grazes the model may then go the other way.
// Grazes come with faces lying along the axes (a vertical ray along a wall, a sample on a flat
// ceiling), as on CAD parts, and such a part's pose judged through the shared index came out up
// to 1.4 % apart (the validation set's fan and enclosure lid), more than the 1 % that ties two
// poses. So poses share the index only where neither the model as given nor the pose has more
// than kMostAlongAxes of its faces along the axes (scans), or past kIndexOnceTriangles, where
// indexing took longer than judging a pose. Either way the chosen pose gets its own index
// afterwards: what is written depends on the turning only through the choice.
constexpr std::size_t kIndexOnceTriangles = 200'000;

// The share of a model's faces along the axes (share_along_axes) up to which it is judged a scan:
// the benchmark's scans have 0-0.01 % (a few faces), its CAD parts, examples and validation parts
// 0.4-100 % (extruder_idler, a CAD part exported turned, has none as given, nor in 3 of its 4
// poses).
constexpr double kMostAlongAxes = 0.001;

Orientation orient_by_support(const Mesh& scaled, const Params& p, const std::string& orient, const EdgeUses& edges) {
    Params coarse = p;
    coarse.sampling_distance = 2 * p.sampling_distance;
    OverhangOptions coarse_oo = overhang_options(coarse);
    coarse_oo.bridge_sampling = p.sampling_distance;  // holes judged at the run's spacing
    const bool big = scaled.faces.size() > kIndexOnceTriangles;
    // Poses are judged only by the automatic search: no other run pays for the count.
    const bool judged = parse_orient(orient).mode == OrientMode::automatic;
    const bool scan = big || (judged && share_along_axes(scaled) <= kMostAlongAxes);
    // Built by the first pose that asks it: a CAD part pays none.
    std::once_flag indexed;
    std::unique_ptr<const ModelQuery> as_given;
    // A user's support blockers are in the chosen pose's coordinates: no pose is judged with them.
    return choose_orientation(scaled, p, orient, [&](const Mesh& rotated, const Rotation& rotation, PoseQuestion question) {
        Placement pl;
        Rotation id;
        Mesh placed = place_on_bed(rotated, 1.0, id.m, pl);
        auto samples = sample_overhangs(placed, coarse_oo, nullptr, &edges);
        if (!samples.samples.empty() && question == PoseQuestion::height_if_it_needs_support)
            return PoseSupport{.grown = false, .height = bounding_box(placed).size().z};
        std::unique_ptr<const ModelQuery> q;
        if (big || (scan && share_along_axes(placed) <= kMostAlongAxes)) {
            std::call_once(indexed, [&] { as_given = std::make_unique<const ModelQuery>(scaled); });
            q = std::make_unique<const ModelQuery>(placed, *as_given, rotation.m, pl.translation);
        } else {
            q = std::make_unique<const ModelQuery>(placed);
        }
        // What finish_supports computes of the volume, without the mesh a pose is not judged by.
        const SizedTree sized = grow_cheaper_tree(*q, samples.samples, coarse);
        const double volume = solid_volume(build_bodies(sized, coarse), coarse.wall_thickness);
        return PoseSupport{true, volume, sized.tree.stats.model_contacts, bounding_box(placed).size().z};
    });
}

}  // namespace

Supports build_supports(const Mesh& placed, const std::vector<Sample>& samples, const Params& p) {
    ModelQuery q(placed);
    return build_supports(q, samples, p);
}

Supports build_supports(const ModelQuery& q, const std::vector<Sample>& samples, const Params& p,
                        const std::vector<int>& omit) {
    return finish_supports(grow_cheaper_tree(q, samples, p), p, omit);
}

SizedTree grow_cheaper_tree(const ModelQuery& q, const std::vector<Sample>& samples, const Params& p) {
    return grow_cheaper_tree(q, hang_leaves(q, samples, p), p);
}

SizedTree grow_cheaper_tree(const ModelQuery& q, const SupportTree& hung, const Params& p,
                            const std::vector<Box3>& support_blockers) {
    SupportTree plain = grow_tree(q, hung, p, {}, support_blockers);  // the leaves are the same for every way of growing
    const TreeStats dropped = plain.stats;
    // Each candidate is sized once, to price it; the chosen one keeps its sizing (size_struts
    // leaves the tree as it is), so finish_supports need not size it again.
    SizedTree best = size_struts(std::move(plain), p);
    if (p.strategy != Strategy::tree) return best;
    // Ranked by PrusaSlicer's price (tree/slicer_cost.hpp says why): the ways differ by a few percent,
    // and only that route's fitted prices tell such trees apart.
    auto price = [&](SizedTree& t) {
        t.tree.slicer_cost = estimate_slicer_cost(t.tree, mean_strut_widths(t), p);
        return t.tree.slicer_cost->prusa_seconds;
    };
    double best_seconds = price(best);
    for (const GrowOptions& way : {GrowOptions{.lean_merging_leaves = true}, GrowOptions{.pair_leaves_first = true},
                                   GrowOptions{.pair_leaves_first = true, .lean_quads = true}}) {
        SupportTree t = grow_tree(q, hung, p, way, support_blockers);
        // A tree that gives up more samples is cheaper to print for that alone: never a saving.
        if (t.stats.dropped > dropped.dropped || t.stats.dropped_branches > dropped.dropped_branches) continue;
        SizedTree sized = size_struts(std::move(t), p);
        if (const double s = price(sized); s < best_seconds) best = std::move(sized), best_seconds = s;
    }
    return best;
}

namespace {

// A counter's question, byte for byte: the samples' points and kinds, and the feet.
std::string question(const std::vector<Sample>& samples, const std::vector<Vec3>& feet) {
    std::string key;
    key.reserve(samples.size() * (3 * sizeof(double) + sizeof(SampleKind)) + feet.size() * 3 * sizeof(double) + 8);
    auto put = [&key](const auto& x) { key.append(reinterpret_cast<const char*>(&x), sizeof x); };
    put(samples.size());
    for (const Sample& s : samples) put(s.p.x), put(s.p.y), put(s.p.z), put(s.kind);
    for (const Vec3& f : feet) put(f.x), put(f.y), put(f.z);
    return key;
}

// The trees a counter grew, by their question: the hybrid's weighing grows the whole tree the
// tree stage then grows again from the same leaves (run_job takes it from here).
using GrownTrees = std::unordered_map<std::string, SizedTree>;

FeetTreeCounter feet_tree_counter(const ModelQuery& q, const Params& p, const std::vector<Box3>& support_blockers,
                                  std::shared_ptr<GrownTrees> keep) {
    // The answers by their question: the walls and the hybrid price the same region's own tree
    // when both lay one out over it.
    auto known = std::make_shared<std::unordered_map<std::string, TreeCount>>();
    return [&q, p, support_blockers, known, keep](const std::vector<Sample>& samples, const std::vector<Vec3>& feet) {
        std::string key = question(samples, feet);
        if (const auto it = known->find(key); it != known->end()) return it->second;
        const SupportTree hung = hang_feet(hang_leaves(q, samples, p, support_blockers), feet, p);
        SizedTree t = grow_cheaper_tree(q, hung, p, support_blockers);
        const SlicerCost c = t.tree.slicer_cost ? *t.tree.slicer_cost : estimate_slicer_cost(t.tree, mean_strut_widths(t), p);
        const TreeCount count{c.island_layers, c.outline_mm, c.travel_mm};
        if (keep) keep->emplace(key, std::move(t));
        known->emplace(std::move(key), count);
        return count;
    };
}

}  // namespace

FeetTreeCounter feet_tree_counter(const ModelQuery& q, const Params& p, const std::vector<Box3>& support_blockers) {
    return feet_tree_counter(q, p, support_blockers, nullptr);
}

namespace {

// The hybrid (ceilings/hybrid.hpp) under what the walls left, kept clear of the walls (their
// boxes, a side clearance around them, join the user's blockers): its pieces, the samples of
// `walls.rest` they leave, and their feet.
Ceilings hybrid_under(const ModelQuery& q, const Ceilings& walls, const Params& p, const std::vector<Box3>& user_blockers,
                      const FeetTreeCounter& tree_count, const TipAt& tip_at) {
    std::vector<Box3> blockers = user_blockers;
    for (const CeilingWall& w : walls.walls) blockers.push_back(wall_box(w, tip_side_clearance(p)));
    return support_hybrid(q, walls.rest, p, tree_count, blockers, tip_at, walls.stay);
}

// The walls and the hybrid's pieces together, the samples neither carries, and the hybrid's feet.
Ceilings joined(const Ceilings& walls, Ceilings hybrid) {
    if (hybrid.walls.empty()) return walls;
    Ceilings out = walls;
    out.walls.insert(out.walls.end(), hybrid.walls.begin(), hybrid.walls.end());
    out.rest = std::move(hybrid.rest), out.stay = std::move(hybrid.stay);
    out.feet = std::move(hybrid.feet);
    out.regions += hybrid.regions, out.covered += hybrid.covered;
    out.tree_cura_s += hybrid.tree_cura_s, out.tree_prusa_s += hybrid.tree_prusa_s;
    out.walls_cura_s += hybrid.walls_cura_s, out.walls_prusa_s += hybrid.walls_prusa_s;
    return out;
}

// Where the tree loses feet of the hybrid, their pieces go (without_feet) and the tree grows again,
// this many times at most before the hybrid goes whole.
constexpr int kFootRounds = 3;

// The seconds a grown tree and the ceilings' pieces add, on the Cura and PrusaSlicer routes (as
// finish_supports estimates them).
std::pair<double, double> whole_seconds(const SizedTree& t, const Ceilings& c, const Params& p) {
    const SlicerCost cost = t.tree.slicer_cost ? *t.tree.slicer_cost : estimate_slicer_cost(t.tree, mean_strut_widths(t), p);
    return {cost.cura_seconds + walls_seconds(kCuraRoute, c.walls, p), cost.prusa_seconds + walls_seconds(kPrusaRoute, c.walls, p)};
}

}  // namespace

TreeCounter tree_counter(const ModelQuery& q, const Params& p, const std::vector<Box3>& support_blockers) {
    return [count = feet_tree_counter(q, p, support_blockers)](const std::vector<Sample>& samples) { return count(samples, {}); };
}

Supports finish_supports(SupportTree grown, const Params& p, const std::vector<int>& omit, std::vector<CeilingWall> walls) {
    return finish_supports(size_struts(std::move(grown), p), p, omit, std::move(walls));
}

Supports finish_supports(SizedTree grown, const Params& p, const std::vector<int>& omit, std::vector<CeilingWall> walls) {
    Supports s;
    s.grown_struts = grown.tree.struts;
    s.grown_pillars = grown.tree.pillars;
    for (const Node& n : grown.tree.nodes) s.grown_kinds.push_back(n.kind);
    s.grown_walls = walls;
    if (omit.empty()) {
        s.sized = std::move(grown);  // sized as grown: nothing pruned
    } else {
        s.sized = size_struts(prune_struts(grown.tree, omit), p);
        walls = prune_pieces(std::move(walls), grown.tree, s.sized.tree);
    }
    const std::optional<SlicerCost>& priced = s.sized.tree.slicer_cost;  // reset by prune_struts
    s.slicer_cost = priced ? *priced : estimate_slicer_cost(s.sized.tree, mean_strut_widths(s.sized), p);
    s.bodies = build_bodies(s.sized, p);
    s.mesh = bodies_mesh(s.bodies, p.wall_thickness);
    s.volume = solid_volume(s.bodies, p.wall_thickness);
    s.walls = std::move(walls);
    // The estimate covers the walls too (a region all walls would otherwise cost nothing).
    s.walls_cura = walls_printed(kCuraRoute, s.walls, p);
    s.walls_prusa = walls_printed(kPrusaRoute, s.walls, p);
    s.slicer_cost.cura_seconds += walls_seconds(kCuraRoute, s.walls, p);
    s.slicer_cost.prusa_seconds += walls_seconds(kPrusaRoute, s.walls, p);
    s.slicer_cost.seconds = 0.5 * (s.slicer_cost.cura_seconds + s.slicer_cost.prusa_seconds);
    for (const auto& w : s.walls) {
        const Mesh m = wall_mesh(w);
        s.volume += signed_volume(m);
        append(s.mesh, m);
    }
    s.bridges_volume = bridges_volume(s.walls);
    s.bodies_volume = signed_volume(s.mesh);  // separate closed shells: their volumes add
    s.length = s.sized.tree.total_length();
    return s;
}

SupportTree prune_struts(SupportTree t, const std::vector<int>& omit) {
    if (omit.empty()) return t;
    t.slicer_cost.reset();  // priced with the struts now pruned
    const int count = static_cast<int>(t.struts.size()), pillars = static_cast<int>(t.pillars.size());
    std::vector<std::vector<int>> in(t.nodes.size());
    for (int e = 0; e < count; ++e) in[t.struts[e].bottom].push_back(e);
    std::vector<char> gone(count, 0), pillar_gone(pillars, 0);
    std::vector<int> stack;
    for (int e : omit) {
        if (e < 0 || e >= count + pillars)
            throw ParameterError(fmt::format("omit_struts: {} is not a strut or a pillar (the tree has {} struts{}, and {} "
                                             "pillars{})",
                                             e, count, count ? fmt::format(", 0 to {}", count - 1) : "", pillars,
                                             pillars ? fmt::format(", {} to {}", count, count + pillars - 1) : ""));
        if (e >= count) pillar_gone[e - count] = 1;
        else stack.push_back(e);
    }
    if (std::find(pillar_gone.begin(), pillar_gone.end(), 1) != pillar_gone.end()) {
        std::vector<Pillar> kept;
        for (int i = 0; i < pillars; ++i)
            if (!pillar_gone[i]) kept.push_back(t.pillars[i]);
        t.stats.pillars -= t.pillars.size() - kept.size();
        t.pillars = std::move(kept);
    }
    while (!stack.empty()) {  // up the branch: every strut into the top of a gone strut goes too
        int e = stack.back();
        stack.pop_back();
        if (gone[e]) continue;
        gone[e] = 1;
        for (int f : in[t.struts[e].top]) stack.push_back(f);
    }
    std::vector<char> kept(t.nodes.size(), 0), touched(t.nodes.size(), 0);
    for (int e = 0; e < count; ++e) {
        touched[t.struts[e].top] = touched[t.struts[e].bottom] = 1;
        if (!gone[e]) kept[t.struts[e].top] = kept[t.struts[e].bottom] = 1;
    }
    for (size_t v = 0; v < t.nodes.size(); ++v) {
        if (!touched[v] || kept[v]) continue;
        if (t.nodes[v].kind == NodeKind::Bed) --t.stats.bed_contacts;
        if (t.nodes[v].kind == NodeKind::ModelContact) --t.stats.model_contacts;
        t.nodes[v].kind = NodeKind::Dropped;
    }
    std::vector<Strut> struts;
    for (int e = 0; e < count; ++e)
        if (!gone[e]) struts.push_back(t.struts[e]);
    t.struts = std::move(struts);
    return t;
}

namespace {

// A foot and the top of the tip under it, as far apart as a .scad's numbers (4 decimals) put them.
constexpr double kSameFoot = 1e-3;

}  // namespace

std::vector<CeilingWall> prune_pieces(std::vector<CeilingWall> walls, const SupportTree& grown, const SupportTree& pruned) {
    std::vector<CeilingWall> kept;
    for (CeilingWall& w : walls) {
        const std::vector<Vec3> foot = feet_of({w});
        if (w.bottom <= 0 || !feet_carried(grown, foot, kSameFoot) || feet_carried(pruned, foot, kSameFoot))
            kept.push_back(std::move(w));
    }
    return kept;
}

namespace {

// Would the tip under sample s stand in one of the user's support blockers?
bool in_support_blocker(const Vec3& s, const std::vector<Box3>& support_blockers, const Params& p) {
    const double tip = p.gap + p.tip_length, tip_width = std::max(p.tip_diameter, p.d_min);
    return sweep_meets_boxes(s, s - Vec3{0, 0, tip}, tip_width, 0, support_blockers);
}

// A sample beside a blocker, whose tip would only graze it: moved straight out from the box, just
// far enough for the tip to clear it, onto the model's underside there. The user blocked the box,
// not the overhang beside it, which would otherwise be left bare up to the next row of samples.
// Nothing when the sample is over the box (its tip stands in it), or when no underside is there.
std::optional<Vec3> beside_blockers(const ModelQuery& model, const Vec3& s, const std::vector<Box3>& support_blockers,
                                    const Params& p) {
    const double tip = p.gap + p.tip_length, half = 0.5 * std::max(p.tip_diameter, p.d_min) + 1e-3;
    Vec3 to = s;
    for (int pass = 0; pass < 2; ++pass)  // moved out of one box, it may graze the one beside it
        for (const Box3& b : support_blockers) {
            if (!sweep_meets_boxes(to, to - Vec3{0, 0, tip}, 2 * half, 0, {b})) continue;
            const bool over_x = to.x >= b.min.x && to.x <= b.max.x, over_y = to.y >= b.min.y && to.y <= b.max.y;
            if (over_x && over_y) return std::nullopt;
            if (!over_x) to.x = to.x < b.min.x ? b.min.x - half : b.max.x + half;
            if (!over_y) to.y = to.y < b.min.y ? b.min.y - half : b.max.y + half;
        }
    if (in_support_blocker(to, support_blockers, p)) return std::nullopt;
    // The underside there: the first face up from below, facing down, about as high as the sample
    // (a face rises at most as steeply as a wall over the distance moved).
    const double shift = horizontal_distance(to, s), slack = 2 * shift + p.layer_height;
    auto hit = model.first_hit({to.x, to.y, s.z - slack}, {0, 0, 1});
    if (!hit || hit->point.z > s.z + slack) return std::nullopt;
    if (face_normal_unnormalized(model.mesh(), model.mesh().faces[hit->face]).z >= 0) return std::nullopt;
    return hit->point;
}

// Each (sample, what holds it up at its height) pair of the tree's live leaves and pillars: a
// leaf's tip top, a pillar's top. The one home of that rule for coverers() and tips_of().
std::vector<std::pair<Vec3, Vec3>> tip_tops(const SupportTree& t) {
    std::vector<std::pair<Vec3, Vec3>> at;
    for (const auto& n : t.nodes)
        if (n.kind == NodeKind::Leaf) at.push_back({n.contact, {n.tip.x, n.tip.y, n.contact.z}});
    for (const auto& pl : t.pillars) at.push_back({pl.sample, {pl.top.x, pl.top.y, pl.sample.z}});
    return at;
}

// What holds each sample's overhang up, at the height of that overhang: a live leaf's tip top, a
// pillar's top, else the sample itself (it rests on material, or is bridged). The samples in
// `lost` hold nothing up: leaves the sweep lost (their strut found no way down; a leaf beside one
// starts elsewhere and may get down) and samples given up before the tree grew (untipped).
std::vector<Vec3> coverers(const SupportTree& t, const std::vector<Sample>& samples, const std::vector<Vec3>& lost = {}) {
    std::vector<Vec3> out, carried = lost;
    for (const auto& [sample, top] : tip_tops(t)) out.push_back(top), carried.push_back(sample);
    auto before = [](const Vec3& a, const Vec3& b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); };
    std::sort(carried.begin(), carried.end(), before);
    for (const auto& s : samples)
        if (!std::binary_search(carried.begin(), carried.end(), s.p, before)) out.push_back(s.p);
    return out;
}

// Where the tip hung for a sample holds the overhang up (tip_tops); the sample itself where it got
// neither.
TipAt tips_of(const SupportTree& hung) {
    auto before = [](const std::pair<Vec3, Vec3>& a, const std::pair<Vec3, Vec3>& b) {
        return std::tie(a.first.x, a.first.y, a.first.z) < std::tie(b.first.x, b.first.y, b.first.z);
    };
    std::vector<std::pair<Vec3, Vec3>> at = tip_tops(hung);
    std::sort(at.begin(), at.end(), before);
    return [at = std::move(at), before](const Sample& s) {
        const auto it = std::lower_bound(at.begin(), at.end(), std::pair{s.p, s.p}, before);
        return it != at.end() && !before({s.p, s.p}, *it) ? it->second : s.p;
    };
}

// Is one of the tips the walls lean on (Ceilings::stay: they hold what the walls let go of) among
// the `lost` samples?
bool leaned_on_lost(const Ceilings& c, const std::vector<Vec3>& lost) {
    for (std::size_t i = 0; i < c.stay.size() && i < c.rest.size(); ++i)
        if (c.stay[i] && std::any_of(lost.begin(), lost.end(), [&](const Vec3& x) { return distance(x, c.rest[i].p) == 0; }))
            return true;
    return false;
}

// The samples hang_leaves gave up (no tip fits under it, its leaf cannot leave the crevice it
// hangs in, or, too low for a tree, no pillar fits under it): they hold nothing up either. A
// sample beside one, where the overhang is left beyond reach, may get its support: the bottom
// edge of a fold in beast's scan (auto pose), whose upper end takes no tip and whose lower end
// does; a slope 2.1 mm over another in the tree example, where a pillar fits beside the sample.
std::vector<Vec3> untipped(const SupportTree& hung) {
    std::vector<Vec3> out = hung.no_pillar;
    for (const Node& n : hung.nodes)
        if (n.kind == NodeKind::Dropped) out.push_back(n.contact);
    return out;
}

// The samples of the leaves hung in `hung` that the sweep lost in `grown` (grown from `hung`:
// its first nodes are those leaves, in order).
std::vector<Vec3> lost_samples(const SupportTree& hung, const SupportTree& grown) {
    std::vector<Vec3> out;
    for (size_t i = 0; i < hung.nodes.size() && i < grown.nodes.size(); ++i)
        if (hung.nodes[i].kind == NodeKind::Leaf && grown.nodes[i].kind == NodeKind::Dropped)
            out.push_back(hung.nodes[i].contact);
    return out;
}

// The samples where the overhang lies beyond reach of what `held` holds up (top_up_samples), but
// outside the user's support blockers: a blocked region is left bare on purpose.
std::vector<Sample> samples_beyond_reach(const Mesh& model, const OverhangOptions& oo, const ModelQuery& q,
                                         const OverhangSamples& sampled, const std::vector<Vec3>& held,
                                         const std::vector<Box3>& blockers, const Params& p) {
    // Where a sample's own leaf or pillar would hold the overhang up, hung alone.
    auto support_at = [&](const Vec3& x) -> std::optional<Vec3> {
        const auto at = tip_tops(hang_leaves(q, {Sample{x, SampleKind::GapFill}}, p, blockers));
        return at.empty() ? std::nullopt : std::optional{at.front().second};
    };
    auto more = top_up_samples(model, oo, &q, sampled, held, support_at);
    std::erase_if(more, [&](const Sample& s) { return in_support_blocker(s.p, blockers, p); });
    return more;
}

// Topped-up samples join the run's, kept top-down as the sweep takes them.
void add_topped_up(OverhangSamples& sampled, const std::vector<Sample>& more) {
    sampled.topped_up += more.size();
    sampled.samples.insert(sampled.samples.end(), more.begin(), more.end());
    sort_top_down(sampled.samples);
}

// Support points (as edited_samples snaps them onto the model) that no leaf or pillar carries in
// the finished tree: where no strut fits. One warning each, with where it is.
std::vector<std::string> untipped_support_points(const ModelQuery& q, const SupportTree& t, const ManualEdits& e,
                                                 const Params& p) {
    std::vector<Vec3> carried;
    for (const auto& n : t.nodes)
        if (n.kind == NodeKind::Leaf) carried.push_back(n.contact);
    for (const auto& pl : t.pillars) carried.push_back(pl.sample);
    std::vector<std::string> out;
    for (const Vec3& given : e.support_points) {
        const Vec3 on = q.closest_point(given);
        if (rests_on_material(q, on, touching_space(p))) continue;  // needs no tip: material right below
        auto same = [&](const Vec3& c) { return c.x == on.x && c.y == on.y && c.z == on.z; };
        if (std::any_of(carried.begin(), carried.end(), same)) continue;
        out.push_back(fmt::format("support point [{}, {}, {}] (on the model at ({:.2f}, {:.2f}, {:.2f})) got no tip: no "
                                  "strut fits under it{}; move it, or remove what is in the way",
                                  given.x, given.y, given.z, on.x, on.y, on.z,
                                  p.supports_on_model ? "" : " that reaches the bed"));
    }
    return out;
}

// A shell of the placed model that stands neither on the bed nor against another shell (their
// boxes apart): a stray piece that prints on supports alone.
std::vector<std::string> floating_shells(const Mesh& model, double bed_z, const std::string& input) {
    int count = 0;
    const std::vector<int> comp = face_components(model, count);
    if (count < 2) return {};
    std::vector<Box3> boxes(count);
    for (size_t f = 0; f < model.faces.size(); ++f)
        for (auto v : model.faces[f]) boxes[comp[f]].add(model.vertices[v]);
    std::vector<std::string> out;
    for (int i = 0; i < count; ++i) {
        if (boxes[i].min.z <= bed_z) continue;
        bool alone = true;
        for (int j = 0; j < count && alone; ++j) alone = j == i || !overlaps(boxes[i], boxes[j]);
        if (!alone) continue;
        const Vec3 c = (boxes[i].min + boxes[i].max) * 0.5, size = boxes[i].size();
        out.push_back(fmt::format("{}: a shell of {:.1f} x {:.1f} x {:.1f} mm at ({:.1f}, {:.1f}, {:.1f}) floats {:.1f} mm "
                                  "above the bed, apart from the rest of the model: it prints on supports alone. If it "
                                  "is a stray piece, remove it from the model",
                                  input, size.x, size.y, size.z, c.x, c.y, c.z, boxes[i].min.z));
    }
    return out;
}

// A lone strut: a leaf's way down to the bed or the model that no other strut joins, much longer
// than it is wide. Nothing braces it: it sways under the nozzle where the strength rule still
// passes it (the hook's 50 mm buildplate-only strut). The most slender one, with where it is.
std::string lone_strut_warning(const SizedTree& sized, bool buildplate_only) {
    const auto& t = sized.tree;
    double worst = 0, worst_length = 0, worst_width = 0;
    Vec3 top, bottom;
    for (size_t leaf = 0; leaf < t.nodes.size(); ++leaf) {
        if (t.nodes[leaf].kind != NodeKind::Leaf) continue;
        double length = 0, width = INFINITY;
        int n = static_cast<int>(leaf), e = sized.out_strut[n];
        bool joined = false;
        for (; e >= 0 && !joined; e = sized.out_strut[n]) {
            length += sized.struts[e].length;
            width = std::min(width, sized.struts[e].top_width);
            n = t.struts[e].bottom;
            joined = sized.in_struts[n].size() > 1;
        }
        if (joined || length == 0 || !(width > 0)) continue;
        if (const double ratio = length / width; ratio > worst)
            worst = ratio, worst_length = length, worst_width = width, top = t.nodes[leaf].p, bottom = t.nodes[n].p;
    }
    if (worst <= kComfortableLengthToWidth) return "";
    return fmt::format("a lone strut from ({:.1f}, {:.1f}, {:.1f}) down to ({:.1f}, {:.1f}, {:.1f}) is {:.0f} mm long and "
                       "{:.1f} mm wide (length-to-width {:.1f}, over {:g}, the strength rule's comfortable range) and "
                       "no other strut braces it: it may sway or snap while printing. Raise --d-min{}",
                       top.x, top.y, top.z, bottom.x, bottom.y, bottom.z, worst_length, worst_width, worst,
                       kComfortableLengthToWidth, buildplate_only ? ", or let supports stand on the model (no --buildplate-only)" : "");
}

}  // namespace

// How far from the model a support point may be given: it is picked by eye from a picture or
// from the coordinates in the .scad, and snapped onto the nearest point of the model.
constexpr double kSupportPointSnap = 2.0;

std::vector<Sample> edited_samples(const ModelQuery& model, std::vector<Sample> samples, const ManualEdits& edits,
                                   const Params& p) {
    auto blocked = [&](const Vec3& s) { return in_support_blocker(s, edits.support_blockers, p); };
    std::vector<Sample> kept;
    for (const Sample& s : samples) {
        if (!blocked(s.p)) kept.push_back(s);
        else if (auto moved = beside_blockers(model, s.p, edits.support_blockers, p)) kept.push_back({*moved, s.kind});
    }
    samples = std::move(kept);
    for (const Vec3& given : edits.support_points) {
        auto where = fmt::format("support point [{}, {}, {}]", given.x, given.y, given.z);
        Vec3 on = model.closest_point(given);
        if (distance(on, given) > kSupportPointSnap)
            throw ParameterError(fmt::format("{} is {:.1f} mm from the model; give a point on its underside, in the "
                                             "coordinates of <name>.model.stl",
                                             where, distance(on, given)));
        if (model.inside(on - Vec3{0, 0, 0.01}))
            throw ParameterError(where + " is on top of material, not on the model's underside");
        if (blocked(on)) throw ParameterError(where + " lies in a support blocker");
        samples.push_back({on, SampleKind::Point});
    }
    sort_top_down(samples);
    return samples;
}

// A private folder (mode 0700) in the system's temporary directory (TMPDIR, else /tmp), removed
// with everything in it when the object goes: on every path out of the function that made it.
struct TempFolder {
    std::filesystem::path path;
    explicit TempFolder(const std::string& for_input) {
        std::error_code ec;
        std::filesystem::path base = std::filesystem::temp_directory_path(ec);
        if (ec)
            throw InputError(for_input + ": cannot render it: the temporary folder is not a folder (" + ec.message() +
                             "). Set TMPDIR to a writable folder.");
        std::string tmpl = (base / "clever-support-XXXXXX").string();
        if (!mkdtemp(tmpl.data()))
            throw InputError(for_input + ": cannot make a temporary folder to render it in (" + tmpl + ": " +
                             std::strerror(errno) + "). Set TMPDIR to a writable folder.");
        path = tmpl;
    }
    ~TempFolder() {
        std::error_code ec;
        std::filesystem::remove_all(path, ec);
    }
    TempFolder(const TempFolder&) = delete;
    TempFolder& operator=(const TempFolder&) = delete;
};

Mesh load_input(const std::string& path, const std::vector<std::string>& defines, std::string* contents) {
    if (!is_scad_input(path)) {
        if (!defines.empty()) throw ParameterError("-D applies to a .scad input only, not " + path);
        return read_mesh(path, false, contents);
    }
    if (!std::ifstream(path)) throw InputError(path + ": cannot open it. Check the path.");
    const TempFolder tmp(path);
    RenderOptions o;
    o.scad = path;
    o.output = (tmp.path / "part.stl").string();
    o.defines = defines;
    try {
        render_scad(o);
    } catch (const ExternalToolError& e) {
        throw InputError(path + ": OpenSCAD could not render the part: " + e.what() +
                         (e.log.empty() ? "" : "\nOpenSCAD said:\n" + e.log));
    }
    try {
        return read_mesh(o.output);
    } catch (const InputError& e) {
        throw InputError(path + ": OpenSCAD rendered no usable solid (" + e.what() + ")");
    }
}

std::vector<std::string> job_stages(const Job& job) {
    std::vector<std::string> stages = {"load", "repair"};
    if (job.self_intersection_check) stages.push_back("self-intersections");
    for (const char* s : {"orient", "model index", "overhangs", "coverage top-up", "ceilings", "tree", "struts", "columns baseline"})
        stages.push_back(s);
    return stages;
}

Result run_job(const Job& job, const std::function<void(const std::string&)>& progress) {
    validate_params(job.params);
    if (!(job.scale != 0 && std::isfinite(job.scale)))
        throw ParameterError("--scale must be a non-zero number");
    if (job.fit && !(*job.fit > 0 && std::isfinite(*job.fit))) throw ParameterError("--fit must be a positive size in mm");
    const Params& p = job.params;
    const std::vector<Box3>& blockers = job.edits.support_blockers;
    const std::string& input = job.shown_input();
    Result r;
    Stopwatch sw(r.stages);
    r.name = stem(job.input);

    Mesh raw = sw.time("load", progress, [&] { return load_input(job.input, job.defines, &r.input_contents); });
    r.input_sha256 = file_sha256(job.input);
    Mesh repaired = sw.time("repair", progress, [&] { return repair_mesh(raw, input, r.repair); });
    raw = Mesh();  // each stage's input is released once the next has its own: big scans need the room
    for (const auto& w : r.repair.warnings) r.warnings.push_back(w);
    if (job.self_intersection_check) {
        r.self_intersections = sw.time("self-intersections", progress, [&] { return count_self_intersections(repaired, 1000); });
        if (r.self_intersections)
            r.warnings.push_back(input + ": " + std::to_string(r.self_intersections) +
                                 (r.self_intersections >= 1000 ? "+" : "") +
                                 " pairs of self-intersecting triangles; supports are still built against its surface");
    }

    // Scale first, so orientation and placement see millimetres.
    Mesh scaled = std::move(repaired);
    const double scale = scale_to_mm(scaled, job, r.warnings);
    const OverhangOptions oo = overhang_options(p);
    // The model's edges, sorted once: they depend on its faces alone, which every pose the search
    // judges and the chosen pose's placed model keep (place_on_bed at scale 1 moves vertices only).
    EdgeUses edges;
    r.orientation = sw.time("orient", progress, [&] {
        edges = edge_uses(scaled);
        return orient_by_support(scaled, p, job.orient, edges);
    });
    r.model = place_on_bed(scaled, 1.0, r.orientation.rotation.m, r.placement);
    r.placement.scale = scale;
    scaled = Mesh();

    // One index of the model serves the sampling, the tree and the baseline (on a 5M-triangle scan
    // it takes seconds and most of a gigabyte).
    auto query = sw.time("model index", progress, [&] { return std::make_unique<ModelQuery>(r.model); });
    // With the index, points resting on material below need no sample (as `check` judges them).
    r.samples = sw.time("overhangs", progress, [&] { return sample_overhangs(r.model, oo, query.get(), &edges); });
    edges = EdgeUses();  // (a 5M-triangle scan's take 240 MB)
    if (!job.edits.empty()) {
        size_t before = r.samples.samples.size();
        r.samples.samples = edited_samples(*query, std::move(r.samples.samples), job.edits, p);
        r.blocked_samples = before + job.edits.support_points.size() - r.samples.samples.size();
    }
    // Where tips and pillars stand aside from their samples, the overhang between them may be left
    // beyond reach: samples there. Judged on the hung leaves (where every tip stands is known before
    // the tree grows); new tips cover their own points, so once is enough.
    SupportTree hung;
    auto extra = sw.time("coverage top-up", progress, [&] {
        hung = hang_leaves(*query, r.samples.samples, p, blockers);
        const auto held = coverers(hung, r.samples.samples, untipped(hung));
        return samples_beyond_reach(r.model, oo, *query, r.samples, held, blockers, p);
    });
    if (!extra.empty()) {
        add_topped_up(r.samples, extra);
        hung = hang_more_leaves(*query, std::move(hung), extra, p, blockers);  // the new samples' leaves, in sample order
    }
    // Walls under ceilings low over the bed take the samples they carry; under ceilings higher up
    // the hybrid's short walls (on the tree) take theirs; the tree grows from the rest.
    Ceilings walls_only, hybrid;
    auto counted = std::make_shared<GrownTrees>();
    Ceilings ceilings = sw.time("ceilings", progress, [&] {
        // One counter for both: it remembers the trees it grew (a region the walls priced is often
        // the hybrid's too).
        const FeetTreeCounter count = feet_tree_counter(*query, p, blockers, counted);
        const TipAt tip_at = tips_of(hung);
        // Walls are taken where they beat the hybrid over the same samples too, since it is laid
        // out on what the walls leave. It stands on the tree with room under its feet
        // (hybrid_floor): where a sample has none, it cannot take the walls' whole region and is
        // not laid out (on propeller's blades, 1.7 mm over the bed at their tips, that cost 9 % of
        // the run's instructions and changed nothing; the same on fandisk).
        RivalSaving hybrid_saving;
        if (p.hybrid_height > 0)
            hybrid_saving = [&](const std::vector<Sample>& s) {
                if (!std::all_of(s.begin(), s.end(), [&](const Sample& x) { return hybrid_floor(*query, x.p, p).has_value(); }))
                    return std::pair{0.0, 0.0};
                // Rows along the longer side only, priced as the walls' rival (support_hybrid).
                const Ceilings h = support_hybrid(*query, s, p, count, blockers, tip_at, {}, false);
                return std::pair{h.tree_cura_s - h.walls_cura_s, h.tree_prusa_s - h.walls_prusa_s};
            };
        walls_only = support_ceilings(*query, r.samples.samples, p,
                                      [&count](const std::vector<Sample>& s) { return count(s, {}); }, blockers,
                                      kMostLeftToPrice, tip_at, hybrid_saving);
        if (p.hybrid_height <= 0) return walls_only;
        hybrid = hybrid_under(*query, walls_only, p, blockers, count, tip_at);
        return joined(walls_only, hybrid);
    });
    auto leaves_of = [&](const Ceilings& c) {
        return c.walls.empty() ? SupportTree{} : hang_feet(hang_leaves(*query, c.rest, p, blockers), c.feet, p);
    };
    SupportTree hung_rest = leaves_of(ceilings);
    // The tree for these leaves, where the hybrid's weighing grew it already (the same leaves, the
    // same growth): taken once, by the first growth below.
    std::optional<SizedTree> counted_tree;
    if (!ceilings.walls.empty())
        if (auto it = counted->find(question(ceilings.rest, ceilings.feet)); it != counted->end()) counted_tree = std::move(it->second);
    counted.reset();
    // The tree and the columns baseline start from the same leaves (hanging them does not depend
    // on the strategy); the baseline carries every sample.
    SupportTree* leaves = ceilings.walls.empty() ? &hung : &hung_rest;
    // Leaves the sweep lost (no way down, even alone) leave their overhang beyond reach: samples
    // beside them, and the tree grown once more with their leaves (bird and molecule at 120 mm).
    // One stage: the regrowth is part of growing the tree.
    auto grow = [&] {
        SizedTree first = counted_tree ? std::move(*counted_tree) : grow_cheaper_tree(*query, *leaves, p, blockers);
        counted_tree.reset();
        if (first.tree.stats.dropped <= leaves->stats.dropped) return first;
        std::vector<Vec3> lost = lost_samples(*leaves, first.tree);
        // A tip the walls leaned on, lost: the samples it held with them hold nothing either.
        if (leaned_on_lost(ceilings, lost)) lost.insert(lost.end(), ceilings.released.begin(), ceilings.released.end());
        const auto held = coverers(first.tree, r.samples.samples, lost);
        auto more = samples_beyond_reach(r.model, oo, *query, r.samples, held, blockers, p);
        if (more.empty()) return first;
        SupportTree more_leaves = hang_more_leaves(*query, *leaves, more, p, blockers);
        SizedTree regrown = grow_cheaper_tree(*query, more_leaves, p, blockers);
        // Kept only where it loses no more leaves: with many dead ends (menger_sponge3 with
        // --buildplate-only) the new leaves crowd the way down and more are lost.
        if (regrown.tree.stats.dropped > first.tree.stats.dropped) return first;
        add_topped_up(r.samples, more);
        if (!ceilings.walls.empty()) hung = hang_more_leaves(*query, std::move(hung), std::move(more), p, blockers);
        *leaves = std::move(more_leaves);
        return regrown;
    };
    auto grow_with = [&](Ceilings c) {
        ceilings = std::move(c);
        hung_rest = leaves_of(ceilings);
        leaves = ceilings.walls.empty() ? &hung : &hung_rest;
        return grow();
    };
    SizedTree grown = sw.time("tree", progress, [&] {
        SizedTree t = grow();
        if (feet_carried(t.tree, ceilings.feet)) return t;
        // The tree lost feet of the hybrid (walls on nothing): their pieces go, the samples only
        // they carried go back to the tree, and it grows again (it may lose others).
        const OverhangSamples samples_before = r.samples;
        const SupportTree hung_before = hung;
        struct Kept {
            SizedTree tree;
            Ceilings ceilings;
            OverhangSamples samples;
            SupportTree hung;
        };
        std::optional<Kept> fewer;
        for (int round = 0; round < kFootRounds; ++round) {
            hybrid = without_feet(*query, walls_only.rest, walls_only.stay, hybrid, lost_feet(t.tree, hybrid.feet), p);
            if (hybrid.walls.empty()) break;
            t = grow_with(joined(walls_only, hybrid));
            if (feet_carried(t.tree, hybrid.feet)) {
                fewer = Kept{std::move(t), ceilings, r.samples, hung};
                break;
            }
        }
        // Without the hybrid, from where the first tree left the samples; the rest of the hybrid
        // only where the time model prefers it on both routes (either slicer may print it).
        r.samples = samples_before, hung = hung_before;
        SizedTree plain = grow_with(walls_only);
        if (!fewer) return plain;
        const auto [with_cura, with_prusa] = whole_seconds(fewer->tree, fewer->ceilings, p);
        const auto [plain_cura, plain_prusa] = whole_seconds(plain, ceilings, p);
        if (!(with_cura < plain_cura && with_prusa < plain_prusa)) return plain;
        ceilings = std::move(fewer->ceilings), r.samples = std::move(fewer->samples), hung = std::move(fewer->hung);
        return std::move(fewer->tree);
    });
    // The user's omitted struts are numbered in the final tree (the one the .scad shows).
    // Neighbouring rows as slabs: the same lines under the ceiling, each drawn once by CuraEngine.
    r.supports = sw.time("struts", progress, [&] {
        ceilings.walls = join_rows_into_slabs(*query, std::move(ceilings.walls), p);
        return finish_supports(std::move(grown), p, job.edits.omit_struts, std::move(ceilings.walls));
    });
    Params columns = p;
    columns.strategy = Strategy::columns;
    r.columns = sw.time("columns baseline", progress, [&] { return finish_supports(grow_tree(*query, hung, columns, {}, blockers), columns); });
    for (auto& w : untipped_support_points(*query, r.supports.sized.tree, job.edits, p)) r.warnings.push_back(std::move(w));
    query.reset();
    for (auto& w : floating_shells(r.model, 0.5 * p.layer_height, input)) r.warnings.push_back(std::move(w));
    if (auto w = lone_strut_warning(r.supports.sized, !p.supports_on_model); !w.empty()) r.warnings.push_back(std::move(w));
    if (const auto& st = r.supports.sized.tree.stats; st.dropped)
        r.warnings.push_back(std::to_string(st.dropped) + " overhang samples lie where no strut fits" +
                             (p.supports_on_model ? "" : " (or can reach the bed)") +
                             " and got no support; `clever-support check` tells whether neighbours cover them");
    if (r.supports.sized.strength_violations)
        r.warnings.push_back(std::to_string(r.supports.sized.strength_violations) +
                             " struts are longer than safe even at d_max; raise --d-max");
    return r;
}

}  // namespace cs

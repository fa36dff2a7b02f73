#include "pipeline/pipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <tuple>

#include <fmt/format.h>
#include <unistd.h>

#include "core/errors.hpp"
#include "core/sha256.hpp"
#include "core/param_table.hpp"
#include "mesh/mesh_io.hpp"
#include "render/render.hpp"
#include "query/model_query.hpp"
#include "struts/solid_volume.hpp"
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
Orientation orient_by_support(const Mesh& scaled, const Params& p, const std::string& orient) {
    Params coarse = p;
    coarse.sampling_distance = 2 * p.sampling_distance;
    coarse.keep_out.clear();  // a user's blockers are in the chosen pose's coordinates
    OverhangOptions coarse_oo{p.critical_angle, coarse.sampling_distance, p.layer_height, touching_space(p)};
    return choose_orientation(scaled, p, orient, [&](const Mesh& rotated) {
        Placement pl;
        Rotation id;
        Mesh placed = place_on_bed(rotated, 1.0, id.m, pl);
        auto samples = sample_overhangs(placed, coarse_oo);
        Supports s = build_supports(placed, samples.samples, coarse);
        return PoseSupport{s.volume, s.sized.tree.stats.model_contacts, bounding_box(placed).size().z};
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

SupportTree grow_cheaper_tree(const ModelQuery& q, const std::vector<Sample>& samples, const Params& p) {
    return grow_cheaper_tree(q, hang_leaves(q, samples, p), p);
}

SupportTree grow_cheaper_tree(const ModelQuery& q, const SupportTree& hung, const Params& p) {
    SupportTree best = grow_tree(q, hung, p);  // the leaves are the same for every way of growing
    if (p.strategy != Strategy::tree) return best;
    auto seconds = [&](const SupportTree& t) {
        const SizedTree sized = size_struts(t, p);
        return estimate_slicer_cost(sized.tree, mean_strut_widths(sized), p).seconds;
    };
    const TreeStats plain = best.stats;
    double best_seconds = seconds(best);
    for (const GrowOptions& way : {GrowOptions{.lean_merging_leaves = true}, GrowOptions{.pair_leaves_first = true}}) {
        SupportTree t = grow_tree(q, hung, p, way);
        // A tree that gives up more samples is cheaper to print for that alone: never a saving.
        if (t.stats.dropped > plain.dropped || t.stats.dropped_branches > plain.dropped_branches) continue;
        if (const double s = seconds(t); s < best_seconds) best = std::move(t), best_seconds = s;
    }
    return best;
}

Supports finish_supports(SupportTree grown, const Params& p, const std::vector<int>& omit, std::vector<CeilingWall> walls) {
    Supports s;
    s.grown_struts = grown.struts;
    s.sized = size_struts(prune_struts(std::move(grown), omit), p);
    s.bodies = build_bodies(s.sized, p);
    s.mesh = bodies_mesh(s.bodies, p.wall_thickness);
    s.volume = solid_volume(s.bodies, p.wall_thickness);
    s.walls = std::move(walls);
    for (const auto& w : s.walls) {
        const Mesh m = wall_mesh(w, p.wall_thickness);
        s.volume += signed_volume(m);
        append(s.mesh, m);
    }
    s.bodies_volume = signed_volume(s.mesh);  // separate closed shells: their volumes add
    s.length = s.sized.tree.total_length();
    return s;
}

SupportTree prune_struts(SupportTree t, const std::vector<int>& omit) {
    if (omit.empty()) return t;
    const int count = static_cast<int>(t.struts.size());
    std::vector<std::vector<int>> in(t.nodes.size());
    for (int e = 0; e < count; ++e) in[t.struts[e].bottom].push_back(e);
    std::vector<char> gone(count, 0);
    std::vector<int> stack;
    for (int e : omit) {
        if (e < 0 || e >= count)
            throw ParameterError("omit_struts: " + std::to_string(e) + " is not a strut (the tree has " + std::to_string(count) +
                                 " struts, 0 to " + std::to_string(count - 1) + ")");
        stack.push_back(e);
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

// Would the tip under sample s stand in one of the user's support blockers?
bool in_blocker(const Vec3& s, const std::vector<Box3>& blockers, const Params& p) {
    const double tip = p.gap + p.tip_length, tip_width = std::max(p.tip_diameter, p.d_min);
    return sweep_meets_boxes(s, s - Vec3{0, 0, tip}, tip_width, 0, blockers);
}

// What holds each sample's overhang up, at the height of that overhang: a live leaf's tip top, a
// pillar's top, else the sample itself (it rests on material, is bridged, or was given up: where
// no strut fits, more samples next to it would be given up too).
std::vector<Vec3> coverers(const SupportTree& t, const std::vector<Sample>& samples) {
    std::vector<Vec3> out, carried;
    for (const auto& n : t.nodes)
        if (n.kind == NodeKind::Leaf) out.push_back({n.tip.x, n.tip.y, n.contact.z}), carried.push_back(n.contact);
    for (const auto& pl : t.pillars) out.push_back({pl.top.x, pl.top.y, pl.sample.z}), carried.push_back(pl.sample);
    auto before = [](const Vec3& a, const Vec3& b) { return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z); };
    std::sort(carried.begin(), carried.end(), before);
    for (const auto& s : samples)
        if (!std::binary_search(carried.begin(), carried.end(), s.p, before)) out.push_back(s.p);
    return out;
}

}  // namespace

// How far from the model a support point may be given: it is picked by eye from a picture or
// from the coordinates in the .scad, and snapped onto the nearest point of the model.
constexpr double kSupportPointSnap = 2.0;

std::vector<Sample> edited_samples(const ModelQuery& model, std::vector<Sample> samples, const ManualEdits& edits,
                                   const Params& p) {
    auto blocked = [&](const Vec3& s) { return in_blocker(s, edits.blockers, p); };
    std::erase_if(samples, [&](const Sample& s) { return blocked(s.p); });
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

Mesh load_input(const std::string& path, const std::vector<std::string>& defines, std::string* contents) {
    if (!is_scad_input(path)) {
        if (!defines.empty()) throw ParameterError("-D applies to a .scad input only, not " + path);
        return read_mesh(path, false, contents);
    }
    if (!std::ifstream(path)) throw InputError(path + ": cannot open it. Check the path.");
    char tmpl[] = "/tmp/clever-support-part-XXXXXX";
    int fd = mkstemp(tmpl);
    if (fd < 0) throw InputError(path + ": cannot make a temporary file to render it into");
    close(fd);
    unlink(tmpl);
    RenderOptions o;
    o.scad = path;
    o.output = std::string(tmpl) + ".stl";
    o.defines = defines;
    try {
        render_scad(o);
    } catch (const ExternalToolError& e) {
        throw InputError(path + ": OpenSCAD could not render the part: " + e.what() +
                         (e.log.empty() ? "" : "\nOpenSCAD said:\n" + e.log));
    }
    try {
        Mesh m = read_mesh(o.output);
        unlink(o.output.c_str());
        return m;
    } catch (const InputError& e) {
        unlink(o.output.c_str());
        throw InputError(path + ": OpenSCAD rendered no usable solid (" + e.what() + ")");
    }
}

Result run_job(const Job& job, const std::function<void(const std::string&)>& progress) {
    validate_params(job.params);
    if (!(job.scale != 0 && std::isfinite(job.scale)))
        throw ParameterError("--scale must be a non-zero number");
    if (job.fit && !(*job.fit > 0 && std::isfinite(*job.fit))) throw ParameterError("--fit must be a positive size in mm");
    Params p = job.params;
    p.keep_out = job.edits.blockers;
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
    OverhangOptions oo{p.critical_angle, p.sampling_distance, p.layer_height, touching_space(p)};
    r.orientation = sw.time("orient", progress, [&] { return orient_by_support(scaled, p, job.orient); });
    r.model = place_on_bed(scaled, 1.0, r.orientation.rotation.m, r.placement);
    r.placement.scale = scale;
    scaled = Mesh();

    // One index of the model serves the sampling, the tree and the baseline (on a 5M-triangle scan
    // it takes seconds and most of a gigabyte).
    auto query = sw.time("model index", progress, [&] { return std::make_unique<ModelQuery>(r.model); });
    // With the index, points resting on material below need no sample (as `check` judges them).
    r.samples = sw.time("overhangs", progress, [&] { return sample_overhangs(r.model, oo, query.get()); });
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
        hung = hang_leaves(*query, r.samples.samples, p);
        auto more = top_up_samples(r.model, oo, query.get(), r.samples, coverers(hung, r.samples.samples));
        std::erase_if(more, [&](const Sample& s) { return in_blocker(s.p, job.edits.blockers, p); });
        return more;
    });
    if (!extra.empty()) {
        r.samples.topped_up = extra.size();
        r.samples.samples.insert(r.samples.samples.end(), extra.begin(), extra.end());
        sort_top_down(r.samples.samples);
        hung = hang_leaves(*query, r.samples.samples, p);  // the new samples' leaves, in sample order
    }
    // Walls under ceilings low over the bed take the samples they carry; the tree grows from the rest.
    Ceilings ceilings = sw.time("ceilings", progress, [&] { return support_ceilings(*query, r.samples.samples, p); });
    const SupportTree hung_rest = ceilings.walls.empty() ? SupportTree{} : hang_leaves(*query, ceilings.rest, p);
    // The tree and the columns baseline start from the same leaves (hanging them does not depend
    // on the strategy); the baseline carries every sample.
    SupportTree grown = sw.time("tree", progress, [&] { return grow_cheaper_tree(*query, ceilings.walls.empty() ? hung : hung_rest, p); });
    // The user's omitted struts are numbered in the final tree (the one the .scad shows).
    r.supports = sw.time("struts", progress, [&] {
        return finish_supports(std::move(grown), p, job.edits.omit_struts, std::move(ceilings.walls));
    });
    Params columns = p;
    columns.strategy = Strategy::columns;
    r.columns = sw.time("columns baseline", progress, [&] { return finish_supports(grow_tree(*query, hung, columns), columns); });
    query.reset();
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

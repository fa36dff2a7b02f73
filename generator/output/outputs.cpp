#include "output/outputs.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "core/param_table.hpp"
#include "mesh/mesh_io.hpp"
#include "output/scad.hpp"
#include "output/threemf.hpp"

namespace cs {
namespace {

using json = nlohmann::ordered_json;

// The preset, then every row of the parameter table under its report key. Reports have always
// listed the clearance last (it was added last): kept there so reports stay byte-identical.
json params_json(const Params& p) {
    json j = {{"preset", p.preset}};
    const ParamRow* last = find_param("--clearance");
    for (const auto& row : param_table())
        if (&row != last) j[row.report_key] = param_value_json(row, p);
    j[last->report_key] = param_value_json(*last, p);
    return j;
}

json supports_json(const Supports& s, const Params& p) {
    const auto& st = s.sized.tree.stats;
    size_t tips = 0;
    for (const auto& b : s.bodies) tips += b.kind == BodyKind::Tip;
    const SlicerCost& cost = s.slicer_cost;
    return {{"struts", s.sized.tree.struts.size()},
            {"nodes", s.sized.tree.nodes.size()},
            {"tips", tips},
            {"merges", st.merges},
            {"bed_contacts", st.bed_contacts},
            {"model_contacts", st.model_contacts},
            {"pillars", st.pillars},
            {"touching_samples", st.touching},
            {"bridged_samples", st.bridged},
            {"internal_samples", st.internal},
            {"bends", st.steps},
            {"tight", st.tight},
            {"dropped_samples", st.dropped},
            {"dropped_branches", st.dropped_branches},
            {"undone_joins", st.undone},
            {"bodies", s.bodies.size()},
            {"ceiling_walls", s.walls.size()},
            {"ceiling_walls_on_model",
             std::count_if(s.walls.begin(), s.walls.end(), [](const CeilingWall& w) { return w.bottom > 0 && !w.on_tree; })},
            {"ceiling_walls_on_tree", std::count_if(s.walls.begin(), s.walls.end(), [](const CeilingWall& w) { return w.on_tree; })},
            {"ceiling_bridges", std::count_if(s.walls.begin(), s.walls.end(), [](const CeilingWall& w) { return w.bridge; })},
            {"total_strut_length_mm", s.length},
            {"support_volume_mm3", s.volume},
            {"bridges_volume_mm3", s.bridges_volume},
            {"bodies_volume_mm3", s.bodies_volume},
            {"worst_length_to_width", s.sized.worst_length_to_width},
            {"strength_violations", s.sized.strength_violations},
            {"grown_with",
             {{"lean_merging_leaves", s.sized.tree.grown_with.lean_merging_leaves},
              {"pair_leaves_first", s.sized.tree.grown_with.pair_leaves_first},
              {"lean_quads", s.sized.tree.grown_with.lean_quads}}},
            {"slicer_estimate", {{"island_layers", cost.island_layers},
                                 {"most_islands", cost.most_islands},
                                 {"outline_mm", cost.outline_mm},
                                 {"travel_mm", cost.travel_mm},
                                 {"seconds", cost.seconds},
                                 {"routes", {{"cura_support_mesh", {{"seconds", cost.cura_seconds}}},
                                             {"prusa_3mf", {{"seconds", cost.prusa_seconds}}}}},
                                 // the walls' part: their islands and their lines' seconds per route
                                 {"walls", {{"island_layers", s.walls_cura.island_layers},
                                            {"routes", {{"cura_support_mesh", {{"line_seconds", s.walls_cura.line_seconds}}},
                                                        {"prusa_3mf", {{"line_seconds", s.walls_prusa.line_seconds}}}}}}}}}};
}

json edits_json(const ManualEdits& e, std::size_t blocked_samples) {
    json blockers = json::array(), points = json::array();
    for (const auto& b : e.support_blockers) blockers.push_back({{b.min.x, b.min.y, b.min.z}, {b.max.x, b.max.y, b.max.z}});
    for (const auto& q : e.support_points) points.push_back({q.x, q.y, q.z});
    return {{"support_blockers", blockers},
            {"support_points", points},
            {"omit_struts", e.omit_struts},
            {"highlight_strut", e.highlight_strut},
            {"samples_blocked", blocked_samples}};
}

// Creates `dir` and its parents; OutputError naming what is in the way, or the system's reason.
void create_output_dir(const std::string& dir) {
    namespace fs = std::filesystem;
    std::error_code ec;
    fs::create_directories(dir, ec);
    if (!ec) return;
    for (fs::path p = fs::path(dir).lexically_normal(); !p.empty() && p != p.parent_path(); p = p.parent_path())
        if (std::error_code e; fs::exists(p, e) && !fs::is_directory(p, e))
            throw OutputError(dir + ": cannot create the output directory: " + p.string() +
                              " exists and is not a directory. Choose another --out directory.");
    throw OutputError(dir + ": cannot create the output directory: " + ec.message() + ". Choose another --out directory.");
}

std::string absolute_path(const std::string& path) {
    std::error_code ec;
    auto abs = std::filesystem::absolute(path, ec);
    return ec ? path : abs.lexically_normal().string();
}

}  // namespace

std::string report_json(const Result& r, const Job& job) {
    json j;
    j["tool"] = "clever-support";
    j["input"] = {{"file", job.shown_input()},
                  {"sha256", r.input_sha256},
                  {"triangles", r.repair.input_triangles},
                  {"shells", r.repair.shells},
                  {"repair",
                   {{"welded_vertices", r.repair.welded_vertices},
                    {"degenerate_removed", r.repair.degenerate_removed},
                    {"duplicates_removed", r.repair.duplicates_removed},
                    {"flipped", r.repair.flipped},
                    {"boundary_edges", r.repair.boundary_edges},
                    {"holes_filled", r.repair.holes_filled},
                    {"boundary_edges_left", r.repair.boundary_edges_left},
                    {"caps_unfolded", r.repair.caps_unfolded},
                    {"nonmanifold_edges", r.repair.nonmanifold_edges},
                    {"self_intersecting_pairs", r.self_intersections}}}};
    if (is_scad_input(job.input)) j["input"]["openscad_defines"] = job.defines;
    if (!r.input_contents.empty()) j["input"]["contents"] = r.input_contents;
    j["parameters"] = params_json(job.params);
    if (!job.edits.empty() || job.edits.highlight_strut >= 0) j["edits"] = edits_json(job.edits, r.blocked_samples);
    const auto& pl = r.placement;
    json rot = json::array();
    for (const auto& row : r.orientation.rotation.m) rot.push_back({row[0], row[1], row[2]});
    Vec3 size = bounding_box(r.model).size();
    const Vec3 rx = euler_deg_from_rotation(pl.rotation);
    json cands = json::array();
    for (size_t i = 0; i < r.orientation.candidates.size(); ++i) {
        const auto& c = r.orientation.candidates[i];
        json cj = {{"down", {c.down.x, c.down.y, c.down.z}}, {"source", c.source}, {"overhang_area_mm2", c.overhang_area}};
        if (c.evaluated && c.support.grown)
            cj["support"] = {{"volume_mm3", c.support.volume}, {"model_contacts", c.support.model_contacts}, {"height_mm", c.support.height}};
        else if (c.evaluated)  // a lower pose with an empty tree was found: this one's was not grown
            cj["support"] = {{"needs_support", true}, {"tree_grown", false}, {"height_mm", c.support.height}};
        if (c.same_pose_as >= 0) cj["same_pose_as"] = c.same_pose_as;  // that candidate turned about the vertical
        cj["chosen"] = i == r.orientation.chosen;
        cands.push_back(cj);
    }
    j["placement"] = {{"scale", pl.scale},
                      {"orientation", to_string(r.orientation.mode)},
                      {"decided_by", r.orientation.decided_by},
                      {"rotation", rot},
                      {"rotation_deg", {rx.x, rx.y, rx.z}},
                      {"translation_mm", {pl.translation.x, pl.translation.y, pl.translation.z}},
                      {"size_mm", {size.x, size.y, size.z}},
                      {"candidates", cands},
                      {"how_to_map", pose_mapping(pl)}};
    j["model"] = {{"volume_mm3", signed_volume(r.model)}, {"triangles", r.model.faces.size()}};
    size_t counts[4] = {0, 0, 0, 0};
    for (const auto& s : r.samples.samples) ++counts[static_cast<int>(s.kind)];
    j["overhangs"] = {{"area_mm2", r.samples.overhang_area},
                      {"faces", r.samples.overhang_faces},
                      {"samples", r.samples.samples.size()},
                      {"face_samples", counts[0]},
                      {"edge_samples", counts[1]},
                      {"point_samples", counts[2]},
                      {"centroid_samples", counts[3]},  // gap fills (SampleKind::GapFill); the key readers know
                      {"top_up_samples", r.samples.topped_up}};
    j["supports"] = supports_json(r.supports, job.params);
    j["columns_baseline"] = supports_json(r.columns, job.params);
    double saved_v = r.columns.volume > 0 ? 1 - printed_volume(r.supports) / r.columns.volume : 0;
    double saved_l = r.columns.length > 0 ? 1 - r.supports.length / r.columns.length : 0;
    j["saving_vs_columns"] = {{"volume", saved_v}, {"length", saved_l}};
    if (job.timings) {  // wall-clock times differ from run to run: --no-timings leaves them out
        json stages = json::object();
        double total = 0;
        for (const auto& s : r.stages) stages[s.name] = s.seconds, total += s.seconds;
        j["seconds"] = stages;
        j["seconds_total"] = total;
    }
    j["warnings"] = r.warnings;
    return j.dump(2) + "\n";
}

std::vector<OutputFile> support_mesh_files(const std::string& name, const Mesh& model, const Mesh& supports,
                                           const Supports& built, const Params& p) {
    std::vector<OutputFile> files;
    // The model's 3MF lines, written for the first 3MF and let go after the second.
    struct ModelLines {
        std::shared_ptr<const MeshXml> xml;
        int uses_left = 2;
    };
    auto model_lines = [&model, shared = std::make_shared<ModelLines>()] {
        if (!shared->xml) shared->xml = mesh_xml(model);
        std::shared_ptr<const MeshXml> xml = shared->xml;
        if (--shared->uses_left == 0) shared->xml.reset();
        return xml;
    };
    files.push_back({name + ".supported.stl", [&model, &supports, &built, &p] {
                         // Printed as model geometry (walls, infill, top layers) a slab would be
                         // filled: where there are bridges (ceilings/slabs.hpp) the supports go in
                         // as a run builds them, bodies then walls, without the bridges.
                         if (std::none_of(built.walls.begin(), built.walls.end(), [](const CeilingWall& w) { return w.bridge; }))
                             return encode_stl({&model, &supports}, "clever-support: model + supports");
                         Mesh unbridged = bodies_mesh(built.bodies, p.wall_thickness);
                         for (const CeilingWall& w : built.walls)
                             if (!w.bridge) append(unbridged, wall_mesh(w));
                         return encode_stl({&model, &unbridged}, "clever-support: model + supports");
                     }});
    files.push_back({name + ".supports.stl", [&supports] { return encode_stl(supports, "clever-support: supports"); }});
    files.push_back({name + ".3mf", [name, &model, &supports, model_lines] {
                         return encode_3mf_cura(name, {{name + " model", model, {}, model_lines()},
                                                       {name + " supports", supports, cura_support_mesh_settings()}});
                     }});
    files.push_back({name + ".prusa.3mf", [name, &model, &built, &p, model_lines] {
                         // The ceiling walls (0.5 mm fins) print as thin walls, like the N-profile's.
                         Mesh struts = bodies_mesh(built.bodies, p.wall_thickness, Profile::N);
                         // Without the slabs' bridges (ceilings/slabs.hpp): PrusaSlicer prints a wall once.
                         for (const CeilingWall& w : built.walls)
                             if (!w.bridge) append(struts, wall_mesh(w));
                         const Mesh solid = bodies_mesh(built.bodies, p.wall_thickness, Profile::Square);
                         return encode_3mf_prusa(
                             name, {{name + " model", model, {}, model_lines()},
                                    {name + " supports", struts, prusa_support_volume_settings(p, PrusaSupportVolume::NProfile)},
                                    {name + " supports, solid", solid,
                                     prusa_support_volume_settings(p, PrusaSupportVolume::Solid)}});
                     }});
    return files;
}

std::vector<OutputFile> output_files(const Result& r, const Job& job, const std::string& version) {
    std::vector<OutputFile> files = support_mesh_files(r.name, r.model, r.supports.mesh, r.supports, job.params);
    files.push_back({r.name + ".model.stl", [&r] { return encode_stl(r.model, "clever-support: placed model"); }});
    files.push_back({r.name + ".report.json", [&r, &job] { return report_json(r, job); }});
    files.push_back({r.name + ".scad", [&r, &job, version] {
                         ScadMeta meta{version, r.input_sha256, absolute_path(job.input), r.name + ".model.stl",
                                       pose_numbers(r.placement), pose_in_words(r.placement)};
                         return emit_scad(r.supports, job, meta);
                     }});
    files.push_back({"clever_support.scad", [] { return scad_template_library(); }});
    for (const CuraPrinterFamily& family : cura_printer_families())
        files.push_back({family.file, [&job, &family] { return encode_cura_profile(family, job.params); }});
    return files;
}

namespace {

// A file's bytes; a file that fails to encode (the 3MF packer) is an OutputError naming it.
std::string encoded(const OutputFile& f, const std::string& dir) {
    try {
        return f.content();
    } catch (const std::bad_alloc&) {
        throw;
    } catch (const std::exception& e) {
        throw OutputError(dir + "/" + f.name + ": cannot encode it (" + e.what() +
                          "). Nothing was written; please report this with the input file.");
    }
}

}  // namespace

void write_outputs(const std::string& dir, const std::vector<OutputFile>& files) {
    create_output_dir(dir);
    std::vector<std::string> temps;
    auto cleanup = [&] {
        for (const auto& t : temps) ::unlink(t.c_str());
    };
    try {
        for (const auto& f : files) {
            std::string tmp = dir + "/." + f.name + ".partial";
            temps.push_back(tmp);
            write_file_atomic(tmp, encoded(f, dir));
        }
    } catch (const OutputError& e) {
        cleanup();
        throw OutputError(std::string(e.what()).replace(0, 0, "writing outputs: "));
    } catch (...) {  // out of memory: nothing half-written either
        cleanup();
        throw;
    }
    // Swap the set in: old files step aside first, so a failure half-way puts everything back.
    std::vector<std::string> finals, backups;
    auto roll_back = [&](size_t placed) {
        for (size_t j = 0; j < placed; ++j) ::unlink(finals[j].c_str());
        for (size_t j = 0; j < backups.size(); ++j)
            if (!backups[j].empty()) ::rename(backups[j].c_str(), finals[j].c_str());
        cleanup();
    };
    for (size_t i = 0; i < files.size(); ++i) {
        finals.push_back(dir + "/" + files[i].name);
        backups.emplace_back();
        struct stat st{};
        if (lstat(finals[i].c_str(), &st) == 0 && !S_ISDIR(st.st_mode)) {
            backups[i] = dir + "/." + files[i].name + ".previous";
            if (::rename(finals[i].c_str(), backups[i].c_str()) != 0) backups[i].clear();
        }
        if (::rename(temps[i].c_str(), finals[i].c_str()) != 0) {
            int err = errno;
            roll_back(i);
            throw OutputError(finals[i] + ": cannot write: " + std::strerror(err) + ". Choose another --out directory.");
        }
    }
    for (const auto& b : backups)
        if (!b.empty()) ::unlink(b.c_str());
}

double printed_volume(const Supports& s) { return s.volume - s.bridges_volume; }

double support_grams(const Supports& s, const Params& p) { return printed_volume(s) / 1000.0 * p.filament_density; }

std::string human_summary(const Result& r, const Job& job, const std::string& dir) {
    const auto& st = r.supports.sized.tree.stats;
    std::string s;
    Vec3 size = bounding_box(r.model).size();
    s += fmt::format("{}: {:.1f} x {:.1f} x {:.1f} mm, orientation {} ({})\n", r.name, size.x, size.y, size.z,
                     to_string(r.orientation.mode), r.orientation.decided_by);
    s += fmt::format("  pose        {}\n", pose_in_words(r.placement));
    if (!r.input_contents.empty()) s += fmt::format("  input       {}\n", r.input_contents);
    s += fmt::format("  overhangs   {:.0f} mm^2, {} samples\n", r.samples.overhang_area, r.samples.samples.size());
    s += fmt::format("  tree        {} struts, {} merges, {} on the bed, {} on the model, {} pillars\n",
                     r.supports.sized.tree.struts.size(), st.merges, st.bed_contacts, st.model_contacts, st.pillars);
    const Params& p = job.params;
    const SlicerCost& cost = r.supports.slicer_cost;  // estimated once, by the pipeline
    s += fmt::format("  support     {:.2f} g of filament ({:.0f} mm^3 at {:g} g/cm^3), about {:.1f} min of printing "
                     "added (estimate: Cura {:.1f}, PrusaSlicer {:.1f})\n",
                     support_grams(r.supports, p), printed_volume(r.supports), p.filament_density, cost.seconds / 60,
                     cost.cura_seconds / 60, cost.prusa_seconds / 60);
    s += fmt::format("              {:.0f} mm of struts\n", r.supports.length);
    double total = 0;
    for (const auto& x : r.stages) total += x.seconds;
    s += fmt::format("  time        {:.2f} s\n", total);
    s += fmt::format("  outputs     {}/{}.supported.stl, .supports.stl, .model.stl, .report.json, .scad\n", dir, r.name);
    s += fmt::format("  print       Cura: open {0}/{1}.3mf (supports print as support); import {0}/clever_support.curaprofile\n"
                     "              once (clever_support_creality.curaprofile on an Ender 3/5 or CR-10), see README\n"
                     "              \"Printing in Cura\". PrusaSlicer: open {0}/{1}.prusa.3mf.\n"
                     "              Any other slicer: {0}/{1}.supported.stl with its own supports off.\n",
                     dir, r.name);
    return s;
}

}  // namespace cs

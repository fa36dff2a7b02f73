#include "cli/apply.hpp"

#include <cstdio>
#include <fstream>
#include <iterator>

#include "cli/defines.hpp"
#include "cli/run_files.hpp"
#include "core/errors.hpp"
#include "edit/edited_scad.hpp"
#include "mesh/mesh_io.hpp"
#include "edit/scad_values.hpp"
#include "output/outputs.hpp"
#include "view/view_tree.hpp"

namespace cs {

int cmd_render(const RenderOptions& o) {
    check_defines(o.defines, o.scad);
    auto r = render_scad(o);
    std::printf("rendered %s in %.1f s\n", r.output.c_str(), r.seconds);
    std::printf("  (the supports STLs and 3MFs are unchanged: `clever-support apply %s` rewrites them from this .scad)\n",
                o.scad.c_str());
    return kExitOk;
}

namespace {

// The bodies and walls an edited .scad renders with the -D values on top (view/view_tree.hpp
// supports_from_scad): what the .prusa.3mf splits into its two volumes, as a run splits its own.
// OpenSCAD's union cannot say which part of it was a tip and which a strut.
Supports recorded_supports(const std::string& scad, const std::vector<std::string>& defines, const Params& p) {
    std::ifstream in(scad, std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::string applied = with_scad_defines(text, defines, scad);
    try {
        const EditedScad edited = read_edited_scad_text(applied, scad);  // checks an omit_struts given with -D
        return supports_from_scad(parse_scad_values(applied, scad), edited.job.edits.omit_struts, p);
    } catch (const InputError& e) {  // the file as written was read: a -D value is what is wrong
        throw ParameterError(std::string("with the -D values given, ") + e.what());
    }
}

}  // namespace

// The supports of an edited .scad, rendered without the model, into the four files that carry
// them. Parameters given with -D also set the PrusaSlicer volumes' settings.
int cmd_apply(const ApplyArgs& a) {
    check_defines(a.defines, a.scad, a.quiet);
    EditedScad edited = read_edited_scad(a.scad);
    Params p = edited.job.params;
    set_scad_params(a.defines, p, /*others_allowed=*/true);
    const std::string name = stem_of(a.scad), dir = edited.folder;
    const std::string model_file = dir + "/" + name + ".model.stl";
    Mesh model = read_mesh(model_file);
    Supports built = recorded_supports(a.scad, a.defines, p);  // before the render: a bad -D fails fast
    RenderOptions ro;
    ro.scad = a.scad;
    ro.output = dir + "/." + name + ".apply.stl";
    ro.defines = a.defines;
    ro.defines.insert(ro.defines.end(), {"show_model=false", "show_supports=true"});
    ro.openscad = a.openscad;
    RenderResult rr;
    Mesh supports;  // empty when every solid was left out (OpenSCAD then renders nothing)
    try {
        rr = render_scad(ro);
        supports = read_mesh(ro.output, /*allow_empty=*/true);
    } catch (const ExternalToolError& e) {
        std::remove(ro.output.c_str());
        if ((std::string(e.what()) + e.log).find("top level object is empty") == std::string::npos) throw;
    } catch (...) {
        std::remove(ro.output.c_str());
        throw;
    }
    std::remove(ro.output.c_str());
    if (supports.faces.empty()) built = {};  // nothing rendered: nothing for PrusaSlicer either
    write_outputs(dir, support_mesh_files(name, model, supports, built, p));
    if (!a.quiet) {
        // What is printed: the slabs' bridges stay hollow (ceilings/slabs.hpp), as in a run's summary.
        const double printed = signed_volume(supports) - bridges_volume(built.walls);
        std::printf("applied %s (rendered in %.1f s): rewrote %s/%s.supports.stl, .supported.stl, .3mf, .prusa.3mf\n",
                    a.scad.c_str(), rr.seconds, dir.c_str(), name.c_str());
        // check judges supports.stl solid by solid (a top, a bottom, a length, a width): OpenSCAD's
        // union has fused them, so its verdicts on this folder would be wrong (README: apply).
        std::printf("  supports now %.2f g (%.0f mm^3); the report still describes the supports as grown, and\n"
                    "  solids that touch are one solid now: check cannot judge this folder (it judges solid by\n"
                    "  solid); check the folder as generated, or regrow the .scad and check that\n",
                    printed / 1000.0 * p.filament_density, printed);
    }
    return kExitOk;
}

}  // namespace cs

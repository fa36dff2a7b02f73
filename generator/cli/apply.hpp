// The two commands that render a generated .scad with OpenSCAD, with -D values on top:
//   render  into <name>.union.stl (or -o): what OpenSCAD makes of it, for a look or another tool
//   apply   the supports alone, into the four files a slicer opens (<name>.supports.stl,
//           .supported.stl, .3mf, .prusa.3mf) beside it; the model and the report stay as written.
//           The STLs and Cura's 3MF carry OpenSCAD's union; the .prusa.3mf, like a run's, the
//           N-profile struts and walls and the solid bodies as two volumes, built from the tree,
//           walls and values the .scad records (with the -D values on top), as `view` draws them
//
// Example (`clever-support apply out/m/m.scad -D k=0.003`):
//   ApplyArgs a;
//   a.scad = "out/m/m.scad";
//   a.defines = {"k=0.003"};
//   int code = cmd_apply(a);  // rewrites out/m/m.supports.stl, ...; kExitOk
#pragma once

#include <string>
#include <vector>

#include "render/render.hpp"

namespace cs {

// `apply`: the supports rendered from an edited .scad into the slicer files beside it.
struct ApplyArgs {
    std::string scad, openscad;
    std::vector<std::string> defines;
    bool quiet = false;
};

// Throws ParameterError for a bad -D, ExternalToolError when OpenSCAD fails.
int cmd_render(const RenderOptions& o);

// Throws as cmd_render, and InputError for a .scad that cannot be read back or a missing
// <name>.model.stl; writes nothing then (output/outputs.hpp write_outputs).
int cmd_apply(const ApplyArgs& a);

}  // namespace cs

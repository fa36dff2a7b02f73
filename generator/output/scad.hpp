// The parametric OpenSCAD output: printer parameters first in Customizer form, the tree as data
// (topology and node positions from the generator), geometry by scad_templates/clever_support.scad.
// Strut widths are NOT in the data: the template computes them from k, d_min, d_max and the tree,
// so `openscad -D k=0.003 x.scad` re-sizes the whole tree as the generator would have.
#pragma once

#include <string>

#include "core/params.hpp"
#include "struts/struts.hpp"

namespace cs {

struct ScadMeta {
    std::string version;
    std::string input;
    std::string input_sha256;
    std::string model_file;  // imported, relative to the .scad
};

std::string emit_scad(const SizedTree& sized, const Params& p, const ScadMeta& meta);

// The template library's text (scad_templates/clever_support.scad, embedded at build time);
// written beside every generated .scad so the output folder is self-contained.
const std::string& scad_template_library();

}  // namespace cs

// The parametric OpenSCAD output, meant to be read and edited by a person:
//   header        tool version, input and its SHA-256 (and -D values of a .scad part), counts
//   Customizer    k, d_min, d_max, strength_length, wall, tips, feet, show: take effect at once
//   [Manual edits] support_blockers, support_points, omit_struts, highlight_strut
//   [Regrow]      critical_angle, sampling, gap, clearance, buildplate_only: take effect with
//                 `clever-support regrow THIS.scad` (which also applies the manual edits)
//   [Hidden]      how the file was made (regrow reads it), then the tree as data, one record per
//                 line with its index and kind as a comment: nodes, struts [top, bottom], leaves
//                 (overhang sample and how far below it the tip ends), contact tips, beds (room for
//                 a foot), pillars.
// Strut widths, incoming lists, run lengths and angles are NOT in the data: the template
// (scad_templates/clever_support.scad) derives them, so `-D k=0.003`, a moved node or a strut
// added by hand re-sizes the tree as the generator would have. The struts stage's decisions
// (contact tips, room for feet, joint overlap) are data, taken from it and not recomputed here.
#pragma once

#include <string>

#include "job/job.hpp"
#include "job/result.hpp"

namespace cs {

struct ScadMeta {
    std::string version;
    std::string input_sha256;
    std::string input_path;  // absolute: where `regrow` finds the input again
    std::string model_file;  // imported, relative to the .scad
    std::vector<double> pose;  // pose_numbers of the placement
};

std::string emit_scad(const Supports& supports, const Job& job, const ScadMeta& meta);

// A value as OpenSCAD source, exact enough to read back the same double.
std::string scad_number(double v);
// A string as an OpenSCAD string literal (quotes and backslashes escaped).
std::string scad_string(const std::string& s);

// The template library's text (scad_templates/clever_support.scad, embedded at build time);
// written beside every generated .scad so the output folder is self-contained.
const std::string& scad_template_library();

}  // namespace cs

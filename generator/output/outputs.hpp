// Everything a run writes, in `--out DIR`:
//   <name>.supported.stl  model + support solids (each closed and outward-facing)
//   <name>.supports.stl   the support solids alone
//   <name>.model.stl      the placed (scaled, rotated, on-bed) model
//   <name>.3mf            for Cura: model + supports grouped, the supports marked "print as support"
//   <name>.prusa.3mf      for PrusaSlicer: one object, the supports two volumes with support-like settings
//   clever_support.curaprofile  Cura's support settings for the supports of <name>.3mf, to import once;
//   clever_support_creality.curaprofile  the same for Creality's qualities (output/threemf.hpp)
//   <name>.report.json    parameters, counts, lengths, volumes, the columns baseline, timings
//   <name>.scad           parametric OpenSCAD (see output/scad.hpp) + clever_support.scad beside it
// All files are written to temporaries first and renamed into place only when every one of them
// was written, so a failure leaves no half-written output behind.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "job/job.hpp"
#include "job/result.hpp"

namespace cs {

struct OutputFile {
    std::string name;                      // file name inside the output directory
    std::function<std::string()> content;  // encoded only as it is written: one file's bytes in
                                           // memory at a time (a 5M-triangle STL is 250 MB)
};

std::string report_json(const Result& r, const Job& job);

// The files of a run (without encoding or writing them; they refer to `r` and `job`, which must
// outlive them).
std::vector<OutputFile> output_files(const Result& r, const Job& job, const std::string& version);

// The four files that carry the supports: <name>.supported.stl, .supports.stl, .3mf (Cura) and
// .prusa.3mf (`p` gives the PrusaSlicer volumes' settings). `supports` is the support solid the
// STLs and Cura's 3MF carry; `built` is what it is made of (its bodies, then its ceiling walls):
// the .prusa.3mf carries what prints as thin walls (N-profile struts, ceiling walls) and the solid
// bodies (tips, feet, pillars, square struts) as two volumes (see prusa_support_volume_settings).
// output_files writes them after a run (`supports` is built's mesh), `clever-support apply` from
// a rendered .scad (`supports` is OpenSCAD's union, `built` the bodies the .scad records:
// view/view_tree.hpp supports_from_scad). The meshes, `built` and `p` must outlive the files.
std::vector<OutputFile> support_mesh_files(const std::string& name, const Mesh& model, const Mesh& supports,
                                           const Supports& built, const Params& p);

// Creates `dir` if needed and writes all files atomically as a set. Throws OutputError.
void write_outputs(const std::string& dir, const std::vector<OutputFile>& files);

// The volume the slicers print (mm^3): the support solid without the slabs' bridges, which both
// slicers' files leave hollow or out (ceilings/slabs.hpp).
double printed_volume(const Supports& s);

// Grams of filament the supports take: their printed volume times the preset's filament density.
double support_grams(const Supports& s, const Params& p);

// A short human summary of a run for stdout: size, pose, tree, support grams and the minutes they
// add (estimate_slicer_cost, tree.hpp), outputs and what to print.
std::string human_summary(const Result& r, const Job& job, const std::string& dir);

}  // namespace cs

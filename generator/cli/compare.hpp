// `--compare cura|prusa`: the model sliced three times by a real slicer, in a temporary folder,
// with the profile bench/slicers uses (bench/slicers/profile.json, resolved by slice.py): without
// supports, with the slicer's own supports (Cura "normal", PrusaSlicer "grid": their defaults),
// and with ours (Cura: <name>.supports.stl as a support mesh, as <name>.3mf marks it; PrusaSlicer:
// <name>.prusa.3mf as written). The support angle and the z gap are the run's. What each adds to
// the unsupported print is what the summary reports, in grams and minutes.
//
// Example:
//   SlicerComparison c = compare_with_slicer("prusa", "out/m", "m", params);
//   if (c.done) printf("%.1f g vs %.1f g\n", c.own.grams - c.bare.grams, c.ours.grams - c.bare.grams);
#pragma once

#include <string>

#include "core/params.hpp"

namespace cs {

struct SlicedPrint {
    double grams = 0, seconds = 0;
};

struct SlicerComparison {
    bool done = false;
    std::string why_not;        // when not done: the slicer is not installed, slice.py is missing, ...
    std::string slicer_name;    // "PrusaSlicer", "CuraEngine"
    std::string own_supports;   // the mode sliced as the slicer's own: "grid", "normal"
    SlicedPrint bare, own, ours;
};

// Slices the run written in `dir` (files <name>.model.stl, .supports.stl, .prusa.3mf). Never
// throws for a missing slicer or a failed slice: `done` is false and `why_not` says why.
SlicerComparison compare_with_slicer(const std::string& slicer, const std::string& dir, const std::string& name,
                                     const Params& p);

// "your slicer's own supports (PrusaSlicer grid): 4.1 g, 12.3 min; ours: 1.9 g, 6.0 min", or why not.
std::string comparison_line(const SlicerComparison& c);

}  // namespace cs

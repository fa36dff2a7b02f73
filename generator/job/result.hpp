// What one run of the generator computed (pipeline/run_job), as plain structs: the placed model,
// its overhang samples, the supports of the chosen strategy and the columns baseline. output/
// writes it; nothing here computes.
#pragma once

#include <string>
#include <vector>

#include "ceilings/ceilings.hpp"
#include "core/geometry.hpp"
#include "mesh/repair.hpp"
#include "orient/orient.hpp"
#include "overhang/overhang.hpp"
#include "struts/struts.hpp"

namespace cs {

// What one strategy built for the placed model.
struct Supports {
    SizedTree sized;
    std::vector<Strut> grown_struts;  // before omit_struts pruned them: the numbering edits refer to
    std::vector<Pillar> grown_pillars;  // likewise; pillar i is solid grown_struts.size() + i
    std::vector<NodeKind> grown_kinds;  // likewise, per node: an omitted branch's leaves stay leaves in the
                                        // .scad, so its tips come back when the omission is undone
    std::vector<Body> bodies;
    std::vector<CeilingWall> walls;  // under ceilings low over the bed or a floor (ceilings/ceilings.hpp)
    std::vector<CeilingWall> grown_walls;  // before omit_struts took out the hybrid pieces on its branches
                                           // (pipeline.hpp prune_pieces): what the .scad records
    Mesh mesh;                       // the bodies, then the walls
    double volume = 0;         // of the support solid, overlaps at joints counted once (solid_volume), mm^3
    double bodies_volume = 0;  // the bodies' volumes added up, overlaps counted twice, mm^3
                               // (both add the walls' own; the ends of joins inside rows count twice)
    // The slabs' bridges (ceilings/slabs.hpp), counted in `volume`: the slicers leave them hollow
    // (CuraEngine prints a slab's outline under our profile; the .prusa.3mf has none), so what is
    // printed is volume - bridges_volume.
    double bridges_volume = 0;
    double length = 0;  // total strut length (mm)
    SlicerCost slicer_cost;  // estimate_slicer_cost of the sized tree, computed once per tree, plus the walls
    WallsPrinted walls_cura, walls_prusa;  // the walls' part of it per route (ceilings/ceilings.hpp)
};

struct Stage {
    std::string name;
    double seconds;
};

struct Result {
    std::string name;          // input file name without folder and extension
    std::string input_sha256;
    Mesh model;                // placed on the bed
    RepairReport repair;
    std::size_t self_intersections = 0;  // pairs, counted up to a limit
    Placement placement;
    Orientation orientation;
    OverhangSamples samples;
    Supports supports;         // by params.strategy
    Supports columns;          // the baseline, same samples
    std::vector<Stage> stages;
    std::vector<std::string> warnings;
    std::string input_contents;  // what a container input held (a 3MF's objects and build items), else ""
    std::size_t blocked_samples = 0;  // overhang samples left unsupported by a user's blockers
};

// The placement as 13 numbers: scale, the rotation's rows, the translation. A user's edits are
// in the placed model's coordinates: a regrow compares these to know whether they still fit.
std::vector<double> pose_numbers(const Placement& placement);

// The placement in words, for the summary and the .scad header:
//   "scaled 1, rotated 90.0 deg about X, then 0.0 about Y, then 0.0 about Z, then moved by (-10.00, 4.00, 12.50) mm"
std::string pose_in_words(const Placement& placement);
// How to map a point of the design (the input file's coordinates) to the placed model's (those
// of <name>.model.stl, the coordinates of --block, --support-point and the .scad's edits).
std::string pose_mapping(const Placement& placement);

}  // namespace cs

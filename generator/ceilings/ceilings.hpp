// Walls under flat and round ceilings low over the bed (issue #32): where a stretch of overhang
// falls freely to the bed, thin walls (one line wide) stand in rows under it, `ceiling_span` apart,
// joined at alternate ends into one meander, so a slicer prints the region as a few long lines per
// layer instead of one small island per tip. Long straight lines print near full speed; a tip's
// 1 mm outline never does (acceleration), and every island costs a travel and often a retraction.
//
// Stage: after overhang sampling, before the tree (core <- mesh <- query <- overhang <- ceilings
// <- tree). It takes the samples and gives the tree back those the walls do not cover.
//
//   support_ceilings(model, samples, p) -> Ceilings{walls, rest, ...}
//     regions   samples whose fall to the bed is free, joined where lattice neighbours lie on the
//               same stretch of surface
//     rows      along the region's longer side, at most ceiling_span apart; each row is cut into
//               walls where the ceiling above it is an overhang of this region all across the
//               wall's width plus tip_side_clearance (a wall beside it, or a hole, ends a wall)
//     tops      one air gap under the lowest point of the ceiling over the wall's width, at every
//               station (ceiling_station apart): a round ceiling gets a stepped top that follows it
//     joins     a short wall between neighbouring rows at alternate ends (a meander); it braces
//               the rows it joins. A row left without a join stays only where the strength rule
//               allows a wall of its width that tall.
//     choice    per region, by estimated slicer seconds (ceiling_seconds against tree_seconds)
//     coverage  a sample is handed to the walls when every point of its lattice cell on its own
//               stretch of surface lies within kWallReach of a wall's top; the others stay with
//               the tree (tips at the ends and rims the walls do not reach).
//
// Example: a 50 x 10 mm roof 5 mm over the bed, span 3.4 mm: 4 rows of 50 mm, 3 joins, one
// meander; the roof's 80 samples all go to the walls.
#pragma once

#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"
#include "overhang/overhang.hpp"

namespace cs {

class ModelQuery;

// A straight wall standing on the bed: its stations run along one horizontal line, each the top
// of the wall there (one gap under the ceiling). The wall is `thickness` wide across that line.
struct CeilingWall {
    std::vector<Vec3> top;
    bool join = false;  // a join between two rows (it ends inside the rows it joins)
};

struct Ceilings {
    std::vector<CeilingWall> walls;
    std::vector<Sample> rest;       // samples left to the tree, in the input's order
    std::size_t regions = 0;        // regions given walls
    std::size_t covered = 0;        // samples the walls carry
    double tree_seconds = 0, wall_seconds = 0;  // the estimates of the chosen regions
};

Ceilings support_ceilings(const ModelQuery& model, const std::vector<Sample>& samples, const Params& p);

// Closed, outward-facing mesh of one wall: a four-cornered cross-section (bed to top, `thickness`
// wide) swept along its stations, with explicit triangle caps at both ends.
Mesh wall_mesh(const CeilingWall& w, double thickness);

}  // namespace cs

// Walls under flat and round ceilings low over the bed or a level floor of the model (issue #32):
// where a stretch of overhang falls freely to the bed or to such a floor, thin walls (one line wide) stand in rows under it, `ceiling_span` apart,
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
//     floors    the bed, or a level face of the model (a gap above it): walls under a roof over
//               the model stand on it as pillars do
//     tops      one air gap under the lowest point of the ceiling over the wall's width, at every
//               station (kStation apart); each row is then cut into pieces with a flat top and
//               floor, so a round ceiling gets a staircase that follows it
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

// A straight piece of wall, `from` to `to` (horizontal; their z unused), its foot flat at `bottom`
// (0 on the bed, or a gap above a level face of the model) and its top flat at `top` (a gap under
// the lowest point of the ceiling over it). Under a round ceiling a row is a staircase of pieces
// that share the station between them. The wall is `thickness` wide across from-to.
struct CeilingWall {
    Vec3 from, to;
    double bottom = 0, top = 0;
    bool join = false;  // joins two rows (it ends inside the rows it joins)
};

struct Ceilings {
    std::vector<CeilingWall> walls;
    std::vector<Sample> rest;       // samples left to the tree, in the input's order
    std::size_t regions = 0;        // regions given walls
    std::size_t covered = 0;        // samples the walls carry
    double tree_seconds = 0, wall_seconds = 0;  // the estimates of the chosen regions
};

Ceilings support_ceilings(const ModelQuery& model, const std::vector<Sample>& samples, const Params& p);

// Closed, outward-facing mesh of one wall: a box, `thickness` wide across from-to, bottom to top,
// its faces as triangles.
Mesh wall_mesh(const CeilingWall& w, double thickness);

}  // namespace cs

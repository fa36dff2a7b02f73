// Walls under flat and round ceilings low over the bed or a level floor of the model (issue #32):
// where a stretch of overhang falls freely to the bed or to such a floor, thin walls (one line wide) stand in rows under it, `ceiling_span` apart,
// joined at alternate ends into one meander, so a slicer prints the region as a few long lines per
// layer instead of one small island per tip. Long straight lines print near full speed; a tip's
// 1 mm outline never does (acceleration), and every island costs a travel and often a retraction.
//
// Stage: after overhang sampling, before the tree (core <- mesh <- query <- overhang <- ceilings
// <- tree). It takes the samples and gives the tree back those the walls do not cover.
//
//   support_ceilings(model, samples, p, tree_count, blockers) -> Ceilings{walls, rest, ...}
//     regions   samples whose fall to the bed is free, joined where lattice neighbours lie on the
//               same stretch of surface and their ceilings are level along alike directions (a
//               pipe tee's run and branch are regions of their own, each with rows along its
//               own axis; where the ceiling has no such direction, flat or where bores meet, a
//               sample joins the region that reaches it first)
//     rows      at most ceiling_span apart (no walls where that is more than twice the walls'
//               reach and a wall: nothing between two rows would be carried), where the ceiling is level (along x or y, whichever
//               changes height less, so a sloping or round ceiling gets long flat pieces; else
//               along the longer side (the hybrid's also across it, kept where faster on both
//               routes: a shelf off a wall with slanted rims, whose rows out from the wall all
//               end on it, where joins fit; along the wall no joins fit at the rims, and each
//               row is a line of its own); where the faces over the samples are level along a
//               direction between x and y, a diagonal bore or a twisted blade, rows along that
//               too, kept where they leave fewer samples); the outer rows as far out as walls stand along them (a
//               bore's or tunnel's ceiling goes on past its outer samples), else just inside the
//               outer samples; where rows the span apart leave samples, also rows 0.9 x twice the
//               walls' reach apart (a slope's staircase is held at each piece's middle only), the
//               layout leaving fewer kept; where the region narrows past an outer row's end (a
//               tapering blade), also the outer row going on stepped in towards the next row
//               (tails, each joined to where the row ended by a short jog: one line), and an
//               inner row the same where a rim crosses the rows and its inner neighbour reaches
//               on past its end (a delta wing's leading edges), kept where they carry more and
//               are faster on both routes; each row is cut into walls where
//               the ceiling above it is an overhang of this region all across the wall's width
//               plus tip_side_clearance (a wall beside it ends a wall); a row goes
//               on under a hole through its ceiling up to kMostCrossed long (ceilings.cpp
//               may_cross; the hybrid's up to one piece), not under a pocket in it
//     floors    the bed, or a level face of the model (a gap above it): walls under a roof over
//               the model stand on it as pillars do
//     tops      one air gap under the lowest point of the ceiling over the wall's width, at every
//               station (kStation apart); each row is then cut into pieces with a flat top and
//               floor, so a round ceiling gets a staircase that follows it; a piece too short to
//               print alone on a layer comes down to where its stretch of wall is long enough
//               (printable_tops)
//     joins     a short wall between neighbouring rows at alternate ends (a meander)
//     strength  every piece stands on its own: as thick as the strength rule asks of a column
//               its height (wall_thickness_for), never thinner than the wall thickness
//     choice    per region, by the slicers' estimated seconds (core/slicer_time.hpp): walls only
//               where they cost less than the region's own tree on the Cura route AND on the
//               PrusaSlicer route (which slicer the user has is not known; on the Cura route
//               the walls are priced as the slabs the pipeline makes of them, ceilings/slabs.hpp);
//               the tree is grown from the region's samples and those beside it (neighbours on
//               the same stretch of surface the walls cannot take: walls split the tree that
//               would merge them) and counted by the caller's `tree_count`; a slab's bridge only
//               between rows whose feet are level (ceilings/slabs.cpp)
//     coverage  a sample is handed to the walls when every point `check` judges (overhang faces,
//               ridges, lowest points: check/judge_overhangs.hpp) that the sample covers (as the
//               sampling counts it: coverage_reach, same stretch of surface) lies within
//               kWallReachMargin x coverage_reach of a wall's contact as `check` finds them (a
//               long top along its length where the model is right above; a short one at its
//               middle, with the model over its nearest corner); the others stay with the tree
//               (tips at the ends and rims the walls do not reach). So `check` finds every point
//               such a sample held within its reach of a wall; steep undersides `check` does not
//               judge (a bore's sides) ask nothing of the walls. A sample the walls leave goes
//               too where every point it covers that the walls leave lies within the walls' reach
//               of another left sample's tip (a rim's tips hold the sliver of rim past the last
//               row); the tips so leaned on stay with the tree (Ceilings::stay). Walls only, not
//               the hybrid (ceilings.cpp says why).
//
// Example: a 50 x 10 mm roof 5 mm over the bed, span 3.4 mm: 4 rows of 50 mm, 3 joins, one
// meander; the roof's 80 samples all go to the walls.
#pragma once

#include <functional>
#include <utility>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"
#include "overhang/overhang.hpp"

namespace cs {

class ModelQuery;

// A straight piece of wall, `from` to `to` (horizontal; their z unused), its foot flat at `bottom`
// (0 on the bed, or a gap above a level face of the model) and its top flat at `top` (a gap under
// the lowest point of the ceiling over it). Under a round ceiling a row is a staircase of pieces
// that share the station between them. The wall is `thickness` wide across from-to: the wall
// thickness, or what the strength rule asks of a column that tall (core/rules.hpp), whichever is
// more, so each piece stands on its own as `check` judges it.
struct CeilingWall {
    Vec3 from, to;
    double bottom = 0, top = 0;
    bool join = false;  // joins two rows (it ends inside the rows it joins)
    double thickness = 0.5;
    bool on_tree = false;  // the hybrid's (ceilings/hybrid.hpp): its foot stands on a tip of the tree
    // Slabs (ceilings/slabs.hpp): a block filling the space between two neighbouring rows, so that
    // the two and it are one solid whose outline CuraEngine prints (each row once, not as a loop).
    // PrusaSlicer prints a row once anyway, and retracts on each travel inside our volume, so the
    // .prusa.3mf leaves the bridges out.
    bool bridge = false;
    double row_thickness = 0;  // a bridge's: the thickness of the rows it lies between
    bool tail = false;  // a piece of a row's tail, stepped in where the region narrows (ceilings.cpp,
                        // add_tails): it lies between two rows, so slabs leave it out
};

// What a tree grown from some samples alone would give a slicer to print, counted as
// tree/slicer_cost.hpp counts it (summed over the layers). The caller grows it: ceilings come before
// the tree.
struct TreeCount {
    double island_layers = 0, outline_mm = 0, hop_mm = 0;
};
using TreeCounter = std::function<TreeCount(const std::vector<Sample>&)>;

struct Ceilings {
    std::vector<CeilingWall> walls;
    std::vector<Sample> rest;       // samples left to the tree, in the input's order
    std::vector<char> stay;         // per sample of `rest`: its tip holds what the walls let go of
                                    // (release_held), so it stays with the tree (empty: none)
    std::vector<Vec3> released;     // samples the walls carry only with those tips (release_held)
    std::vector<Vec3> feet;         // the hybrid's: where a tip of the tree carries a piece's foot
    std::size_t regions = 0;        // regions given walls
    std::size_t covered = 0;        // samples the walls carry
    // The estimates of the chosen regions, seconds on the Cura and PrusaSlicer routes.
    double tree_cura_s = 0, tree_prusa_s = 0, walls_cura_s = 0, walls_prusa_s = 0;
};

// Walls that would leave more than this share of their region's samples to a tree are not priced:
// the region keeps its tree. Pricing grows the region's tree twice (for all its samples, and for
// those the walls leave), the stage's whole cost: on menger_sponge3 that took twice as long as
// growing its tree, for regions the walls left 0.5-0.9 of. On the tuning set no region the time
// model gave walls left more than 0.37 of them.
constexpr double kMostLeftToPrice = 0.5;

// Where the tip hung for a sample holds the overhang up (its top, at the sample's height: placement
// moves a tip aside from its sample); empty: at the sample.
using TipAt = std::function<Vec3(const Sample&)>;

// What another structure than walls would save on some samples against their own tree: seconds
// on the Cura and PrusaSlicer routes (the pipeline's: the hybrid, ceilings/hybrid.hpp, laid out
// over them alone; nothing where it takes no region).
using RivalSaving = std::function<std::pair<double, double>(const std::vector<Sample>&)>;

// A region whose walls would enter one of the user's `support_blockers` (placed-model coordinates)
// keeps its tree (the tree routes around blockers; a wall cannot). `most_left`: kMostLeftToPrice
// (tests of the walls' geometry pass 1 to price every region). `rival`: walls beating a region's
// tree give way where the rival saves more on the region's samples on both routes (the hybrid
// comes after the walls, on what they leave: a deck 12 mm up once got walls that beat its tree and
// shut out a hybrid cheaper than both on both routes).
Ceilings support_ceilings(const ModelQuery& model, const std::vector<Sample>& samples, const Params& p,
                          const TreeCounter& tree_count, const std::vector<Box3>& support_blockers = {},
                          double most_left = kMostLeftToPrice, const TipAt& tip_at = {}, const RivalSaving& rival = {});

// The layout support_ceilings and support_hybrid (ceilings/hybrid.hpp) share: regions of samples
// whose fall `floor_under` allows (p.hybrid_height > 0: room under a foot that far below the
// ceiling for a tip and a strut; else the bed or a level floor), rows, joins and flat pieces as
// above; `finish` then makes the region's pieces what is built (support_ceilings keeps them; the
// hybrid cuts them at its feet); the region is priced with `tree_count(samples, pieces)` (the
// tree for some samples, with a tip under the foot of each of `pieces` where they stand on the
// tree; called with no pieces for the region's own tree). Where the pieces stand on the tree
// (p.hybrid_height > 0), the regions' choices are then weighed in the whole (hybrid.hpp, choice).
// `rows_across`: a flat region also gets rows across its longer side, kept where faster on both
// routes (the hybrid's, support_hybrid; not the walls': rows across under stanford_bunny's belly,
// priced faster on both routes, printed 33 s slower on PrusaSlicer, and pipe_tee gained nothing).
using PiecesRule = std::function<std::vector<CeilingWall>(std::vector<CeilingWall>)>;
using PiecesTreeCounter = std::function<TreeCount(const std::vector<Sample>&, const std::vector<CeilingWall>&)>;
Ceilings lay_out_ceilings(const ModelQuery& model, const std::vector<Sample>& samples, const Params& p,
                          const PiecesRule& finish, const PiecesTreeCounter& tree_count,
                          const std::vector<Box3>& support_blockers, double most_left, const TipAt& tip_at = {},
                          const std::vector<char>& stay = {}, const RivalSaving& rival = {},
                          bool rows_across = false);

// What `pieces` carry of `samples` (as lay_out_ceilings took them, `stay` per sample; a sample
// that stays is never carried), judged as lay_out_ceilings judges it: `walls` the pieces, `rest`
// and `stay` the samples they leave (in order), `covered` how many they carry. Example: the hybrid
// without the pieces the tree could not carry (ceilings/hybrid.hpp, without_feet).
Ceilings carried_by(const ModelQuery& model, const std::vector<Sample>& samples, const std::vector<char>& stay,
                    std::vector<CeilingWall> pieces, const Params& p);

// Are walls laid out at all with these parameters: a span, rows within reach of each other, a tree?
bool ceilings_laid_out(const Params& p);

struct SlicerRoute;
// Seconds a wall `length` long, `height` tall and `thickness` wide adds on a route: its line
// (core/slicer_time's line_route_seconds) on every layer it spans.
double wall_line_seconds(const SlicerRoute& r, double length, double height, double thickness, const Params& p);

// The walls as a slicer prints them, layer by layer (a layer holds a piece where its middle height
// lies between the piece's foot and top): pieces in line that meet end to end (a row whose top steps
// with its ceiling, one station a piece) draw one line, and pieces that meet (a meander: its rows and
// joins) are one island. line_seconds: each line's line_route_seconds on a route.
struct WallsPrinted {
    double island_layers = 0;  // islands, summed over the layers
    double line_seconds = 0;
};
WallsPrinted walls_printed(const SlicerRoute& r, const std::vector<CeilingWall>& walls, const Params& p);
// Seconds all the walls add on a route: their lines, and the route's price of a wall island
// (SlicerRoute::wall_island_s) for each island on each layer.
double walls_seconds(const SlicerRoute& r, const std::vector<CeilingWall>& walls, const Params& p);

// The length from which `check` finds a wall's top long (a contact along its length, README
// "check"), for a wall `thickness` thick: two coverage reaches, or three times its thickness.
// Example: at the default sampling (2.5 mm) and a 0.5 mm wall, 3.54 mm.
double long_top(const Params& p, double thickness);

// Closed, outward-facing mesh of one wall: a box, w.thickness wide across from-to, bottom to top,
// its faces as triangles.
Mesh wall_mesh(const CeilingWall& w);

// The volume of the slabs' bridges among `walls` (mm^3, their wall_mesh's): what no slicer prints
// (ceilings/slabs.hpp), so the grams leave it out.
double bridges_volume(const std::vector<CeilingWall>& walls);

// The box one wall takes, `margin` wider on every side across the floor plan (its ends and faces):
// from `bottom` to `top`, its footprint the from-to line grown by half its thickness and `margin`.
// Axis-aligned, so it holds a turned wall too (with some air at its corners). Example: the hybrid
// keeps out of wall_box(w, tip_side_clearance(p)) of every wall.
Box3 wall_box(const CeilingWall& w, double margin = 0);

// How thick a wall `height` tall is built: the wall thickness, or the strength rule's width for a
// column that tall, whichever is more.
double wall_thickness_for(const Params& p, double height);

// PrusaSlicer's classic perimeter generator (perimeter_generator = classic, the user's choice)
// prints a wall one bead wide as a thin wall, its medial axis, only where the wall stands on the
// layer at least this many times as long as it is thick; shorter, the layer prints nothing of
// it. Measured with the .prusa.3mf's supports volume (PrusaSlicer 2.5, bench/slicers/profile.json):
// 0.5 mm thick, 0.99 mm long printed nothing and 1.0 mm printed; 0.7 mm thick, 1.36 nothing and
// 1.4 printed. (Arachne, the default, prints any length.)
constexpr double kClassicLengthOverThickness = 2.0;

// A region's flat pieces (its rows and joins) with tops that every slicer prints: on every layer,
// each stretch of pieces reaching it (pieces that touch: end to end along a row, a join's end in
// its row) is at least kClassicLengthOverThickness times as long as its thickest piece is thick.
// So a piece shorter than that is lowered to the highest level at which the stretch holding it is
// that long: a short piece standing above its neighbours comes down to where it and they make such
// a stretch (the wheel at 80 mm: two rows' 0.5 mm end pieces, 0.06 and 0.19 mm over the rest of
// their row and the join there, printed nothing on their top layers under classic). Where less than a layer of a
// piece would be left it is not built (classic prints none of it). A stretch shorter than that in
// all is left as it is, and so is a piece's foot (the hybrid's feet stand on tips). A lowered top
// is then judged as any other: where the ceiling is out of a contact's reach (wall_contacts), the
// samples it held stay with the tree.
std::vector<CeilingWall> printable_tops(std::vector<CeilingWall> pieces, const Params& p);

}  // namespace cs

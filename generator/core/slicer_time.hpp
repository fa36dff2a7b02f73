// The minutes a slicer adds to print a piece of our supports, per route (issue #32): the two
// routes the generator writes, CuraEngine 4.13 from the support mesh of our .3mf and PrusaSlicer 2.5
// from our .prusa.3mf, on the bench profile (bench/slicers/profile.json: 0.2 mm layers, 60 mm/s
// support lines, 1500 mm/s^2, jerk 10 mm/s).
//
// Two kinds of structure are priced:
//   tree_route_seconds   a tree counted as tree/slicer_cost.hpp counts it (island-layers, outline
//                        and hops between islands, summed over the layers): a linear model whose
//                        three prices were fitted to the slicers' G-code of the tuning set
//                        (bench/fit_time_model.py on bench/results/tuning.json; never the
//                        validation parts). On the validation set's baseline G-code (never fitted
//                        on) the estimate is 1.08x the G-code's added seconds for Cura (median;
//                        0.82-1.34 but a tiny clip at 0.37) and 1.03x for PrusaSlicer (0.84-1.16).
//   line_route_seconds   a long straight line one wall thick, drawn `passes` times per layer: the
//                        planner's trapezoid (accelerate from a turn, cruise, slow into the next),
//                        the physics bench/slicers/gcode_time.py replays the G-code with. CuraEngine
//                        4.13 draws a support area one line wide as a closed loop, out along the
//                        line and back (2 passes); PrusaSlicer's Arachne draws it once.
//
// Example:
//   double tree = tree_route_seconds(kCuraRoute, 2400, 14000, 9000);   // ~710 s
//   double wall = line_route_seconds(kCuraRoute, 30, 0.5) * 40;        // a 30 mm wall, 40 layers
#pragma once

namespace cs {

struct SlicerRoute {
    // Fitted to the G-code (tuning set): seconds per island-layer, per mm of a tree's outline, per
    // mm of hop between islands (the hop's retractions, and the starts and stops, fall in these).
    double island_s, outline_s_per_mm, hop_s_per_mm;
    // The machine and the slicer's support line: speed, acceleration, the speed a line turns at.
    double print_speed, acceleration, turn_speed;
    // Passes per layer over a support line one wall thick (up to `one_pass_width` wide).
    double passes;
    double one_pass_width;
    // Seconds each island of walls (a meander, a piece alone) adds on a layer beyond its lines: the
    // travel to it, the retraction, its start and stop. Fitted to the seconds the tuning set's G-code
    // spends on its walls (bench/fit_time_model.py --walls, bench/slicers/wall_time.py).
    double wall_island_s;
};

// CuraEngine 4.13, support mesh (one support wall, no infill): fitted on bridge, u_overhang,
// extruder_idler, spot, fandisk, rocker_arm, armadillo (generator 66db138). Its hops cost most:
// limit_support_retractions routes many around the model, and each retraction is 6.5 mm.
inline constexpr SlicerRoute kCuraRoute{0.0581, 0.0036, 0.0577, 60, 1500, 5, 2, 0.8, 0.126};
// wall_island_s: fitted (bench/fit_time_model.py --walls bench/results/tuning.json) to the seconds
// the G-code spends on the walls of the tuning set's seven walled models (bridge, u_overhang,
// extruder_idler, spot, fandisk, rocker_arm, stanford_bunny; generator 6d30265, 2026-12-06; first
// fitted at 50c1fb0 on six of them, 0.195 and 0.261, before tails and rows under holes): the walls'
// estimate over those seconds is 0.97 (median; 0.86-1.10) for Cura, whose lines alone (out and
// back) give 0.89; on the validation set (never fitted on) 0.85.
// PrusaSlicer 2.5, the supports part of our .prusa.3mf (one perimeter, Arachne): same fit. It
// retracts before nearly every hop (2 mm, quick), so its islands cost more and its hops less. Its
// wall_island_s, same fit: 0.78 (0.67-1.26; the lines alone, drawn once, 0.47); validation set 0.85.
inline constexpr SlicerRoute kPrusaRoute{0.114, 0.0245, 0.0138, 60, 1500, 5, 1, 0.68, 0.312};

// Seconds a tree adds on a route, from its island-layers, outline (mm) and hops (mm).
double tree_route_seconds(const SlicerRoute& r, double island_layers, double outline_mm, double hop_mm);

// Seconds one layer of a straight support line `mm` long and `width` wide adds on a route: its
// passes (more where it is wider than one pass), each a trapezoid from and to the turn speed.
double line_route_seconds(const SlicerRoute& r, double mm, double width);

// Seconds one layer of a support area's outline adds on a route, for an area `length` by `width`
// (a slab of two rows, ceilings/slabs.hpp): drawn once, its four sides each a trapezoid.
double outline_route_seconds(const SlicerRoute& r, double length, double width);

// Seconds a straight move of `mm` takes that starts and ends at `end_speed` and cruises at `speed`
// where it is long enough, accelerating at `acceleration` (the planner's trapezoid).
double stroke_seconds(double mm, double end_speed, double speed, double acceleration);

}  // namespace cs

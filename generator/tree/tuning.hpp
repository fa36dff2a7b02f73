// The tree sweep's tuning constants, in one place, each with the reason for its value.
//
// These are not user parameters (core/params.hpp) nor geometric rules shared with the struts
// stage and the .scad (core/rules.hpp): they steer how the sweep searches, and changing one
// changes the trees it grows. bench/same_outputs.sh shows by how much.
#pragma once

#include <array>
#include <cstddef>

namespace cs {

struct TreeTuning {
    // ---- the cone fan (tree/candidates.hpp): the axis, then rings of directions
    // Rings at half and 95% of the critical angle: half finds model points straight-ish below;
    // 95% reaches as far as the cone does while a contact tip (which sits above its model point)
    // stays inside the cone.
    std::array<double, 2> fan_rings{0.5, 0.95};
    // Eight directions per ring; the outer ring turned by half a step so the two rings interleave.
    int fan_directions = 8;

    // ---- clearance tests (tree/clearance.hpp)
    // can_escape tries a strut this long (mm) along each fan direction: a couple of strut widths,
    // enough to leave a crevice, short enough that the answer is about here and not far away.
    double escape_length = 2.0;
    // A tip can stand on a face sloping at most this much (degrees from horizontal); steeper, it
    // would slide off and dig into the wall.
    double stand_on_slope_deg = 45;
    // The ball test along a strut skips a point whose ball a distance measured nearby already
    // keeps clear by more than this (mm): far above the rounding of a square root at model
    // scale, so skipping never changes the answer.
    double distance_bound_margin = 1e-9;

    // ---- merge candidates
    // Partners are fetched least island span first, this many in the first batch (tree.cpp,
    // take_cheapest_clear). The first six nearly always hold the pick; when all of them are
    // blocked (a wall between the node and its nearest partners) the next batch is fetched, twice
    // as big, so a partner beyond them still wins over going down alone. Fetching all at once
    // picks the same and costs the big models a third more time (menger_sponge3: 27 -> 36 s,
    // 32 s in batches); batches of a fixed size rescan the active nodes once per batch, doubling
    // ones only a few times. Where every partner is blocked (the buildplate-only Menger sponge,
    // 162 -> 280 s) each is tested: capping the batches (six, twelve and 24 partners) gave
    // worse trees on four benchmark models, so every partner is tried.
    std::size_t merge_batch = 6;

    // ---- step_down: bends out of a tight spot
    double step_reach = 20;      // longest bend tried (mm): beyond, the fan's landings take over
    double step_shrink = 0.4;    // a blocked bend is retried this much shorter
    double step_min_drop = 0.5;  // a bend must descend at least this (mm), or the sweep would crawl
    double step_min_cos = 0.2;   // floor of the ray's cosine when converting a margin to a length
                                 // (keeps near-horizontal rays from backing off without limit)
    // A bend that led to a dead end is not tried again: its node's retry skips every ray passing
    // within this much (mm) of it (a strut width: a bend that near would end in the same pocket).
    double failed_bend_radius = 1.0;
    // ---- leaning tips (tree/lean_tips.cpp)
    // Two leaves whose feet could move towards each other by less than this (mm, together) stay
    // as they hang: a lean that small moves nothing a slicer sees, and the tips stay straight.
    double least_lean = 1e-3;

    // Neighbouring feet on the bed stay at least this far apart (mm), so no two share a corner
    // (the supports mesh would not be a set of closed solids where they did).
    double feet_apart = 0.05;

};

inline constexpr TreeTuning kTreeTuning{};

}  // namespace cs

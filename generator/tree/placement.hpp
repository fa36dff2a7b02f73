// Where the solids that meet an overhang go: the tops of tips, and short pillars under low
// overhangs (README "Profiles, tips, feet"). Both are placed by their whole square, not by their
// axis alone: every corner of a tip's or pillar's top stays the z gap under the overhang above
// it, every corner of a pillar's foot the z gap above the model below it, and no edge of the
// solid cuts the model. When the square does not fit straight under the sample (a slope too
// steep across it, a wall beside it), it moves up to half a millimetre aside; a tip's top also
// moves (as far) to keep tip_side_clearance (core/rules.hpp) from a wall beside it.
#pragma once

#include <optional>

#include "core/geometry.hpp"
#include "core/params.hpp"
#include "tree/tree.hpp"

namespace cs {

class ModelQuery;

// Where a pillar goes instead of a tree: where an overhang hangs less than two tips above what is
// below it, or where a tip's strut cannot leave (a slot too low for a tip and a strut). A pillar
// is a square column, d_min wide at its foot and tip_diameter at its top, on the bed or on the
// model (its foot the z gap above the highest point under any corner of it: a floor that steps
// down under the sample must not swallow it). Of the placements that fit near the sample, one on a
// level floor wins over one on a slope, then one that keeps tip_side_clearance from a wall beside
// it over one that does not, then the nearest.
enum class PillarFit {
    Fits,
    TooLow,  // less than a layer between the gap under the overhang and the gap above the floor:
             // the print bridges the slot
    NoRoom,  // a wall beside the sample cuts every placement
};

struct PillarPlacement {
    PillarFit fit = PillarFit::NoRoom;
    Pillar pillar;
};

PillarPlacement fit_pillar(const ModelQuery& model, const Vec3& sample, const Params& p);

// The top of the tip carrying `sample`: a gap below it, lowered where a corner of its square
// (tip_diameter wide) would come nearer a sloping overhang than the gap. Under a curved overhang
// (the crown of a round hole) a square straight below the sample may need more lowering than a
// contact allows; the top then moves towards the flatter side, so its corners keep the gap.
// Of the tops that fit, the nearest that keeps tip_side_clearance from a wall beside it in its
// own layer, with the ceiling still a gap above it, wins (a tip against a wall prints fused to
// it); the nearest that fits when none does.
// Where no top fits so, a square under a slope running diagonally to it (its downhill corner half a
// diagonal out, not half a side) may drop that much further: a sample at the upper edge of such a
// slope (a twisted blade), where uphill is past the edge, still gets its tip.
// A top away from the overhang (moved where the model over all of its square is higher than the
// sample: a gap under the sample, it holds nothing up) is taken only when no other fits, in
// either pass.
// nullopt where no square near the sample keeps the gap within what a contact allows (a sample
// on a knife edge or in a crevice narrower than a tip): a tip there would be built into the model.
std::optional<Vec3> place_tip_top(const ModelQuery& model, const Vec3& sample, const Params& p);

// Where the upside-down tip under a strut onto the model stands: the model point `contact`,
// raised to the highest point of the model under any corner of the tip's foot (tip_diameter wide;
// rays down from `from_z`, the top of the tip), so on a curved or sloping surface (the bottom of a
// round hole) every corner of its foot keeps the z gap above the model.
Vec3 contact_under_tip(const ModelQuery& model, const Vec3& contact, double from_z, const Params& p);

// Where a tip's foot (d_min wide, a tip's length under `top`) can go near `foot` so the tip
// from there up to `top` misses the model: `foot` itself or up to half a millimetre aside, never
// slanting the tip beyond 90% of the critical angle. nullopt when nothing near is clear.
std::optional<Vec3> clear_tip_foot(const ModelQuery& model, const Vec3& foot, const Vec3& top, const Params& p);

// Is the horizontal square of width w around c (a tip's foot) in the air: no corner in the model,
// no side crossing it?
bool square_is_clear(const ModelQuery& model, const Vec3& c, double w);

// Does the tapered square prism from `bottom` (width wb) up to `top` (width wt) miss the model?
// Its four side edges, its axis and the rims of both ends are asked.
bool prism_is_clear(const ModelQuery& model, const Vec3& bottom, double wb, const Vec3& top, double wt);

}  // namespace cs

// Independent verification of a supported print, from meshes alone: the placed model and the
// support STL (any tool's, as long as each support solid is a separate closed shell). It shares no
// sampling, exemption or tolerance code with the generator; every rule is written down here and in
// README "check".
//
//  coverage     every overhang point the judge finds itself (judge_overhangs.hpp: faces, ridges,
//               lowest points) has a contact within `reach` horizontally, on the same stretch of
//               surface (no further up or down than the steepest overhang rises over that reach,
//               plus the air gap and a layer). A contact is the top of a solid with the model right
//               above it; a long top (a wall's: the highest ring long and thin) is a contact at
//               every point of it with the model right above. `reach` defaults to 0.71 x the sampling distance: the largest gap a
//               square lattice of contacts leaves on a flat overhang (half its diagonal).
//               Exempt: points whose free fall to the model below is at most `bridge_height`
//               (2 air gaps and a layer: nothing printable fits under them, the print rests on
//               what is below). Anchors: such resting points, and the border of an overhang where
//               a printable face goes down from it (a wall below carries that edge), cover points
//               within reach as contacts do. Reported: the largest gap from any overhang point to
//               its nearest contact or anchor, where it is, and the area beyond reach.
//               Left out on purpose: points in a region the user blocked (`left_out` boxes: the
//               run's support blockers, `check --block`), or whose tip (gap plus tip length below
//               the point, tip diameter wide) would reach into one. They are counted, not failed.
//               Likewise, left out by the user's edit: a point beyond reach of every contact that
//               lies within reach (on the same stretch of surface) of a tip the user's omit_struts
//               took out. The judge finds those tips itself from the tree the run recorded
//               (`tree`): an omitted strut goes with every strut above it, a leaf with the strut
//               leaving it, a pillar by its number after the struts; the model right above a
//               tip's top is where it would have held the print. No wider: a point that no
//               omitted tip held is judged as any other.
//  air gap      every contact's gap (the smallest vertical distance from its top to the model) is
//               at least `gap - gap_tolerance`; a solid fused to the print fails.
//  penetration  every solid, tips included, is sampled over its faces; no point lies inside the
//               model deeper than `penetration_tolerance` (default half the air gap). Only a
//               contact end (the last `contact_depth` of a solid whose top touches the model from
//               below or whose bottom stands on it) may reach `contact_depth` into the model: a
//               square end on a slope of up to 45 degrees does. A model with holes is judged
//               too: inside is then the winding test's best guess (the report says so).
//  grounding    every solid rests on the bed, on the model (within the gap), or on another solid
//               that is itself grounded; a solid whose bottom lies inside the model is reported
//               as buried, not only as resting on nothing.
//  closed       every solid is closed and outward-facing.
//  angles       every solid's axis is within the critical angle of vertical.
//  strength     no solid is longer for its width than the strength rule allows: its length less
//               a layer (its end caps print fused into what they meet), over its width (the
//               narrowest horizontal extent of its narrower end, across any direction: a wall's
//               thickness, whichever way it runs), at most
//               strength_length * width * slant(angle) (check.cpp says where that comes from);
//               the worst length-to-width ratio is reported.
//
// The model is judged as written (`<name>.model.stl`, what the user's slicer gets): vertices are
// welded, nothing else. No hole is filled and no fold unfolded: the generator's repair is not the
// judge's, and a change to it cannot move a verdict (tests/unit/test_check.cpp, CheckMutantRepair).
#pragma once

#include <string>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"
#include "core/recorded_tree.hpp"

namespace cs {

struct CheckOptions {
    double reach = 0;                   // mm; 0: kLatticeReach x the sampling distance
    double penetration_tolerance = -1;  // mm; < 0: half the air gap
    double gap_tolerance = 0.05;        // mm an air gap may fall short of p.gap (slicers round to 0.01)
    double angle_tolerance = 0.5;       // degrees
    double spacing = 0;                 // mm between the judge's overhang points; 0: min(0.5, reach / 3)
    std::vector<Box3> left_out;         // regions the user blocked: their overhang needs no contact
    RecordedTree tree;                  // the run's tree as its .scad records it, and
    std::vector<int> omitted_struts;    // the struts the user left out there (omit_struts): what their
                                        // tips held needs no contact, nor what the hybrid pieces on
                                        // those tips held

    // Half the diagonal of a unit square, rounded up: the farthest a point of a flat overhang is
    // from the nearest lattice contact.
    static constexpr double kLatticeReach = 0.71;
};

// One thing that failed, with where it is.
struct Flag {
    std::string what;
    Vec3 at;
};

struct CheckResult {
    // coverage
    std::size_t overhang_points = 0, covered = 0, exempt = 0;
    std::size_t left_out = 0;         // of overhang_points: in a blocked region, left out on purpose
    double left_out_area = 0;         // mm^2 of overhang they stand for
    std::size_t blocked_regions = 0;
    std::size_t omitted = 0;          // of overhang_points: held by a tip the user omitted, left out on purpose
    double omitted_area = 0;          // mm^2 of overhang they stand for
    std::size_t omitted_struts = 0, omitted_tips = 0;  // the user's omissions, and the tips they took out
    std::size_t omitted_pieces = 0;  // the hybrid pieces standing on those tips, which went with them
    std::size_t face_points = 0, ridge_points = 0, lowest_points = 0;
    std::size_t contacts = 0;
    double reach = 0;
    double largest_gap = 0;  // farthest any overhang point is from its nearest contact or anchor
    Vec3 largest_gap_at;
    double uncovered_area = 0;  // mm^2 of overhang beyond reach
    std::vector<Vec3> uncovered;  // first few
    // air gap
    double min_air_gap = INFINITY;
    Vec3 min_air_gap_at;
    std::size_t fused_contacts = 0;
    // solids
    std::size_t bodies = 0, open_bodies = 0, inward_bodies = 0;
    std::size_t penetrating_bodies = 0, buried_bottoms = 0;
    double max_penetration = 0;
    Vec3 max_penetration_at;
    std::size_t ungrounded_bodies = 0;
    std::size_t steep_bodies = 0;
    double max_angle = 0;
    double worst_length_to_width = 0;
    std::size_t weak_bodies = 0;  // longer for their width than the strength rule allows
    bool model_closed = true;  // with holes, inside is the winding test's fair guess
    std::vector<Flag> flagged;  // first few failures of the solid checks, with places

    bool coverage_ok() const { return covered + exempt + left_out + omitted == overhang_points; }
    bool gap_ok() const { return fused_contacts == 0; }
    bool ok() const {
        return coverage_ok() && gap_ok() && open_bodies == 0 && inward_bodies == 0 && penetrating_bodies == 0 &&
               buried_bottoms == 0 && ungrounded_bodies == 0 && steep_bodies == 0 && weak_bodies == 0;
    }
    std::string summary() const;
    std::string json() const;
};

// `p` gives the critical angle, the air gap, the layer height, the tip diameter and the sampling
// distance the supports were made for (the user's settings, not the generator's decisions).
CheckResult check_supports(const Mesh& model, const Mesh& supports, const Params& p, const CheckOptions& o);

// A place as every check message prints it: "(x, y, z)" to two decimals (mm).
std::string format_place(const Vec3& p);

// Splits a mesh into its shells: faces connected across edges shared by exactly two faces, after
// welding identical vertices (bodies that touch at a vertex or a whole ring stay apart).
std::vector<Mesh> split_shells(const Mesh& m);

// Every edge used exactly twice, once in each direction (one clean solid, e.g. a support body).
bool is_closed_and_consistent(const Mesh& m);

// Every edge used as often in one direction as in the other: watertight and consistently
// oriented, allowing solids that touch along an edge (as a boolean union may leave them).
bool is_watertight(const Mesh& m);

}  // namespace cs

// The geometric rules of the support, each named once: how wide a strut is, how far solids
// overlap where they join, how much free space an overhang may print across, how far below the
// model a tip still counts as a contact.
//
// The tree (tree/), the struts stage (struts/) and the SCAD emitter (output/scad.cpp) all ask
// here, so the estimate the tree makes while growing, the solid the struts stage builds and the
// data the .scad carries cannot drift apart. scad_templates/clever_support.scad implements the
// same width rules in OpenSCAD (its header lists them); tests/e2e/test_scad_widths.cpp compares
// the two strut by strut.
//
// `check/` does NOT use this header: it is the independent judge and keeps its own tolerances.
//
// Inputs are the user's Params; every result is in millimetres.
#pragma once

#include <optional>

#include "core/params.hpp"

namespace cs {

// ----------------------------------------------------------------------------- strut widths
//
// Eqn (1) of the paper: d = k * l * alpha (l in mm, alpha in degrees from vertical), clamped.
double eqn1_width(const Params& p, double length, double angle_deg);
// Width of the strut leaving a branch point that joins struts of widths w_i: (sum w_i^3)^(1/3)
// (Murray's rule, as trees and vessels branch), never below the widest of them, clamped.
double merged_width(const Params& p, const std::vector<double>& widths);

// Width needed for a run of length `length` at `angle_deg` from vertical (strength rule).
double strength_width(const Params& p, double length, double angle_deg);
// Safe length of a strut of width `d` at `angle_deg` (inverse of strength_width).
double safe_length(const Params& p, double d, double angle_deg);
// Beyond this length-to-width a lone strut (no other joins it on its way down) that the strength
// rule still passes is a thin rod that sways under the nozzle (the hook's 50 mm buildplate-only
// strut, 26.8): the run warns (pipeline).
inline constexpr double kComfortableLengthToWidth = 20;

// strut_end_widths combines them for one strut; nothing else in the generator may.

// The widths at the two ends of one strut.
struct EndWidths {
    double top = 0, bottom = 0;
};

// A strut leaving a node of width `node_width` (the width carried into it: d_min at a leaf)
// down a run of `run_length` mm whose steepest strut is `run_angle_deg` from vertical; the strut
// itself is `length` mm at `angle_deg`.
//   top    = clamp(max(node width, strength rule for the run), d_min, d_max)
//   bottom = max(top, Eqn 1 for the strut): struts never narrow going down.
EndWidths strut_end_widths(const Params& p, double node_width, double run_length, double run_angle_deg, double length,
                           double angle_deg);

// Narrowest width at which an N-profile keeps open gaps between its three walls.
double min_n_width(const Params& p);

// ----------------------------------------------------------------------------- what needs support

// A face at the critical angle itself is printable; so is one within this much of it (in n_z,
// about 0.001 degree): the model.stl a slicer (and `check`) reads is float32, which tilts a face
// drawn at exactly the critical angle (a 45 degree chamfer under a 45 degree preset, or a face the
// pose turned there) by its corners' rounding, to either side. Its corners, up to 150 mm from the
// origin, move by 1e-5 mm at most: a face a millimetre across tilts by about that.
constexpr double kCriticalRounding = 1e-5;

// A face whose unit outward normal has n_z below this needs support: n_z < -sin(critical angle),
// beyond kCriticalRounding. Orientation (orient/) scores poses and sampling (overhang/) classifies
// faces by it.
double overhang_normal_z_limit(double critical_angle_deg);

// ----------------------------------------------------------------------------- joints and contacts

// How far a strut (or a tip) reaches into the solid below it, so joints overlap instead of
// sharing a face: half a layer, enough for any slicer to fuse them on the layer they meet.
double joint_overlap(const Params& p);

// Free vertical space below an overhang under which no support is built: the overhang is printed
// on what is below it (two z gaps and a layer).
double touching_space(const Params& p);

// How far a height in the model.stl a slicer (and `check`) reads may lie from the generator's own:
// float32 keeps 24 bits, so a corner up to 150 mm from the origin moves by 1e-5 mm at most.
constexpr double kHeightRounding = 1e-5;

// Does an overhang point with `air` mm of free fall under it rest on what is below, `space` being
// touching_space? Only where it does beyond kHeightRounding: at the threshold itself the float32
// file decides, and a flange drawn exactly 2 gaps + 1 layer over the bed (bearing_block at 0.6x:
// 0.6 mm) lies 0.6000000238 mm up in it, where `check` finds nothing resting. The sampling
// (overhang/) and the tree's leaves (tree/) both ask this.
bool rests_at(double air, double space);

// How far a tip's top keeps, sideways, from a wall of the model beside it in its own layer: half
// a line width, PrusaSlicer's default xy spacing for its own supports (50 % of a line). Nearer,
// the tip's outer line prints against the wall's and fuses with it. The Cura profile we write
// sets Cura's support_xy_distance to this (output/threemf.hpp): at Cura's 0.7 mm default it trims
// tips we placed this close, and keeping 0.7 mm here would take tips further from their samples
// than placement moves them.
double tip_side_clearance(const Params& p);

// How far below the model a tip's top may sit and still count as a contact: the z gap, plus what
// a tip's square top needs under the steepest overhang that needs support.
double contact_tolerance(const Params& p);

// A tip, under an overhang sample (leaf_tip) or standing on the model (contact_tip), is ONE square
// taper between its strut's end (the strut's width) and the contact (tip_diameter wide), along
// the straight line that placement tested for clearance (tree/placement.hpp: clear_tip_foot,
// prism_is_clear). A leaf's tip starts joint_overlap down inside its strut's top. The template's
// cs_tip and cs_contact_tip build the same solid from the same points.
struct TipEnds {
    Vec3 bottom, top;
    double bottom_width = 0, top_width = 0;
};
// `node`: the leaf; `tip_top`: where placement put the tip's top; `strut_width`: the top width of
// the strut leaving the leaf.
TipEnds leaf_tip(const Params& p, const Vec3& node, const Vec3& tip_top, double strut_width);
// `tip_bottom`: a gap above the model; `node`: the contact node; `strut_width`: the bottom width
// of the strut ending there.
TipEnds contact_tip(const Params& p, const Vec3& tip_bottom, const Vec3& node, double strut_width);

// How far the steepest overhang rises over a horizontal run: points further apart in z than this
// over `run` lie on different surfaces (the sampling's and the ceiling walls' "same stretch of
// surface"). Example: surface_rise(1, 45) == 1.
double surface_rise(double run, double critical_angle_deg);

// The lowest a contact tip's bottom may come to the top of its node and still be built: a tip
// shorter than this (a node already on the model's gap) is left out.
constexpr double kShortestContactTip = 0.01;

// Where the upside-down tip under a model-contact node at `node` ends: a gap above `contact`, the
// point of the model it stands on; nothing when the node is too close to the model for a tip
// (kShortestContactTip). The tree asks it before landing, the struts when building: one rule.
// Example: contact_tip_bottom({0, 0, 5}, {0, 0, 7}, p) == Vec3{0, 0, 5 + p.gap}.
std::optional<Vec3> contact_tip_bottom(const Vec3& contact, const Vec3& node, const Params& p);

}  // namespace cs

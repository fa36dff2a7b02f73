// From a support tree to printable solids (docs/algorithm.md section 4).
//
// size_struts gives every strut a width at each end, by the rules of core/rules.hpp:
//   node width   leaf: d_min; one strut in: its lower width; several: merged_width (Murray's rule)
//   upper width  max(node width, strength_width(run length, run angle)), clamped to [d_min, d_max]
//   lower width  max(upper width, Eqn (1) k*l*alpha), clamped            (strut_end_widths)
// so widths never shrink going down, grow at merges with what they carry, and no strut (or
// unbranched run of struts down to its foot) is longer than the safe length for its width.
//
// build_bodies turns the sized tree into bodies: N-profile struts (a horizontal N swept along the
// strut, a sheared prism tapering between its end widths; a solid square where the strut is too
// narrow for an N with printable walls), tapered tips under every overhang sample and above every
// model contact, feet on the bed and short pillars. body_mesh makes each a closed,
// outward-facing triangle mesh.
//
// The stage decides once, in SizedTree, what both build_bodies and the SCAD emitter need: which
// struts meet at each node, where each contact tip ends, how far joints overlap. The emitter only
// writes these down.
#pragma once

#include <optional>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"
#include "core/rules.hpp"
#include "tree/tree.hpp"

namespace cs {

struct StrutSize {
    double top_width = 0, bottom_width = 0;
    double length = 0, angle = 0;         // mm, degrees from vertical
    double run_length = 0, run_angle = 0;  // the unbranched run this strut belongs to
};

struct SizedTree {
    SupportTree tree;
    std::vector<double> node_width;  // width of the struts leaving each node at their top
    std::vector<StrutSize> struts;   // parallel to tree.struts
    // Per node: the strut leaving it (-1: none) and the struts ending at it, in strut order.
    std::vector<int> out_strut;
    std::vector<std::vector<int>> in_struts;
    // Per node: where the upside-down tip under a model-contact node ends (a gap above the
    // model); nothing for other nodes, and for a contact node too close to the model for a tip.
    std::vector<std::optional<Vec3>> contact_tip;
    double overlap = 0;  // how far a strut reaches into the joint or contact below it (joint_overlap)
    double worst_length_to_width = 0;  // run length / width, worst strut
    std::size_t strength_violations = 0;  // runs longer than safe even at d_max
};

SizedTree size_struts(SupportTree tree, const Params& p);

// Each strut's mean width (the average of its end widths), parallel to sized.tree.struts: what
// estimate_slicer_cost (tree/slicer_cost.hpp) takes.
std::vector<double> mean_strut_widths(const SizedTree& sized);

enum class BodyKind { Strut, Tip, ContactTip, Foot, Pillar };
enum class Profile { N, Square };

// A prism between two horizontal squares (centred at bottom and top, side widths), filled with
// the given profile. Every support solid is one of these.
struct Body {
    BodyKind kind;
    Profile profile;
    Vec3 bottom, top;
    double bottom_width, top_width;
};

// How far a foot may reach beyond its strut on each side, given the room to the model: it keeps
// the model clearance, and is dropped (0) when less than a quarter millimetre is left.
double foot_extra(const Params& p, double strut_width, double room);
// Where a foot under the strut from `above` down to `bed_point` ends, on the strut's axis.
Vec3 foot_top(const Vec3& bed_point, const Vec3& above, const Params& p);

std::vector<Body> build_bodies(const SizedTree& sized, const Params& p);

// Closed, outward-facing mesh of one body. `wall` is the N-profile wall thickness.
Mesh body_mesh(const Body& b, double wall);

// All bodies in one mesh (separate closed shells that overlap where they join).
Mesh bodies_mesh(const std::vector<Body>& bodies, double wall);

// The bodies of one profile only, in one mesh, in body order. Example: the solid bodies of a tree
// (its tips, feet, pillars, square struts) are bodies_mesh(bodies, wall, Profile::Square).
Mesh bodies_mesh(const std::vector<Body>& bodies, double wall, Profile only);

}  // namespace cs

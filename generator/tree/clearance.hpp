// Does a strut fit where the sweep wants it: clear of the model (by the clearance), of the
// user's support blockers, and with somewhere to go from its lower end?
//
// Inputs are points and the widths the struts stage will give the strut's ends (the sweep
// estimates them by core/rules.hpp); the answers are yes or no. Nothing here chooses between
// candidates (tree/candidates.hpp lists them, the sweep in tree.cpp takes the first that fits).
#pragma once

#include "core/geometry.hpp"
#include "core/params.hpp"

namespace cs {

class ModelQuery;
struct ConeFan;

// Is a strut from a (width wa) down to b (width wb) at least `clearance` away from the model?
// Checks the axis and the four edges of its square envelope (widened by the clearance), and
// balls along the axis that contain its cross-section.
// `onto_model`: b is a contact node a tip's length above the model, where only the edges judge;
// the built strut then reaches `joint_reach` (joint_overlap, half a layer) past b into its
// contact tip, and that end must stay clear too.
bool strut_is_clear(const ModelQuery& model, const Vec3& a, double wa, const Vec3& b, double wb, double clearance,
                    bool onto_model = false, double joint_reach = 0);

// Does the upside-down tip under a contact node `node` miss the model, as the struts stage will
// build it (core/rules.hpp contact_tip): a square taper from tip_diameter a gap above where it
// stands (contact_under_tip from `contact`, tree/placement.hpp) up to `node`, as wide there as the
// strut ending at it (`width`)? The strut's own clearance stops at its foot; the tip widens into
// that width within a tip's length of the model, so a step of the model beside the contact (a
// ledge in front of a wall) can cut the tip's upper part while strut and contact both clear it.
// A node too close to the model for a tip (kShortestContactTip) has none: true.
bool contact_tip_is_clear(const ModelQuery& model, const Params& p, const Vec3& node, const Vec3& contact, double width);

// Does a strut from a down to b (width wb at b), reaching half a layer into its joint, or its
// foot on the bed enter one of the user's support blockers (placed-model coordinates)?
bool enters_support_blocker(const Params& p, const std::vector<Box3>& support_blockers, const Vec3& a, const Vec3& b,
                            double wb);

// Can a strut of width w leave point a at all: is a short strut (kTreeTuning.escape_length) along
// some fan direction clear, with the z gap's air around it (nearer, it would print fused to the
// model)? Asked of leaves, merge points and bends before they are made, so no node is put where
// nothing can carry it down.
bool can_escape(const ModelQuery& model, const Params& p, const ConeFan& fan, const Vec3& a, double w);

// Where a leaf hangs below its tip's foot `below`: there, unless the model is too close beside it
// (a sample next to a wall); then it moves away from the wall, slanting its tip, so the strut
// below it keeps its clearance. The shift stays well inside the cone and within half a sample
// spacing, and is not taken across a slot narrower than a strut.
Vec3 leaf_position(const ModelQuery& model, const Params& p, double tan_c, const Vec3& below);

}  // namespace cs

// Independent verification of a supported print, from meshes alone: the placed model and the
// support STL (any tool's, as long as each support solid is a separate closed shell).
//
//  coverage     every overhang point (sampled twice as densely as the generator samples, plus
//               local minima) has a support contact within `reach` of it horizontally, on the
//               same stretch of surface (no higher or lower than the steepest overhang rises over
//               that reach, plus the contact gap), unless it hangs within touching_space of what is below;
//               such resting points, and inside corners where the overhang meets a wall below
//               it, anchor the overhang within `reach` of them as contacts do;
//  penetration  no support solid beyond the tips (solids whose top or bottom is a contact, which
//               touch the model by design) reaches into the model deeper than `penetration_tolerance`;
//  grounding    every support solid rests on the bed, on the model (within the gap), or on
//               another solid that is itself grounded;
//  closed       every support solid is closed and outward-facing;
//  angles       every solid's axis is within the critical angle of vertical;
//  strength     the worst length-to-width ratio of any solid (reported; struts are sized by the
//               strength rule, so this is informative).
#pragma once

#include <string>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"

namespace cs {

struct CheckOptions {
    double reach = 0;                    // 0: the sampling distance
    double penetration_tolerance = 0.25;  // mm
    double angle_tolerance = 0.5;         // degrees
};

struct CheckResult {
    std::size_t overhang_points = 0, covered = 0, exempt = 0;  // exempt: within touching space
    std::vector<Vec3> uncovered;  // first few, for the message
    std::size_t bodies = 0, open_bodies = 0, inward_bodies = 0;
    std::size_t penetrating_bodies = 0;
    std::vector<std::pair<Vec3, Vec3>> flagged;  // first few failing solids: (bottom, top) centres
    double max_penetration = 0;
    std::size_t ungrounded_bodies = 0;
    std::size_t steep_bodies = 0;
    double max_angle = 0;
    double worst_length_to_width = 0;
    bool model_closed = true;  // penetration is only judged inside a closed model

    bool coverage_ok() const { return covered + exempt == overhang_points; }
    bool ok() const {
        return coverage_ok() && open_bodies == 0 && inward_bodies == 0 && penetrating_bodies == 0 &&
               ungrounded_bodies == 0 && steep_bodies == 0;
    }
    std::string summary() const;
    std::string json() const;
};

CheckResult check_supports(const Mesh& model, const Mesh& supports, const Params& p, const CheckOptions& o);

// Splits a mesh into its shells: faces connected across edges shared by exactly two faces, after
// welding identical vertices (bodies that touch at a vertex or a whole ring stay apart).
std::vector<Mesh> split_shells(const Mesh& m);

// Every edge used exactly twice, once in each direction (one clean solid, e.g. a support body).
bool is_closed_and_consistent(const Mesh& m);

// Every edge used as often in one direction as in the other: watertight and consistently
// oriented, allowing solids that touch along an edge (as a boolean union may leave them).
bool is_watertight(const Mesh& m);

// Identical vertices merged (an STL stores each triangle's corners separately).
Mesh weld(const Mesh& m);

}  // namespace cs

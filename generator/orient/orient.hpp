// Orientation: put the model where it needs the least support (paper Sec. 3, docs/algorithm.md section 1).
//
// Candidate "down" directions are the outward normals of the convex hull's faces (the rest
// positions of Alexander et al. 1998), near-parallel ones merged, plus the six axis directions and
// the input orientation. Each is scored by overhang area; the few best are then judged by the
// support they really need (the caller builds the tree: `support_volume`), ties broken by fewer
// model contacts, then lower height. Where those few are all one pose turned about the vertical (a
// symmetric part: a cube's faces), none is judged: the first is kept. `keep` keeps the input
// exactly; `RX,RY,RZ` applies a rotation.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/geometry.hpp"
#include "core/modes.hpp"
#include "core/params.hpp"

namespace cs {

struct Rotation {
    double m[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    Vec3 apply(const Vec3& v) const {
        return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
                m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
    }
};

// What the tree built for one candidate pose.
struct PoseSupport {
    bool grown = true;  // false: the pose has overhang samples and its tree was not grown; only
                        // `height` is known (see choose_orientation)
    double volume = 0;
    std::size_t model_contacts = 0;
    double height = 0;
};

// How much of a pose the orientation search asks about: its tree, or, where the pose has overhang
// samples, its height only.
enum class PoseQuestion { tree, height_if_it_needs_support };

struct OrientCandidate {
    Vec3 down;          // direction in input coordinates that becomes -Z
    std::string source; // "input", "axis", "hull"
    Rotation rotation;
    double overhang_area = 0;
    bool evaluated = false;  // `support` was asked about it (its tree grown unless support.grown is false)
    PoseSupport support;
    // Where the poses to judge are all one print (a symmetric part: a cube's six faces), the
    // candidate each of the others is, turned about the vertical (orient/symmetry.hpp); then none
    // is judged. Otherwise -1.
    int same_pose_as = -1;
};

struct Orientation {
    Rotation rotation;
    OrientMode mode = OrientMode::automatic;
    std::string decided_by;  // "kept", "given", "overhang area", "support volume", "model contacts", "height"
    std::vector<OrientCandidate> candidates;  // ordered by overhang area
    std::size_t chosen = 0;
};

// A facet of the convex hull: a rest position of the model (Alexander et al. 1998).
struct HullFacet {
    Vec3 normal;      // outward, unit length
    double area = 0;  // mm^2 (coplanar hull triangles make one facet)
};

// The facets of the points' convex hull (CGAL convex_hull_3), in a canonical order (by normal):
// the same points give the same list whatever ran before, on any thread.
std::vector<HullFacet> hull_facets(const std::vector<Vec3>& points);

// The rotation taking `down` to -Z (a minimal rotation; identity when already so).
Rotation rotation_to_down(const Vec3& down);

// `mode` is an --orient value (parse_orient: "auto", "keep" or "RX,RY,RZ"); throws ParameterError
// for anything else.
// `support` is called for the best few candidates in auto mode (the mesh rotated by `rotation`,
// that rotation and the question -> what its tree needs), on several threads at once. Once a pose
// is found whose tree is empty, only a pose as low can beat it, so the others are first asked
// PoseQuestion::height_if_it_needs_support: `support` then returns {grown = false, height} for a
// pose with overhang samples, without growing its tree (and grows it, empty, for a pose without).
// The choice is the one growing every tree makes.
using PoseJudge = std::function<PoseSupport(const Mesh& rotated, const Rotation& rotation, PoseQuestion question)>;
Orientation choose_orientation(const Mesh& mesh, const Params& p, const std::string& mode, const PoseJudge& support,
                               std::size_t evaluate_best = 4);

}  // namespace cs

// Which parts of the placed model need support, and the points that will carry it
// (docs/algorithm.md section 2).
//
// A face needs support when its outward normal n has n_z < -sin(critical angle), unless it lies on
// the bed. Face overhangs are sampled on ONE global XY lattice of spacing `sampling_distance`, so
// neighbouring faces share it without gaps or doubles (a lattice point on a shared edge belongs to
// exactly one face, by the top-left rule of rasterisers). Extras are added only where coverage needs
// them (lean sampling): every overhang point must have a sample within `reach` = (sqrt 2 / 2) *
// sampling distance horizontally, on the same surface (the largest gap a square lattice leaves).
// Points the lattice leaves uncovered get, in this order: local minima (at their exact position),
// rims and downward ridges (one sample per 2 * reach of edge, placed as far along the edge as still
// covers the first uncovered point), and gap fills inside faces (a face point the lattice and the
// rims miss; also small faces that catch no lattice point). Inside corners where an overhang meets
// a wall going down need no sample and cover their neighbours within reach; a lattice point whose
// every neighbour within reach is so covered (a hole or slot the print bridges: a horizontal screw
// hole, a slot up to about twice the reach wide) gets no sample either, unless `support_bridges`.
// Points with material
// within touching space below need no sample; lattice points among them cover their neighbours
// (the overhang bridges from the material there), other points do not.
// Coverage is judged on fine demand points (the lattice refined 16 times, rims at an eighth of the
// reach), each within the reach less half their spacing, so the points between them are covered
// too; only inside a lattice cell whose four corners all carry a sample on the same surface does
// the lattice cover at the full reach (there every point is within reach of a corner).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <utility>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"

namespace cs {

class ModelQuery;

// Face: a lattice point. GapFill: a face point the lattice and the rims leave uncovered.
enum class SampleKind { Face, Edge, Point, GapFill };

struct Sample {
    Vec3 p;
    SampleKind kind;
};

// A rim or ridge of the overhang that needs samples of its own (coverage is judged along it).
struct EdgeSegment {
    Vec3 a, b;
};

struct OverhangSamples {
    std::vector<Sample> samples;  // sorted from top to bottom, ties by x then y: deterministic
    std::vector<Vec3> anchors;    // inside corners where an overhang meets a wall below it: the
                                  // wall carries the overhang there (no support needed)
    std::vector<EdgeSegment> edges;  // rims and ridges that need samples (top_up_samples reuses them)
    double overhang_area = 0;     // area of faces needing support (mm^2)
    std::size_t overhang_faces = 0, ridge_edges = 0, point_overhangs = 0;
    std::size_t topped_up = 0;    // samples added where built supports left a point beyond reach
};

struct OverhangOptions {
    double critical_angle = 50;     // degrees from vertical
    double sampling_distance = 2.5;
    double bed_height = 0.2;        // samples below this lie in the first layer: printed on the bed
    double touching_space = 0.6;    // free space below a point under which it rests on what is below
                                    // (the tree's touching_space: two z gaps and a layer)
    bool support_bridges = false;   // true: lattice points in holes the print bridges keep their samples
    double bridge_sampling = 0;     // the spacing whose reach judges what bridges (0: sampling_distance);
                                    // orientation scores poses at twice the spacing, holes at the run's
};

// The sampling's options for a printer's parameters: its critical angle, sample spacing, first
// layer and touching_space (core/rules.hpp). The one place they are taken from Params.
OverhangOptions overhang_options(const Params& p);

// Horizontal distance within which a support contact covers an overhang point: half the diagonal of
// a lattice cell, the largest gap a square lattice of this spacing leaves.
double coverage_reach(double sampling_distance);

// Does a sample at `sample` cover the overhang point `x`? Within coverage_reach horizontally and on
// the same surface: no further up or down than the steepest overhang rises over that reach.
bool covers(const Vec3& sample, const Vec3& x, double reach, double critical_angle_deg);
// The same for many points at one reach: the rise (a tangent) taken once. Cover(r, a)(s, x) ==
// covers(s, x, r, a).
struct Cover {
    Cover(double reach, double critical_angle_deg);
    bool operator()(const Vec3& sample, const Vec3& x) const { return near(sample, x) && std::abs(sample.z - x.z) <= rise; }
    double reach, rise;
    Reach near;  // within_reach at `reach`
};

// The air straight below an overhang point: down to the first face a ray meets from just under
// the point (the bed, z = 0, when none). The ray starts far enough under the point that a wall
// rising from the rim the point lies on, which the ray runs along, is not met at the point itself.
double air_below(const ModelQuery& model, const Vec3& x);

// Is there material right under an overhang point (overlapping shells: the face is no surface of
// the print)? Probed as far under the point as air_below starts its ray.
bool material_right_below(const ModelQuery& model, const Vec3& x);

// Does an overhang point rest on material below it (inside overlapping shells, or with at most
// `touching_space` of air below)? Such a point needs no support (and gets no contact).
bool rests_on_material(const ModelQuery& model, const Vec3& x, double touching_space);

// True when a face with unit outward normal `n` must be supported.
bool needs_support(const Vec3& unit_normal, double critical_angle_deg);

// Per face: does it need support (needs_support, and not lying on the bed)?
std::vector<char> classify_faces(const Mesh& m, const OverhangOptions& o);

// Lattice samples of one triangle (projected to XY), by the top-left rule; z from its plane.
void rasterize_triangle(const Vec3& a, const Vec3& b, const Vec3& c, double spacing, std::vector<Vec3>& out);

// Every (edge, face) pair of the mesh's faces (edge_key of its two vertices, the face's index),
// sorted by edge, then face: where sample_overhangs finds each edge's faces. It depends on the
// faces alone, so the orientation search makes it once for all its poses (each the same faces
// with the vertices turned).
using EdgeUses = std::vector<std::pair<std::uint64_t, std::uint32_t>>;
EdgeUses edge_uses(const Mesh& m);

// All support points of the placed model. With `model` (an index of the same mesh), points resting
// on material below need no sample; without it every point is judged as hanging in the air.
// `edges`: edge_uses of a mesh with m's faces (made here when null).
OverhangSamples sample_overhangs(const Mesh& m, const OverhangOptions& o, const ModelQuery* model = nullptr,
                                 const EdgeUses* edges = nullptr);

// Sorts samples as sample_overhangs does: top down, ties by x then y (deterministic).
void sort_top_down(std::vector<Sample>& samples);

// Samples to add where the supports as built leave an overhang point uncovered. `coverers` are
// the points that hold the overhang up, each at the height of the overhang it holds: a placed
// contact (a tip's top moved aside from its sample under a curved overhang, a pillar moved off a
// wall) and every sample that got no contact of its own (it rests on material, or was given up).
// The same demand and the same rules as sample_overhangs, whose result `sampled` gives the rims,
// ridges and inside corners; a coverer still on its lattice point counts as that lattice point.
// Sorted as sample_overhangs sorts; empty when all is covered.
// `support_at` (given by the stage that places supports): where the support a sample at x would
// get holds the overhang up (its tip's top, at x's height), nullopt where none fits (a knife edge,
// a slot too low for a pillar). A sample goes on the uncovered point itself when its support fits
// there, or when, bare, it would leave no point near it beyond the full reach (`check`'s) of what
// holds the overhang up or of a point resting on material (as `check` lets those hold their
// neighbours): it then adds nothing built, as before. Else it goes on the nearest point of the
// overhang, within reach of it, whose support fits and still covers it; else on the point, bare.
using SupportAt = std::function<std::optional<Vec3>(const Vec3&)>;
std::vector<Sample> top_up_samples(const Mesh& m, const OverhangOptions& o, const ModelQuery* model,
                                   const OverhangSamples& sampled, const std::vector<Vec3>& coverers,
                                   const SupportAt& support_at = {});

}  // namespace cs

// Which parts of the placed model need support, and the points that will carry it
// (algorithm.md section 2).
//
// A face needs support when its outward normal n has n_z < -sin(critical angle), unless it lies on
// the bed. Face overhangs are sampled on ONE global XY lattice of spacing `sampling_distance`, so
// neighbouring faces share it without gaps or doubles (a lattice point on a shared edge belongs to
// exactly one face, by the top-left rule of rasterisers). Edges and points add samples where the
// lattice cannot reach: overhang region borders, downward ridges, local minima, and small faces
// that catch no lattice point (their centroid). Those extras are dropped when a sample already
// lies within half the sampling distance, so density stays what the user asked for.
#pragma once

#include <vector>

#include "core/geometry.hpp"

namespace cs {

enum class SampleKind { Face, Edge, Point, Centroid };

struct Sample {
    Vec3 p;
    SampleKind kind;
};

struct OverhangSamples {
    std::vector<Sample> samples;  // sorted from top to bottom, ties by x then y: deterministic
    std::vector<Vec3> anchors;    // inside corners where an overhang meets a wall below it: the
                                  // wall carries the overhang there (no support needed)
    double overhang_area = 0;     // area of faces needing support (mm^2)
    std::size_t overhang_faces = 0, ridge_edges = 0, point_overhangs = 0;
};

struct OverhangOptions {
    double critical_angle = 50;     // degrees from vertical
    double sampling_distance = 2.5;
    double bed_height = 0.2;        // samples below this lie in the first layer: printed on the bed
};

// True when a face with unit outward normal `n` must be supported.
bool needs_support(const Vec3& unit_normal, double critical_angle_deg);

// Per face: does it need support (needs_support, and not lying on the bed)?
std::vector<char> classify_faces(const Mesh& m, const OverhangOptions& o);

// Total area of the faces classify_faces marks.
double overhang_area(const Mesh& m, const OverhangOptions& o);

// Lattice samples of one triangle (projected to XY), by the top-left rule; z from its plane.
void rasterize_triangle(const Vec3& a, const Vec3& b, const Vec3& c, double spacing, std::vector<Vec3>& out);

// All support points of the placed model.
OverhangSamples sample_overhangs(const Mesh& m, const OverhangOptions& o);

}  // namespace cs

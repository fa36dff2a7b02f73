// The judge's own view of what needs support, from the model mesh and the critical angle alone.
// It shares no code with the generator's sampling (generator/overhang/): if the generator stops
// emitting a kind of sample, this still finds the surface that needed it.
//
//  face points    overhang faces (outward normal n_z < -sin(critical angle), by more than the
//                 float32 rounding of the file: kCriticalRounding in the .cpp), sampled on a
//                 barycentric grid no coarser than `spacing`, each carrying its share of the area;
//  ridge points   convex edges between two downward-facing faces whose line is itself flatter than
//                 the critical angle (a hanging keel), sampled along the edge;
//  lowest points  vertices lower than every neighbour (the first thing of an island to print);
//  corner anchors points along the border of an overhang where the face beside it goes DOWN from
//                 the border (a wall below): the wall carries that edge, the print bridges from it.
// Everything lower than `bed_z` lies in the first layer and is printed on the bed.
//
// Example:
//   JudgeOverhangs j = judge_overhangs(welded_model, 50.0, 0.2, 0.5);
//   for (const auto& pt : j.points) ...
#pragma once

#include <vector>

#include "core/geometry.hpp"

namespace cs {

enum class JudgeKind { Face, Ridge, Lowest };

struct JudgePoint {
    Vec3 p;
    double area = 0;  // overhang area this point stands for (mm^2); 0 for ridge and lowest points
    JudgeKind kind = JudgeKind::Face;
};

struct JudgeOverhangs {
    std::vector<JudgePoint> points;
    std::vector<Vec3> corner_anchors;
};

// `welded`: indexed mesh with shared vertices (neighbours are found through shared indices).
JudgeOverhangs judge_overhangs(const Mesh& welded, double critical_angle_deg, double bed_z, double spacing);

}  // namespace cs

// The volume of the support solid: the union of the bodies, each overlap counted once.
//
// Bodies overlap where they join (a strut reaches `SizedTree::overlap` into the joint below it,
// tips and feet overlap their struts), so the sum of their volumes counts those overlaps twice:
// 4-11 % on the benchmark models. A slicer prints the union, and grams are the union's, so the
// report, the orientation choice and the bench's sliced/mesh ratio all take this volume.
//
// Inputs:  bodies (build_bodies), wall (the N-profile wall thickness, as for body_mesh).
// Output:  mm^3. Every body is cut in thin horizontal slices and every slice in thin rows; in each
//          row the bodies' exact x-intervals are merged. The sampled union is scaled by the exact
//          sum of the bodies' volumes over the sampled sum, so a slice grid that misses a sliver
//          of a body's top or bottom costs nothing: only the overlaps are estimated, to well
//          under 1 %. Deterministic; disjoint bodies give exactly the sum.
//
// Example: two unit cubes, the second shifted by 0.5 in x: 1.5 (the sum is 2).
#pragma once

#include <vector>

#include "struts/struts.hpp"

namespace cs {

double solid_volume(const std::vector<Body>& bodies, double wall);

}  // namespace cs

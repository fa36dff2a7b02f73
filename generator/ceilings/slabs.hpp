// Neighbouring rows of walls joined into slabs, for CuraEngine's sake (issue #32).
//
// CuraEngine 4.13 prints a support-mesh area one line wide as a closed loop: out along the wall and
// back, twice the filament and twice the time of the line (docs/experiments/cura-walls-once.md).
// Under our .curaprofile (one support wall, no infill) it prints any wider support-mesh area as its
// outline alone. So two neighbouring rows, the span apart, with a block filling the space between
// them (a bridge) are one solid whose outline is the two rows drawn once each and two short ends:
// the same lines under the ceiling, the same contacts, the slab's inside bridged by the printer as
// the space between any two rows is. PrusaSlicer already prints a wall once (Arachne, one bead), and
// it retracts on every travel of 2 mm or more inside our volume, which a slab's outline adds: the
// .prusa.3mf leaves the bridges out (measured on enclosure_lid: +113 s with them).
//
//   join_rows_into_slabs(model, walls, p) -> walls, then the bridges
//     lines      the pieces that are neither joins nor on the tree, gathered by their line (same
//                direction, same offset across it)
//     pairs      in order across, a line pairs with the first line of its direction the span or
//                less beyond it; a line pairs once, so pairs alternate (rows 1-2, 3-4, ...); an
//                outer row's tails (ceilings.hpp, rows) pair after, each with the line beside it
//                longest, where that line's bridges lie on the tail's side or nowhere: its slab goes
//                on beside the tail
//     bridges    one for each stretch where a piece of one line runs beside a piece of the other:
//                between the rows' inner faces (reaching kIntoRows into each, so that no face of
//                it lies on one of theirs), from the higher foot to the lower top of the two; the
//                two lines pair where their bridges are at least a span long in all
//     clear      a bridge's box, and the air gap over it, grown along the rows by the side
//                clearance, must not meet the model; else that stretch gets none
//
// Example: a 50 x 10 mm roof 5 mm over the bed, span 3.4 mm: 4 rows and 3 joins get 2 bridges
// (rows 1-2 and 3-4); the middle join links the two slabs into one island.
#pragma once

#include <vector>

#include "ceilings/ceilings.hpp"
#include "core/params.hpp"

namespace cs {

class ModelQuery;

// `walls` as support_ceilings (and the hybrid) left them, then the bridges; unchanged where no two
// rows pair (and with p.ceiling_span 0, which lays out no walls).
std::vector<CeilingWall> join_rows_into_slabs(const ModelQuery& model, std::vector<CeilingWall> walls, const Params& p);

}  // namespace cs

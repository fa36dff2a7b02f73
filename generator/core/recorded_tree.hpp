// The support tree as a run's .scad records it (cs_struts, cs_leaves, cs_pillars, cs_walls), read back as
// plain data (edit/edited_scad.hpp): what a reader that must not use the generator's own tree
// needs to know of it. check uses it to leave out the overhang the user's omit_struts left bare.
//
// Example (a strut 0 from node 1 down to node 2, under a leaf 1 whose tip's top is at z 9.8):
//   RecordedTree t{{{1, 2}}, {{1, {0, 0, 9.8}}}, {}};
#pragma once

#include <array>
#include <utility>
#include <vector>

#include "core/geometry.hpp"

namespace cs {

struct RecordedTree {
    std::vector<std::array<int, 2>> struts;  // cs_struts: [top node, bottom node], numbered as omit_struts numbers them
    std::vector<std::pair<int, Vec3>> tips;  // cs_leaves: a leaf node and the top of its tip
    std::vector<Vec3> pillar_tops;           // cs_pillars: each pillar's top, numbered after the struts
    // cs_walls standing off the bed: the middle of the foot, and the top's two ends. A hybrid piece
    // stands on the tip whose top is the middle of its foot, and goes with it.
    struct Wall {
        Vec3 foot, top_from, top_to;
    };
    std::vector<Wall> walls_off_bed;
};

}  // namespace cs

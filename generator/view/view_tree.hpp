// The support tree a generated .scad records (cs_nodes, cs_struts, cs_leaves, cs_contacts,
// cs_beds, cs_pillars) and its ceiling walls (cs_walls), read back so that `clever-support view`
// can draw and size it with the generator's own rules (size_struts) without growing it again, and
// `clever-support apply` can build the bodies the file renders. Strut indices are the file's:
// those omit_struts and highlight_strut name.
#pragma once

#include <string>
#include <vector>

#include "core/params.hpp"
#include "edit/scad_values.hpp"
#include "job/result.hpp"
#include "tree/tree.hpp"

namespace cs {

struct ScadTree {
    SupportTree tree;                    // nodes (kinds as the file implies them) and every strut
    std::vector<std::string> node_kind;  // "leaf", "merge", "chain", "bed", "contact", per node
};

// Input: the values parse_scad_values read from a file clever-support wrote (read_edited_scad has
// checked them). Leaf nodes get their sample and tip top, contact nodes their tip bottom (as
// `contact`, a gap above the model), bed nodes their room; a node with several struts in is a
// merge, any other a chain. Example: tree_from_scad(parse_scad_values(text, "m.scad")).
ScadTree tree_from_scad(const ScadValues& values);

// The walls under low ceilings the file records (cs_walls), in its order; none without the list.
std::vector<CeilingWall> walls_from_scad(const ScadValues& values);

// The solids the file renders, as the generator builds them (Supports::bodies and ::walls, what
// output/outputs.hpp support_mesh_files splits into the .prusa.3mf's volumes; the other members
// are left empty): its tree without the struts and pillars in `omit` and what hangs from them
// (prune_struts), sized with `p` (size_struts), each contact tip ending where the file records it
// and every joint overlapping by its cs_overlap, as the library's cs_tree draws them; then its
// walls, without the hybrid pieces standing on the tips `omit` takes out (prune_pieces; all of
// them in grown_walls), as the library's cs_walls draws them. `values`: read_edited_scad has
// checked the file. Throws ParameterError for an index of `omit` that names no strut or pillar.
// Example: supports_from_scad(parse_scad_values(text, "m.scad"), {3}, p).bodies: the bodies of the
//          file's tree without strut 3's branch.
Supports supports_from_scad(const ScadValues& values, const std::vector<int>& omit, const Params& p);

}  // namespace cs

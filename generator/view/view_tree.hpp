// The support tree a generated .scad records (cs_nodes, cs_struts, cs_leaves, cs_contacts,
// cs_beds, cs_pillars), read back so that `clever-support view` can draw and size it with the
// generator's own rules (size_struts) without growing it again. Strut indices are the file's:
// those omit_struts and highlight_strut name.
#pragma once

#include <string>
#include <vector>

#include "edit/scad_values.hpp"
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

}  // namespace cs

// What the page of `clever-support view` shows, read from one output folder: the .scad's
// parameters, edits and tree (sized by the generator's rules, so the Customizer's values re-size
// it without a regrow), the report's figures and `check`'s verdict on the written supports.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace cs {

// The one output folder a view serves, and the only files it reads and writes.
struct ViewFolder {
    std::string folder;  // the output folder
    std::string name;    // the stem: <name>.scad, <name>.model.stl, ...
    std::string file(const std::string& suffix) const { return folder + "/" + name + suffix; }
    std::string scad() const { return file(".scad"); }
};

// `target`: an output folder (holding exactly one <name>.scad besides clever_support.scad) or its
// .scad. Throws InputError naming the path and what to give instead.
// Example: find_view_folder("out/m/") -> {"out/m", "m"}.
ViewFolder find_view_folder(const std::string& target);

// The page's picture of the .scad `text` (which may be an edit not yet written):
//   sliders  the Customizer's numbers that need no regrow, with their ranges
//   edits    support_blockers, support_points, omit_struts
//   struts   [top, bottom, top width, bottom width, kind, length, omitted] per strut of the file
//            (omitted: left out by omit_struts or hanging from one; drawn at d_min)
//   tips     [top, bottom, top width, bottom width] of the tips and pillars
// Throws InputError (FILE:LINE: ...) or ParameterError when the text does not read as regrow reads it.
nlohmann::json view_scad_state(const std::string& text, const std::string& scad_path);

// `check` (check/check.hpp) on the folder's model and supports as `clever-support check FOLDER`
// judges them (the .scad's parameters; its blockers and omitted struts left out on purpose): its
// verdict, summary, the overhang area left out on purpose and the places it flags (overhang points
// beyond reach, fused contacts, solids in the model). Throws what read_mesh throws for a missing
// or broken STL.
nlohmann::json view_check(const ViewFolder& f, const std::string& scad_text);

}  // namespace cs

// One edit from the page of `clever-support view`, made to the .scad's text: the [Manual edits]
// lists a person edits by hand, and the Customizer's values. The file stays the source of truth;
// the result is read back as `regrow` reads it before anything is written.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace cs {

// `edit` is one of
//   {"op": "toggle_strut", "strut": 12}                 omit_struts gains 12, or loses it
//   {"op": "add_point", "at": [x, y, z]}                support_points gains the point
//   {"op": "remove_point", "index": 0}
//   {"op": "add_blocker", "box": [[x0, y0, z0], [x1, y1, z1]]}
//   {"op": "remove_blocker", "index": 0}
//   {"op": "set", "name": "k", "value": 0.002}          a Customizer slider (view_scad_state)
// Coordinates are rounded to 0.01 mm. Returns the new text. Throws UsageError for an edit that is
// not one of these, and what regrow's reading throws (FILE:LINE: ...) when the result does not read.
// Example: apply_view_edit(text, {{"op", "toggle_strut"}, {"strut", 3}}, "out/m/m.scad").
std::string apply_view_edit(const std::string& text, const nlohmann::json& edit, const std::string& scad_path);

}  // namespace cs

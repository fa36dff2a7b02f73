// The files of a run, found from its generated .scad: out/m/m.scad sits beside m.model.stl,
// m.supports.stl and the rest (output/outputs.hpp), all named by the .scad's stem.
//
// Example:
//   stem_of("out/m/m.scad")  -> "m"
//   run_scad("out/m/")       -> "out/m/m.scad" (the one generated .scad in the folder)
#pragma once

#include <string>

namespace cs {

// The file name without its folder and its last extension.
std::string stem_of(const std::string& path);

// A run's generated .scad: `path` itself, or the one in the folder `path` (clever_support.scad,
// the library beside it, is not one). Throws UsageError, worded for `check`, for a file that is no
// .scad and for a folder with none or several.
std::string run_scad(const std::string& path);

}  // namespace cs

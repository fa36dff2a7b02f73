// "Did you mean" for the command line: the known word nearest to what a user typed, when it is
// near enough to be a slip of the keyboard (a letter missing, added, swapped or wrong).
//
// Example:
//   closest_word("--samplng", {"--sampling", "--scale"})  -> "--sampling" (one letter missing)
//   closest_word("--sampel", {"--sampling", "--scale"})   -> "--sampling" (starts as it does)
//   closest_word("--zoom", {"--sampling", "--scale"})     -> ""
//   did_you_mean("chek", {"check", "regrow", "render"})    -> " (did you mean `check`?)"
#pragma once

#include <string>
#include <vector>

namespace cs {

// Edits (insert, delete, replace, swap two neighbours) that turn a into b, case-insensitively.
int edit_distance(const std::string& a, const std::string& b);

// The word of `known` fewest edits from `typed`, if those are at most a third of its length
// (at least 1, at most 3; ties: the earlier word); else the one word that shares the longest
// start with it, of at least four letters (leading dashes not counted); else "".
std::string closest_word(const std::string& typed, const std::vector<std::string>& known);

// " (did you mean `WORD`?)" for closest_word, or "" when none is near.
std::string did_you_mean(const std::string& typed, const std::vector<std::string>& known);

}  // namespace cs

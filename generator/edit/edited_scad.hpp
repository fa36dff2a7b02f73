// What `clever-support regrow` needs from a generated .scad that a person edited: the job that
// made it (input, its hash and -D values, orientation, scale), every parameter (the Customizer's
// and the [Regrow] section's), and the [Manual edits]. Every list a person may edit is checked:
// a malformed value or an index out of range is an InputError naming the file and the line.
#pragma once

#include <string>

#include "core/recorded_tree.hpp"
#include "job/job.hpp"

namespace cs {

struct EditedScad {
    Job job;                    // input, defines, orientation, scale, parameters and edits
    std::string input_sha256;   // of the input when the file was written
    std::string folder;         // where the file is: regrow writes the outputs there
    std::vector<double> pose;   // the placement the edits' coordinates assume (pose_numbers)
    RecordedTree tree;          // the tree as recorded: what omit_struts and highlight_strut number
};

// Throws InputError "PATH:LINE: ..." for a malformed file, ParameterError for a value out of range.
EditedScad read_edited_scad(const std::string& path);
// The same from the file's text (`path` names it in messages and gives the output folder).
EditedScad parse_edited_scad(const std::string& text, const std::string& path);

// The same from the file's text (e.g. an edit not yet written): errors name `path` and the line.
EditedScad read_edited_scad_text(const std::string& text, const std::string& path);

}  // namespace cs

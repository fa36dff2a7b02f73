// 3MF (3D Manufacturing Format) output: the model and its supports as separate objects of one
// build, the way slicers (PrusaSlicer, Cura) open a multi-part print. A 3MF file is a ZIP package
// of XML parts; ours is written uncompressed ("stored"), which every ZIP reader accepts.
#pragma once

#include <string>
#include <vector>

#include "core/geometry.hpp"

namespace cs {

struct NamedMesh {
    std::string name;
    const Mesh& mesh;  // triangle soup or indexed: identical vertices are shared in the output
};

std::string encode_3mf(const std::vector<NamedMesh>& objects);

// A ZIP archive of the given (name, content) entries, stored without compression.
// Entries are taken by value: move large ones in.
std::string encode_zip(std::vector<std::pair<std::string, std::string>> entries);

}  // namespace cs

// Reading and writing triangle meshes.
//
// Readers accept STL (ASCII and binary), OBJ, OFF, PLY (ASCII and binary) and 3MF (every build
// item as one mesh: mesh/read_3mf.hpp), chosen by the file extension, and throw InputError with a message that names the file, says what is wrong and what
// to do. They return the triangles as stored (STL gives three fresh vertices per triangle); welding
// and repair are the job of mesh/repair.hpp.
//
// Writers never leave a half-written file: they write to a temporary file next to the target and
// rename it into place, throwing OutputError on any failure.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "core/geometry.hpp"

namespace cs {

// The input formats, as file extensions without the dot: {"stl", "obj", "off", "ply", "3mf"}. The
// one list that the readers, their messages and the command line's help name.
const std::vector<std::string>& mesh_formats();
// The same for people: ".stl, .obj, .off, .ply or .3mf".
std::string mesh_formats_text();

// Reads any supported format. Throws InputError; a file with no triangles is an error unless
// `allow_empty` (a support STL of a model that needs no support is empty). `contents`, when given,
// gets one line on what a container format held (for a 3MF: its objects, build items, components;
// ThreeMfContents::summary) and stays empty for the single-mesh formats.
Mesh read_mesh(const std::string& path, bool allow_empty = false, std::string* contents = nullptr);

// Parses in-memory content; `name` is used in messages and `format` is one of mesh_formats().
// This is what the fuzz targets call.
Mesh parse_mesh(std::string_view bytes, const std::string& format, const std::string& name, bool allow_empty = false,
                std::string* contents = nullptr);

// Binary STL with recomputed facet normals. Throws OutputError.
void write_stl(const std::string& path, const Mesh& mesh, const std::string& header = "clever-support");

// Writes `content` atomically (temporary file + fsync + rename). Throws OutputError.
void write_file_atomic(const std::string& path, std::string_view content);

// The binary STL encoding of `mesh`, as written by write_stl.
std::string encode_stl(const Mesh& mesh, const std::string& header);
// The same of the meshes one after the other, byte for byte encode_stl of them appended (a face's
// record depends only on its corners), without making that mesh.
// Example: encode_stl({&model, &supports}, "model + supports").
std::string encode_stl(const std::vector<const Mesh*>& parts, const std::string& header);

}  // namespace cs

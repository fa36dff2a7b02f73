// Reading the meshes of a 3MF file (3D Manufacturing Format: a ZIP package of XML parts), as model
// sites, CAD tools and slicers (Cura, PrusaSlicer, Bambu Studio projects) write them.
//
// What is read: the model part named by the package's relationships (_rels/.rels; 3D/3dmodel.model
// when there are none), every <object> in it (triangle meshes and <components> groups, also those
// in other model parts a component names with the production extension's p:path), and every
// <build> <item> with its transform. All build items together become ONE mesh, in the file's
// coordinates converted to millimetres: a multi-object plate is supported as one placement, as it
// is printed. Objects of type "support" or "other" (a slicer's own supports, helpers) are left out.
// A file without build items places each object that no other object uses as a component.
//
// Libraries: minizip unpacks (from memory: mesh/zip_memory.hpp), expat parses the XML (streamed: a big scan's model part is never held
// as a document tree). Decompression is bounded: a part whose declared size, or whose actual
// inflated bytes, pass `max_unpacked_bytes` in total is rejected before it fills the memory (a ZIP
// bomb). Every problem is an InputError that names the file, says what is wrong and what to do.
//
// Example:
//   ThreeMfContents what;
//   Mesh m = parse_3mf(bytes, "plate.3mf", &what);   // what.summary(): "2 build items of ..."
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "core/geometry.hpp"

namespace cs {

// Inflated XML of all parts read from one 3MF, at most. A 5-million-triangle scan's model part is
// about 400 MB of XML.
constexpr std::size_t kMax3mfUnpackedBytes = std::size_t(1) << 30;

// What a 3MF held, for the run's summary and report.
struct ThreeMfContents {
    int mesh_objects = 0;       // objects with a <mesh>
    int component_objects = 0;  // objects made of <components>
    int components = 0;         // component references in them
    int build_items = 0;        // <item>s placed (or objects placed for a file without a build)
    int skipped_objects = 0;    // objects of type support / other, left out
    int model_parts = 0;        // XML model parts read (more than one with p:path components)
    std::string unit = "millimeter";
    std::size_t triangles = 0;  // in the placed result

    // One line, e.g. "3MF: 2 build items of 3 objects (2 meshes, 1 group of 2 components), read
    // as one model, unit millimeter".
    std::string summary() const;
};

// Parses a 3MF package held in memory. `name` is used in messages; `contents`, when given, says
// what was read. Throws InputError.
Mesh parse_3mf(std::string_view bytes, const std::string& name, ThreeMfContents* contents = nullptr,
               std::size_t max_unpacked_bytes = kMax3mfUnpackedBytes);

}  // namespace cs

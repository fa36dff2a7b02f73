// 3MF (3D Manufacturing Format) output: the model and its supports in the forms the two slicers we
// target read as "print these struts as support" (see shared notes slicer-handoff.md). A 3MF file
// is a ZIP package of XML parts; ours is deflated by libdeflate and packed by minizip (a scan's
// 3MF is about a quarter of its STL).
//
// One file cannot serve both slicers: Cura reads one mesh object as one model (its per-object
// settings cannot address part of it), and PrusaSlicer drops separate objects onto the bed one by
// one and refuses a model standing on near-point feet whose supports are another object. So:
//   encode_3mf_cura   model and supports as components of one group; the supports object carries
//                     Cura's per-object settings support_mesh=True, support_mesh_drop_down=False
//   encode_3mf_prusa  one object with ModelPart volumes: the model, and the supports (N-profile
//                     struts, solid bodies) with per-volume settings that print them like support
//                     (one perimeter, no infill)
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/geometry.hpp"
#include "core/params.hpp"

namespace cs {

using Settings = std::vector<std::pair<std::string, std::string>>;  // key, value (in file order)

// A mesh as the lines of a 3MF model part: its <vertex> lines, and its <triangle> lines numbered
// from its first vertex. The model is the same part of the .3mf and the .prusa.3mf: its lines are
// written once for both (mesh_xml) and handed to each in NamedMesh::xml.
struct MeshXml;
std::shared_ptr<const MeshXml> mesh_xml(const Mesh& mesh);

struct NamedMesh {
    std::string name;
    const Mesh& mesh;   // triangle soup or indexed: identical vertices are shared in the output
    Settings settings;  // slicer settings for this part (keys without any prefix)
    std::shared_ptr<const MeshXml> xml = {};  // mesh_xml(mesh) when written already; else written here
};

// Cura's "Per Model Settings -> Print as support", and no smallest support area. Read by Cura's 3MF
// reader as object metadata "cura:<key>"; it keeps every key the object's setting stack knows (any
// printer setting) and sends them to CuraEngine as the mesh's own settings. minimum_support_area is
// read from the support mesh's own settings (CuraEngine 4.13 support.cpp 695-702, the same in 5.x),
// so 0 here keeps every strut, tips included, on the printers whose definitions delete support
// areas under 2 or 5 mm2 (creality_base and about ten other bases), with or without our profile.
const Settings& cura_support_mesh_settings();

// The two supports volumes of the .prusa.3mf: the N-profile struts, and the solid bodies (tips,
// contact tips, feet, pillars and the struts too narrow for an N), whose cross-sections are squares.
enum class PrusaSupportVolume { NProfile, Solid };

// PrusaSlicer 2.5 per-volume settings that make struts print like its supports: one perimeter a
// little wider than the N-profile wall, no infill, a solid first layer (the feet), perimeters at
// the support speed; and the thin_walls each volume needs under PrusaSlicer's classic perimeter
// generator (Arachne, the default, ignores it). `p` gives the wall thickness.
// Example: prusa_support_volume_settings(p, PrusaSupportVolume::Solid) holds {"thin_walls", "0"}.
Settings prusa_support_volume_settings(const Params& p, PrusaSupportVolume volume);

// Cura's global / per-extruder support settings under which a support mesh prints like its tree
// supports (they cannot be set per object; CuraEngine takes them from the support extruder even
// when a support mesh carries its own): one wall, no infill, no joining of neighbouring struts
// (support_join_distance would fill the N-profile), no interface, no retraction between support
// islands (Cura's default, which some printer profiles switch off), and an xy distance from the
// model no wider than the clearance our tips keep (core/rules.hpp: tip_side_clearance), so Cura
// does not trim tips our geometry already kept clear. `p` gives that clearance.
Settings cura_support_line_settings(const Params& p);

// A family of Cura printers that share one set of quality profiles. Cura 4.13 imports a profile
// only on a printer that has the profile's quality_type (CuraContainerRegistry._configureProfile:
// "Quality type ... is not compatible"), and choosing the profile switches the printer to that
// quality, layer height included. So each family gets its own profile file, whose quality_type is
// the family's quality at the supports' layer height.
struct CuraQuality {
    std::string type;     // Cura's quality_type
    double layer_height;  // mm: that quality's layer_height in Cura 4.13
};
struct CuraPrinterFamily {
    std::string file;                    // the profile's file; Cura names the profile after it
    std::string printers;                // which printers it is for, in words
    std::vector<CuraQuality> qualities;  // the family's global qualities
};

// The families we write a profile for: Cura's generic qualities (fdmprinter: Prusa i3 MK3, Custom
// FFF, Ultimaker S3/S5 and most printers without their own) and creality_base's (Ender 3/5, CR-10
// and the bases that copy its quality names). bench/slicers/cura_check.py checks each against
// Cura 4.13's own definitions and quality lookup.
const std::vector<CuraPrinterFamily>& cura_printer_families();

// The family's quality whose layer height is nearest `layer_height` (the first of equals).
// Example: creality at 0.2 mm -> "standard"; generic at 0.2 mm -> "draft" (Cura's 0.2 mm quality).
const CuraQuality& cura_quality_for(const CuraPrinterFamily& family, double layer_height);

// A Cura profile (.curaprofile: a ZIP of one quality_changes .cfg) for one printer family, to
// import once in Cura (Preferences -> Profiles -> Import): cura_support_line_settings on top of the
// family's quality at p.layer_height, and layer_height itself only where that quality's differs.
// Cura 4.13's format; newer Cura versions upgrade it on import.
std::string encode_cura_profile(const CuraPrinterFamily& family, const Params& p);

// Cura form: an object per part, grouped as components of one build item (so they keep their
// relative position); each part's settings become <metadatagroup> "cura:" metadata.
std::string encode_3mf_cura(const std::string& name, const std::vector<NamedMesh>& parts);

// PrusaSlicer form: one object whose mesh holds every part's triangles in one contiguous block of
// vertices and triangles per part, described as ModelPart volumes in Metadata/Slic3r_PE_model.config
// with each part's settings.
std::string encode_3mf_prusa(const std::string& name, const std::vector<NamedMesh>& parts);

// A ZIP archive of the given (name, content) entries, each deflated (libdeflate), written by minizip in memory.
// Entries are taken by value: move large ones in. Throws OutputError if minizip fails.
std::string encode_zip(std::vector<std::pair<std::string, std::string>> entries);

}  // namespace cs

#include "output/threemf.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <fmt/compile.h>
#include <fmt/format.h>
#include <iterator>
#include <libdeflate.h>
#include <memory>
#include <minizip/zip.h>
#include <stdexcept>

#include "core/errors.hpp"
#include "core/rules.hpp"
#include "mesh/weld.hpp"
#include "mesh/zip_memory.hpp"

namespace cs {
namespace {

// Deflate level of every entry (libdeflate's): the fastest. Measured on beast's 4.7 MB of model XML:
// level 1 packs it to 0.90 MB in 10 ms, level 6 to 0.75 MB in 45 ms, zlib's level 1 (used until
// 2026-12-07) to 1.04 MB in 22 ms. All are far below the STL; the generator's speed counts for more
// than the last 20 % of size.
constexpr int kDeflateLevel = 1;
// Every entry's modification time is fixed, 2000-01-01 12:00, so the same input gives the same
// bytes. ZIP stores a DOS date and time with no time zone: written as they are, the bytes are the
// same in every time zone.
constexpr tm_zip kFixedTime = {0, 0, 12, 1, 0, 2000};  // sec, min, hour, day, month from 0, year

std::string xml_escape(const std::string& text) {
    std::string out;
    for (char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

// A mesh as 3MF wants it: indexed vertices in order of first use and the non-degenerate triangles.
struct IndexedMesh {
    std::vector<std::uint32_t> vertices;  // indices into the source mesh's vertices
    std::vector<std::array<std::uint32_t, 3>> triangles;  // indices into `vertices`
};

// Identical vertices are shared (3MF meshes are indexed: mesh/weld.hpp), numbered in order of
// first use by the faces; degenerate triangles (two corners welded into one) are left out.
IndexedMesh index_mesh(const Mesh& m) {
    const Welded w = weld_vertices(m);
    std::vector<std::uint32_t> source;  // each welded vertex -> its first vertex in `m`
    source.reserve(w.mesh.vertices.size());
    for (std::uint32_t i = 0; i < w.remap.size(); ++i)
        if (w.remap[i] == source.size()) source.push_back(i);
    constexpr std::uint32_t kUnused = UINT32_MAX;
    std::vector<std::uint32_t> out_id(w.mesh.vertices.size(), kUnused);
    IndexedMesh out;
    for (const auto& f : w.mesh.faces)
        for (int k = 0; k < 3; ++k)
            if (out_id[f[k]] == kUnused)
                out_id[f[k]] = static_cast<std::uint32_t>(out.vertices.size()), out.vertices.push_back(source[f[k]]);
    out.triangles.reserve(m.faces.size());
    for (const auto& f : w.mesh.faces) {
        std::array<std::uint32_t, 3> v = {out_id[f[0]], out_id[f[1]], out_id[f[2]]};
        if (v[0] != v[1] && v[1] != v[2] && v[0] != v[2]) out.triangles.push_back(v);
    }
    return out;
}

// Writes x at `out` as fmt's "{:.6f}" does and moves `out` past it, where the digits are certain
// without fmt's general float formatting (most of writing a scan's 3MF): |x| < 2^33, so x in
// millionths is exact in 128 bits, rounded to the nearest, and x is not exactly halfway between
// two millionths (fmt's rule for ties stays fmt's). Otherwise returns false and writes nothing.
bool write_fixed6(double x, char*& out) {
    const auto bits = std::bit_cast<std::uint64_t>(x);
    const int biased = static_cast<int>((bits >> 52) & 0x7ff);
    if (biased - 1023 >= 33) return false;  // too big, or not finite
    const std::uint64_t fraction = bits & ((std::uint64_t{1} << 52) - 1);
    const std::uint64_t mantissa = biased ? fraction | (std::uint64_t{1} << 52) : fraction;
    const int shift = 1075 - (biased ? biased : 1);  // |x| = mantissa / 2^shift, shift > 19 here
    const unsigned __int128 scaled = static_cast<unsigned __int128>(mantissa) * 1000000u;  // < 2^73
    std::uint64_t millionths = 0;  // shift >= 127: |x| under 2^-54, far from half a millionth
    if (shift < 127) {
        const unsigned __int128 half = static_cast<unsigned __int128>(1) << (shift - 1);
        const unsigned __int128 rest = scaled & ((half << 1) - 1);
        if (rest == half) return false;
        millionths = static_cast<std::uint64_t>(scaled >> shift) + (rest > half);
    }
    char* p = out;
    if (bits >> 63) *p++ = '-';  // as fmt: the sign even where the digits round to zero
    std::uint64_t whole = millionths / 1000000;
    char digits[20];
    int n = 0;
    do digits[n++] = static_cast<char>('0' + whole % 10), whole /= 10;
    while (whole);
    while (n) *p++ = digits[--n];
    *p++ = '.';
    for (std::uint32_t d = 100000, part = static_cast<std::uint32_t>(millionths % 1000000); d; d /= 10)
        *p++ = static_cast<char>('0' + part / d % 10);
    out = p;
    return true;
}

// One vertex's line, written by write_fixed6 where it can (the same bytes), else by fmt.
void append_vertex(fmt::memory_buffer& buf, const Vec3& p) {
    char line[128];
    char* at = line;
    auto text = [&at](const char* s) {
        const std::size_t n = std::strlen(s);
        std::memcpy(at, s, n), at += n;
    };
    text("<vertex x=\"");
    if (write_fixed6(p.x, at)) {
        text("\" y=\"");
        if (write_fixed6(p.y, at)) {
            text("\" z=\"");
            if (write_fixed6(p.z, at)) {
                text("\"/>\n");
                buf.append(line, at);
                return;
            }
        }
    }
    fmt::format_to(std::back_inserter(buf), FMT_COMPILE("<vertex x=\"{:.6f}\" y=\"{:.6f}\" z=\"{:.6f}\"/>\n"), p.x, p.y, p.z);
}

// Formatted into a memory buffer and appended in one go: a back_inserter into the string grows
// it a character at a time, and a scan has hundreds of thousands of these lines.
void append_vertices(std::string& s, const Mesh& m, const IndexedMesh& im) {
    fmt::memory_buffer buf;
    buf.reserve(60 * im.vertices.size());
    for (std::uint32_t c : im.vertices) append_vertex(buf, m.vertices[c]);
    s.append(buf.data(), buf.size());
}

// `offset`: the number of vertices written before this part in the same object.
void append_triangles(std::string& s, const IndexedMesh& im, std::uint32_t offset) {
    fmt::memory_buffer buf;
    buf.reserve(45 * im.triangles.size());
    for (const auto& t : im.triangles)
        fmt::format_to(std::back_inserter(buf), FMT_COMPILE("<triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>\n"), t[0] + offset,
                       t[1] + offset, t[2] + offset);
    s.append(buf.data(), buf.size());
}

}  // namespace

struct MeshXml {
    std::uint32_t vertex_count = 0;
    std::size_t triangle_count = 0;
    std::string vertices, triangles;
};

namespace {

// A part's lines, its triangles numbered from `offset`.
MeshXml mesh_lines(const Mesh& m, std::uint32_t offset) {
    const IndexedMesh im = index_mesh(m);
    MeshXml x;
    x.vertex_count = static_cast<std::uint32_t>(im.vertices.size());
    x.triangle_count = im.triangles.size();
    append_vertices(x.vertices, m, im);
    append_triangles(x.triangles, im, offset);
    return x;
}

// The part's own lines when it brings them (numbered from 0: only where it comes first), else
// written here.
std::shared_ptr<const MeshXml> lines_of(const NamedMesh& part, std::uint32_t offset) {
    if (part.xml && offset == 0) return part.xml;
    return std::make_shared<const MeshXml>(mesh_lines(part.mesh, offset));
}

constexpr const char* kCoreNamespace = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02";

std::string model_header(const std::string& extra_namespaces, const std::string& metadata) {
    return fmt::format(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        "<model unit=\"millimeter\" xml:lang=\"en-US\" xmlns=\"{}\"{}>\n"
        "<metadata name=\"Application\">clever-support</metadata>\n{}<resources>\n",
        kCoreNamespace, extra_namespaces, metadata);
}

// The package around 3D/3dmodel.model (plus any extra parts, e.g. a slicer's config).
std::string package(std::string model, std::vector<std::pair<std::string, std::string>> extra) {
    std::vector<std::pair<std::string, std::string>> parts;
    parts.emplace_back("[Content_Types].xml",
                       "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                       "<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\">"
                       "<Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/>"
                       "<Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>"
                       "<Default Extension=\"config\" ContentType=\"text/xml\"/>"
                       "</Types>\n");
    parts.emplace_back("_rels/.rels",
                       "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                       "<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">"
                       "<Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" "
                       "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>\n");
    parts.emplace_back("3D/3dmodel.model", std::move(model));
    for (auto& e : extra) parts.push_back(std::move(e));
    return encode_zip(std::move(parts));
}

std::vector<const NamedMesh*> non_empty(const std::vector<NamedMesh>& parts) {
    std::vector<const NamedMesh*> out;
    for (const auto& p : parts)
        if (!p.mesh.faces.empty()) out.push_back(&p);
    return out;
}

// 3MF coordinates start at the build plate's front-left corner, and Cura keeps a 3MF's positions on
// load (it arranges only other formats): our print, centred on the origin, would hang off that
// corner. The build item shifts it so its footprint starts this far from the corner, which keeps it
// on any plate it fits, clear of the slicers' border zones (skirt, brim, travel clearance).
constexpr double kPlateCornerMarginMm = 10;

std::string build_item(int object_id, const std::vector<const NamedMesh*>& parts) {
    Box3 b;
    for (const NamedMesh* p : parts)
        for (const auto& f : p->mesh.faces)
            for (int k = 0; k < 3; ++k) b.add(p->mesh.vertices[f[k]]);
    double dx = parts.empty() ? 0 : kPlateCornerMarginMm - b.min.x, dy = parts.empty() ? 0 : kPlateCornerMarginMm - b.min.y;
    return fmt::format("<build>\n<item objectid=\"{}\" transform=\"1 0 0 0 1 0 0 0 1 {:.6f} {:.6f} 0\"/>\n</build>\n",
                       object_id, dx, dy);
}

// PrusaSlicer 2.5's default support_material_speed, mm/s: the per-volume perimeter speeds of the
// supports volume are set to it (its default small_perimeter_speed, 15 mm/s, would otherwise
// apply to every strut's closed loop).
constexpr const char* kPrusaSupportSpeed = "60";
// The supports volume's perimeter line width over the N-profile wall thickness (see below).
constexpr double kPrusaStrutLineOverWall = 1.1;

}  // namespace

std::string encode_zip(std::vector<std::pair<std::string, std::string>> entries) {
    // Each entry is deflated in one call by libdeflate and handed to minizip raw, with its size and
    // CRC: minizip writes the container, libdeflate the deflate stream (twice zlib's speed at the
    // same level, see kDeflateLevel).
    std::unique_ptr<libdeflate_compressor, decltype(&libdeflate_free_compressor)> deflater(
        libdeflate_alloc_compressor(kDeflateLevel), libdeflate_free_compressor);
    if (!deflater) throw OutputError("3MF packaging failed: no memory for the compressor");
    MemoryZipFile file;
    zlib_filefunc64_def io = memory_zip_io(file);
    zipFile archive = zipOpen2_64("3MF package", APPEND_STATUS_CREATE, nullptr, &io);
    if (!archive) throw OutputError("3MF packaging failed (open)");
    auto fail = [&](const std::string& what, int code) {
        zipClose(archive, nullptr);
        throw OutputError(fmt::format("3MF packaging failed ({}): minizip error {}", what, code));
    };
    zip_fileinfo info{};
    info.tmz_date = kFixedTime;
    std::string packed;
    for (const auto& [name, data] : entries) {
        packed.resize(libdeflate_deflate_compress_bound(deflater.get(), data.size()));
        packed.resize(libdeflate_deflate_compress(deflater.get(), data.data(), data.size(), packed.data(), packed.size()));
        if (packed.empty() && !data.empty()) fail(name + ": deflate", ZIP_INTERNALERROR);
        const int zip64 = data.size() >= 0xffffffffu;  // ZIP64 only where an entry needs it
        const int raw = 1;                               // the bytes given are the deflate stream
        int rc = zipOpenNewFileInZip3_64(archive, name.c_str(), &info, nullptr, 0, nullptr, 0, nullptr, Z_DEFLATED,
                                         kDeflateLevel, raw, -MAX_WBITS, DEF_MEM_LEVEL, Z_DEFAULT_STRATEGY, nullptr,
                                         0, zip64);
        if (rc != ZIP_OK) fail(name, rc);
        // zipWriteInFileInZip takes an unsigned int length: big parts go in pieces.
        constexpr std::size_t kPiece = 1u << 30;
        for (std::size_t at = 0; at < packed.size() && rc == ZIP_OK; at += kPiece)
            rc = zipWriteInFileInZip(archive, packed.data() + at, static_cast<unsigned>(std::min(kPiece, packed.size() - at)));
        if (rc == ZIP_OK) rc = zipCloseFileInZipRaw64(archive, data.size(), libdeflate_crc32(0, data.data(), data.size()));
        if (rc != ZIP_OK) fail(name, rc);
    }
    if (const int rc = zipClose(archive, nullptr); rc != ZIP_OK)
        throw OutputError(fmt::format("3MF packaging failed (write): minizip error {}", rc));
    return std::move(file.bytes);
}

const Settings& cura_support_mesh_settings() {
    static const Settings settings = {
        {"support_mesh", "True"}, {"support_mesh_drop_down", "False"}, {"minimum_support_area", "0"}};
    return settings;
}

Settings prusa_support_volume_settings(const Params& p, PrusaSupportVolume volume) {
    // One bead a little wider than the N-profile's wall: Arachne then prints each wall as a single
    // line that fills it, and a d_min strut as one loop with no hole. Measured on nefertiti, spot and
    // stanford_bunny at benchmark scale: support filament / mesh volume 0.73-0.84 -> 0.77-0.88 at the
    // same print time (within 1.5 %); 0.6 mm changed nothing more.
    const std::string line_width = fmt::format("{:.2f}", kPrusaStrutLineOverWall * p.wall_thickness);
    // PrusaSlicer's classic perimeter generator (perimeter_generator = classic, per object only, so
    // the user's choice) prints a region one bead wide in one of two ways (PerimeterGenerator.cpp):
    // - thin_walls on (its default; off in Prusa's own printer presets): a loop only where the
    //   region is wider than about 1.8 beads (0.96 mm at 0.55 mm), and a thin wall (medial axis)
    //   only where it is at least twice as long as wide. An N-profile's 0.5 mm walls print so; a
    //   tip's top, a 0.8 mm square, is neither and was left out (6-13 % of the body layers).
    // - thin_walls off: a loop wherever the region is wider than one bead; the N's walls, thinner
    //   than a bead, vanish.
    // So each volume gets the one that prints it, whatever the user's preset says.
    const char* thin_walls = volume == PrusaSupportVolume::NProfile ? "1" : "0";
    return {{"perimeters", "1"},
            {"fill_density", "0%"},
            {"top_solid_layers", "0"},
            // The first layer solid: a foot meets the bed with its whole area, not with a ring.
            // Solid to the foot's top cost 2.5 % more support time on spot for no more grip.
            {"bottom_solid_layers", "1"},
            {"perimeter_speed", kPrusaSupportSpeed},
            {"external_perimeter_speed", kPrusaSupportSpeed},
            {"small_perimeter_speed", kPrusaSupportSpeed},
            {"perimeter_extrusion_width", line_width},
            {"external_perimeter_extrusion_width", line_width},
            {"thin_walls", thin_walls}};
}

Settings cura_support_line_settings(const Params& p) {
    return {{"support_wall_count", "1"},
            {"support_infill_rate", "0"},
            {"support_join_distance", "0"},
            {"support_interface_enable", "False"},
            {"limit_support_retractions", "True"},
            // Cura trims a support mesh to its xy distance from the model on every layer (0.7 mm by
            // default), which cut the top layers off tips our geometry had already kept clear of a
            // wall: 3-15 tip layers per benchmark model. Our tips keep tip_side_clearance, so Cura
            // may keep that much and no more.
            {"support_xy_distance", fmt::format("{:.3g}", tip_side_clearance(p))}};
}

const std::vector<CuraPrinterFamily>& cura_printer_families() {
    // Layer heights from Cura 4.13's resources/quality: fdmprinter's *.inst.cfg (its "normal" sets
    // none: fdmprinter's 0.1 mm default) and creality/base/base_global_*.inst.cfg. creality's
    // "adaptive" (0.16 mm with adaptive layers) is left out: it is not one layer height.
    static const std::vector<CuraPrinterFamily> families = {
        {"clever_support.curaprofile",
         "Prusa i3 MK3, Ultimaker S3/S5, Custom FFF and most printers without qualities of their own",
         {{"high", 0.06}, {"normal", 0.1}, {"fast", 0.15}, {"draft", 0.2}, {"verydraft", 0.3}, {"coarse", 0.4},
          {"extra coarse", 0.6}}},
        {"clever_support_creality.curaprofile",
         "Creality Ender 3/5, CR-10 and other printers with Standard/Super/Ultra qualities",
         {{"ultra", 0.08}, {"super", 0.12}, {"standard", 0.2}, {"low", 0.28}, {"draft", 0.32}}},
    };
    return families;
}

const CuraQuality& cura_quality_for(const CuraPrinterFamily& family, double layer_height) {
    return *std::min_element(family.qualities.begin(), family.qualities.end(), [&](const auto& a, const auto& b) {
        return std::abs(a.layer_height - layer_height) < std::abs(b.layer_height - layer_height);
    });
}

std::string encode_cura_profile(const CuraPrinterFamily& family, const Params& p) {
    // Cura 4.13's container format: version 4, setting_version 19 (CuraApplication.SettingVersion).
    // Its importer renames the profile after the file; the name inside says the same.
    const std::string name = family.file.substr(0, family.file.rfind('.'));
    const CuraQuality& quality = cura_quality_for(family, p.layer_height);
    std::string cfg = fmt::format(
        "[general]\nversion = 4\nname = {}\ndefinition = fdmprinter\n\n"
        "[metadata]\ntype = quality_changes\nquality_type = {}\nsetting_version = 19\n\n[values]\n",
        name, quality.type);
    // The supports are built for p.layer_height: where the family's nearest quality has another,
    // the profile keeps ours rather than move the user to that quality's.
    if (std::abs(quality.layer_height - p.layer_height) > 1e-9) cfg += fmt::format("layer_height = {:.3g}\n", p.layer_height);
    for (const auto& [key, value] : cura_support_line_settings(p)) cfg += key + " = " + value + "\n";
    return encode_zip({{name, std::move(cfg)}});
}

std::shared_ptr<const MeshXml> mesh_xml(const Mesh& mesh) { return std::make_shared<const MeshXml>(mesh_lines(mesh, 0)); }

std::string encode_3mf_cura(const std::string& name, const std::vector<NamedMesh>& parts) {
    std::string model = model_header("", "");
    std::string components;
    int id = 1;
    for (const NamedMesh* p : non_empty(parts)) {
        model += fmt::format("<object id=\"{}\" name=\"{}\" type=\"model\">", id, xml_escape(p->name));
        if (!p->settings.empty()) {
            model += "<metadatagroup>";
            for (const auto& [key, value] : p->settings)
                model += fmt::format("<metadata name=\"cura:{}\" preserve=\"true\">{}</metadata>", xml_escape(key),
                                     xml_escape(value));
            model += "</metadatagroup>";
        }
        const std::shared_ptr<const MeshXml> lines = lines_of(*p, 0);
        model += "<mesh><vertices>\n";
        model += lines->vertices;
        model += "</vertices><triangles>\n";
        model += lines->triangles;
        model += "</triangles></mesh></object>\n";
        components += fmt::format("<component objectid=\"{}\"/>", id++);
    }
    model += fmt::format("<object id=\"{}\" name=\"{}\" type=\"model\"><components>{}</components></object>\n", id,
                         xml_escape(name), components);
    model += "</resources>\n" + build_item(id, non_empty(parts)) + "</model>\n";
    return package(std::move(model), {});
}

std::string encode_3mf_prusa(const std::string& name, const std::vector<NamedMesh>& parts) {
    std::string model = model_header(" xmlns:slic3rpe=\"http://schemas.slic3r.org/3mf/2017/06\"",
                                     "<metadata name=\"slic3rpe:Version3mf\">1</metadata>\n");
    model += fmt::format("<object id=\"1\" name=\"{}\" type=\"model\"><mesh><vertices>\n", xml_escape(name));
    std::vector<const NamedMesh*> used = non_empty(parts);
    std::vector<std::shared_ptr<const MeshXml>> lines;
    for (std::uint32_t offset = 0; const NamedMesh* p : used) {
        lines.push_back(lines_of(*p, offset));
        model += lines.back()->vertices;
        offset += lines.back()->vertex_count;
    }
    model += "</vertices><triangles>\n";
    std::string config = fmt::format(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<config>\n<object id=\"1\" instances_count=\"1\">\n"
        "<metadata type=\"object\" key=\"name\" value=\"{}\"/>\n",
        xml_escape(name));
    size_t first_triangle = 0;
    for (size_t i = 0; i < used.size(); ++i) {
        model += lines[i]->triangles;
        if (lines[i]->triangle_count == 0) continue;
        config += fmt::format("<volume firstid=\"{}\" lastid=\"{}\">\n", first_triangle,
                              first_triangle + lines[i]->triangle_count - 1);
        first_triangle += lines[i]->triangle_count;
        config += fmt::format("<metadata type=\"volume\" key=\"name\" value=\"{}\"/>\n", xml_escape(used[i]->name));
        config += "<metadata type=\"volume\" key=\"volume_type\" value=\"ModelPart\"/>\n";
        for (const auto& [key, value] : used[i]->settings)
            config += fmt::format("<metadata type=\"volume\" key=\"{}\" value=\"{}\"/>\n", xml_escape(key),
                                  xml_escape(value));
        config += "</volume>\n";
    }
    config += "</object>\n</config>\n";
    model += "</triangles></mesh></object>\n</resources>\n" + build_item(1, used) + "</model>\n";
    return package(std::move(model), {{"Metadata/Slic3r_PE_model.config", std::move(config)}});
}

}  // namespace cs

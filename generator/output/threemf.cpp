#include "output/threemf.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <fmt/format.h>
#include <iterator>
#include <numeric>
#include <tuple>

namespace cs {
namespace {

std::uint32_t crc32(std::string_view data) {
    static const auto table = [] {
        std::array<std::uint32_t, 256> t{};
        for (std::uint32_t i = 0; i < 256; ++i) {
            std::uint32_t c = i;
            for (int k = 0; k < 8; ++k) c = c & 1 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
            t[i] = c;
        }
        return t;
    }();
    std::uint32_t c = 0xFFFFFFFFu;
    for (unsigned char b : data) c = table[(c ^ b) & 0xFF] ^ (c >> 8);
    return c ^ 0xFFFFFFFFu;
}

void put16(std::string& s, std::uint16_t v) { s.push_back(char(v & 0xFF)), s.push_back(char(v >> 8)); }
void put32(std::string& s, std::uint32_t v) {
    for (int i = 0; i < 4; ++i) s.push_back(char((v >> (8 * i)) & 0xFF));
}

// Appends the object's XML to `s`. Identical vertices are shared (3MF meshes are indexed), found
// by sorting rather than a map: a 5M-triangle scan stays within a few hundred megabytes.
void append_mesh_xml(std::string& s, int id, const NamedMesh& o) {
    const auto& mv = o.mesh.vertices;
    std::vector<std::uint32_t> by_coords(mv.size());
    std::iota(by_coords.begin(), by_coords.end(), 0u);
    auto key = [&](std::uint32_t i) { return std::make_tuple(mv[i].x, mv[i].y, mv[i].z); };
    std::sort(by_coords.begin(), by_coords.end(), [&](std::uint32_t a, std::uint32_t b) {
        return key(a) != key(b) ? key(a) < key(b) : a < b;
    });
    std::vector<std::uint32_t> same(mv.size());  // each vertex -> first of its coordinates
    for (size_t i = 0; i < by_coords.size(); ++i)
        same[by_coords[i]] = i > 0 && key(by_coords[i]) == key(by_coords[i - 1]) ? same[by_coords[i - 1]] : by_coords[i];
    // Output numbers in order of first use by the faces.
    constexpr std::uint32_t kUnused = UINT32_MAX;
    std::vector<std::uint32_t> out_id(mv.size(), kUnused);
    std::vector<std::uint32_t> order;
    for (const auto& f : o.mesh.faces)
        for (int k = 0; k < 3; ++k)
            if (std::uint32_t c = same[f[k]]; out_id[c] == kUnused) out_id[c] = static_cast<std::uint32_t>(order.size()), order.push_back(c);
    s.reserve(s.size() + 60 * order.size() + 45 * o.mesh.faces.size() + 200);
    s += fmt::format("<object id=\"{}\" name=\"{}\" type=\"model\"><mesh><vertices>\n", id, o.name);
    for (std::uint32_t c : order)
        fmt::format_to(std::back_inserter(s), "<vertex x=\"{:.6f}\" y=\"{:.6f}\" z=\"{:.6f}\"/>\n", mv[c].x, mv[c].y, mv[c].z);
    s += "</vertices><triangles>\n";
    for (const auto& f : o.mesh.faces) {
        std::uint32_t v[3] = {out_id[same[f[0]]], out_id[same[f[1]]], out_id[same[f[2]]]};
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
        fmt::format_to(std::back_inserter(s), "<triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>\n", v[0], v[1], v[2]);
    }
    s += "</triangles></mesh></object>\n";
}

}  // namespace

std::string encode_zip(std::vector<std::pair<std::string, std::string>> entries) {
    std::string out, central;
    for (const auto& entry : entries) {
        const std::string& name = entry.first;  // captured below: clang 14 cannot capture structured bindings
        const std::string& data = entry.second;
        std::uint32_t offset = static_cast<std::uint32_t>(out.size()), crc = crc32(data);
        auto size = static_cast<std::uint32_t>(data.size());
        auto header = [&](std::string& s, bool central_entry) {
            put32(s, central_entry ? 0x02014b50u : 0x04034b50u);
            if (central_entry) put16(s, 20);  // made by
            put16(s, 20);                     // version needed
            put16(s, 0);                      // flags
            put16(s, 0);                      // stored
            put16(s, 0), put16(s, 0x21);      // time, date: 1980-01-01 (fixed: deterministic output)
            put32(s, crc), put32(s, size), put32(s, size);
            put16(s, static_cast<std::uint16_t>(name.size()));
            put16(s, 0);  // extra
            if (central_entry) {
                put16(s, 0), put16(s, 0), put16(s, 0);  // comment, disk, internal attributes
                put32(s, 0);                            // external attributes
                put32(s, offset);
            }
            s += name;
        };
        header(out, false);
        out += data;
        header(central, true);
    }
    auto central_offset = static_cast<std::uint32_t>(out.size());
    out += central;
    put32(out, 0x06054b50u);
    put16(out, 0), put16(out, 0);
    put16(out, static_cast<std::uint16_t>(entries.size())), put16(out, static_cast<std::uint16_t>(entries.size()));
    put32(out, static_cast<std::uint32_t>(central.size()));
    put32(out, central_offset);
    put16(out, 0);
    return out;
}

std::string encode_3mf(const std::vector<NamedMesh>& objects) {
    std::string model =
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
        "<model unit=\"millimeter\" xml:lang=\"en-US\" "
        "xmlns=\"http://schemas.microsoft.com/3dmanufacturing/core/2015/02\">\n"
        "<metadata name=\"Application\">clever-support</metadata>\n<resources>\n";
    std::string build = "<build>\n";
    int id = 1;
    for (const auto& o : objects) {
        if (o.mesh.faces.empty()) continue;
        append_mesh_xml(model, id, o);
        build += fmt::format("<item objectid=\"{}\"/>\n", id);
        ++id;
    }
    model += "</resources>\n" + build + "</build>\n</model>\n";
    std::vector<std::pair<std::string, std::string>> parts;
    parts.emplace_back("[Content_Types].xml",
                       "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                       "<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\">"
                       "<Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/>"
                       "<Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>"
                       "</Types>\n");
    parts.emplace_back("_rels/.rels",
                       "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
                       "<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">"
                       "<Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" "
                       "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>\n");
    parts.emplace_back("3D/3dmodel.model", std::move(model));
    return encode_zip(std::move(parts));
}

}  // namespace cs

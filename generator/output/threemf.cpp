#include "output/threemf.hpp"

#include <array>
#include <cstdint>
#include <fmt/format.h>
#include <map>
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

std::string mesh_xml(int id, const NamedMesh& o) {
    // Share identical vertices: 3MF meshes are indexed.
    std::map<std::tuple<double, double, double>, std::uint32_t> index;
    std::vector<Vec3> verts;
    std::string tris;
    for (const auto& f : o.mesh.faces) {
        std::uint32_t v[3];
        for (int k = 0; k < 3; ++k) {
            const Vec3& p = o.mesh.vertices[f[k]];
            auto [it, fresh] = index.emplace(std::make_tuple(p.x, p.y, p.z), static_cast<std::uint32_t>(verts.size()));
            if (fresh) verts.push_back(p);
            v[k] = it->second;
        }
        if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
        tris += fmt::format("<triangle v1=\"{}\" v2=\"{}\" v3=\"{}\"/>\n", v[0], v[1], v[2]);
    }
    std::string s = fmt::format("<object id=\"{}\" name=\"{}\" type=\"model\"><mesh><vertices>\n", id, o.name);
    for (const auto& p : verts) s += fmt::format("<vertex x=\"{:.6f}\" y=\"{:.6f}\" z=\"{:.6f}\"/>\n", p.x, p.y, p.z);
    s += "</vertices><triangles>\n" + tris + "</triangles></mesh></object>\n";
    return s;
}

}  // namespace

std::string encode_zip(const std::vector<std::pair<std::string, std::string>>& entries) {
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
        model += mesh_xml(id, o);
        build += fmt::format("<item objectid=\"{}\"/>\n", id);
        ++id;
    }
    model += "</resources>\n" + build + "</build>\n</model>\n";
    return encode_zip({
        {"[Content_Types].xml",
         "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<Types xmlns=\"http://schemas.openxmlformats.org/package/2006/content-types\">"
         "<Default Extension=\"rels\" ContentType=\"application/vnd.openxmlformats-package.relationships+xml\"/>"
         "<Default Extension=\"model\" ContentType=\"application/vnd.ms-package.3dmanufacturing-3dmodel+xml\"/>"
         "</Types>\n"},
        {"_rels/.rels",
         "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
         "<Relationships xmlns=\"http://schemas.openxmlformats.org/package/2006/relationships\">"
         "<Relationship Target=\"/3D/3dmodel.model\" Id=\"rel0\" "
         "Type=\"http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel\"/></Relationships>\n"},
        {"3D/3dmodel.model", model},
    });
}

}  // namespace cs

#include "mesh/mesh_io.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

#include "core/errors.hpp"
#include "mesh/read_3mf.hpp"

namespace cs {
namespace {

[[noreturn]] void fail(const std::string& name, const std::string& what, const std::string& todo) {
    throw InputError(name + ": " + what + ". " + todo);
}

const char* kReexport = "Re-export it from your CAD or mesh tool, or repair it (e.g. with Meshmixer or admesh).";

std::string lower(std::string s) {
    std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::tolower(c); });
    return s;
}

std::string extension_of(const std::string& path) {
    auto slash = path.find_last_of('/');
    auto dot = path.find_last_of('.');
    if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
    return lower(path.substr(dot + 1));
}

// A small cursor over whitespace-separated text with line numbers for messages.
struct Lines {
    std::string_view text;
    size_t pos = 0;
    size_t line_no = 0;

    bool next(std::string_view& line) {
        while (pos < text.size()) {
            size_t end = text.find('\n', pos);
            if (end == std::string_view::npos) end = text.size();
            line = text.substr(pos, end - pos);
            pos = end + 1;
            ++line_no;
            if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
            return true;
        }
        return false;
    }
};

std::vector<std::string_view> split_ws(std::string_view s) {
    std::vector<std::string_view> out;
    size_t i = 0;
    while (i < s.size()) {
        while (i < s.size() && std::isspace(static_cast<unsigned char>(s[i]))) ++i;
        size_t j = i;
        while (j < s.size() && !std::isspace(static_cast<unsigned char>(s[j]))) ++j;
        if (j > i) out.push_back(s.substr(i, j - i));
        i = j;
    }
    return out;
}

bool to_double(std::string_view s, double& out) {
    // strtod accepts "nan"/"inf" as numbers: they are caught later with a precise message.
    std::string tmp(s);
    char* end = nullptr;
    errno = 0;
    out = std::strtod(tmp.c_str(), &end);
    return end == tmp.c_str() + tmp.size() && !tmp.empty();
}

bool to_long(std::string_view s, long& out) {
    auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

// ---------------------------------------------------------------- STL

Mesh parse_ascii_stl(std::string_view text, const std::string& name) {
    Mesh m;
    Lines lines{text};
    std::string_view line;
    int in_loop = -1;  // vertices seen in the current loop, -1 outside a loop
    while (lines.next(line)) {
        auto tok = split_ws(line);
        if (tok.empty()) continue;
        std::string key = lower(std::string(tok[0]));
        auto where = " (line " + std::to_string(lines.line_no) + ")";
        if (key == "vertex") {
            if (in_loop < 0 || in_loop >= 3 || tok.size() != 4)
                fail(name, "malformed ASCII STL: bad 'vertex' line" + where, kReexport);
            Vec3 v;
            if (!to_double(tok[1], v.x) || !to_double(tok[2], v.y) || !to_double(tok[3], v.z))
                fail(name, "malformed ASCII STL: '" + std::string(line) + "' is not three numbers" + where, kReexport);
            m.vertices.push_back(v);
            ++in_loop;
        } else if (key == "outer") {
            in_loop = 0;
        } else if (key == "endloop") {
            if (in_loop != 3) fail(name, "malformed ASCII STL: a facet does not have 3 vertices" + where, kReexport);
            auto n = static_cast<std::uint32_t>(m.vertices.size());
            m.faces.push_back({n - 3, n - 2, n - 1});
            in_loop = -1;
        } else if (key == "solid" || key == "facet" || key == "endfacet" || key == "endsolid") {
            continue;
        } else {
            fail(name, "malformed ASCII STL: unexpected '" + std::string(tok[0].substr(0, 40)) + "'" + where,
                 kReexport);
        }
    }
    if (in_loop >= 0) fail(name, "ASCII STL ends inside a facet (truncated file)", kReexport);
    return m;
}

template <typename T>
T read_le(const unsigned char* p) {
    T v;
    std::memcpy(&v, p, sizeof(T));  // x86 and ARM hosts are little-endian, as STL is
    return v;
}

Mesh parse_stl(std::string_view bytes, const std::string& name) {
    size_t start = bytes.find_first_not_of(" \t\r\n");
    // Keywords are case-insensitive; look for "facet" in the first few KiB only.
    bool looks_ascii = start != std::string_view::npos && lower(std::string(bytes.substr(start, 5))) == "solid" &&
                       lower(std::string(bytes.substr(0, 4096))).find("facet") != std::string::npos;
    if (bytes.size() < 84) {
        if (looks_ascii) return parse_ascii_stl(bytes, name);
        fail(name, "only " + std::to_string(bytes.size()) + " bytes: too short to be an STL file",
             "Check that the file was copied completely.");
    }
    auto n = read_le<std::uint32_t>(reinterpret_cast<const unsigned char*>(bytes.data()) + 80);
    std::uint64_t expected = 84 + 50ull * n;
    if (expected != bytes.size()) {
        if (looks_ascii) return parse_ascii_stl(bytes, name);
        if (bytes.size() < expected)
            fail(name,
                 "truncated binary STL: its header promises " + std::to_string(n) + " triangles (" +
                     std::to_string(expected) + " bytes) but the file has " + std::to_string(bytes.size()) + " bytes",
                 "The download or export was cut short; get the file again.");
        fail(name,
             "binary STL whose triangle count (" + std::to_string(n) + ") disagrees with its size (" +
                 std::to_string(bytes.size()) + " bytes, expected " + std::to_string(expected) + ")",
             kReexport);
    }
    Mesh m;
    m.vertices.reserve(3ull * n);
    m.faces.reserve(n);
    auto* p = reinterpret_cast<const unsigned char*>(bytes.data()) + 84;
    for (std::uint32_t i = 0; i < n; ++i, p += 50) {
        for (int k = 0; k < 3; ++k) {
            const unsigned char* q = p + 12 + 12 * k;
            m.vertices.push_back({read_le<float>(q), read_le<float>(q + 4), read_le<float>(q + 8)});
        }
        m.faces.push_back({3 * i, 3 * i + 1, 3 * i + 2});
    }
    return m;
}

// ---------------------------------------------------------------- OBJ

void add_polygon(Mesh& m, const std::vector<std::uint32_t>& poly) {
    for (size_t i = 1; i + 1 < poly.size(); ++i) m.faces.push_back({poly[0], poly[i], poly[i + 1]});
}

Mesh parse_obj(std::string_view text, const std::string& name) {
    Mesh m;
    Lines lines{text};
    std::string_view line;
    struct PendingFace {
        std::vector<long> idx;
        size_t line_no;
    };
    std::vector<PendingFace> pending;
    while (lines.next(line)) {
        auto tok = split_ws(line);
        if (tok.empty() || tok[0][0] == '#') continue;
        auto where = " (line " + std::to_string(lines.line_no) + ")";
        if (tok[0] == "v") {
            Vec3 v;
            if (tok.size() < 4 || !to_double(tok[1], v.x) || !to_double(tok[2], v.y) || !to_double(tok[3], v.z))
                fail(name, "malformed OBJ vertex '" + std::string(line.substr(0, 60)) + "'" + where, kReexport);
            m.vertices.push_back(v);
        } else if (tok[0] == "f") {
            PendingFace f{{}, lines.line_no};
            for (size_t i = 1; i < tok.size(); ++i) {
                long idx;
                auto first = tok[i].substr(0, tok[i].find('/'));
                if (!to_long(first, idx) || idx == 0)
                    fail(name, "malformed OBJ face '" + std::string(line.substr(0, 60)) + "'" + where, kReexport);
                // Negative indices count back from the vertices read so far.
                if (idx < 0) idx = static_cast<long>(m.vertices.size()) + idx + 1;
                f.idx.push_back(idx - 1);
            }
            if (f.idx.size() < 3) fail(name, "OBJ face with fewer than 3 vertices" + where, kReexport);
            pending.push_back(std::move(f));
        }
        // vt, vn, g, o, s, usemtl, mtllib, l, p: not needed for a solid.
    }
    for (const auto& f : pending) {
        std::vector<std::uint32_t> poly;
        for (long i : f.idx) {
            if (i < 0 || i >= static_cast<long>(m.vertices.size()))
                fail(name, "OBJ face refers to vertex " + std::to_string(i + 1) + " but there are only " +
                               std::to_string(m.vertices.size()) + " (line " + std::to_string(f.line_no) + ")",
                     kReexport);
            poly.push_back(static_cast<std::uint32_t>(i));
        }
        add_polygon(m, poly);
    }
    return m;
}

// ---------------------------------------------------------------- OFF

Mesh parse_off(std::string_view text, const std::string& name) {
    // Tokens with the line they came from: a face line may end in a colour (integers or floats).
    std::vector<std::string_view> tok;
    std::vector<size_t> tok_line;
    Lines lines{text};
    std::string_view line;
    while (lines.next(line)) {
        auto hash = line.find('#');
        if (hash != std::string_view::npos) line = line.substr(0, hash);
        for (auto t : split_ws(line)) tok.push_back(t), tok_line.push_back(lines.line_no);
    }
    size_t i = 0;
    if (tok.empty() || tok[0].size() < 3 || tok[0].substr(tok[0].size() - 3) != "OFF")
        fail(name, "not an OFF file (it must start with 'OFF')", kReexport);
    bool colored = tok[0].find('C') != std::string_view::npos;
    bool normals = tok[0].find('N') != std::string_view::npos;
    ++i;
    long nv, nf, ne;
    if (i + 3 > tok.size() || !to_long(tok[i], nv) || !to_long(tok[i + 1], nf) || !to_long(tok[i + 2], ne) ||
        nv < 0 || nf < 0)
        fail(name, "OFF header must give vertex, face and edge counts", kReexport);
    i += 3;
    size_t per_vertex = 3 + (normals ? 3 : 0) + (colored ? 4 : 0);
    if (static_cast<size_t>(nv) > (tok.size() - i) / std::max<size_t>(per_vertex, 1))
        fail(name, "OFF file ends before its " + std::to_string(nv) + " vertices (truncated)", kReexport);
    Mesh m;
    m.vertices.reserve(nv);
    for (long v = 0; v < nv; ++v) {
        Vec3 p;
        if (!to_double(tok[i], p.x) || !to_double(tok[i + 1], p.y) || !to_double(tok[i + 2], p.z))
            fail(name, "OFF vertex " + std::to_string(v) + " is not three numbers", kReexport);
        m.vertices.push_back(p);
        i += per_vertex;
    }
    for (long f = 0; f < nf; ++f) {
        long n;
        if (i >= tok.size() || !to_long(tok[i], n) || n < 0 || static_cast<size_t>(n) > tok.size() - i - 1)
            fail(name, "OFF file ends before its " + std::to_string(nf) + " faces (truncated)", kReexport);
        size_t face_line = tok_line[i];
        ++i;
        std::vector<std::uint32_t> poly;
        for (long k = 0; k < n; ++k, ++i) {
            long idx;
            if (!to_long(tok[i], idx) || idx < 0 || idx >= nv)
                fail(name, "OFF face " + std::to_string(f) + " has a bad vertex index", kReexport);
            poly.push_back(static_cast<std::uint32_t>(idx));
        }
        // Whatever follows the indices on the face's line is its colour.
        while (i < tok.size() && tok_line[i] == face_line) ++i;
        add_polygon(m, poly);
    }
    return m;
}

// ---------------------------------------------------------------- PLY

struct PlyProperty {
    std::string name, type, count_type;  // count_type non-empty for lists
};
struct PlyElement {
    std::string name;
    long count = 0;
    std::vector<PlyProperty> props;
};

size_t ply_type_size(const std::string& t) {
    if (t == "char" || t == "uchar" || t == "int8" || t == "uint8") return 1;
    if (t == "short" || t == "ushort" || t == "int16" || t == "uint16") return 2;
    if (t == "int" || t == "uint" || t == "float" || t == "int32" || t == "uint32" || t == "float32") return 4;
    if (t == "double" || t == "float64") return 8;
    return 0;
}

struct PlyHeader {
    std::string format;
    std::vector<PlyElement> elements;
    size_t body_start = 0;
};

PlyHeader parse_ply_header(std::string_view bytes, const std::string& name) {
    auto header_end = bytes.find("end_header");
    if (bytes.substr(0, 3) != "ply" || header_end == std::string_view::npos)
        fail(name, "not a PLY file (missing 'ply' magic or 'end_header')", kReexport);
    PlyHeader h;
    h.body_start = bytes.find('\n', header_end);
    if (h.body_start == std::string_view::npos) fail(name, "PLY header is not terminated", kReexport);
    ++h.body_start;
    Lines lines{bytes.substr(0, header_end)};
    std::string_view line;
    while (lines.next(line)) {
        auto tok = split_ws(line);
        if (tok.empty()) continue;
        if (tok[0] == "format" && tok.size() >= 2) h.format = tok[1];
        else if (tok[0] == "element" && tok.size() == 3) {
            PlyElement e;
            e.name = tok[1];
            if (!to_long(tok[2], e.count) || e.count < 0) fail(name, "bad PLY element count", kReexport);
            h.elements.push_back(e);
        } else if (tok[0] == "property" && !h.elements.empty()) {
            PlyProperty p;
            if (tok.size() == 5 && tok[1] == "list") p = {std::string(tok[4]), std::string(tok[3]), std::string(tok[2])};
            else if (tok.size() == 3) p = {std::string(tok[2]), std::string(tok[1]), ""};
            else fail(name, "bad PLY property line '" + std::string(line) + "'", kReexport);
            if (!ply_type_size(p.type) || (!p.count_type.empty() && !ply_type_size(p.count_type)))
                fail(name, "unknown PLY property type in '" + std::string(line) + "'", kReexport);
            h.elements.back().props.push_back(p);
        }
    }
    if (h.format != "ascii" && h.format != "binary_big_endian" && h.format != "binary_little_endian")
        fail(name, "unknown PLY format '" + h.format + "'", kReexport);
    return h;
}

// Every row of every element takes at least one byte (binary) or one word (ASCII) of the body,
// so the rows of all elements together cannot outnumber the body's bytes: a cheap guard that
// keeps a tiny file with huge counts from making us allocate gigabytes. A row with no
// properties would take no bytes at all, so such elements must be empty.
void check_ply_rows(const std::vector<PlyElement>& elements, size_t body_size, const std::string& name) {
    size_t rows = 0;
    for (const auto& e : elements) {
        if (e.count > 0 && e.props.empty())
            fail(name, "PLY element '" + e.name + "' has " + std::to_string(e.count) + " rows but no properties",
                 kReexport);
        if (e.name == "vertex" && e.count > 0) {
            for (const char* axis : {"x", "y", "z"}) {
                bool found = std::any_of(e.props.begin(), e.props.end(),
                                         [&](const PlyProperty& p) { return p.name == axis && p.count_type.empty(); });
                if (!found) fail(name, std::string("PLY vertex element has no '") + axis + "' property", kReexport);
            }
        }
        rows += static_cast<size_t>(e.count);
        if (rows > body_size) fail(name, "PLY element counts exceed what the file can hold (truncated or corrupt)", kReexport);
    }
}

// Values of a PLY body, one after another: words of an ASCII body, or binary in either byte order.
class PlyValues {
public:
    PlyValues(std::string_view body, const std::string& format, const std::string& name)
        : body_(body), ascii_(format == "ascii"), big_(format == "binary_big_endian"), name_(name) {
        if (ascii_) words_ = split_ws(body);
    }
    double next(const std::string& type) {
        if (ascii_) {
            double v;
            if (word_ >= words_.size()) fail(name_, "PLY data ends early (truncated file)", kReexport);
            if (!to_double(words_[word_++], v)) fail(name_, "PLY data has a non-number", kReexport);
            return v;
        }
        size_t sz = ply_type_size(type);
        if (pos_ + sz > body_.size()) fail(name_, "PLY data ends early (truncated file)", kReexport);
        unsigned char buf[8];
        std::memcpy(buf, body_.data() + pos_, sz);
        if (big_) std::reverse(buf, buf + sz);
        pos_ += sz;
        if (type == "char" || type == "int8") return static_cast<std::int8_t>(buf[0]);
        if (type == "uchar" || type == "uint8") return buf[0];
        if (type == "short" || type == "int16") return read_le<std::int16_t>(buf);
        if (type == "ushort" || type == "uint16") return read_le<std::uint16_t>(buf);
        if (type == "int" || type == "int32") return read_le<std::int32_t>(buf);
        if (type == "uint" || type == "uint32") return read_le<std::uint32_t>(buf);
        if (type == "float" || type == "float32") return read_le<float>(buf);
        return read_le<double>(buf);
    }

private:
    std::string_view body_;
    bool ascii_, big_;
    const std::string& name_;
    std::vector<std::string_view> words_;
    size_t word_ = 0, pos_ = 0;
};

// One row of an element: a vertex's coordinates, a face's polygon; other properties are read past.
void read_ply_row(const PlyElement& e, PlyValues& values, Mesh& m, const std::string& name) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    Vec3 v;
    for (const auto& p : e.props) {
        if (p.count_type.empty()) {
            double x = values.next(p.type);
            if (is_vertex && p.name == "x") v.x = x;
            if (is_vertex && p.name == "y") v.y = x;
            if (is_vertex && p.name == "z") v.z = x;
            continue;
        }
        double n = values.next(p.count_type);
        if (!(n >= 0 && n < 1e6)) fail(name, "PLY list has a bad length", kReexport);
        std::vector<std::uint32_t> poly;
        for (long k = 0; k < static_cast<long>(n); ++k) {
            double idx = values.next(p.type);
            if (is_face && (p.name == "vertex_indices" || p.name == "vertex_index")) {
                if (!(idx >= 0 && idx < static_cast<double>(m.vertices.size())))
                    fail(name, "PLY face refers to a missing vertex", kReexport);
                poly.push_back(static_cast<std::uint32_t>(idx));
            }
        }
        if (is_face) add_polygon(m, poly);
    }
    if (is_vertex) m.vertices.push_back(v);
}

Mesh parse_ply(std::string_view bytes, const std::string& name) {
    const PlyHeader h = parse_ply_header(bytes, name);
    std::string_view body = bytes.substr(h.body_start);
    check_ply_rows(h.elements, body.size(), name);
    PlyValues values(body, h.format, name);
    Mesh m;
    for (const auto& e : h.elements)
        for (long r = 0; r < e.count; ++r) read_ply_row(e, values, m, name);
    return m;
}

void check_coordinates(const Mesh& m, const std::string& name) {
    for (size_t i = 0; i < m.vertices.size(); ++i) {
        const auto& v = m.vertices[i];
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
            fail(name, "vertex " + std::to_string(i) + " has a NaN or infinite coordinate", kReexport);
        // Beyond 1e9 mm (1000 km) float32 input has no millimetre precision left: a corrupt file.
        if (std::abs(v.x) > 1e9 || std::abs(v.y) > 1e9 || std::abs(v.z) > 1e9)
            fail(name, "vertex " + std::to_string(i) + " has a coordinate beyond 1e9 (corrupt or wrong units)",
                 "Check the export units, or re-export the model.");
    }
}

}  // namespace

const std::vector<std::string>& mesh_formats() {
    static const std::vector<std::string> formats = {"stl", "obj", "off", "ply", "3mf"};
    return formats;
}

std::string mesh_formats_text() {
    const auto& f = mesh_formats();
    std::string s;
    for (size_t i = 0; i < f.size(); ++i) s += (i == 0 ? "." : i + 1 == f.size() ? " or ." : ", .") + f[i];
    return s;
}

Mesh parse_mesh(std::string_view bytes, const std::string& format, const std::string& name, bool allow_empty,
                std::string* contents) {
    Mesh m;
    if (format == "stl") m = parse_stl(bytes, name);
    else if (format == "obj") m = parse_obj(bytes, name);
    else if (format == "off") m = parse_off(bytes, name);
    else if (format == "ply") m = parse_ply(bytes, name);
    else if (format == "3mf") {
        ThreeMfContents what;
        m = parse_3mf(bytes, name, &what);
        if (contents) *contents = what.summary();
    } else
        fail(name, "unknown mesh format '" + format + "'", "Use an " + mesh_formats_text() + " file.");
    check_coordinates(m, name);
    if (m.faces.empty() && !allow_empty)
        fail(name, "the file contains no triangles", "Check that it is a mesh file and was exported completely.");
    return m;
}

namespace {

// Everything `in` holds: a regular file in one read of its size (a scan is tens of megabytes,
// which a character at a time took most of the loading), then as a stream whatever is left (all
// of a pipe, or what a file gained since `st` was taken).
std::string whole_file(std::ifstream& in, const struct stat& st) {
    std::string bytes;
    if (S_ISREG(st.st_mode) && st.st_size > 0) {
        bytes.resize(static_cast<std::size_t>(st.st_size));
        in.read(bytes.data(), st.st_size);
        bytes.resize(static_cast<std::size_t>(in.gcount()));
    }
    bytes.append(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return bytes;
}

}  // namespace

Mesh read_mesh(const std::string& path, bool allow_empty, std::string* contents) {
    struct stat st{};
    if (stat(path.c_str(), &st) != 0)
        fail(path, std::string("cannot open: ") + std::strerror(errno), "Check the path.");
    if (S_ISDIR(st.st_mode))
        fail(path, "is a directory, not a mesh file",
             "Give the path of an " + mesh_formats_text() + " file, or of an OpenSCAD part (.scad).");
    std::string ext = extension_of(path);
    if (std::find(mesh_formats().begin(), mesh_formats().end(), ext) == mesh_formats().end())
        fail(path, "unknown format" + (ext.empty() ? std::string(" (no file extension)") : " '." + ext + "'"),
             "Use an " + mesh_formats_text() + " file, or an OpenSCAD part (.scad).");
    std::ifstream in(path, std::ios::binary);
    if (!in) fail(path, std::string("cannot read: ") + std::strerror(errno), "Check the file's permissions.");
    std::string bytes = whole_file(in, st);
    if (in.bad()) fail(path, "read error", "Check the disk and the file.");
    if (bytes.empty()) fail(path, "the file is empty", "Check that the export finished and the file was copied completely.");
    return parse_mesh(bytes, ext, path, allow_empty, contents);
}

std::string encode_stl(const Mesh& mesh, const std::string& header) { return encode_stl(std::vector{&mesh}, header); }

std::string encode_stl(const std::vector<const Mesh*>& parts, const std::string& header) {
    std::size_t faces = 0;
    for (const Mesh* m : parts) faces += m->faces.size();
    std::string out(84 + 50 * faces, '\0');
    std::memcpy(out.data(), header.data(), std::min<size_t>(header.size(), 80));
    auto n = static_cast<std::uint32_t>(faces);
    std::memcpy(out.data() + 80, &n, 4);
    char* p = out.data() + 84;
    for (const Mesh* m : parts)
        for (const auto& f : m->faces) {
            Vec3 nrm = normalized(face_normal_unnormalized(*m, f));
            float v[12] = {float(nrm.x), float(nrm.y), float(nrm.z)};
            for (int k = 0; k < 3; ++k) {
                const Vec3& q = m->vertices[f[k]];
                v[3 + 3 * k] = float(q.x);
                v[4 + 3 * k] = float(q.y);
                v[5 + 3 * k] = float(q.z);
            }
            std::memcpy(p, v, 48);
            p += 50;
        }
    return out;
}

void write_stl(const std::string& path, const Mesh& mesh, const std::string& header) {
    write_file_atomic(path, encode_stl(mesh, header));
}

void write_file_atomic(const std::string& path, std::string_view content) {
    std::string tmp = path + ".tmp-" + std::to_string(::getpid());
    int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd < 0) throw OutputError(path + ": cannot write: " + std::strerror(errno) + ". Choose another --out directory.");
    size_t done = 0;
    while (done < content.size()) {
        ssize_t w = ::write(fd, content.data() + done, content.size() - done);
        if (w < 0) {
            if (errno == EINTR) continue;
            int err = errno;
            ::close(fd);
            ::unlink(tmp.c_str());
            throw OutputError(path + ": write failed: " + std::strerror(err) + ". Free some disk space or choose another --out directory.");
        }
        done += static_cast<size_t>(w);
    }
    if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
        int err = errno;
        ::close(fd);
        ::unlink(tmp.c_str());
        throw OutputError(path + ": write failed: " + std::strerror(err) + ".");
    }
    if (::close(fd) != 0 || ::rename(tmp.c_str(), path.c_str()) != 0) {
        int err = errno;
        ::unlink(tmp.c_str());
        throw OutputError(path + ": cannot write: " + std::strerror(err) + ". Choose another --out directory.");
    }
}

}  // namespace cs

#include "mesh/read_3mf.hpp"

#include <expat.h>
#include <minizip/unzip.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <deque>
#include <map>
#include <memory>
#include <new>
#include <set>
#include <vector>

#include <fmt/format.h>

#include "core/errors.hpp"
#include "mesh/zip_memory.hpp"

namespace cs {
namespace {

const char* kReexport = "Re-export it as 3MF from your CAD tool or slicer, or export the model as STL.";

// Placing components multiplies triangles: a small file can describe billions. Beyond this many
// placed triangles (ten times the largest scan we support) the file is refused before any is made.
constexpr std::size_t kMaxPlacedTriangles = 50'000'000;
// Components nest: object -> group -> group ... Deeper than this is a loop or a generated bomb.
constexpr int kMaxNesting = 32;

[[noreturn]] void fail(const std::string& name, const std::string& what, const std::string& todo = kReexport) {
    throw InputError(name + ": " + what + ". " + todo);
}

// ---------------------------------------------------------------- transforms

// A 3MF transform "m00 m01 m02 m10 m11 m12 m20 m21 m22 m30 m31 m32": a point p (a row vector)
// goes to p * M + t, with M[i][j] = m[3i + j] and t[j] = m[9 + j].
struct Affine {
    std::array<double, 12> m{1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
};

Vec3 apply(const Affine& a, const Vec3& p) {
    const auto& m = a.m;
    return {p.x * m[0] + p.y * m[3] + p.z * m[6] + m[9], p.x * m[1] + p.y * m[4] + p.z * m[7] + m[10],
            p.x * m[2] + p.y * m[5] + p.z * m[8] + m[11]};
}

// `inner` first, then `outer` (a component's transform, then its parent's).
Affine then(const Affine& inner, const Affine& outer) {
    Affine c;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 3; ++j) {
            double s = i == 3 ? outer.m[9 + j] : 0;
            for (int k = 0; k < 3; ++k) s += inner.m[3 * i + k] * outer.m[3 * k + j];
            c.m[3 * i + j] = s;
        }
    return c;
}

double determinant(const Affine& a) {
    const auto& m = a.m;
    return m[0] * (m[4] * m[8] - m[5] * m[7]) - m[1] * (m[3] * m[8] - m[5] * m[6]) + m[2] * (m[3] * m[7] - m[4] * m[6]);
}

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t' || s.front() == '\n' || s.front() == '\r'))
        s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\n' || s.back() == '\r'))
        s.remove_suffix(1);
    return s;
}

bool parse_number(std::string_view s, double& out) {
    s = trim(s);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size() && std::isfinite(out);
}

bool parse_index(std::string_view s, std::uint64_t& out) {
    s = trim(s);
    auto r = std::from_chars(s.data(), s.data() + s.size(), out);
    return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

// ---------------------------------------------------------------- the package's contents

struct Component {
    std::string key;  // the object's part + "#" + id
    Affine transform;
};

struct Object {
    std::string where;  // "3D/3dmodel.model line 12", for messages
    std::string type = "model";
    bool has_mesh = false;
    std::vector<Vec3> vertices;
    std::vector<Triangle> faces;
    std::vector<Component> components;
};

struct Item {
    std::string where;
    std::string key;
    Affine transform;
};

struct Package {
    std::map<std::string, Object> objects;  // by key
    std::vector<Item> items;
    std::string unit;                       // of the root model part
    std::deque<std::string> parts_to_read;  // model parts named by p:path, not read yet
    std::set<std::string> parts_named;
};

std::string part_name(std::string_view path) {
    path = trim(path);
    while (!path.empty() && path.front() == '/') path.remove_prefix(1);
    return std::string(path);
}

std::string key_of(const std::string& part, std::string_view id) { return part + "#" + std::string(trim(id)); }

// ---------------------------------------------------------------- ZIP

// An archive open for reading, with the bytes it reads from (minizip reads through memory_zip_io).
struct Zip {
    MemoryZipFile file;
    unzFile z = nullptr;
    Zip() = default;
    Zip(const Zip&) = delete;
    Zip& operator=(const Zip&) = delete;
    ~Zip() {
        if (z) unzClose(z);
    }
};

std::unique_ptr<Zip> open_zip(std::string_view bytes, const std::string& name) {
    auto zip = std::make_unique<Zip>();
    zip->file.bytes.assign(bytes);
    zlib_filefunc64_def io = memory_zip_io(zip->file);
    zip->z = unzOpen2_64(name.c_str(), &io);
    if (!zip->z)
        fail(name, "is not a 3MF file: it is not a ZIP archive, which every 3MF is (no readable ZIP directory)",
             "Check that the download or export finished; if it is another format, give it that format's extension.");
    return zip;
}

// Makes `part` the archive's current entry; false if there is none. Part names are
// case-insensitive in OPC packages: an exact match first, then one in any case.
bool find_entry(Zip& zip, const std::string& part) {
    constexpr int kCaseSensitive = 1, kCaseInsensitive = 2;  // unzLocateFile's iCaseSensitivity
    return unzLocateFile(zip.z, part.c_str(), kCaseSensitive) == UNZ_OK ||
           unzLocateFile(zip.z, part.c_str(), kCaseInsensitive) == UNZ_OK;
}

// Streams one entry's inflated bytes to `sink` in chunks, charging them to `budget` (the bytes
// still allowed). The declared size is checked first, and the bytes as they come (the header can
// lie).
struct Budget {
    std::size_t left;   // bytes still allowed
    std::size_t limit;  // in all
};

// The current entry (find_entry), streamed; its CRC is checked once it is all read.
template <class Sink>
void read_entry(Zip& zip, const std::string& part, const std::string& name, Budget& budget, Sink&& sink) {
    const std::string bomb = fmt::format(
        "unpacks to more than {} of XML in all (a ZIP bomb, or a model far larger than any printer's)",
        budget.limit >= (1u << 20) ? std::to_string(budget.limit >> 20) + " MB" : std::to_string(budget.limit) + " bytes");
    unz_file_info64 info{};
    if (unzGetCurrentFileInfo64(zip.z, &info, nullptr, 0, nullptr, 0, nullptr, 0) != UNZ_OK)
        fail(name, "cannot unpack " + part + " (damaged ZIP directory)", kReexport);
    if (info.uncompressed_size > budget.left)
        fail(name, part + " " + bomb, "Check where the file came from; simplify the model before exporting it.");
    if (const int rc = unzOpenCurrentFile(zip.z); rc != UNZ_OK)
        fail(name, fmt::format("cannot unpack {} (damaged or unsupported ZIP entry: minizip error {})", part, rc),
             kReexport);
    struct Closer {  // an entry left open is closed whichever way this ends
        unzFile z;
        ~Closer() {
            if (z) unzCloseCurrentFile(z);
        }
    } closer{zip.z};
    std::vector<char> buf(1 << 20);
    for (;;) {
        const int n = unzReadCurrentFile(zip.z, buf.data(), static_cast<unsigned>(buf.size()));
        if (n < 0) fail(name, fmt::format("cannot unpack {} (damaged ZIP: minizip error {})", part, n), kReexport);
        if (static_cast<std::size_t>(n) > budget.left)
            fail(name, part + " " + bomb, "Check where the file came from; simplify the model before exporting it.");
        budget.left -= static_cast<std::size_t>(n);
        const bool last = n == 0;
        if (last) {
            closer.z = nullptr;
            if (unzCloseCurrentFile(zip.z) == UNZ_CRCERROR)
                fail(name, "cannot unpack " + part + " (damaged ZIP: its CRC does not match)", kReexport);
        }
        sink(buf.data(), static_cast<std::size_t>(n), last);
        if (last) break;
    }
}

// ---------------------------------------------------------------- XML (expat, namespace-aware)

std::string_view local_name(const XML_Char* qualified) {
    std::string_view s(qualified);
    auto bar = s.rfind('|');
    return bar == std::string_view::npos ? s : s.substr(bar + 1);
}

const XML_Char* attribute(const XML_Char** attrs, std::string_view local) {
    for (int i = 0; attrs[i]; i += 2)
        if (local_name(attrs[i]) == local) return attrs[i + 1];
    return nullptr;
}

// One XML part parsed with expat; `Handler` gets start and end of each element by local name and
// reports a problem by returning a non-empty message. DOCTYPEs and entities are refused: 3MF has
// none, and they are how XML expands a small file into a huge one.
class XmlStream {
public:
    using Start = std::string (*)(void* self, std::string_view element, const XML_Char** attrs);
    using End = void (*)(void* self, std::string_view element);

    XmlStream(std::string where, void* self, Start start, End end)
        : where_(std::move(where)), self_(self), start_(start), end_(end), p_(XML_ParserCreateNS(nullptr, '|')) {
        if (!p_) throw std::bad_alloc();
        XML_SetUserData(p_, this);
        XML_SetElementHandler(p_, on_start, on_end);
        XML_SetStartDoctypeDeclHandler(p_, on_doctype);
        XML_SetEntityDeclHandler(p_, on_entity);
    }
    ~XmlStream() { XML_ParserFree(p_); }
    XmlStream(const XmlStream&) = delete;
    XmlStream& operator=(const XmlStream&) = delete;

    // Feeds a chunk; returns "" or the problem, with its line.
    std::string feed(const char* data, std::size_t n, bool last) {
        if (XML_Parse(p_, data, static_cast<int>(n), last ? XML_TRUE : XML_FALSE) != XML_STATUS_ERROR) return "";
        if (problem_.empty())
            problem_ = fmt::format("broken XML in {} at line {}: {}", where_, XML_GetCurrentLineNumber(p_),
                                   XML_ErrorString(XML_GetErrorCode(p_)));
        return problem_;
    }
    std::string here() const { return fmt::format("{} line {}", where_, XML_GetCurrentLineNumber(p_)); }

private:
    void stop(std::string problem) {
        problem_ = std::move(problem);
        XML_StopParser(p_, XML_FALSE);
    }
    static void on_start(void* data, const XML_Char* name, const XML_Char** attrs) {
        auto* x = static_cast<XmlStream*>(data);
        std::string problem = x->start_(x->self_, local_name(name), attrs);
        if (!problem.empty()) x->stop(problem + " (" + x->here() + ")");
    }
    static void on_end(void* data, const XML_Char* name) {
        auto* x = static_cast<XmlStream*>(data);
        x->end_(x->self_, local_name(name));
    }
    static void on_doctype(void* data, const XML_Char*, const XML_Char*, const XML_Char*, int) {
        auto* x = static_cast<XmlStream*>(data);
        x->stop("a DOCTYPE declaration, which 3MF does not use (" + x->here() + ")");
    }
    static void on_entity(void* data, const XML_Char*, int, const XML_Char*, int, const XML_Char*, const XML_Char*,
                          const XML_Char*, const XML_Char*) {
        auto* x = static_cast<XmlStream*>(data);
        x->stop("an entity declaration, which 3MF does not use (" + x->here() + ")");
    }

    std::string where_;
    void* self_;
    Start start_;
    End end_;
    XML_Parser p_;
    std::string problem_;
};

// Streams one ZIP entry through an XmlStream; throws the stream's problem as an InputError.
void parse_entry(Zip& zip, const std::string& part, const std::string& name, Budget& budget, XmlStream& xml) {
    read_entry(zip, part, name, budget, [&](const char* data, std::size_t n, bool last) {
        std::string problem = xml.feed(data, n, last);
        if (!problem.empty()) fail(name, problem, kReexport);
    });
}

// ---------------------------------------------------------------- _rels/.rels

struct RelsReader {
    std::string model_part;
    static std::string start(void* self, std::string_view element, const XML_Char** attrs) {
        auto* r = static_cast<RelsReader*>(self);
        if (element != "Relationship" || !r->model_part.empty()) return "";
        const char* type = attribute(attrs, "Type");
        const char* target = attribute(attrs, "Target");
        std::string_view t = type ? std::string_view(type) : std::string_view();
        if (target && t.size() >= 8 && t.substr(t.size() - 8) == "/3dmodel") r->model_part = part_name(target);
        return "";
    }
    static void end(void*, std::string_view) {}
};

// The root model part: the relationship of type .../3dmodel, else the usual name.
std::string root_model_part(Zip& zip, const std::string& name, Budget& budget) {
    if (find_entry(zip, "_rels/.rels")) {
        RelsReader reader;
        XmlStream xml("_rels/.rels", &reader, RelsReader::start, RelsReader::end);
        parse_entry(zip, "_rels/.rels", name, budget, xml);
        if (!reader.model_part.empty()) return reader.model_part;
    }
    return "3D/3dmodel.model";
}

// ---------------------------------------------------------------- model parts

struct ModelReader {
    Package& pkg;
    std::string part;
    bool root;
    XmlStream* xml = nullptr;
    Object* object = nullptr;  // inside <object>
    bool in_build = false;

    std::string here() const { return xml->here(); }

    // A transform attribute, or "" with `out` set; else the problem.
    static std::string read_transform(const XML_Char* text, Affine& out) {
        if (!text) return "";
        std::string_view s(text);
        int n = 0;
        std::size_t i = 0;
        while (true) {
            while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\n' || s[i] == '\r')) ++i;
            if (i == s.size()) break;
            std::size_t j = i;
            while (j < s.size() && !(s[j] == ' ' || s[j] == '\t' || s[j] == '\n' || s[j] == '\r')) ++j;
            if (n == 12 || !parse_number(s.substr(i, j - i), out.m[static_cast<std::size_t>(n)]))
                return fmt::format("a transform \"{}\" that is not 12 numbers", s.substr(0, 120));
            ++n;
            i = j;
        }
        if (n != 12) return fmt::format("a transform \"{}\" that is not 12 numbers", s.substr(0, 120));
        return "";
    }

    std::string reference(const XML_Char** attrs, std::string& key, Affine& t) {
        const char* id = attribute(attrs, "objectid");
        if (!id || trim(id).empty()) return "no objectid";
        std::string target = part;
        if (const char* path = attribute(attrs, "path")) {
            target = part_name(path);
            if (pkg.parts_named.insert(target).second) pkg.parts_to_read.push_back(target);
        }
        key = key_of(target, id);
        return read_transform(attribute(attrs, "transform"), t);
    }

    std::string on_start(std::string_view e, const XML_Char** attrs) {
        if (e == "model") {
            if (const char* unit = attribute(attrs, "unit"); unit && root) pkg.unit = std::string(trim(unit));
        } else if (e == "object") {
            const char* id = attribute(attrs, "id");
            if (!id || trim(id).empty()) return "an <object> without id";
            auto [it, fresh] = pkg.objects.try_emplace(key_of(part, id));
            if (!fresh) return fmt::format("two objects with id {}", id);
            object = &it->second;
            object->where = here();
            if (const char* type = attribute(attrs, "type")) object->type = std::string(trim(type));
        } else if (e == "mesh") {
            if (!object) return "a <mesh> outside any <object>";
            object->has_mesh = true;
        } else if (e == "vertex") {
            if (!object) return "a <vertex> outside any <object>";
            Vec3 v;
            const char* x = attribute(attrs, "x");
            const char* y = attribute(attrs, "y");
            const char* z = attribute(attrs, "z");
            if (!x || !y || !z || !parse_number(x, v.x) || !parse_number(y, v.y) || !parse_number(z, v.z))
                return "a <vertex> whose x, y, z are not three finite numbers";
            object->vertices.push_back(v);
        } else if (e == "triangle") {
            if (!object) return "a <triangle> outside any <object>";
            Triangle t{};
            const char* names[3] = {"v1", "v2", "v3"};
            for (int k = 0; k < 3; ++k) {
                const char* v = attribute(attrs, names[k]);
                std::uint64_t idx = 0;
                if (!v || !parse_index(v, idx))
                    return fmt::format("a <triangle> whose {} is not a vertex number", names[k]);
                if (idx >= object->vertices.size())
                    return fmt::format("a <triangle> refers to vertex {}, but its object has {} vertices", idx,
                                       object->vertices.size());
                t[static_cast<std::size_t>(k)] = static_cast<std::uint32_t>(idx);
            }
            object->faces.push_back(t);
        } else if (e == "component") {
            if (!object) return "a <component> outside any <object>";
            Component c;
            std::string problem = reference(attrs, c.key, c.transform);
            if (!problem.empty()) return "a <component> with " + problem;
            object->components.push_back(std::move(c));
        } else if (e == "build") {
            in_build = true;
        } else if (e == "item" && in_build) {
            Item item;
            item.where = here();
            std::string problem = reference(attrs, item.key, item.transform);
            if (!problem.empty()) return "a build <item> with " + problem;
            pkg.items.push_back(std::move(item));
        }
        return "";
    }
    void on_end(std::string_view e) {
        if (e == "object") object = nullptr;
        if (e == "build") in_build = false;
    }
    static std::string start(void* self, std::string_view e, const XML_Char** attrs) {
        return static_cast<ModelReader*>(self)->on_start(e, attrs);
    }
    static void end(void* self, std::string_view e) { static_cast<ModelReader*>(self)->on_end(e); }
};

void read_model_part(Zip& zip, const std::string& part, bool root, Package& pkg, const std::string& name,
                     Budget& budget) {
    if (!find_entry(zip, part))
        fail(name, root ? "has no 3D model part (" + part + "): it is a ZIP, but not a 3MF model"
                        : "a component refers to the model part " + part + ", which the package does not contain",
             kReexport);
    ModelReader reader{pkg, part, root};
    XmlStream xml(part, &reader, ModelReader::start, ModelReader::end);
    reader.xml = &xml;
    parse_entry(zip, part, name, budget, xml);
}

// ---------------------------------------------------------------- placing

bool printable(const Object& o) { return o.type == "model" || o.type == "solidsupport"; }

// Triangles an object places (its mesh and, recursively, its components), counted before any is
// made; refuses missing references, loops and nesting past kMaxNesting.
std::size_t count_triangles(const Package& pkg, const std::string& key, const std::string& where,
                            std::map<std::string, std::size_t>& memo, std::vector<std::string>& path,
                            const std::string& name) {
    auto it = pkg.objects.find(key);
    const std::string id = key.substr(key.find('#') + 1);
    if (it == pkg.objects.end())
        fail(name, fmt::format("{} refers to object {}, which the file does not define", where, id), kReexport);
    if (auto m = memo.find(key); m != memo.end()) return m->second;
    if (std::find(path.begin(), path.end(), key) != path.end())
        fail(name, fmt::format("object {} contains itself through its components", id), kReexport);
    if (path.size() >= static_cast<std::size_t>(kMaxNesting))
        fail(name, fmt::format("components nest deeper than {} levels", kMaxNesting), kReexport);
    const Object& o = it->second;
    std::size_t n = printable(o) ? o.faces.size() : 0;
    path.push_back(key);
    for (const auto& c : o.components) {
        n += count_triangles(pkg, c.key, "a component of the object at " + o.where, memo, path, name);
        n = std::min(n, kMaxPlacedTriangles + 1);  // saturate: the caller only compares with the limit
    }
    path.pop_back();
    if (!printable(o)) n = 0;
    memo[key] = n;
    return n;
}

void place(const Package& pkg, const std::string& key, const Affine& t, Mesh& out) {
    const Object& o = pkg.objects.at(key);
    if (!printable(o)) return;
    const auto base = static_cast<std::uint32_t>(out.vertices.size());
    for (const auto& v : o.vertices) out.vertices.push_back(apply(t, v));
    // A mirroring transform turns the triangles inside out; swap two corners to keep them facing out.
    const bool mirrored = determinant(t) < 0;
    for (const auto& f : o.faces)
        out.faces.push_back(mirrored ? Triangle{base + f[0], base + f[2], base + f[1]}
                                     : Triangle{base + f[0], base + f[1], base + f[2]});
    for (const auto& c : o.components) place(pkg, c.key, then(c.transform, t), out);
}

double millimetres_per_unit(const std::string& unit, const std::string& name) {
    static const std::map<std::string, double> units = {{"micron", 0.001}, {"millimeter", 1},  {"centimeter", 10},
                                                        {"inch", 25.4},    {"foot", 304.8},    {"meter", 1000}};
    auto it = units.find(unit);
    if (it == units.end())
        fail(name, "the model's unit \"" + unit.substr(0, 40) + "\" is not one 3MF defines",
             "Use micron, millimeter, centimeter, inch, foot or meter; re-export it.");
    return it->second;
}

// Every object that no other object uses: what a file without <build> items would print.
std::vector<Item> top_level_objects(const Package& pkg) {
    std::set<std::string> used;
    for (const auto& [key, o] : pkg.objects)
        for (const auto& c : o.components) used.insert(c.key);
    std::vector<Item> items;
    for (const auto& [key, o] : pkg.objects)
        if (!used.count(key)) items.push_back({o.where, key, Affine{}});
    return items;
}

void count_contents(const Package& pkg, ThreeMfContents& what) {
    for (const auto& [key, o] : pkg.objects) {
        if (!printable(o)) ++what.skipped_objects;
        else if (!o.components.empty()) ++what.component_objects, what.components += static_cast<int>(o.components.size());
        else if (o.has_mesh) ++what.mesh_objects;
    }
}

}  // namespace

std::string ThreeMfContents::summary() const {
    auto plural = [](int n, const char* one, const char* many) { return fmt::format("{} {}", n, n == 1 ? one : many); };
    std::string s = fmt::format("3MF: {} of {} ({}", plural(build_items, "build item", "build items"),
                                plural(mesh_objects + component_objects, "object", "objects"),
                                plural(mesh_objects, "mesh", "meshes"));
    if (component_objects > 0)
        s += fmt::format(", {} of {}", plural(component_objects, "group", "groups"),
                         plural(components, "component", "components"));
    s += ")";
    if (skipped_objects > 0)
        s += fmt::format(", {} of type support/other left out", plural(skipped_objects, "object", "objects"));
    if (model_parts > 1) s += fmt::format(", from {} model parts", model_parts);
    s += fmt::format(", read as one model of {} triangles, unit {}", triangles, unit);
    return s;
}

Mesh parse_3mf(std::string_view bytes, const std::string& name, ThreeMfContents* contents,
               std::size_t max_unpacked_bytes) {
    const std::unique_ptr<Zip> zip = open_zip(bytes, name);
    Budget budget{max_unpacked_bytes, max_unpacked_bytes};
    Package pkg;
    pkg.unit = "millimeter";
    const std::string root = root_model_part(*zip, name, budget);
    pkg.parts_named.insert(root);
    read_model_part(*zip, root, true, pkg, name, budget);
    ThreeMfContents what;
    what.model_parts = 1;
    while (!pkg.parts_to_read.empty()) {
        std::string part = pkg.parts_to_read.front();
        pkg.parts_to_read.pop_front();
        read_model_part(*zip, part, false, pkg, name, budget);
        ++what.model_parts;
    }
    const double scale = millimetres_per_unit(pkg.unit, name);
    what.unit = pkg.unit;

    std::vector<Item> items = pkg.items.empty() ? top_level_objects(pkg) : pkg.items;
    std::map<std::string, std::size_t> memo;
    std::vector<std::string> path;
    std::size_t total = 0;
    for (const auto& item : items)
        total += count_triangles(pkg, item.key, "the build item at " + item.where, memo, path, name);
    if (total > kMaxPlacedTriangles)
        fail(name, fmt::format("its build places more than {} million triangles", kMaxPlacedTriangles / 1'000'000),
             "Simplify the model, or place fewer copies, before exporting it.");

    Mesh out;
    out.vertices.reserve(total * 3 / 2);
    out.faces.reserve(total);
    for (const auto& item : items) place(pkg, item.key, item.transform, out);
    if (scale != 1)
        for (auto& v : out.vertices) v = v * scale;
    what.build_items = static_cast<int>(items.size());
    what.triangles = out.faces.size();
    count_contents(pkg, what);
    if (contents) *contents = what;
    return out;
}

}  // namespace cs

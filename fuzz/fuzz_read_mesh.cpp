// libFuzzer target for the mesh readers and repair: one source, five binaries (fuzz_stl, fuzz_obj,
// fuzz_off, fuzz_ply, fuzz_3mf), the format chosen at compile time by CS_FUZZ_FORMAT ("stl", "obj", ...).
//
// For any input, parse_mesh must either return a mesh or throw InputError; a parsed mesh then goes
// through repair_mesh, which must do the same. InputError is the expected outcome for junk and is
// swallowed here. Anything else is a finding: a crash or sanitizer report, another exception (it
// escapes and libFuzzer reports it as a deadly signal via std::terminate), a hang (-timeout) or
// runaway memory (-rss_limit_mb / -malloc_limit_mb).
//
// Built by fuzz/CMakeLists.txt (cmake -DCS_FUZZ=ON with clang) and run by scripts/fuzz.sh. The
// reproducers it finds are kept in tests/data/fuzz/<format>/ and replayed by
// tests/unit/test_fuzz_replay.cpp in every normal test run.
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "core/errors.hpp"
#include "mesh/mesh_io.hpp"
#include "mesh/repair.hpp"

#ifndef CS_FUZZ_FORMAT
#error "CS_FUZZ_FORMAT must be defined (\"stl\", \"obj\", \"off\", \"ply\" or \"3mf\")"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const std::string format = CS_FUZZ_FORMAT;
    static const std::string name = "fuzz." + format;
    const std::string_view bytes(reinterpret_cast<const char*>(data), size);
    try {
        cs::Mesh raw = cs::parse_mesh(bytes, format, name);
        cs::RepairReport report;
        cs::Mesh repaired = cs::repair_mesh(raw, name, report);
        (void)repaired;
    } catch (const cs::InputError&) {
        // Expected for junk input.
    }
    return 0;
}

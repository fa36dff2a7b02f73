// libFuzzer target for an edited .scad read back by `clever-support regrow` (edit/edited_scad.hpp):
// what a person may type into the generated file. InputError (a malformed file, with its line)
// and ParameterError (a value out of range) are the expected outcomes for junk and are swallowed;
// anything else (another exception, a crash, a sanitizer report such as a double converted to an
// int it does not fit, a hang) is a finding. Seeds and reproducers: tests/data/fuzz/scad/
// (replayed by tests/unit/test_fuzz_replay.cpp in every test run).
#include <cstddef>
#include <cstdint>
#include <string>

#include "core/errors.hpp"
#include "edit/edited_scad.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string text(reinterpret_cast<const char*>(data), size);
    try {
        cs::EditedScad e = cs::read_edited_scad_text(text, "fuzz/fuzz.scad");
        (void)e;
    } catch (const cs::InputError&) {
        // Expected for junk input.
    } catch (const cs::ParameterError&) {
        // A value out of its range.
    }
    return 0;
}

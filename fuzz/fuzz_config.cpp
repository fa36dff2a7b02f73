// libFuzzer target for what a user types into a --config file (core/config.hpp): the JSON is read
// and checked whole, its preset looked up, its parameters set and range-checked, as the CLI does.
// ParameterError is the expected outcome for junk and is swallowed; anything else (a JSON library
// exception, a crash, a sanitizer report, a hang) is a finding. Seeds and reproducers:
// tests/data/fuzz/config/ (replayed by tests/unit/test_fuzz_replay.cpp in every test run).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/config.hpp"
#include "core/errors.hpp"
#include "core/param_table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    try {
        cs::ConfigFile c = cs::parse_config(text, "--config fuzz.json");
        cs::Params p = cs::preset_params(c.preset.value_or("generic-0.4"));
        cs::apply_config(c.values, p, "--config fuzz.json");
        cs::validate_params(p);
    } catch (const cs::ParameterError&) {
        // Expected for junk input.
    }
    return 0;
}

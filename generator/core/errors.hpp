// Error types and the process exit codes they map to (documented in README "Exit codes").
#pragma once

#include <stdexcept>
#include <string>

namespace cs {

enum ExitCode : int {
    kExitOk = 0,
    kExitInternal = 1,   // a bug: please report it
    kExitUsage = 2,      // bad command line
    kExitBadInput = 3,   // the input file cannot be used
    kExitCheckFailed = 4,
    kExitRenderFailed = 5,
    kExitOutputFailed = 6,  // an output could not be written
};

// The input mesh cannot be used. `what()` names the file, the problem and what to do.
struct InputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// An output file could not be written (nothing half-written is left behind).
struct OutputError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// A parameter value is out of its valid range.
struct ParameterError : std::runtime_error {
    using std::runtime_error::runtime_error;
};

}  // namespace cs

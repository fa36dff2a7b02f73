// Every failure a user can be told about, as one small hierarchy of exceptions, and the process
// exit codes they map to (documented in README "Exit codes"). The library throws these and
// returns only results; the command line (cli/exit_code.cpp, `exit_code_for`) is the one place that
// turns them into a message on stderr and an exit code.
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

// The base of every error below: `what()` is a complete sentence for the user (what is wrong, with
// which file or flag, and what to do).
struct Error : std::runtime_error {
    using std::runtime_error::runtime_error;
};

// The command line itself is incomplete (e.g. no input given). Exit 2.
struct UsageError : Error {
    using Error::Error;
};

// A parameter value is out of its valid range, or a flag or config value cannot be used. Exit 2.
struct ParameterError : Error {
    using Error::Error;
};

// The input mesh cannot be used. `what()` names the file, the problem and what to do. Exit 3.
struct InputError : Error {
    using Error::Error;
};

// An output file could not be written (nothing half-written is left behind). Exit 6.
struct OutputError : Error {
    using Error::Error;
};

// An external program (OpenSCAD) is missing or failed. Exit 5.
struct ExternalToolError : Error {
    ExternalToolError(const std::string& what, std::string tool_log = "") : Error(what), log(std::move(tool_log)) {}
    std::string log;  // what the program printed (noise removed), shown after the message; may be empty
};

}  // namespace cs

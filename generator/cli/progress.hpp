// What a command prints while it works: warnings, and the stages of a run that grows supports as
// they start. Everything goes to stderr, so stdout holds only the summary or the report JSON.
//
// Example:
//   warn("--compare prusa: PrusaSlicer is not installed");  // "clever-support: warning: --compare ..."
//   Result r = run_showing_progress(job, RunOptions{});     // "  [ 70%] tree..." on a terminal
#pragma once

#include <string>

#include "job/job.hpp"
#include "job/result.hpp"

namespace cs {

// How a run that grows supports (generate, regrow) talks and what it does after writing.
struct RunOptions {
    bool render = false, preview = false, quiet = false, verbose = false, as_json = false;
    int threads = 0;  // 0: all cores
};

// "clever-support: warning: <w>" on stderr.
void warn(const std::string& w);

// run_job with the stages shown as they start: every one with -v, a one-line progress on a
// terminal, nothing when stderr is a pipe or a file. `o.threads` limits the worker threads for
// this run only.
Result run_showing_progress(const Job& job, const RunOptions& o);

}  // namespace cs

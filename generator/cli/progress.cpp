#include "cli/progress.hpp"

#include <unistd.h>

#include <cstdio>
#include <optional>
#include <tbb/global_control.h>

#include "pipeline/pipeline.hpp"

namespace cs {

void warn(const std::string& w) { std::fprintf(stderr, "clever-support: warning: %s\n", w.c_str()); }

Result run_showing_progress(const Job& job, const RunOptions& o) {
    const int total_stages = static_cast<int>(job_stages(job).size());
    int stage_no = 0;
    auto progress = [&](const std::string& stage) {
        int pct = 100 * stage_no++ / total_stages;
        if (o.verbose) std::fprintf(stderr, "  [%3d%%] %s...\n", pct, stage.c_str());
        else if (!o.quiet && isatty(2)) std::fprintf(stderr, "\r\033[K  [%3d%%] %s...", pct, stage.c_str());
    };
    // Scoped to the run: the library itself keeps no global state.
    std::optional<tbb::global_control> limit;
    if (o.threads > 0) limit.emplace(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(o.threads));
    Result r = run_job(job, progress);
    if (!o.quiet && !o.verbose && isatty(2)) std::fprintf(stderr, "\r\033[K");
    return r;
}

}  // namespace cs

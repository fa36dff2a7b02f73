"""The open issues' targets, as the benchmarks report against them (never tuned to). One home for
each number; run_bench.py and handoff.py take them from here.

Each target is (median limit, each model's limit); None where the issue sets none.
"""

NO_TARGET = (None, None)  # a ratio the reports give without a target

# Issue 32, minutes on mechanical parts: our support time over the better of the slicer's own
# (Cura normal/tree; PrusaSlicer snug), per set of models.
SUPPORT_TIME = (0.7, 1.0)
# Issue 32: our support filament over Cura's better support, and over snug.
SUPPORT_FILAMENT_CURA = (0.5, None)
SUPPORT_FILAMENT_SNUG = (0.35, None)
# Issue 29: generation (orientation search included) this many times faster than Cura tree's CPU
# overhead (tree support - no support) on the benchmark set.
GENERATION_SPEEDUP = (30.0, 10.0)
# Issue 29: a 5M-triangle scan generated in under this many seconds (wall) and GiB (peak RSS).
SCAN_5M_SECONDS, SCAN_5M_GIB = 60.0, 4.0

#!/usr/bin/env bash
# Installs what is missing, builds, and runs every test (unit, end to end, rendering, bad input),
# then the same suite again built with AddressSanitizer + UndefinedBehaviorSanitizer
# (scripts/test-sanitize.sh; about 12 minutes from scratch on 2 cores, seconds when built).
# Tests that need ../shared/models, OpenSCAD or a slicer skip with a message when those are absent;
# with CI=true (as CI sets it) such a test fails instead, so a green CI means the suite ran.
# Then every fuzz target for 30 s (scripts/fuzz.sh). CS_SANITIZE=0 scripts/test.sh skips the
# sanitizer pass and CS_FUZZ_SECONDS=0 the fuzzing (a quicker local loop; CI always runs both).
# Extra arguments go to ctest in both passes (e.g. -R Orient).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
jobs=$(nproc 2>/dev/null || echo 2)
(cd build && ctest --output-on-failure -j"$jobs" "$@")
# As root, files with no read permission can still be read and read-only folders written, so the
# tests of those errors skip themselves. Run them again as an unprivileged user (nobody).
as_nobody="setpriv --reuid=nobody --regid=nogroup --clear-groups --reset-env"
if [ "$(id -u)" = 0 ] && [ $# = 0 ] && ! $as_nobody test -x "$PWD/build/generator/clever-support"; then
  echo "== permission tests NOT rerun as nobody: $PWD is not reachable for that user (clone into a world-readable folder)"
elif [ "$(id -u)" = 0 ] && [ $# = 0 ]; then
  echo "== permission tests as an unprivileged user (nobody)"
  filter='BadCorpus.UnreadableFile:MeshIoErrors.UnreadableFile:Cli.ReadOnlyOutputDirectoryFailsWithExitSix:MeshIoWrite.WriteFileAtomicToDevFullThrowsOutputError'
  # --fail-on-skip semantics: a test that skips as nobody did not prove anything.
  out=$(cd /tmp && $as_nobody "$OLDPWD/build/tests/unit_tests" --gtest_filter="$filter" 2>&1) || { echo "$out"; exit 1; }
  echo "$out" | tail -n 3
  if echo "$out" | grep -q "SKIPPED"; then echo "$out"; echo "a permission test skipped as nobody"; exit 1; fi
fi
# Every fuzz target is built (clang, build-fuzz/) and run for a short budget on its seed corpus, so
# a fuzz build that breaks, or a finding, fails the run (the corpora are also replayed above, by
# FuzzCorpus in unit_tests). CS_FUZZ_SECONDS=0 skips it (a quicker local loop; CI always runs it).
fuzz_seconds=${CS_FUZZ_SECONDS:-30}
if [ "$fuzz_seconds" != 0 ] && [ $# = 0 ]; then
    echo "== fuzz targets, ${fuzz_seconds}s each"
    # A fixed seed and run count, so CI's verdict is the same on every run of the same commit (the
    # seconds stay as a cap on a slow machine, which then runs a prefix of the same inputs). For
    # exploration run scripts/fuzz.sh by hand: it draws a new seed each time.
    FUZZ_JOBS=${FUZZ_JOBS:-$jobs} FUZZ_FLAGS="${FUZZ_FLAGS:--seed=1 -runs=50000}" scripts/fuzz.sh "$fuzz_seconds"
fi
if [ "${CS_SANITIZE:-1}" != 0 ]; then
    echo "== the same suite under AddressSanitizer + UndefinedBehaviorSanitizer"
    scripts/test-sanitize.sh "$@"
fi

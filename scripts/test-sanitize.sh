#!/usr/bin/env bash
# Builds with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/ (RelWithDebInfo) and
# runs the unit tests there (the end-to-end suites SharedModel, Example, Render and Determinism
# are left out: too slow under the sanitizers). Any sanitizer report aborts the test it occurs in,
# which fails it. Extra arguments go to ctest (e.g. -R Repair, --repeat until-fail:3).
# From scratch on 2 cores: about 12 minutes (configure 1 s, build ~11 min, tests ~30 s); it prints
# its own timing at the end.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
start=$(date +%s)

cmake -S . -B build-asan -DCS_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
configured=$(date +%s)
# Only what the unit tests need: the library, the CLI (test_cli runs it) and unit_tests.
cmake --build build-asan -j"$jobs" --target unit_tests
built=$(date +%s)

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# e2e_tests is not built, so its discovery placeholder (e2e_tests_NOT_BUILT) is excluded as well.
status=0
(cd build-asan && ctest --output-on-failure -j"$jobs" \
    -E '^([A-Za-z0-9_]+/)?(SharedModel|Example|Render|Determinism)\.|_NOT_BUILT' "$@") || status=$?
done_=$(date +%s)
echo "test-sanitize: configure $((configured - start))s, build $((built - configured))s, tests $((done_ - built))s, total $((done_ - start))s"
exit "$status"

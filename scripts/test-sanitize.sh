#!/usr/bin/env bash
# Builds everything with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/
# (RelWithDebInfo) and runs the whole test suite there: unit, end to end, rendering, bad input.
# Any sanitizer report aborts the test it occurs in, which fails it. Extra arguments go to ctest
# (e.g. -R Repair, --repeat until-fail:3). scripts/test.sh runs this after the normal suite.
# Measured on this 2-core machine: build from scratch about 11 minutes, tests about 40 s.
set -euo pipefail
cd "$(dirname "$0")/.."
jobs=$(nproc 2>/dev/null || echo 2)
start=$(date +%s)

cmake -S . -B build-asan -DCS_SANITIZE=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
configured=$(date +%s)
cmake --build build-asan -j"$jobs"
built=$(date +%s)

export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
status=0
# The Menger sponge's two end-to-end runs take minutes each under the sanitizers and exercise no
# code the other eleven shared models do not: the plain pass runs them, this one leaves them out
# (unless arguments choose the tests).
if [ $# = 0 ]; then set -- -E 'SharedModel.*menger_sponge3'; fi
(cd build-asan && ctest --output-on-failure -j"$jobs" "$@") || status=$?
done_=$(date +%s)
echo "test-sanitize: configure $((configured - start))s, build $((built - configured))s, tests $((done_ - built))s, total $((done_ - start))s"
exit "$status"

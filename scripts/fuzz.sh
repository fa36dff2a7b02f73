#!/usr/bin/env bash
# Fuzzes the mesh readers (+ repair) with libFuzzer: scripts/fuzz.sh [SECONDS_PER_TARGET=60]
#
# Configures build-fuzz/ with clang (-DCS_FUZZ=ON -DCS_TESTS=OFF), builds fuzz_stl, fuzz_obj,
# fuzz_off, fuzz_ply and fuzz_3mf, and runs each for SECONDS_PER_TARGET on a copy of its seed corpus
# tests/data/fuzz/<format>/ (new corpus entries stay in build-fuzz/run/<format>/corpus, out of the
# repository). Reproducers of crashes, timeouts, out-of-memory and leaks are copied into
# tests/data/fuzz/<format>/ as <kind>-<sha1> (crash-, timeout-, oom-, leak-), where
# tests/unit/test_fuzz_replay.cpp replays them in every test run. fuzz/<format>.dict, when present,
# is passed as the libFuzzer dictionary.
#
# Reproducers already in tests/data/fuzz/ are re-checked first: those that still fail are reported
# (and kept out of the fuzzing corpus, so they don't stop the run at once); fixed ones are seeds.
#
# Exits 1 if any target found something (new or still failing), 0 otherwise.
# Environment: FUZZ_JOBS=N runs N targets at once (default 1); FUZZ_FORMATS="stl ply" limits the
# formats; extra libFuzzer flags can be given in FUZZ_FLAGS.
set -euo pipefail
cd "$(dirname "$0")/.."
root=$(pwd)
seconds=${1:-60}
formats=${FUZZ_FORMATS:-"stl obj off ply 3mf"}
parallel=${FUZZ_JOBS:-1}
jobs=$(nproc 2>/dev/null || echo 2)
limits=(-max_len=65536 -timeout=10 -rss_limit_mb=2048)

echo "== configuring and building build-fuzz/ (clang, CS_FUZZ=ON)"
CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCS_FUZZ=ON -DCS_TESTS=OFF >/dev/null
targets=()
for f in $formats; do targets+=("fuzz_$f"); done
cmake --build build-fuzz -j"$jobs" --target "${targets[@]}"

# Runs one format; writes its summary to build-fuzz/run/<format>/summary and returns 1 on findings.
fuzz_one() {
    local f=$1
    local bin=$root/build-fuzz/fuzz/fuzz_$f seeds=$root/tests/data/fuzz/$f run=$root/build-fuzz/run/$f
    rm -rf "$run"
    mkdir -p "$run/corpus" "$run/artifacts"
    local found=0 summary=$run/summary
    : >"$summary"

    # Known reproducers: still failing -> report and keep out of the corpus; fixed -> seed.
    for old in "$seeds"/crash-* "$seeds"/timeout-* "$seeds"/oom-* "$seeds"/leak-*; do
        [ -e "$old" ] || continue
        if "$bin" "${limits[@]}" "$old" >"$run/recheck-$(basename "$old").log" 2>&1; then
            cp "$old" "$run/corpus/"
        else
            echo "$f: STILL FAILS: tests/data/fuzz/$f/$(basename "$old") (log: build-fuzz/run/$f/recheck-$(basename "$old").log)" >>"$summary"
            found=1
        fi
    done
    for s in "$seeds"/*; do
        case $(basename "$s") in crash-* | timeout-* | oom-* | leak-*) continue ;; esac
        cp "$s" "$run/corpus/"
    done

    local dict=()
    [ -f "$root/fuzz/$f.dict" ] && dict=(-dict="$root/fuzz/$f.dict")
    # shellcheck disable=SC2086  # FUZZ_FLAGS is a list of flags
    "$bin" "${limits[@]}" "${dict[@]}" -max_total_time="$seconds" -print_final_stats=1 \
        -artifact_prefix="$run/artifacts/" ${FUZZ_FLAGS:-} "$run/corpus" >"$run/fuzz.log" 2>&1 || true

    local stats
    stats=$(grep -E '^#[0-9]+.*(DONE|pulse|NEW|REDUCE|INITED)' "$run/fuzz.log" | tail -1 || true)
    echo "$f: last status: ${stats:-none}" >>"$summary"
    grep -E '^stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb)' "$run/fuzz.log" |
        sed "s/^/$f: /" >>"$summary" || true

    for a in "$run"/artifacts/*; do
        [ -e "$a" ] || continue
        local base kind sha
        base=$(basename "$a")
        case $base in
            crash-* | timeout-* | oom-* | leak-*) kind=${base%%-*} ;;
            *) continue ;;  # slow-unit-* and the like are not failures
        esac
        sha=$(sha1sum "$a" | cut -d' ' -f1)
        cp "$a" "$seeds/$kind-$sha"
        echo "$f: NEW $kind: tests/data/fuzz/$f/$kind-$sha ($(stat -c %s "$a") bytes; log: build-fuzz/run/$f/fuzz.log)" >>"$summary"
        found=1
    done
    if [ "$found" = 0 ] && ! grep -q '^Done [0-9]* runs' "$run/fuzz.log"; then
        echo "$f: the fuzzer did not finish normally (see build-fuzz/run/$f/fuzz.log)" >>"$summary"
        found=1
    fi
    return "$found"
}

echo "== fuzzing $formats for ${seconds}s each ($parallel at a time)"
status=0
pids=()
for f in $formats; do
    fuzz_one "$f" &
    pids+=("$!")
    if [ "${#pids[@]}" -ge "$parallel" ]; then
        wait "${pids[0]}" || status=1
        pids=("${pids[@]:1}")
    fi
done
for p in "${pids[@]}"; do wait "$p" || status=1; done

echo "== results"
for f in $formats; do cat "build-fuzz/run/$f/summary"; done
if [ "$status" != 0 ]; then
    echo "fuzz: FINDINGS (reproducers are in tests/data/fuzz/<format>/; replay one with build-fuzz/fuzz/fuzz_<format> FILE)"
else
    echo "fuzz: nothing found"
fi
exit "$status"

#!/usr/bin/env bash
# Supports for every OpenSCAD part in a folder, checked: the CI step of a parts library.
#
#   supports.sh [PARTS_DIR=.] [OUT_DIR=supports-out]
#
# For each PARTS_DIR/*.scad (not the clever_support.scad library, not the parts the config skips):
#   clever-support PART [-D ...] [parameters] --out OUT_DIR/<part> --render [--preview]
#   clever-support check --model <part>.model.stl --supports <part>.supports.stl [parameters]
# and keeps everything in OUT_DIR/<part>/: <part>.3mf (Cura), <part>.prusa.3mf (PrusaSlicer),
# <part>.supported.stl, <part>.union.stl (OpenSCAD's union of part and supports), the pictures
# <part>-front/back/side.png, <part>.scad, <part>.report.json, and check.txt (check's verdict).
# OUT_DIR/summary.txt lists every part's result. Exits 1 when any part fails to generate, render
# or pass check (every part is still tried), 2 on a bad command line or config.
#
# Config: PARTS_DIR/supports.conf (or $SUPPORTS_CONF), one line per part, "#" starts a comment:
#   *              --preset prusa-mk4-pla          parameters for every part
#   bracket.scad   -D width=30 -D holes=2          OpenSCAD values (-D) and parameters for one part
#   library.scad   skip                            not a part (modules only)
# Arguments are split at spaces (a string value is written -D label="abc", without spaces).
# "-D name=value" pairs go to OpenSCAD when the part is rendered. --fit, --scale, --orient,
# --block and --support-point (each with its value) shape the job and go to the generator only.
# Every other argument is a clever-support parameter (--preset, --config FILE, --critical-angle,
# --gap ..., see clever-support --help) and is given to check too, so check judges the supports by
# the rules they were made for.
#
# Environment: CLEVER_SUPPORT (the command, default clever-support on PATH), PREVIEW=0 (no
# pictures: they need Debian's openscad and xvfb), SUPPORTS_CONF (another config file).
set -uo pipefail

parts_dir=${1:-.}
out_dir=${2:-supports-out}
tool=${CLEVER_SUPPORT:-clever-support}
conf=${SUPPORTS_CONF:-$parts_dir/supports.conf}
preview=${PREVIEW:-1}

die() { echo "supports.sh: $*" >&2; exit 2; }
[ -d "$parts_dir" ] || die "$parts_dir is not a folder (usage: supports.sh [PARTS_DIR] [OUT_DIR])"
command -v "$tool" >/dev/null || die "$tool not found: install clever-support (the .deb, or cmake --install) or set CLEVER_SUPPORT"

# The config's lines, by part name ("*" for every part).
declare -A conf_args=()
if [ -f "$conf" ]; then
    line_no=0
    while IFS= read -r line || [ -n "$line" ]; do
        line_no=$((line_no + 1))
        line=${line%%#*}
        read -r name rest <<<"$line" || true
        [ -n "${name:-}" ] || continue
        [ "$name" = "*" ] || [ -f "$parts_dir/$name" ] ||
            die "$conf line $line_no: there is no part $parts_dir/$name"
        conf_args[$name]="${conf_args[$name]:-} $rest"
    done <"$conf"
fi

mkdir -p "$out_dir" || die "cannot make $out_dir"
summary=$out_dir/summary.txt
: >"$summary"
failed=0
parts=0
shopt -s nullglob
for scad in "$parts_dir"/*.scad; do
    file=$(basename "$scad")
    name=${file%.scad}
    [ "$file" = clever_support.scad ] && continue
    read -r -a args <<<"${conf_args["*"]:-} ${conf_args[$file]:-}"
    if [ "${args[0]:-}" = skip ] || [[ " ${args[*]} " == *" skip "* ]]; then
        echo "$file: skipped (supports.conf)" | tee -a "$summary"
        continue
    fi
    parts=$((parts + 1))
    # -D pairs are OpenSCAD's, the job's options the generator's; the rest are parameters for the
    # generator and for check alike.
    defines=() job=() params=()
    for ((i = 0; i < ${#args[@]}; i++)); do
        case ${args[i]} in
            -D) defines+=(-D "${args[i + 1]:-}"); i=$((i + 1)) ;;
            --fit | --scale | --orient | --block | --support-point) job+=("${args[i]}" "${args[i + 1]:-}"); i=$((i + 1)) ;;
            --no-self-intersection-check) job+=("${args[i]}") ;;
            *) params+=("${args[i]}") ;;
        esac
    done
    dir=$out_dir/$name
    extras=(--render)
    [ "$preview" = 0 ] || extras+=(--preview)
    echo "== $file"
    if ! "$tool" "$scad" "${defines[@]}" "${job[@]}" "${params[@]}" --out "$dir" "${extras[@]}"; then
        echo "$file: FAILED to generate or render (see the log above)" | tee -a "$summary"
        failed=1
        continue
    fi
    if "$tool" check --model "$dir/$name.model.stl" --supports "$dir/$name.supports.stl" "${params[@]}" >"$dir/check.txt" 2>&1; then
        echo "$file: ok (supports, union, check passed)" | tee -a "$summary"
    else
        cat "$dir/check.txt"
        echo "$file: CHECK FAILED (see $dir/check.txt)" | tee -a "$summary"
        failed=1
    fi
done
[ "$parts" -gt 0 ] || die "no .scad part in $parts_dir"
echo "== $parts parts, outputs in $out_dir/ (summary: $summary)"
exit "$failed"

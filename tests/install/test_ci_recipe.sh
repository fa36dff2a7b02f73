#!/usr/bin/env bash
# The CI recipe (examples/ci/supports.sh) as a project's CI runs it: from the INSTALLED tool
# (cmake --install, moved elsewhere, source and build trees hidden), on a copy of examples/models
# with its supports.conf. Every part gets supports, a union, pictures and a passing check; the
# summary says so. Then the failure path: when check fails the script exits 1 and says which part.
#   tests/install/test_ci_recipe.sh BUILD_DIR SOURCE_DIR      (ctest: install.ci_recipe)
source "$(dirname "$0")/lib.sh"
build=$1 source_dir=$2
install_moved "$build" "$source_dir"
script=$prefix/share/clever-support/ci/supports.sh
[ -x "$script" ] || fail "the CI script is not installed as an executable: $script"
command -v openscad >/dev/null && command -v xvfb-run >/dev/null ||
    skip "the pictures need openscad and xvfb-run (scripts/install-deps.sh installs them)"

mkdir -p "$tmp/project"
cp "$source_dir"/examples/models/*.scad "$source_dir"/examples/models/supports.conf "$tmp/project/"
cd "$tmp/project"
parts=$(ls *.scad | wc -l)

hidden env -u CLEVER_SUPPORT_OPENSCAD PATH="$prefix/bin:/usr/bin:/bin" "$script" . out >"$tmp/ci.log" 2>&1 ||
    { cat "$tmp/ci.log"; fail "supports.sh failed on examples/models"; }
[ "$(grep -c ': ok (supports, union, check passed)' out/summary.txt)" = "$parts" ] ||
    { cat out/summary.txt; fail "not every one of the $parts parts passed"; }
for scad in *.scad; do
    n=${scad%.scad}
    for f in "$n.union.stl" "$n.3mf" "$n.prusa.3mf" "$n.supported.stl" "$n-front.png" check.txt; do
        [ -s "out/$n/$f" ] || fail "missing artifact out/$n/$f"
    done
done
# supports.conf gives the arches a -D value: it reached OpenSCAD.
grep -q 'span_wide=18' out/arches/arches.report.json || fail "the -D value of supports.conf did not reach the arches"

# A check that fails fails the job: a tool whose check always finds a failure (exit 4).
cat >"$tmp/failing-check" <<WRAP
#!/usr/bin/env bash
if [ "\$1" = check ]; then echo "coverage: FAILED at (1, 2, 3)"; exit 4; fi
exec "$prefix/bin/clever-support" "\$@"
WRAP
chmod +x "$tmp/failing-check"
mkdir -p one && cp arches.scad one/
status=0
hidden env -u CLEVER_SUPPORT_OPENSCAD PREVIEW=0 CLEVER_SUPPORT="$tmp/failing-check" PATH=/usr/bin:/bin \
    "$script" one out-fail >"$tmp/fail.log" 2>&1 || status=$?
[ "$status" = 1 ] || { cat "$tmp/fail.log"; fail "a failing check gave exit $status, not 1"; }
grep -q 'arches.scad: CHECK FAILED' out-fail/summary.txt || { cat out-fail/summary.txt; fail "the summary does not name the failing part"; }
echo "ok: the installed CI script supported, rendered and checked all $parts example parts; a failing check fails it"

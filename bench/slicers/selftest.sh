#!/usr/bin/env bash
# Self-check of the slicing harness (bench/slicers).  Needs CuraEngine, prusa-slicer,
# /usr/bin/python3 and the Cura definitions (fetched by fetch_cura_defs.sh if absent).
#
# Slices:
#   * a 20 mm cube (made here) with both slicers, no support: must be within 15% of the
#     analytic volume for 2 walls, 4+4 top/bottom layers and 20% infill (3.74 g of PLA);
#   * /work/shared/models/bridge.stl (40 mm deck at z=5 over two pillars, 50x10x8 mm) with
#     Cura none/normal/tree and PrusaSlicer none/grid: grams > 0, time > 0, and with support
#     >= without (grams and time);
#   * bridge.stl + a filler block (the space under the deck) given as TWO STLs: they are merged
#     into one mesh and must slice like a solid 50x10x8 box (pitfall 5), in both slicers;
#   * gcode_time.py: its replay of every G-code above within 3 % of the slicer's own estimate, and
#     its terms on a hand-made G-code;
#   * measured_run.py's own self-check (exit codes, a grandchild's CPU, a timeout), and
#     gcode_layer.py's count of a hand-made layer.
# Prints the numbers, then "N passed, N failed"; exits 1 if any check failed.
set -uo pipefail

HERE="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
PY=/usr/bin/python3
export PYTHONDONTWRITEBYTECODE=1
MODELS="${CLEVER_MODELS_DIR:-$HERE/../../../shared/models}"
[[ -f "$MODELS/bridge.stl" ]] || MODELS=/work/shared/models
BRIDGE="$MODELS/bridge.stl"
WORK="$(mktemp -d "${TMPDIR:-/tmp}/clever-selftest.XXXXXX")"
trap 'rm -rf "$WORK"' EXIT

"$HERE/fetch_cura_defs.sh" >/dev/null || { echo "cannot obtain the Cura definitions"; exit 1; }
[[ -f "$BRIDGE" ]] || { echo "missing $BRIDGE"; exit 1; }

# Test meshes: 20 mm cube, filler block under the bridge deck, solid 50x10x8 box.
"$PY" - "$WORK" "$HERE" <<'EOF'
import sys
sys.path.insert(0, sys.argv[2])
import slice as s
work = sys.argv[1]
def box(x0, y0, z0, x1, y1, z1):
    v = [(x0,y0,z0),(x1,y0,z0),(x1,y1,z0),(x0,y1,z0),(x0,y0,z1),(x1,y0,z1),(x1,y1,z1),(x0,y1,z1)]
    f = [(0,2,1),(0,3,2),(4,5,6),(4,6,7),(0,1,5),(0,5,4),(1,2,6),(1,6,5),(2,3,7),(2,7,6),(3,0,4),(3,4,7)]
    return [tuple(v[i] for i in t) for t in f]
s.write_stl(work + "/cube20.stl", box(0, 0, 0, 20, 20, 20))
# bridge.stl: pillars x 75..80 and 120..125, deck z 5..8, y 84.5..94.5
s.write_stl(work + "/filler.stl", box(80, 84.5, 0, 120, 94.5, 5))
s.write_stl(work + "/solid_box.stl", box(75, 84.5, 0, 125, 94.5, 8))
EOF

run() {  # name slicer support files...
  local name="$1" slicer="$2" support="$3"; shift 3
  if ! "$PY" "$HERE/slice.py" --slicer "$slicer" --support "$support" --json \
       --out-dir "$WORK/$name" "$@" > "$WORK/$name.json" 2> "$WORK/$name.err"; then
    echo "FAILED to slice $name:"; tail -20 "$WORK/$name.err"
    echo '{}' > "$WORK/$name.json"
  fi
}

run cube_cura    cura  none   "$WORK/cube20.stl"
run cube_prusa   prusa none   "$WORK/cube20.stl"
run bridge_cura_none    cura  none   "$BRIDGE"
run bridge_cura_normal  cura  normal "$BRIDGE"
run bridge_cura_tree    cura  tree   "$BRIDGE"
run bridge_prusa_none   prusa none   "$BRIDGE"
run bridge_prusa_grid   prusa grid   "$BRIDGE"
run bridge_prusa_snug   prusa snug   "$BRIDGE"
run mesh_cura     cura  mesh --support-mesh "$WORK/filler.stl" "$BRIDGE"
run merged_cura   cura  none "$BRIDGE" "$WORK/filler.stl"
run box_cura      cura  none "$WORK/solid_box.stl"
run merged_prusa  prusa none "$BRIDGE" "$WORK/filler.stl"
run box_prusa     prusa none "$WORK/solid_box.stl"

"$PY" - "$WORK" "$HERE" <<'EOF'
import json, sys, os
work = sys.argv[1]
def load(n):
    with open(os.path.join(work, n + ".json")) as f:
        return json.load(f)
R = {n: load(n) for n in ["cube_cura", "cube_prusa", "bridge_cura_none", "bridge_cura_normal",
                          "bridge_cura_tree", "bridge_prusa_none", "bridge_prusa_grid", "bridge_prusa_snug",
                          "merged_cura", "box_cura", "merged_prusa", "box_prusa", "mesh_cura"]}
print("%-20s %8s %8s %10s %9s" % ("run", "grams", "minutes", "mm3", "slice_s"))
for n, r in R.items():
    if r:
        print("%-20s %8.3f %8.1f %10.1f %9.3f" % (n, r["grams"], r["print_time_s"] / 60,
                                                 r["filament_mm3"], r["slice_seconds"]))
    else:
        print("%-20s   (failed)" % n)
passed = failed = 0
def check(ok, what):
    global passed, failed
    print(("PASS  " if ok else "FAIL  ") + what)
    if ok: passed += 1
    else: failed += 1
def g(n, k):
    return R[n].get(k, float("nan"))
# Analytic 20 mm cube: 2 walls of 0.4 (outer 20x20, inner 18.4x18.4), 4+4 layers of 0.2 mm,
# 20% infill in the 18.4 x 18.4 x 18.4 core.
core = 18.4 * 18.4
cube_mm3 = (400 - core) * 20 + 8 * 0.2 * core + 0.20 * core * 18.4
cube_g = cube_mm3 * 1.24e-3
for n in ("cube_cura", "cube_prusa"):
    check(abs(g(n, "grams") - cube_g) <= 0.15 * cube_g,
          "%s: %.2f g within 15%% of the analytic %.2f g" % (n, g(n, "grams"), cube_g))
    check(g(n, "print_time_s") > 0, "%s: print time > 0" % n)
sys.path.insert(0, sys.argv[2])
import gcode_stats
G = {n: gcode_stats.parse(os.path.join(work, n, "out.gcode")) if R[n] else {} for n in R}
for n in [k for k in R if k.startswith("bridge_")]:
    check(g(n, "grams") > 0 and g(n, "print_time_s") > 0 and g(n, "filament_mm3") > 0,
          "%s: grams, time, volume > 0" % n)
for base, sup in (("bridge_cura_none", "bridge_cura_normal"), ("bridge_cura_none", "bridge_cura_tree"),
                  ("bridge_prusa_none", "bridge_prusa_grid"), ("bridge_prusa_none", "bridge_prusa_snug")):
    check(g(sup, "grams") >= g(base, "grams") and g(sup, "print_time_s") >= g(base, "print_time_s"),
          "%s >= %s (%.3f g >= %.3f g, %.1f >= %.1f min)" % (sup, base, g(sup, "grams"), g(base, "grams"),
                                                           g(sup, "print_time_s") / 60, g(base, "print_time_s") / 60))
    # the support must be a real amount, not noise: the space under the deck is ~2000 mm3
    check(g(sup, "filament_mm3") - g(base, "filament_mm3") > 100,
          "%s adds > 100 mm3 of support (+%.0f mm3)" % (sup, g(sup, "filament_mm3") - g(base, "filament_mm3")))
for m, b in (("merged_cura", "box_cura"), ("merged_prusa", "box_prusa")):
    check(abs(g(m, "filament_mm3") - g(b, "filament_mm3")) <= 0.02 * g(b, "filament_mm3"),
          "%s (bridge.stl + filler.stl, 2 files) slices like the solid box: %.0f vs %.0f mm3"
          % (m, g(m, "filament_mm3"), g(b, "filament_mm3")))
# A support mesh (--support mesh): the filler block under the deck prints in support sections, as one
# island per layer, and the bridge prints exactly as it does alone.
gm, gn = G["mesh_cura"], G["bridge_cura_none"]
model_mm3 = lambda st: sum(v for k, v in st.get("extruded_mm3_by_type", {}).items() if not gcode_stats.is_support(k))
check(gm.get("support_extruded_mm3", 0) > 100, "mesh_cura: the support mesh prints as support (%.0f mm3 in support sections)"
      % gm.get("support_extruded_mm3", 0))
check(abs(model_mm3(gm) - model_mm3(gn)) <= 0.01 * model_mm3(gn),
      "mesh_cura: the model prints as alone (%.0f vs %.0f mm3)" % (model_mm3(gm), model_mm3(gn)))
check(gm.get("support_islands_max_per_layer") == 1, "mesh_cura: one support island per layer (max %s)"
      % gm.get("support_islands_max_per_layer"))
check(gn.get("support_islands") == 0 and G["bridge_cura_tree"].get("support_islands", 0) > 0,
      "gcode_stats: no support islands without support, some with Cura tree (%s)" % G["bridge_cura_tree"].get("support_islands"))
# support_to_support_retractions on a hand-made G-code: support -> retract -> support counts; support ->
# retract -> wall, a support -> support travel without retraction, and wall -> retract -> support do not.
synthetic = os.path.join(work, "s2s.gcode")
with open(synthetic, "w") as f:
    f.write("M82\n;LAYER:0\n;TYPE:SUPPORT\nG0 X0 Y0\nG1 X1 Y0 E1\nG1 E0\nG0 X10 Y0\nG1 E1\nG1 X11 Y0 E2\n"
            "G0 X20 Y0\nG1 X21 Y0 E3\nG1 E2\n;TYPE:WALL-OUTER\nG0 X30 Y0\nG1 E3\nG1 X31 Y0 E4\nG1 E3\n"
            ";TYPE:SUPPORT\nG0 X40 Y0\nG1 E4\nG1 X41 Y0 E5\n")
st = gcode_stats.parse(synthetic)
check(st["retractions"] == 3 and st["support_to_support_retractions"] == 1,
      "gcode_stats: 1 of 3 retractions is support -> support (%s of %s)"
      % (st["support_to_support_retractions"], st["retractions"]))
# gcode_time: the replay of the moves gives each slicer's own estimate back (within 3 %), and a hand-made
# G-code's terms match the trapezoid worked out by hand.
import gcode_time
for n in R:
    if R[n]:
        t = gcode_time.split(os.path.join(work, n, "out.gcode"), R[n]["print_time_s"])
        check(abs(t["residual_s"]) <= 0.03 * t["slicer_s"],
              "gcode_time %s: replay %.0f s against the slicer's %.0f s" % (n, t["sim_s"], t["slicer_s"]))
hand = os.path.join(work, "time.gcode")
with open(hand, "w") as f:  # 100 mm of extrusion at 60 mm/s from rest, a 2 mm retraction at 25 mm/s, a 10 mm travel
    f.write(";FLAVOR:Marlin\nM82\n;LAYER:0\nG0 X0 Y0\nG1 F3600 X100 Y0 E5\nG1 F1500 E3\nG0 F7200 X100 Y10\n")
t = gcode_time.split(hand)
a, v0, vmin = 1500.0, 5.0, gcode_time.MIN_PLANNER_SPEED  # from rest: half the 10 mm/s jerk
up, down = (60 ** 2 - v0 ** 2) / (2 * a), (60 ** 2 - v0 ** 2) / (2 * a)  # a corner into a retraction: jerk again
expect = (60 - v0) / a + (100 - up - down) / 60 + (60 - v0) / a
check(abs(t["extrusion_s"] - 100 / 60) < 1e-9 and abs(t["extrusion_s"] + t["accel_extrusion_s"] - expect) < 0.01,
      "gcode_time: 100 mm at 60 mm/s = %.3f s at feedrate + %.3f s of starting and stopping (by hand %.3f s)"
      % (t["extrusion_s"], t["accel_extrusion_s"], expect - 100 / 60))
check(t["retraction_s"] > 2 / 25 and abs(t["travel_s"] - 10 / 120) < 1e-9,
      "gcode_time: retraction %.3f s (> 2 mm / 25 mm/s), travel %.3f s at feedrate" % (t["retraction_s"], t["travel_s"]))
import subprocess
import gcode_layer
hand = os.path.join(work, "layer.gcode")
with open(hand, "w") as f:  # two lines on one layer, a retraction and a travel between them
    f.write("M82\nG92 E0\nG1 Z0.2 F600\nG1 X10 Y0 E1 F1800\nG1 E0.2\nG1 X20 Y5 F7200\nG1 E1\nG1 X30 Y5 E2 F1800\n")
said = gcode_layer.draw(hand, 0.2, os.path.join(work, "layer.svg"))
check(said.startswith("z = 0.2: 2 paths, 1 travels, 1 retractions") and os.path.getsize(os.path.join(work, "layer.svg")) > 0,
      "gcode_layer: a hand-made layer drawn, " + said)
m = subprocess.run([sys.executable, os.path.join(sys.argv[2], "..", "measured_run.py")],
                   capture_output=True, text=True)
check(m.returncode == 0, "measured_run.py (how the benchmarks count a run's CPU): " + m.stdout.strip())
print("selftest: %d passed, %d failed" % (passed, failed))
sys.exit(1 if failed else 0)
EOF

#!/usr/bin/python3
"""How much of one strut PrusaSlicer 2.5 prints: the ceiling on its sliced / mesh volume.

usage: bench/prusa_bead.py [--bin build/generator/clever-support] [--out bench/results] [--work DIR]

handoff.py's PrusaSlicer sliced/mesh (support filament over our support mesh volume) stays at
0.83-0.88 on every model, with no body layer left out. This asks why, on single vertical struts,
10 mm tall, sliced alone:

* the cross-sections we build: the N-profile (struts) and the solid square (tips, feet, narrow
  struts), drawn by scad_templates/clever_support.scad's cs_prism (OpenSCAD renders them, so the
  geometry is the generator's own, not a copy);
* a closed square tube with the same walls, the closed profile we did not choose;
* each with the settings our .prusa.3mf gives the volume it belongs to: the N-profile struts' or the
  solid bodies' (read from a .prusa.3mf the generator writes for examples/models/bird.stl, so they
  are the generator's own too), under PrusaSlicer's default Arachne perimeter generator and its
  classic one.

PrusaSlicer takes `perimeter_generator` per object only: the user picks it, and the supports
volumes carry the thin_walls that prints them under classic. Output: results/prusa_bead.md and
.json.
"""
import argparse
import datetime
import json
import math
import os
import re
import shutil
import subprocess
import sys
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(HERE, "slicers"))
import slice as S  # noqa: E402

HEIGHT_MM = 10.0
WALL_MM = 0.5      # the generic preset's wall (core/params.cpp)
LAYER_MM = 0.2     # slicers/profile.json
# (profile, widths): what handoff.py's models hold. N struts are at least 3 walls wide
# (rules.cpp min_n_width); tips end at 0.8 (tip_diameter) and widen down to their strut.
CASES = [("N", [1.5, 2.0, 3.0, 4.0]), ("square tube", [1.5, 2.0, 3.0, 4.0]), ("solid", [0.8, 1.0, 1.5])]
GENERATORS = ["arachne", "classic"]


def scad_for(profile, width):
    """OpenSCAD source of one vertical strut, from the template's own cs_prism."""
    top = "[0, 0, %g]" % HEIGHT_MM
    if profile == "N":
        body = "cs_prism([0, 0, 0], %s, %g, %g, true, %g);" % (top, width, width, WALL_MM)
    elif profile == "solid":
        body = "cs_prism([0, 0, 0], %s, %g, %g, false, %g);" % (top, width, width, WALL_MM)
    else:  # the tube: a solid square less one 2 walls narrower, reaching through both ends
        inner = width - 2 * WALL_MM
        body = ("difference() { cs_prism([0, 0, 0], %s, %g, %g, false, 0); "
                "cs_prism([0, 0, -1], [0, 0, %g], %g, %g, false, 0); }" % (top, width, width, HEIGHT_MM + 1, inner, inner))
    return "include <clever_support.scad>\n%s\n" % body


def volume_of(tris):
    v = 0.0
    for a, b, c in tris:
        v += (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
              + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0
    return v


def render(profile, width, work):
    scad = os.path.join(work, "strut.scad")
    stl = os.path.join(work, "strut.stl")
    with open(scad, "w") as f:
        f.write(scad_for(profile, width))
    env = dict(os.environ, OPENSCADPATH=os.path.join(REPO, "scad_templates"))
    subprocess.run(["openscad", "-o", stl, scad], check=True, env=env, capture_output=True, timeout=600)
    tris = S.read_stl(stl)
    placed = [tuple((x + 150.0, y + 150.0, z) for x, y, z in t) for t in tris]  # bed centre
    S.write_stl(stl, placed)
    return stl, volume_of(tris)


def support_volume_settings(binary, work):
    """The settings the generator gives the supports volumes of its .prusa.3mf: {"N": the N-profile
    struts' volume, "solid": the solid bodies' volume (tips, feet, square struts)}."""
    out = os.path.join(work, "bird")
    subprocess.run([binary, os.path.join(REPO, "examples", "models", "bird.stl"), "--out", out, "--no-timings"],
                   check=True, capture_output=True, timeout=600)
    path = os.path.join(out, "bird.prusa.3mf")
    with zipfile.ZipFile(path) as z:
        config = z.read("Metadata/Slic3r_PE_model.config").decode()
    found = {}
    for v in re.findall(r"<volume [^>]*>(.*?)</volume>", config, re.S):
        settings = dict(re.findall(r'key="([a-z_0-9]+)" value="([^"]*)"', v))
        name = settings.get("name", "")
        kind = "solid" if name.endswith("supports, solid") else "N" if name.endswith("supports") else None
        if kind:
            found[kind] = {k: val for k, val in settings.items() if k not in ("name", "volume_type")}
    if set(found) != {"N", "solid"}:
        raise SystemExit("prusa_bead.py: %s has not the two supports volumes (N-profile, solid)" % path)
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--bin", default=os.path.join(REPO, "build", "generator", "clever-support"))
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--work", default=os.path.join(HERE, "work", "prusa_bead"))
    args = ap.parse_args()
    for tool in (args.bin, "openscad", S.PRUSA_BIN):
        if not shutil.which(tool):
            raise SystemExit("prusa_bead.py: %s not found (build with scripts/build.sh; scripts/install-deps.sh "
                             "installs openscad and prusa-slicer)" % tool)
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    with open(os.path.join(HERE, "slicers", "profile.json")) as f:
        profile = json.load(f)
    volume = support_volume_settings(args.bin, args.work)
    rows = []
    for name, widths in CASES:
        for width in widths:
            work = os.path.join(args.work, "%s-%g" % (name.replace(" ", "_"), width))
            os.makedirs(work)
            stl, mesh_mm3 = render(name, width, work)
            row = {"profile": name, "width_mm": width, "mesh_mm3": mesh_mm3}
            for gen in GENERATORS:
                extra = dict(volume["solid" if name == "solid" else "N"], perimeter_generator=gen)
                try:
                    r = S.slice_prusa(stl, "none", profile, work, 600, extra=extra)
                    row[gen] = {"sliced_over_mesh": r["filament_mm3"] / mesh_mm3, "seconds": r["print_time_s"]}
                except S.SliceError as e:  # "the print is empty": the strut vanished
                    row[gen] = {"sliced_over_mesh": 0.0, "seconds": 0.0, "error": str(e).splitlines()[-1]}
            rows.append(row)
            print("%-12s %4.1f  arachne %.3f  classic %.3f" % (name, width, row["arachne"]["sliced_over_mesh"],
                                                             row["classic"]["sliced_over_mesh"]), flush=True)
    stamp = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    commit = subprocess.run(["git", "-C", REPO, "rev-parse", "HEAD"], capture_output=True, text=True).stdout.strip()
    data = {"stamp": stamp, "commit": commit, "volume_settings": volume, "height_mm": HEIGHT_MM, "wall_mm": WALL_MM,
            "rows": rows}
    os.makedirs(args.out, exist_ok=True)
    with open(os.path.join(args.out, "prusa_bead.json"), "w") as f:
        json.dump(data, f, indent=1)
    with open(os.path.join(args.out, "prusa_bead.md"), "w") as f:
        f.write(report_md(data))


def bead_fraction(w, h):
    """PrusaSlicer's extrusion of one bead over w x h (Flow::mm3_per_mm, not a bridge)."""
    return (w - h * (1 - math.pi / 4)) / w


def volume_settings_md(volumes):
    """The two supports volumes' settings in words; runs before 2026-11-26 stored one volume's."""
    if "N" not in volumes:
        return ", ".join("%s=%s" % kv for kv in sorted(volumes.items()))
    return "; ".join("%s: %s" % (title, ", ".join("%s=%s" % kv for kv in sorted(volumes[key].items())))
                     for key, title in (("N", "N-profile struts and tubes"), ("solid", "solid squares")))


def report_md(data):
    s = ["# How much of one strut PrusaSlicer 2.5 prints (bench/prusa_bead.py)", "",
         "_Run %s, git commit `%s`._" % (data["stamp"], data["commit"]), "",
         "One vertical strut, %g mm tall, %g mm walls, sliced alone with the bench profile plus the settings "
         "our .prusa.3mf gives the volume it belongs to (%s). *Sliced/mesh*: filament PrusaSlicer lays down over the "
         "strut's volume; *s*: its print time estimate. Arachne is PrusaSlicer's default and what a user gets; "
         "classic is set per object only: the user's choice." % (
             data["height_mm"], data["wall_mm"], volume_settings_md(data["volume_settings"])),
         "",
         "PrusaSlicer meters a bead of width w and height h as a rounded rectangle, h (w - h (1 - pi/4)) per mm "
         "(its Flow::mm3_per_mm): %.3f of w x h for one %g mm wall at %g mm layers, before the ends of open lines "
         "and the corners. That is the most one bead can reach." % (bead_fraction(data["wall_mm"], LAYER_MM),
                                                                    data["wall_mm"], LAYER_MM),
         "",
         "| profile | width mm | mesh mm³ | Arachne sliced/mesh | Arachne s | classic sliced/mesh | classic s |",
         "|---|---:|---:|---:|---:|---:|---:|"]
    for r in data["rows"]:
        s.append("| %s | %.1f | %.1f | %.3f | %.0f | %.3f | %.0f |" % (
            r["profile"], r["width_mm"], r["mesh_mm3"], r["arachne"]["sliced_over_mesh"], r["arachne"]["seconds"],
            r["classic"]["sliced_over_mesh"], r["classic"]["seconds"]))
    return "\n".join(s) + "\n"


if __name__ == "__main__":
    main()

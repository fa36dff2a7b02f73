#!/usr/bin/python3
"""What our supports cost CuraEngine 4.13 as a support mesh, read from its G-code (issue #11).

usage: tree_shape.py [--json] [--keep DIR] OUTDIR [OUTDIR ...]

Each OUTDIR is a clever-support output directory (<name>.model.stl, <name>.supports.stl,
<name>.report.json). The placed model is sliced alone and with the supports as a second mesh
printed as support (`support_mesh=true`, `support_mesh_drop_down=false`), with the bench profile
(bench/slicers/profile.json) and the support settings of shared/notes/slicer-handoff.md:
support_wall_count=1, support_infill_rate=0, support_join_distance=0. Both meshes keep the
generator's coordinates (centred on the bed by CuraEngine's machine centre).

Per directory it prints what the supports add (with supports minus model alone): print time,
filament, travel, retractions; and from the support sections of the G-code: island-layers (a new
island after more than 1 mm of travel), the most islands in one layer, support extrusion length and
travel between support islands, and island-layers by eighths of the height (bottom first); next to them the generator's own `slicer_estimate` from the report.
Python 3 stdlib only; imports cura_settings.py and slice.py from bench/slicers (unchanged).
"""
import argparse
import json
import math
import os
import re
import shutil
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "slicers"))
sys.dont_write_bytecode = True
import cura_settings  # noqa: E402
import slice as slicer  # noqa: E402

SUPPORT_SETTINGS = {"support_wall_count": 1, "support_infill_rate": 0, "support_join_distance": 0}
NEW_ISLAND_TRAVEL_MM = 1.0  # the handoff note's rule: more travel than this starts a new island


def cura_command(model, supports, glob, ext, defs_dir, gcode):
    cmd = [slicer.CURA_BIN, "slice", "-v", "-j", os.path.join(defs_dir, "fdmprinter.def.json")]
    for k in sorted(glob):
        cmd += ["-s", "%s=%s" % (k, cura_settings.to_engine_string(glob[k]))]
    cmd += ["-e0"]
    for k in sorted(ext):
        cmd += ["-s", "%s=%s" % (k, cura_settings.to_engine_string(ext[k]))]
    # Our outputs are centred on x = y = 0; CuraEngine adds the machine centre to every mesh.
    place = ["-s", "mesh_position_x=0", "-s", "mesh_position_y=0", "-s", "mesh_position_z=0",
             "-s", "center_object=False"]
    cmd += ["-l", model] + place
    if supports:
        cmd += ["-l", supports] + place + ["-s", "support_mesh=true", "-s", "support_mesh_drop_down=false"]
    return cmd + ["-o", gcode]


def slice_once(model, supports, work):
    profile = cura_settings.load_profile(None)
    overrides = cura_settings.cura_overrides(profile, "none")
    overrides.update(SUPPORT_SETTINGS)
    resolver = cura_settings.Resolver()
    glob, ext, report = resolver.resolve(overrides)
    if report["errors"] or report["unknown_overrides"]:
        raise slicer.SliceError("settings did not resolve: %s" % json.dumps(report))
    gcode = os.path.join(work, "out.gcode")
    cmd = cura_command(model, supports, glob, ext, resolver.defs_dir, gcode)
    slicer.write_cmd(os.path.join(work, "cura_cmd.sh"), cmd)
    _, err, _ = slicer.run_slicer(cmd, work, os.path.join(work, "cura"), 3600)
    t = float(re.findall(r"Print time \(s\):\s*([0-9.]+)", err)[-1])
    mm3 = float(re.findall(r"Filament \(mm\^3\):\s*([0-9.]+)", err)[-1])
    res = parse_gcode(gcode)
    res.update({"print_time_s": t, "filament_mm3": mm3})
    return res


def parse_gcode(path):
    """Travel, retractions, and support islands per layer of a CuraEngine G-code."""
    x = y = e = 0.0
    relative_e = False
    in_support = False
    layer = -1
    travel = support_travel = support_extrusion = 0.0
    retractions = 0
    pending = 0.0  # travel since the last extrusion
    islands = {}
    started = False  # an extrusion already made in the current support section
    with open(path) as f:
        for line in f:
            if line.startswith(";"):
                if line.startswith(";LAYER:"):
                    layer = int(line[7:])
                elif line.startswith(";TYPE:"):
                    in_support = line.startswith(";TYPE:SUPPORT")
                    started = False
                continue
            code = line.split(";", 1)[0].split()
            if not code:
                continue
            if code[0] == "M83":
                relative_e = True
            elif code[0] == "M82":
                relative_e = False
            if code[0] == "G92":
                for w in code[1:]:
                    if w[0] == "E":
                        e = float(w[1:])
                continue
            if code[0] not in ("G0", "G1"):
                continue
            nx, ny, ne = x, y, None
            for w in code[1:]:
                if w[0] == "X":
                    nx = float(w[1:])
                elif w[0] == "Y":
                    ny = float(w[1:])
                elif w[0] == "E":
                    ne = float(w[1:])
            d = math.hypot(nx - x, ny - y)
            de = 0.0 if ne is None else (ne if relative_e else ne - e)
            if ne is not None and not relative_e:
                e = ne
            if d > 0 and de <= 0:
                travel += d
                pending += d
                if in_support:
                    support_travel += d
            elif de > 0 and d > 0:
                if in_support:
                    support_extrusion += d
                    if not started or pending > NEW_ISLAND_TRAVEL_MM:
                        islands[layer] = islands.get(layer, 0) + 1
                    started = True
                pending = 0.0
            elif de < 0 and d == 0:
                retractions += 1
            x, y = nx, ny
    layers = layer + 1
    by_eighth = [sum(n for l, n in islands.items() if i * layers // 8 <= l < (i + 1) * layers // 8) for i in range(8)]
    return {"travel_mm": travel, "retractions": retractions, "support_travel_mm": support_travel,
            "support_extrusion_mm": support_extrusion, "island_layers": sum(islands.values()),
            "most_islands": max(islands.values()) if islands else 0, "islands_by_eighth": by_eighth}


def measure(outdir, keep=None, cache={}):
    outdir = os.path.abspath(outdir)
    name = os.path.basename(outdir)
    model = os.path.join(outdir, name + ".model.stl")
    supports = os.path.join(outdir, name + ".supports.stl")
    with open(os.path.join(outdir, name + ".report.json")) as f:
        report = json.load(f)
    work = tempfile.mkdtemp(prefix="tree-shape-")
    try:
        key = open(model, "rb").read()
        if key not in cache:
            os.makedirs(os.path.join(work, "alone"))
            cache[key] = slice_once(model, None, os.path.join(work, "alone"))
        alone = cache[key]
        os.makedirs(os.path.join(work, "with"))
        both = slice_once(model, supports, os.path.join(work, "with"))
        if keep:
            shutil.copytree(work, os.path.join(keep, name + "-" + os.path.basename(os.path.dirname(os.path.abspath(outdir)))),
                            dirs_exist_ok=True)
    finally:
        shutil.rmtree(work, ignore_errors=True)
    ov = report["overhangs"]
    sup = report["supports"]
    return {
        "dir": outdir, "model": name,
        "samples": {k: ov[k] for k in ("samples", "face_samples", "edge_samples", "point_samples", "centroid_samples")},
        "tree": {k: sup[k] for k in ("struts", "merges", "bed_contacts", "model_contacts", "dropped_samples",
                                     "dropped_branches", "strength_violations", "support_volume_mm3")},
        "estimate": sup.get("slicer_estimate"),
        "support_time_s": both["print_time_s"] - alone["print_time_s"],
        "support_filament_mm3": both["filament_mm3"] - alone["filament_mm3"],
        "added_travel_m": (both["travel_mm"] - alone["travel_mm"]) / 1000,
        "added_retractions": both["retractions"] - alone["retractions"],
        "island_layers": both["island_layers"], "most_islands": both["most_islands"],
        "islands_by_eighth": both["islands_by_eighth"],
        "support_extrusion_m": both["support_extrusion_mm"] / 1000,
        "support_travel_m": both["support_travel_mm"] / 1000,
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("outdirs", nargs="+")
    ap.add_argument("--json", action="store_true")
    ap.add_argument("--keep", help="keep G-code and commands under this directory")
    a = ap.parse_args(argv)
    rows = [measure(d, a.keep) for d in a.outdirs]
    if a.json:
        print(json.dumps(rows, indent=1))
        return 0
    print("| run | samples | support time s | filament mm3 | travel +m | retractions + | island-layers | most islands | support lines m | estimate: island-layers, most, travel m, s |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---|")
    for r in rows:
        est = r["estimate"] or {}
        print("| %s | %d | %.0f | %.0f | %.1f | %d | %d | %d | %.1f | %s |" % (
            r["dir"], r["samples"]["samples"], r["support_time_s"], r["support_filament_mm3"], r["added_travel_m"],
            r["added_retractions"], r["island_layers"], r["most_islands"], r["support_extrusion_m"],
            "%.0f, %d, %.1f, %.0f" % (est["island_layers"], est["most_islands"], est["travel_mm"] / 1000, est["seconds"])
            if est else "-"))
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Every route from our supports to a slicer, against the slicers' own supports, in one run and one profile.

usage: bench/handoff.py [--bin build/generator/clever-support] [--models a,b,PATH@80mm,...] [--jobs 2] [--work DIR]
                        [--out bench/results] [--stem handoff] [--routes k1,k2] [--prusa-set KEY=VALUE ...]
                        [--keep-gcode] [--report-only] [--orient keep|auto]
       bench/handoff.py --validation   the validation parts (bench/validation, never tuned on) and the five
                                        examples at 80 mm -> <out>/validation.{json,md,svg}
       bench/handoff.py --tuning       the shared models (the tuning set) -> <out>/tuning.{json,md,svg}

Per model (shared models at their benchmark.json scale, orientation kept unless --orient auto):
  generator  clever-support --orient keep (tree) and --strategy columns; `clever-support check` on the tree.
             With --orient auto the tree is grown in the pose the generator picks (what a user gets by
             default); the columns baseline and every slicer's own supports are then made on that placed
             model (<name>.model.stl, pose kept), so all routes print the part in the same pose
  Cura       none, normal, tree (on <name>.model.stl); ours as model geometry (<name>.supported.stl, supports
             off); ours as a Cura support mesh (model.stl + supports.stl, per-mesh support_mesh=true,
             support_mesh_drop_down=false, profile mode "mesh"); our columns baseline the same way
  Prusa      none, grid, snug (model.stl); ours from our 3MF (<name>.prusa.3mf, per-volume settings);
             ours as model geometry (supported.stl)
Each G-code is parsed by slicers/gcode_stats.py (retractions, travel, islands per layer) and, for the
routes that print our tree, by slicers/printed_bodies.py (cross-sections of our bodies the slicer left
out), then deleted.
Writes <out>/<stem>.json (raw + derived), <out>/<stem>.md (tables) and <out>/<stem>.svg (chart); the stem is
handoff unless --stem, --validation or --tuning says otherwise. Each model is reported in its set (tuning:
the shared models; validation: bench/validation; examples; other), with medians per set.
See bench/README.md.
"""
import argparse
import concurrent.futures as cf
import datetime
import gzip
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared", "models"))
VALIDATION = os.path.join(HERE, "validation")
EXAMPLES = os.path.join(ROOT, "examples", "models")
SLICE_PY = os.path.join(HERE, "slicers", "slice.py")
sys.path.insert(0, os.path.join(HERE, "slicers"))
sys.dont_write_bytecode = True
import gcode_stats  # noqa: E402
import gcode_time  # noqa: E402
import printed_bodies  # noqa: E402
import slice as slice_stl  # noqa: E402
import wall_time  # noqa: E402
from measured_run import run_measured  # noqa: E402
from targets import (GENERATION_SPEEDUP, NO_TARGET, SUPPORT_FILAMENT_CURA, SUPPORT_FILAMENT_SNUG,  # noqa: E402
                     SUPPORT_TIME)

# How the report names the pose of a run (--orient).
ORIENT_WORDS = {"keep": "orientation kept",
                "auto": "orientation the generator's own (--orient auto; the slicers' own supports and the columns "
                        "baseline on that placed model)"}
DEFAULT_MODELS = ["u_overhang", "extruder_idler", "rocker_arm", "armadillo", "beast", "nefertiti"]
# The tuning set of --tuning: every shared benchmark model but menger_sponge3, whose Cura tree slice alone
# takes 5-8 min and whose columns baseline does not slice within the timeout (README, run times).
TUNING_SKIP = {"menger_sponge3"}
# Sets a model is reported in, in this order.
SETS = [("tuning", "Tuning set (shared models: the generator is tuned on these)"),
        ("validation", "Validation set (bench/validation: never tuned on)"),
        ("examples", "Examples (examples/models at 80 mm)"),
        ("other", "Other models")]

# Sliced over mesh support volume (issue 11's 0.9) is reported without a target (NO_TARGET): issue 32
# restated it as "no body layer left out" (the dropped body layers below). The others: targets.py.

# key -> (slicer, support mode, what is sliced)
ROUTES = {
    "cura_none": ("cura", "none", "model"),
    "cura_normal": ("cura", "normal", "model"),
    "cura_tree": ("cura", "tree", "model"),
    "cura_ours_model": ("cura", "none", "supported"),
    "cura_ours_mesh": ("cura", "mesh", "support_mesh"),
    "cura_columns_mesh": ("cura", "mesh", "columns_support_mesh"),
    "prusa_none": ("prusa", "none", "model"),
    "prusa_grid": ("prusa", "grid", "model"),
    "prusa_snug": ("prusa", "snug", "model"),
    "prusa_ours_3mf": ("prusa", "none", "prusa_3mf"),
    "prusa_ours_model": ("prusa", "none", "supported"),
}
# Routes whose supports print in the slicer's support sections (their islands are counted there).
SUPPORT_SECTION_ROUTES = {"cura_normal", "cura_tree", "cura_ours_mesh", "cura_columns_mesh", "prusa_grid",
                          "prusa_snug"}
# Routes whose G-code is searched for our tree's bodies, layer by layer (printed_bodies.py).
PRINTED_BODIES_ROUTES = {"cura_ours_model", "cura_ours_mesh", "prusa_ours_3mf", "prusa_ours_model"}
# Routes whose G-code is split into our walls' seconds and the rest (slicers/wall_time.py).
WALL_ROUTES = {"cura_ours_mesh", "prusa_ours_3mf"}
# The bed both routes centre the print on (printed_bodies.py places the G-code back by it).
BED_MM = json.load(open(os.path.join(HERE, "slicers", "profile.json")))["common"]["bed_mm"]
# Routes that print our mesh (sliced volume is compared with the mesh volume).
OURS = {"cura_ours_model": "tree", "cura_ours_mesh": "tree", "cura_columns_mesh": "columns",
        "prusa_ours_3mf": "tree", "prusa_ours_model": "tree"}


def log(msg):
    print(time.strftime("%H:%M:%S"), msg, flush=True)


def generate(args, name, path, scale, work, strategy, orient="keep"):
    out = os.path.join(work, name, strategy)
    cmd = [args.bin, path, "--scale", repr(scale), "--orient", orient, "--strategy", strategy, "--out", out,
           "--json", "--no-timings"]
    p = run_measured(cmd, args.gen_timeout)
    if p.returncode != 0:
        return {"cmd": " ".join(cmd), "error": p.stderr[-800:] if p.returncode is not None else "timeout"}
    rep = json.loads(p.stdout)
    files = {suffix: os.path.getsize(os.path.join(out, name + suffix))
             for suffix in (".3mf", ".prusa.3mf", ".supported.stl", ".model.stl")
             if os.path.exists(os.path.join(out, name + suffix))}
    return {"cmd": " ".join(cmd), "dir": out, "cpu_s": p.cpu_s, "file_bytes": files,
            # What the slicers are given to print: the slabs' bridges (generator/ceilings/slabs.hpp)
            # are hollow under our Cura profile and absent from the .prusa.3mf.
            "support_volume_mm3": rep["supports"]["support_volume_mm3"] - rep["supports"].get("bridges_volume_mm3", 0),
            "struts": rep["supports"]["struts"], "samples": rep["overhangs"]["samples"],
            "slicer_estimate": rep["supports"].get("slicer_estimate"),
            "triangles": rep["input"]["triangles"]}


def columns_in_pose_of(args, name, path, scale, tree):
    """The columns baseline in the tree's pose: as given (--orient keep), or on the tree's placed model."""
    if args.orient == "keep" or "error" in tree:
        return generate(args, name, path, scale, args.work, "columns")
    posed = os.path.join(args.work, name, "posed", name + ".stl")  # the generator names outputs by the input's stem
    os.makedirs(os.path.dirname(posed), exist_ok=True)
    shutil.copyfile(os.path.join(tree["dir"], name + ".model.stl"), posed)
    return generate(args, name, posed, 1.0, args.work, "columns")


def check(args, name, gen):
    stem = os.path.join(gen["dir"], name)
    cmd = [args.bin, "check", "--model", stem + ".model.stl", "--supports", stem + ".supports.stl", "--json"]
    p = run_measured(cmd, args.gen_timeout)
    if p.returncode is None:
        return {"ok": False, "error": "timeout"}
    try:
        j = json.loads(p.stdout)
    except ValueError:
        return {"ok": False, "error": (p.stderr or p.stdout)[-400:]}
    c = j.get("coverage", {})
    pts = c.get("points") or 0
    return {"ok": bool(j.get("ok")), "coverage": (c.get("covered", 0) + c.get("exempt", 0)) / pts if pts else 1.0}


def inputs_of(what, name, tree, columns):
    t = os.path.join(tree["dir"], name)
    c = os.path.join(columns["dir"], name) if columns and "dir" in columns else None
    return {
        "model": ([t + ".model.stl"], []),
        "supported": ([t + ".supported.stl"], []),
        "support_mesh": ([t + ".model.stl"], [t + ".supports.stl"]),
        "columns_support_mesh": (([c + ".model.stl"], [c + ".supports.stl"]) if c else None),
        "prusa_3mf": ([t + ".prusa.3mf"], []),
    }[what]


def stl_triangles(path):
    """Triangles in a binary STL (the generator writes binary), from its header's count."""
    with open(path, "rb") as f:
        head = f.read(84)
    return int.from_bytes(head[80:84], "little") if len(head) == 84 else 0


def removed_note(n):
    """Body layers in first layers CuraEngine removed because the model's slice there was empty."""
    return f" (+{n} in the empty first layer the slicer removed)" if n else ""


def slice_route(args, key, name, tree, columns, work):
    slicer, support, what = ROUTES[key]
    ins = inputs_of(what, name, tree, columns)
    if ins is None:
        return {"error": "no columns output"}
    models, meshes = ins
    if meshes and not any(stl_triangles(m) for m in meshes):
        # No support at all (a pose that needs none, as --orient auto may pick): the bare model is what
        # the route prints. slice.py refuses an empty support mesh.
        meshes, support = [], "none"
    out_dir = os.path.join(work, name, "slices", key)
    cmd = [sys.executable, SLICE_PY, "--slicer", slicer, "--support", support, "--json", "--timeout",
           str(args.slice_timeout), "--out-dir", out_dir] + sum((["--support-mesh", m] for m in meshes), [])
    if slicer == "prusa":  # e.g. perimeter_generator=classic: on every PrusaSlicer route, bare model included
        cmd += sum((["--set", kv] for kv in args.prusa_set), [])
    cmd += models
    p = run_measured(cmd, args.slice_timeout + 120)  # CPU of slice.py and the slicer it waits for
    if p.returncode != 0:
        return {"error": p.stderr.strip()[-600:] if p.returncode is not None else "timeout", "cmd": " ".join(cmd)}
    res = json.loads(p.stdout)
    out = {k: res[k] for k in ("grams", "print_time_s", "filament_mm3", "slice_seconds")}
    out["cpu_s"] = p.cpu_s
    out["gcode"] = gcode_stats.parse(os.path.join(out_dir, "out.gcode"))
    out["time"] = gcode_time.split(os.path.join(out_dir, "out.gcode"), res["print_time_s"])
    if args.keep_gcode and os.path.exists(os.path.join(out_dir, "out.gcode")):
        with open(os.path.join(out_dir, "out.gcode"), "rb") as src, gzip.open(os.path.join(out_dir, "out.gcode.gz"),
                                                                            "wb", compresslevel=6) as dst:
            shutil.copyfileobj(src, dst)
    if key in PRINTED_BODIES_ROUTES:
        stem = os.path.join(tree["dir"], name)
        out["printed_bodies"] = printed_bodies.measure(os.path.join(out_dir, "out.gcode"), stem + ".supports.stl",
                                                       stem + ".model.stl", float(BED_MM[0]), float(BED_MM[1]),
                                                       res.get("removed_empty_first_layers", 0))
    if key in WALL_ROUTES:
        out["walls"] = walls_of(os.path.join(out_dir, "out.gcode"), tree, name)
    # Keep the command, settings and logs; drop the bulky G-code and meshes.
    for f in ("out.gcode", "merged.stl", "support_mesh.stl"):
        try:
            os.remove(os.path.join(out_dir, f))
        except OSError:
            pass
    shutil.rmtree(os.path.join(out_dir, "prusa-datadir"), ignore_errors=True)
    return out


def walls_of(gcode, tree, name):
    """The seconds the G-code spends on our walls (slicers/wall_time.py), where the tree has walls."""
    stem = os.path.join(tree["dir"], name)
    if not wall_time.read_walls(stem + ".scad"):
        return None
    return wall_time.measure(gcode, stem + ".scad", stem + ".supports.stl", stem + ".model.stl")


def reparse(work, name, m):
    """Parses a model's kept G-codes (<work>/<name>/slices/<key>/out.gcode.gz) and its reports again."""
    for strategy, g in m.get("gen", {}).items():
        rep = os.path.join(g.get("dir", ""), name + ".report.json")
        if os.path.exists(rep):
            g["slicer_estimate"] = json.load(open(rep))["supports"].get("slicer_estimate")
    for key, r in m.get("slices", {}).items():
        gz = os.path.join(work, name, "slices", key, "out.gcode.gz")
        if "error" not in r and os.path.exists(gz):
            r["gcode"] = gcode_stats.parse(gz)
            r["time"] = gcode_time.split(gz, r["print_time_s"])
            if key in WALL_ROUTES and "dir" in m.get("gen", {}).get("tree", {}):
                r["walls"] = walls_of(gz, m["gen"]["tree"], name)


def ratio(a, b):
    return a / b if a is not None and b not in (None, 0) else None


# Routes the generator's report estimates (supports.slicer_estimate), by the report's name for them.
ESTIMATED = {"cura_ours_mesh": "cura_support_mesh", "prusa_ours_3mf": "prusa_3mf"}


def estimate_seconds(est, key):
    """The generator's estimate of the seconds the supports add on this route: its per-route estimate,
    or the one number that reports before 2026-11-26 gave (priced for Cura's support-mesh route)."""
    if not est:
        return None
    if "routes" in est:
        return est["routes"].get(ESTIMATED[key], {}).get("seconds")
    return est.get("seconds")


def derive(m):
    """Support-only numbers per route (route − the bare model in the same slicer) and the target ratios."""
    s = m["slices"]
    d = {}
    for key, r in s.items():
        if "error" in r or key.endswith("_none"):
            continue
        none = s.get(ROUTES[key][0] + "_none", {})
        if "error" in none or not none:
            continue
        g, gn = r["gcode"], none["gcode"]
        row = {
            "support_g": r["grams"] - none["grams"],
            "support_mm3": r["filament_mm3"] - none["filament_mm3"],
            "support_min": (r["print_time_s"] - none["print_time_s"]) / 60,
            "retractions": g["retractions"] - gn["retractions"],
            # The bare model has no support sections, so these are the route's own.
            "support_to_support_retractions": (g.get("support_to_support_retractions")
                                               if key in SUPPORT_SECTION_ROUTES else None),
            "travel_m": (g["travel_mm"] - gn["travel_mm"]) / 1000,
            "support_islands": (g["support_islands"] if key in SUPPORT_SECTION_ROUTES
                                else g["islands"] - gn["islands"]),
            "support_islands_max_per_layer": (g["support_islands_max_per_layer"] if key in SUPPORT_SECTION_ROUTES
                                              else None),
            "support_islands_by_eighth": g["support_islands_by_eighth"] if key in SUPPORT_SECTION_ROUTES else None,
        }
        if row["support_islands_max_per_layer"] is None and "islands_by_layer" in g and "islands_by_layer" in gn:
            # our supports printed as model geometry: the most islands a layer has beyond the bare model's
            row["support_islands_max_per_layer"] = max(
                (a - b for a, b in zip(g["islands_by_layer"], gn["islands_by_layer"] + [0] * len(g["islands_by_layer"]))),
                default=0)
        if "time" in r and "time" in none:
            split = {k: r["time"][k] - none["time"][k] for k in gcode_time.TERMS + ("accel_s",)}
            row["time_split_s"] = split
            row["time_split_residual_s"] = row["support_min"] * 60 - sum(split[k] for k in gcode_time.TERMS)
            row["starts_stops_per_island_s"] = ratio(split["accel_s"], row["support_islands"])
        if key in ESTIMATED:
            est = estimate_seconds(m["gen"]["tree"].get("slicer_estimate"), key)
            row["estimate_s"] = est
            row["estimate_over_gcode"] = ratio(est, row["support_min"] * 60)
        if key in OURS:
            mesh = m["gen"][OURS[key]].get("support_volume_mm3")
            row["sliced_over_mesh"] = ratio(row["support_mm3"], mesh)
            if "printed_bodies" in r:
                row["dropped_body_layers"] = r["printed_bodies"]["dropped"]
                row["body_layers"] = r["printed_bodies"]["body_layers"]
                row["body_layers_removed_with_first_layers"] = r["printed_bodies"].get("in_removed_first_layers", 0)
            if key in SUPPORT_SECTION_ROUTES:
                row["support_section_over_mesh"] = ratio(g["support_extruded_mm3"], mesh)
        d[key] = row

    def best(keys, field):
        vals = [d[k][field] for k in keys if k in d]
        return min(vals) if len(vals) == len(keys) else None

    t = {}
    if "cura_ours_mesh" in d:
        t["cura_mesh_time_vs_better_cura"] = ratio(d["cura_ours_mesh"]["support_min"],
                                                   best(["cura_normal", "cura_tree"], "support_min"))
        t["cura_mesh_filament_vs_better_cura"] = ratio(d["cura_ours_mesh"]["support_mm3"],
                                                       best(["cura_normal", "cura_tree"], "support_mm3"))
        t["cura_mesh_sliced_over_mesh"] = d["cura_ours_mesh"].get("sliced_over_mesh")
        t["cura_mesh_dropped_body_layers"] = d["cura_ours_mesh"].get("dropped_body_layers")
    if "cura_ours_model" in d and "cura_ours_mesh" in d:
        t["cura_mesh_time_vs_ours_as_model"] = ratio(d["cura_ours_mesh"]["support_min"],
                                                     d["cura_ours_model"]["support_min"])
    if "cura_columns_mesh" in d and "cura_ours_mesh" in d:
        t["cura_mesh_filament_vs_columns_mesh"] = ratio(d["cura_ours_mesh"]["support_mm3"],
                                                        d["cura_columns_mesh"]["support_mm3"])
    if "prusa_ours_3mf" in d and "prusa_snug" in d:
        t["prusa_3mf_time_vs_snug"] = ratio(d["prusa_ours_3mf"]["support_min"], d["prusa_snug"]["support_min"])
        t["prusa_3mf_filament_vs_snug"] = ratio(d["prusa_ours_3mf"]["support_mm3"], d["prusa_snug"]["support_mm3"])
        t["prusa_3mf_sliced_over_mesh"] = d["prusa_ours_3mf"].get("sliced_over_mesh")
        t["prusa_3mf_dropped_body_layers"] = d["prusa_ours_3mf"].get("dropped_body_layers")
    for key, field in (("cura_ours_mesh", "cura_mesh_estimate_over_gcode"),
                       ("prusa_ours_3mf", "prusa_3mf_estimate_over_gcode")):
        if key in d and d[key].get("estimate_over_gcode") is not None:
            t[field] = d[key]["estimate_over_gcode"]
    gen_cpu = m["gen"]["tree"].get("cpu_s")
    tree_cpu, none_cpu = s.get("cura_tree", {}).get("cpu_s"), s.get("cura_none", {}).get("cpu_s")
    if gen_cpu and tree_cpu is not None and none_cpu is not None:
        t["generation_speedup_vs_cura_tree"] = ratio(tree_cpu - none_cpu, gen_cpu)
    if "prusa_ours_3mf" in d and "prusa_ours_model" in d:
        t["prusa_3mf_time_vs_ours_as_model"] = ratio(d["prusa_ours_3mf"]["support_min"],
                                                     d["prusa_ours_model"]["support_min"])
    return d, t


TARGETS = [  # (ratio key, (median limit, each model's limit), direction): met when <= ("max") or >= ("min")
    ("cura_mesh_time_vs_better_cura", SUPPORT_TIME, "max"),
    ("cura_mesh_filament_vs_better_cura", SUPPORT_FILAMENT_CURA, "max"),
    ("cura_mesh_sliced_over_mesh", NO_TARGET, "min"),
    ("prusa_3mf_time_vs_snug", SUPPORT_TIME, "max"),
    ("prusa_3mf_filament_vs_snug", SUPPORT_FILAMENT_SNUG, "max"),
    ("prusa_3mf_sliced_over_mesh", NO_TARGET, "min"),
    ("generation_speedup_vs_cura_tree", GENERATION_SPEEDUP, "min"),
]


def meets(value, limit, direction):
    return value <= limit if direction == "max" else value >= limit


def target_words(limits, direction):
    """A target as the tables say it: 'median ≤ 0.7, each ≤ 1.0', or '–' where there is none."""
    sign = "≤" if direction == "max" else "≥"
    median, each = limits
    words = ([f"median {sign} {median:g}"] if median is not None else []) + ([f"each {sign} {each:g}"] if each is not None else [])
    return ", ".join(words) or "–"


def met_words(summary, key, limits):
    """Whether a set met a target as the tables say it: 'median no, 7/11' (the median, then how many
    models meet the per-model limit), or '–'."""
    words = []
    if limits[0] is not None and key in summary["median_met"]:
        words.append("median " + ("yes" if summary["median_met"][key] else "no"))
    if limits[1] is not None and key in summary["met"]:
        words.append(f"{summary['met'][key]}/{summary['n'][key]}")
    return ", ".join(words) or "–"


def dumps_records(value, depth=0, record_depth=4):
    """JSON with one record a line: objects open a level a line down to `record_depth` (the file, its
    models, a model, a section of it such as its slices), and every value deeper is written compactly on
    its record's line (a route's slice, a route's derived numbers), so a re-run's diff names the routes
    that changed. json.load reads it as it read the indented files before; the content is the same."""
    if not isinstance(value, dict) or not value or depth >= record_depth:
        return json.dumps(value, separators=(",", ":"))
    pad = " " * (depth + 1)
    items = (f"{pad}{json.dumps(k)}: {dumps_records(v, depth + 1, record_depth)}" for k, v in value.items())
    return "{\n" + ",\n".join(items) + "\n" + " " * depth + "}"


def write_json(data, path):
    with open(path, "w") as f:
        f.write(dumps_records(data) + "\n")


def fmt(v, spec="{:.2f}"):
    return "–" if v is None else spec.format(v)


def report_md(data):
    st = data["stamp"]
    L = ["# Handing our supports to the slicers: every route, one run, one profile\n",
         f"_Run {st['date']} on {st['nproc']} cores (load average at start {st['load']}), git commit "
         f"`{st['commit']}`, {st['jobs']} slices at a time; CPU total {st.get('cpu_total_s', 0):.0f} s "
         f"(generator + slicers), wall {st.get('wall_total_s', 0) / 60:.0f} min._\n",
         (f"PrusaSlicer settings on top of the profile, on every PrusaSlicer route: "
          f"{', '.join('`' + kv + '`' for kv in st['prusa_set'])}.\n" if st.get("prusa_set") else ""),
         "Profile: bench/slicers/profile.json (both slicers). Models: shared models at their benchmark.json scale "
         "(others at the scale their row gives), " + ORIENT_WORDS[st.get("orient", "keep")] + ". *Support* numbers are the route minus the bare model sliced in the same slicer "
         "and run: grams, minutes, retractions, travel (m). *Of them support→support*: retractions on a travel from one "
         "support extrusion to the next (routes the slicer prints as support); with Cura's limit_support_retractions "
         "those are travels it routed around the model instead of straight through air. *Islands*: support islands summed over layers (a new "
         "island after > 1 mm of travel inside support sections; for routes that print our supports as model "
         "geometry: all islands − the bare model's). *Sliced/mesh*: support filament the slicer printed over the "
         "support mesh volume (our routes). *Body layers dropped*: cross-sections of our bodies (each body cut "
         "at the middle of every layer it spans) with no extrusion inside that are not part of a joint, of all "
         "(slicers/printed_bodies.py): struts the slicer left out.\n"]
    names = {"cura_normal": "Cura normal", "cura_tree": "Cura tree", "cura_ours_model": "ours as model",
             "cura_ours_mesh": "ours as support mesh", "cura_columns_mesh": "our columns as support mesh",
             "prusa_grid": "Prusa grid", "prusa_snug": "Prusa snug", "prusa_ours_3mf": "ours from our 3MF",
             "prusa_ours_model": "ours as model (STL)"}
    for slicer, title in (("cura", "CuraEngine 4.13"), ("prusa", "PrusaSlicer 2.5")):
        L.append(f"\n## {title}\n")
        L.append("| model | route | support g | support min | retractions | of them support→support | travel m | "
                 "islands | max/layer | sliced/mesh | support sections/mesh | body layers dropped |")
        L.append("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
        for name, m in data["models"].items():
            for key, row in m.get("derived", {}).items():
                if ROUTES[key][0] != slicer:
                    continue
                L.append(f"| {name} | {names[key]} | {row['support_g']:.2f} | {row['support_min']:.0f} | "
                         f"{row['retractions']} | {fmt(row.get('support_to_support_retractions'), '{}')} | "
                         f"{row['travel_m']:.1f} | {row['support_islands']} | "
                         f"{fmt(row['support_islands_max_per_layer'], '{}')} | {fmt(row.get('sliced_over_mesh'))} | "
                         f"{fmt(row.get('support_section_over_mesh'))} | "
                         f"{fmt(row.get('dropped_body_layers'), '{}')}"
                         f"{' of ' + str(row['body_layers']) if 'body_layers' in row else ''}"
                         f"{removed_note(row.get('body_layers_removed_with_first_layers'))} |")
            for key, r in m["slices"].items():
                if ROUTES[key][0] == slicer and "error" in r:
                    L.append(f"| {name} | {key} | failed: {r['error'][-200:].replace(chr(10), ' ')} ||||||||| |")
    L.append("\n## Against the targets (ratios of support-only numbers, same slicer, same run)\n")
    L.append("Each set has its own medians: the validation set and the examples are never pooled with the tuning "
             "set.\n")
    by_set = data.get("summary_by_set") or {"other": data["summary"]}
    for group, title in SETS:
        if group not in by_set:
            continue
        L.append(f"\n### {title}\n")
        L.append("| model | coverage | " + " | ".join(k for k, _, _ in TARGETS) + " |")
        L.append("|---|---:|" + "---:|" * len(TARGETS))
        for name, m in data["models"].items():
            if m.get("set", "other") != group and "summary_by_set" in data:
                continue
            t = m.get("targets", {})
            cov = m.get("check", {})
            L.append(f"| {name} | {fmt(cov.get('coverage'), '{:.2%}')}{'' if cov.get('ok') else ' ✗'} | " +
                     " | ".join(fmt(t.get(k)) for k, _, _ in TARGETS) + " |")
        s = by_set[group]
        L.append("| **median** | | " + " | ".join(fmt(s["median"].get(k)) for k, _, _ in TARGETS) + " |")
        L.append("| **worst** | | " + " | ".join(fmt(s["worst"].get(k)) for k, _, _ in TARGETS) + " |")
        L.append("| **target** | | " + " | ".join(target_words(v, d) for _, v, d in TARGETS) + " |")
        L.append("| **met** | | " + " | ".join(met_words(s, k, v) for k, v, _ in TARGETS) + " |")
    L.append("\n## Generation and files\n")
    L.append("*Speed-up*: Cura tree's CPU overhead (CuraEngine with tree support − without supports, same run) over "
             "our generator's CPU (`clever-support`, every output written). Files: what the generator wrote.\n")
    L.append("| model | scale | triangles | our CPU s | Cura tree overhead CPU s | speed-up | .prusa.3mf MB | .3mf MB | "
             ".supported.stl MB |")
    L.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for name, m in data["models"].items():
        g, sl = m["gen"].get("tree", {}), m.get("slices", {})
        over = (sl["cura_tree"]["cpu_s"] - sl["cura_none"]["cpu_s"]
                if "cpu_s" in sl.get("cura_tree", {}) and "cpu_s" in sl.get("cura_none", {}) else None)
        fb = g.get("file_bytes", {})
        mb = lambda k: fmt(fb[k] / 1e6, "{:.2f}") if k in fb else "–"  # noqa: E731
        L.append(f"| {name} | {fmt(m.get('scale'), '{:.4g}')} | {g.get('triangles', '–')} | {fmt(g.get('cpu_s'))} | {fmt(over, '{:.1f}')} | "
                 f"{fmt(m.get('targets', {}).get('generation_speedup_vs_cura_tree'), '{:.1f}×')} | "
                 f"{mb('.prusa.3mf')} | {mb('.3mf')} | {mb('.supported.stl')} |")
    extra = ["cura_mesh_time_vs_ours_as_model", "prusa_3mf_time_vs_ours_as_model", "cura_mesh_filament_vs_columns_mesh",
             "cura_mesh_dropped_body_layers", "prusa_3mf_dropped_body_layers"]
    L += routes_md(data)
    L += split_md(data)
    s = data["summary"]
    L.append("\nOther ratios over every model (median, worst): " + "; ".join(
        f"{k} {fmt(s['median'].get(k))}, {fmt(s['worst'].get(k))}" for k in extra) + ".\n")
    return "\n".join(L) + "\n"


SPLIT_ROUTES = [("cura_normal", "Cura normal"), ("cura_tree", "Cura tree"), ("cura_ours_mesh", "ours, Cura support mesh"),
                ("prusa_snug", "Prusa snug"), ("prusa_ours_3mf", "ours, Prusa 3MF")]


def models_by_set(data):
    """[(set title, [(name, model)])] in the order of SETS, sets without models left out."""
    out = []
    for group, title in SETS:
        ms = [(n, m) for n, m in data["models"].items() if m.get("set", "other") == group and m.get("derived")]
        if ms:
            out.append((title, ms))
    return out


def routes_md(data):
    """Issue 32's per-model table: time, filament, island-layers and max islands per layer, ours and the
    slicers' own, both slicers."""
    L = ["\n## Per model, both slicers: time, filament, island-layers, max islands per layer\n",
         "Support-only: route − bare model, same slicer and run. *min*: added minutes; *g*: added filament; "
         "*isl*: support island-layers; *max*: most islands in one layer (for our Prusa route, where our struts "
         "print as model geometry: the route's islands − the bare model's, layer by layer). *ratio*: our minutes "
         "over the better of the slicer's own.\n"]
    groups = {"cura": (["cura_ours_mesh", "cura_normal", "cura_tree"], ["cura_normal", "cura_tree"]),
              "prusa": (["prusa_ours_3mf", "prusa_snug"], ["prusa_snug"])}
    for slicer, (keys, peers) in groups.items():
        head = " | ".join(f"{dict(SPLIT_ROUTES)[k]}: min | g | isl | max" for k in keys)
        for title, ms in models_by_set(data):
            L.append(f"\n### {'CuraEngine 4.13' if slicer == 'cura' else 'PrusaSlicer 2.5'}: {title}\n")
            L.append(f"| model | {head} | ratio |")
            L.append("|---|" + "---:|" * (4 * len(keys) + 1))
            for name, m in ms:
                d = m["derived"]
                cells = []
                for k in keys:
                    r = d.get(k)
                    cells += ([fmt(r["support_min"], "{:.1f}"), fmt(r["support_g"]), fmt(r["support_islands"], "{}"),
                               fmt(r["support_islands_max_per_layer"], "{}")] if r else ["–"] * 4)
                better = min((d[k]["support_min"] for k in peers if k in d), default=None)
                ours = d.get(keys[0], {}).get("support_min")
                L.append(f"| {name} | " + " | ".join(cells) + f" | {fmt(ratio(ours, better))} |")
    return L


def split_md(data):
    """Where the added minutes go, per route (gcode_time.py), and the generator's estimate against them."""
    L = ["\n## Where the added minutes go (slicers/gcode_time.py)\n",
         "Each G-code is replayed with the profile's machine (1500 mm/s², jerk 10) the way both slicers' "
         "estimators do, and its time split into *extrusion* and *travel* at their feedrates, *retractions* "
         "(filament-only moves), *starts/stops* (what acceleration and corners add to extrusion and travel: "
         "it grows with islands and corners, not with length) and *other* (Z-only moves, dwells). Every column "
         "is the route minus the bare model, in seconds; *residual* = the slicer's own added seconds − the sum "
         "of the five. *per island*: starts/stops over the support island-layers.\n"]
    terms = [("extrusion_s", "extrusion"), ("travel_s", "travel"), ("retraction_s", "retractions"),
             ("accel_s", "starts/stops"), ("other_s", "other")]
    L.append("| set | model | route | added s | " + " | ".join(t for _, t in terms) + " | residual | per island s |")
    L.append("|---|---|---|---:|" + "---:|" * (len(terms) + 2))
    totals = {}
    for title, ms in models_by_set(data):
        for name, m in ms:
            for key, label in SPLIT_ROUTES:
                r = m["derived"].get(key)
                if not r or "time_split_s" not in r:
                    continue
                sp = r["time_split_s"]
                tot = totals.setdefault(key, {k: 0.0 for k, _ in terms + [("added", ""), ("residual", "")]})
                for k, _ in terms:
                    tot[k] += sp[k]
                tot["added"] += r["support_min"] * 60
                tot["residual"] += r["time_split_residual_s"]
                L.append(f"| {title.split(' ')[0]} | {name} | {label} | {r['support_min'] * 60:.0f} | " +
                         " | ".join(f"{sp[k]:.0f}" for k, _ in terms) +
                         f" | {r['time_split_residual_s']:.0f} | {fmt(r.get('starts_stops_per_island_s'), '{:.3f}')} |")
    L.append("\nSummed over every model above (share of the added seconds):\n")
    L.append("| route | added s | " + " | ".join(t for _, t in terms) + " | residual |")
    L.append("|---|---:|" + "---:|" * (len(terms) + 1))
    for key, label in SPLIT_ROUTES:
        if key not in totals:
            continue
        tot = totals[key]
        share = lambda v: f"{v:.0f} ({v / tot['added']:.0%})" if tot["added"] else f"{v:.0f}"  # noqa: E731
        L.append(f"| {label} | {tot['added']:.0f} | " + " | ".join(share(tot[k]) for k, _ in terms) +
                 f" | {share(tot['residual'])} |")
    L.append("\n## The generator's estimate against the G-code\n")
    L.append("`supports.slicer_estimate` of the report (seconds the supports add, per route) over the seconds "
             "the slicer's own estimate adds for that route. Worst = furthest from 1.\n")
    L.append("| set | model | Cura mesh: estimate s | G-code s | ratio | Prusa 3MF: estimate s | G-code s | ratio |")
    L.append("|---|---|---:|---:|---:|---:|---:|---:|")
    for title, ms in models_by_set(data):
        for name, m in ms:
            cells = []
            for key in ("cura_ours_mesh", "prusa_ours_3mf"):
                r = m["derived"].get(key, {})
                cells += [fmt(r.get("estimate_s"), "{:.0f}"),
                          fmt(r["support_min"] * 60 if "support_min" in r else None, "{:.0f}"),
                          fmt(r.get("estimate_over_gcode"))]
            L.append(f"| {title.split(' ')[0]} | {name} | " + " | ".join(cells) + " |")
    L.append("")
    L.append("| set | Cura mesh: median ratio | worst | Prusa 3MF: median ratio | worst |")
    L.append("|---|---:|---:|---:|---:|")
    for group, title in SETS:
        sm = data.get("summary_by_set", {}).get(group)
        if not sm:
            continue
        L.append(f"| {title.split(' (')[0]} | " + " | ".join(
            fmt(sm[w].get(k)) for k in ("cura_mesh_estimate_over_gcode", "prusa_3mf_estimate_over_gcode")
            for w in ("median", "worst")) + " |")
    return L


CHART_ROUTES = [  # (route, label, colour); ours hatched
    ("cura_normal", "Cura normal", "#9ecae1"), ("cura_tree", "Cura tree", "#3182bd"),
    ("cura_ours_mesh", "ours, Cura support mesh", "#e6550d"),
    ("prusa_snug", "Prusa snug", "#a1d99b"), ("prusa_ours_3mf", "ours, Prusa 3MF", "#a63603"),
]


def write_chart_svg(data, path):
    """Support minutes and support grams per model and route, as a plain SVG (no plotting library)."""
    models = [n for n, m in data["models"].items() if m.get("derived")]
    if not models:
        return
    panels = [("support_min", "support print time (min): route − bare model, same slicer"),
              ("support_g", "support filament (g): route − bare model, same slicer")]
    gap, left, top, height, between = 14, 60, 50, 220, 70
    # Bars at least 9 px wide; wider where the legend's width leaves room.
    group = max(9 * len(CHART_ROUTES) + gap, 170 * len(CHART_ROUTES) / len(models))
    bar = (group - gap) / len(CHART_ROUTES)
    width = left + group * len(models) + 20
    total_h = top + len(panels) * (height + between) + 20
    out = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{total_h}" '
           f'font-family="sans-serif" font-size="11">',
           '<defs><pattern id="ours" width="4" height="4" patternUnits="userSpaceOnUse" '
           'patternTransform="rotate(45)"><rect width="2" height="4" fill="white" fill-opacity="0.5"/></pattern></defs>',
           f'<rect width="{width}" height="{total_h}" fill="white"/>',
           f'<text x="{left}" y="18" font-size="13">Hand-off routes against the slicers\' own supports '
           f'({data["stamp"]["date"]}, commit {data["stamp"]["commit"][:7]}); hatched = ours</text>']
    for i, (_, label, colour) in enumerate(CHART_ROUTES):  # legend
        x = left + i * 170
        out.append(f'<rect x="{x}" y="28" width="10" height="10" fill="{colour}"/>')
        out.append(f'<text x="{x + 14}" y="37">{label}</text>')
    for p_i, (field, title) in enumerate(panels):
        y0 = top + p_i * (height + between) + 20
        vals = [m.get("derived", {}).get(k, {}).get(field) for n in models for k, _, _ in CHART_ROUTES
                for m in [data["models"][n]]]
        vmax = max([v for v in vals if v is not None] + [1e-9])
        step = 10 ** math.floor(math.log10(vmax))  # then 4 to 10 grid lines
        step /= 5 if vmax / step < 2 else 2 if vmax / step < 5 else 1
        out.append(f'<text x="{left}" y="{y0 - 8}" font-size="12">{title}</text>')
        tick = 0.0
        while tick <= vmax * 1.0001:
            y = y0 + height - height * tick / vmax
            out.append(f'<line x1="{left}" x2="{width - 20}" y1="{y:.1f}" y2="{y:.1f}" stroke="#ddd"/>')
            out.append(f'<text x="{left - 5}" y="{y + 4:.1f}" text-anchor="end">{tick:g}</text>')
            tick += step
        for j, n in enumerate(models):
            d = data["models"][n].get("derived", {})
            for k_i, (key, _, colour) in enumerate(CHART_ROUTES):
                v = d.get(key, {}).get(field)
                if v is None or v <= 0:
                    continue
                x, h = left + j * group + k_i * bar, height * v / vmax
                out.append(f'<rect x="{x:.1f}" y="{y0 + height - h:.1f}" width="{bar - 1:.1f}" height="{h:.1f}" '
                           f'fill="{colour}"/>')
                if key.endswith(("_mesh", "_3mf")):
                    out.append(f'<rect x="{x:.1f}" y="{y0 + height - h:.1f}" width="{bar - 1:.1f}" '
                               f'height="{h:.1f}" fill="url(#ours)"/>')
            out.append(f'<text x="{left + j * group + group / 2 - gap / 2:.1f}" y="{y0 + height + 14}" '
                       f'text-anchor="middle">{n.replace("stanford_", "").replace("extruder_", "")}</text>')
        out.append(f'<line x1="{left}" x2="{width - 20}" y1="{y0 + height}" y2="{y0 + height}" stroke="black"/>')
    out.append("</svg>")
    with open(path, "w") as f:
        f.write("\n".join(out) + "\n")


def summarize(data):
    """Medians, worst values and targets met: over every model (`summary`) and per set (`summary_by_set`)."""
    data["summary"] = summary_of(list(data["models"].values()))
    data["summary_by_set"] = {}
    for group, _ in SETS:
        ms = [m for m in data["models"].values() if m.get("set", "other") == group]
        if ms:
            data["summary_by_set"][group] = summary_of(ms)


def summary_of(models):
    med, worst, met, n = {}, {}, {}, {}
    keys = [(k, d) for k, _, d in TARGETS] + [("cura_mesh_time_vs_ours_as_model", "max"),
                                               ("prusa_3mf_time_vs_ours_as_model", "max"),
                                               ("cura_mesh_filament_vs_columns_mesh", "max"),
                                               ("cura_mesh_dropped_body_layers", "max"),
                                               ("prusa_3mf_dropped_body_layers", "max"),
                                               ("cura_mesh_estimate_over_gcode", "far"),
                                               ("prusa_3mf_estimate_over_gcode", "far")]
    limits = {k: v for k, v, _ in TARGETS}
    median_met = {}
    for k, d in keys:
        vals = [m["targets"][k] for m in models if m.get("targets", {}).get(k) is not None]
        if not vals:
            continue
        med[k] = statistics.median(vals)
        worst[k] = (max(vals) if d == "max" else min(vals) if d == "min"
                    else max(vals, key=lambda v: abs(math.log(v)) if v > 0 else math.inf))  # "far": furthest from 1
        median_limit, each_limit = limits.get(k, NO_TARGET)
        if median_limit is not None:
            median_met[k] = meets(med[k], median_limit, d)
        if each_limit is not None:
            n[k] = len(vals)
            met[k] = sum(meets(v, each_limit, d) for v in vals)
    return {"median": med, "worst": worst, "met": met, "n": n, "median_met": median_met}


def model_entry(spec, bench):
    """A --models entry -> (name, STL path, scale). A shared model's name takes its benchmark.json
    scale; any other STL is given by its path, as PATH (scale 1), PATH@SCALE or PATH@<N>mm (scaled so
    its largest extent is N mm, as a user sizes a model they have not printed before)."""
    if spec in bench:
        return (spec,) + bench[spec] + ("tuning",)
    path, _, size = spec.partition("@")
    if not path.lower().endswith(".stl") or not os.path.isfile(path):
        raise ValueError(f"{spec}: neither a shared model ({', '.join(sorted(bench))}) nor an STL file "
                         "(PATH, PATH@SCALE or PATH@<N>mm)")
    scale = 1.0
    try:
        if size.endswith("mm"):
            tris = slice_stl.read_stl(path)
            extent = max(max(v[i] for t in tris for v in t) - min(v[i] for t in tris for v in t) for i in range(3))
            scale = float(size[:-2]) / extent
        elif size:
            scale = float(size)
    except (ValueError, ZeroDivisionError):
        raise ValueError(f"{spec}: the part after @ must be a scale (2.5) or a size in mm (80mm)")
    apath = os.path.abspath(path)
    where = os.path.dirname(apath)
    group = "validation" if where == VALIDATION else "examples" if where == EXAMPLES else "other"
    return os.path.splitext(os.path.basename(path))[0], apath, scale, group


def validation_specs():
    """The validation parts as they are (written in mm) and the five examples at 80 mm."""
    parts = sorted(f for f in os.listdir(VALIDATION) if f.endswith(".stl"))
    examples = sorted(f for f in os.listdir(EXAMPLES) if f.endswith(".stl"))
    return [os.path.join(VALIDATION, f) for f in parts] + [os.path.join(EXAMPLES, f) + "@80mm" for f in examples]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "generator", "clever-support"))
    ap.add_argument("--models", default=",".join(DEFAULT_MODELS),
                    help="shared model names and/or STL paths (PATH, PATH@SCALE, PATH@<N>mm), comma-separated")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "bench-handoff"))
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--gen-timeout", type=float, default=600)
    ap.add_argument("--slice-timeout", type=float, default=900)
    ap.add_argument("--report-only", action="store_true", help="redo <stem>.md from <stem>.json")
    ap.add_argument("--stem", help="output file names <out>/<stem>.json/.md/.svg (default handoff)")
    ap.add_argument("--validation", action="store_true",
                    help="the validation parts (bench/validation) and the five examples at 80 mm; stem validation")
    ap.add_argument("--tuning", action="store_true",
                    help="the shared benchmark models but " + ", ".join(sorted(TUNING_SKIP)) + "; stem tuning")
    ap.add_argument("--routes", help="only these slice keys (comma-separated; the *_none ones are always sliced)")
    ap.add_argument("--reparse", action="store_true",
                    help="with --report-only: parse the G-codes kept by --keep-gcode in --work again (gcode_stats, "
                         "gcode_time) and re-read the generator's reports, then redo the tables")
    ap.add_argument("--prusa-set", action="append", default=[], metavar="KEY=VALUE",
                    help="a PrusaSlicer setting on top of profile.json for every PrusaSlicer route (repeatable), "
                         "e.g. perimeter_generator=classic: what a user who picked the classic perimeters gets")
    ap.add_argument("--orient", choices=sorted(ORIENT_WORDS), default="keep",
                    help="keep: every model as given (default); auto: the tree in the pose the generator picks, "
                         "the columns baseline and the slicers' own supports on that placed model")
    ap.add_argument("--keep-gcode", action="store_true",
                    help="keep each G-code gzipped beside its slice (<work>/<model>/slices/<key>/out.gcode.gz)")
    args = ap.parse_args()
    stem = args.stem or ("validation" if args.validation else "tuning" if args.tuning else "handoff")
    jpath, mpath = os.path.join(args.out, stem + ".json"), os.path.join(args.out, stem + ".md")
    svg = os.path.join(args.out, stem + ".svg")
    bad = [kv for kv in args.prusa_set if "=" not in kv or kv.startswith("=")]
    if bad:
        print(f"handoff.py: --prusa-set needs KEY=VALUE, got {', '.join(bad)}", file=sys.stderr)
        return 2
    routes = list(ROUTES)
    if args.routes:
        want = {k.strip() for k in args.routes.split(",") if k.strip()}
        unknown = want - set(ROUTES)
        if unknown:
            print(f"handoff.py: --routes: unknown {', '.join(sorted(unknown))} (known: {', '.join(ROUTES)})",
                  file=sys.stderr)
            return 2
        routes = [k for k in ROUTES if k in want or k.endswith("_none")]
    if args.report_only:
        data = json.load(open(jpath))
        for name, m in data["models"].items():
            if args.reparse:
                reparse(args.work, name, m)
            if "slices" in m:
                m["derived"], m["targets"] = derive(m)
        summarize(data)
        if args.reparse:  # the G-codes' new numbers are kept, for a later --report-only
            write_json(data, jpath)
        open(mpath, "w").write(report_md(data))
        write_chart_svg(data, svg)
        return 0
    bench = {os.path.splitext(m["file"])[0]: (os.path.join(SHARED, m["file"]), float(m["scale"]))
             for m in json.load(open(os.path.join(SHARED, "benchmark.json")))["models"]}
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "HEAD"], capture_output=True, text=True).stdout.strip()
    data = {"stamp": {"date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC"),
                      "nproc": os.cpu_count(), "load": " ".join(open("/proc/loadavg").read().split()[:3]),
                      "commit": commit, "jobs": args.jobs, "profile": "bench/slicers/profile.json",
                      "routes": routes, "prusa_set": args.prusa_set, "orient": args.orient},
            "models": {}}
    cpu_total = 0.0
    os.makedirs(args.work, exist_ok=True)
    if args.validation:
        specs = validation_specs()
    elif args.tuning:
        specs = [n for n in bench if n not in TUNING_SKIP]
    else:
        specs = [n.strip() for n in args.models.split(",") if n.strip()]
    started = time.time()
    for spec in specs:
        try:
            name, path, scale, group = model_entry(spec, bench)
        except ValueError as exc:
            print(f"handoff.py: {exc}", file=sys.stderr)
            return 2
        log(f"{name}: generating (scale {scale})")
        strategies = ("tree", "columns") if "cura_columns_mesh" in routes else ("tree",)
        m = {"set": group, "scale": scale, "gen": {"tree": generate(args, name, path, scale, args.work, "tree", args.orient)}}
        if "columns" in strategies:
            m["gen"]["columns"] = columns_in_pose_of(args, name, path, scale, m["gen"]["tree"])
        cpu_total += sum(g.get("cpu_s") or 0 for g in m["gen"].values())
        if "error" in m["gen"]["tree"]:
            m["error"] = m["gen"]["tree"]["error"]
            data["models"][name] = m
            continue
        m["check"] = check(args, name, m["gen"]["tree"])
        with cf.ThreadPoolExecutor(args.jobs) as ex:
            futs = {k: ex.submit(slice_route, args, k, name, m["gen"]["tree"], m["gen"].get("columns"), args.work)
                    for k in routes}
            m["slices"] = {k: f.result() for k, f in futs.items()}
        for k, r in m["slices"].items():
            cpu_total += r.get("cpu_s") or 0
            log(f"{name} {k}: " + (r["error"][-200:] if "error" in r else
                                   f"{r['grams']:.2f} g {r['print_time_s'] / 60:.0f} min, cpu {r['cpu_s'] or 0:.0f} s"))
        m["derived"], m["targets"] = derive(m)
        data["models"][name] = m
        data["stamp"]["cpu_total_s"] = cpu_total
        data["stamp"]["wall_total_s"] = time.time() - started
        summarize(data)
        os.makedirs(args.out, exist_ok=True)
        write_json(data, jpath)
        open(mpath, "w").write(report_md(data))
        write_chart_svg(data, svg)
    log(f"done, CPU {cpu_total:.0f} s, wall {time.time() - started:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())

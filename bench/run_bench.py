#!/usr/bin/env python3
"""clever-support benchmark: the paper's Table 2 against real slicers, plus speed, scaling and memory.

Usually run through scripts/bench.sh (which builds the generator and the microbenchmarks first).
See bench/README.md for what every number means.

Per model (orientation kept, scale from shared/models/benchmark.json, examples at scale 1):
  generator  clever-support --strategy tree (timed R times: per-stage seconds, peak RSS) and
             --strategy columns; `clever-support check` on both support sets
  slicing    CuraEngine and PrusaSlicer with their own supports OFF on our <name>.supported.stl
             (tree and columns); the bare placed <name>.model.stl with Cura normal, Cura tree,
             Prusa grid and with no support in each slicer (Cura none/tree R times for timing)
Optional sections: --scaling (sampling series on armadillo + a ~1M-triangle igea), --orient
(--orient auto vs keep). Full mode (no --quick) runs all three.

Nothing is cached between runs except the Cura definitions (bench/slicers/fetch_cura_defs.sh).
Python 3 stdlib only; matplotlib (optional) for the chart.
"""
import argparse
import concurrent.futures as cf
import datetime
import json
import math
import os
import platform
import shutil
import statistics
import struct
import subprocess
import sys
import threading
import time
import traceback

from measured_run import run_measured
from targets import GENERATION_SPEEDUP, SCAN_5M_GIB, SCAN_5M_SECONDS

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared", "models"))
EXAMPLES = os.path.join(ROOT, "examples", "models")
# Mechanical parts the generator is never tuned on (bench/validation/README.md): run with --validation only.
VALIDATION = os.path.join(HERE, "validation")
SLICE_PY = os.path.join(HERE, "slicers", "slice.py")
PY = "/usr/bin/python3" if os.path.exists("/usr/bin/python3") else sys.executable

QUICK_SHARED = ["bridge", "u_overhang", "extruder_idler"]
QUICK_EXAMPLES = ["arches"]
SCALING_MODEL = "armadillo"
SCALING_SAMPLINGS = [2.5, 1.25, 0.625, 0.3125]  # the default, halved three times
BIG_MODEL = "igea"
# The 5M-triangle scan (issue 29: under 60 s and 4 GiB): armadillo, each triangle split 10 x 10.
SCAN_5M_MODEL, SCAN_5M_K = "armadillo", 10

_lock = threading.Lock()


def log(msg):
    with _lock:
        print(time.strftime("%H:%M:%S"), msg, flush=True)


def loadavg():
    """The 1-minute load average now (the machine is shared: every timing carries it)."""
    try:
        return float(open("/proc/loadavg").read().split()[0])
    except (OSError, ValueError, IndexError):
        return None


def median(xs):
    xs = [x for x in xs if x is not None]
    return statistics.median(xs) if xs else None


# ----------------------------------------------------------------------------------------------
# Machine stamp
# ----------------------------------------------------------------------------------------------

def sources_newer(binary):
    if not os.path.exists(binary):
        return None
    t = os.path.getmtime(binary)
    newer = []
    for d, _, files in os.walk(os.path.join(ROOT, "generator")):
        newer += [os.path.relpath(os.path.join(d, f), ROOT) for f in files if os.path.getmtime(os.path.join(d, f)) > t]
    return sorted(newer)


def stamp(args):
    cpu = "?"
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "HEAD"], capture_output=True, text=True,
                                timeout=10).stdout.strip() or "?"
    except Exception:
        commit = "?"
    try:
        load = open("/proc/loadavg").read().split()[:3]
    except OSError:
        load = []
    try:
        mem_kb = int([l for l in open("/proc/meminfo") if l.startswith("MemTotal")][0].split()[1])
    except Exception:
        mem_kb = None
    return {
        "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M:%S UTC"),
        "nproc": os.cpu_count(),
        "cpu": cpu,
        "mem_total_gb": round(mem_kb / 1048576, 1) if mem_kb else None,
        "loadavg_at_start": load,
        "git_commit": commit,
        "python": platform.python_version(),
        "generator": os.path.relpath(args.bin, ROOT) if args.bin.startswith(ROOT) else args.bin,
        "generator_built": (datetime.datetime.fromtimestamp(os.path.getmtime(args.bin), datetime.timezone.utc)
                            .strftime("%Y-%m-%d %H:%M:%S UTC") if os.path.exists(args.bin) else None),
        # Generator sources changed after the binary was built: the commit above may not be what ran.
        "sources_newer_than_generator": sources_newer(args.bin),
        "slicers": "CuraEngine 4.13 + PrusaSlicer 2.5 via bench/slicers/slice.py (profile bench/slicers/profile.json)",
        "repeats": args.repeats,
        "jobs": args.jobs,
    }


def stamp_md(st):
    return (f"_Run {st['date']} on {st['nproc']} x {st['cpu']} ({st.get('mem_total_gb')} GB RAM, load average at "
            f"start {' '.join(st.get('loadavg_at_start') or [])}), git commit `{st['git_commit']}`; "
            f"timings are medians of {st['repeats']} runs; slices ran {st['jobs']} at a time; generator binary built "
            f"{st.get('generator_built', '?')}" +
            (f" (**{len(st['sources_newer_than_generator'])} generator sources changed since it was built: the commit "
             f"is approximate**)" if st.get("sources_newer_than_generator") else "") + "._\n")


# ----------------------------------------------------------------------------------------------
# Models
# ----------------------------------------------------------------------------------------------

def model_list(args, notes):
    """[(name, path, scale, source)] in run order."""
    shared = []
    bj = os.path.join(SHARED, "benchmark.json")
    if os.path.exists(bj):
        for m in json.load(open(bj))["models"]:
            name = os.path.splitext(m["file"])[0]
            shared.append((name, os.path.join(SHARED, m["file"]), float(m["scale"]), "shared"))
    else:
        notes.append(f"{SHARED} is absent: the shared benchmark models were skipped.")
    examples = []
    if os.path.isdir(EXAMPLES):
        for f in sorted(os.listdir(EXAMPLES)):
            if f.endswith(".stl"):
                examples.append((os.path.splitext(f)[0], os.path.join(EXAMPLES, f), 1.0, "examples"))
    validation = [(os.path.splitext(f)[0], os.path.join(VALIDATION, f), 1.0, "validation")
                  for f in sorted(os.listdir(VALIDATION)) if f.endswith(".stl")] if os.path.isdir(VALIDATION) else []
    if args.validation:
        models = validation
    elif args.quick:
        models = [m for m in shared if m[0] in QUICK_SHARED] + [m for m in examples if m[0] in QUICK_EXAMPLES]
        for n in QUICK_SHARED:
            if not any(m[0] == n for m in shared):
                notes.append(f"quick model {n} skipped (shared models absent)")
    else:
        models = shared + examples
    if args.models:
        want = [w.strip() for w in args.models.split(",") if w.strip()]
        every = {m[0]: m for m in shared + examples + validation}
        models = []
        for w in want:
            if w in every:
                models.append(every[w])
            else:
                notes.append(f"model {w} not found (shared models absent or unknown name): skipped")
    return models


# ----------------------------------------------------------------------------------------------
# Running the generator
# ----------------------------------------------------------------------------------------------

def run_generator(args, model_path, scale, out_dir, extra, name_hint=None):
    """One generator run, measured alone (measured_run.py). Returns dict with report, wall, peak_kb, rc, cmd."""
    os.makedirs(out_dir, exist_ok=True)
    cmd = [args.bin, model_path, "--scale", repr(scale), "--out", out_dir, "--json"] + extra
    load = loadavg()
    m = run_measured(cmd, args.gen_timeout)
    rc = "timeout" if m.returncode is None else m.returncode
    out, err = m.stdout, (f"timed out after {args.gen_timeout} s" if m.returncode is None else m.stderr)
    res = {"cmd": " ".join(cmd), "rc": rc, "wall_s": m.wall_s, "stderr": err.strip()[-2000:], "loadavg": load,
           "peak_kb": m.peak_kb, "cpu_s": m.cpu_s}
    if rc == 0:
        try:
            res["report"] = json.loads(out)
        except ValueError:
            stem = name_hint or os.path.splitext(os.path.basename(model_path))[0]
            try:
                res["report"] = json.load(open(os.path.join(out_dir, stem + ".report.json")))
            except Exception as e:
                res["rc"] = f"no report: {e}"
    return res


def timed_generation(args, model_path, scale, out_dir, extra, repeats):
    """Runs the generator `repeats` times into the same dir; returns a summary (medians)."""
    runs = [run_generator(args, model_path, scale, out_dir, extra)]
    # A run longer than --long-run seconds is not repeated (the median of 1 is quoted; "runs" says so).
    while len(runs) < repeats and runs[0]["wall_s"] <= args.long_run:
        runs.append(run_generator(args, model_path, scale, out_dir, extra))
    ok = [r for r in runs if r["rc"] == 0 and "report" in r]
    s = {"cmd": runs[0]["cmd"], "runs": len(runs), "ok_runs": len(ok)}
    if not ok:
        s["error"] = f"rc={runs[-1]['rc']}: {runs[-1]['stderr'][-600:]}"
        return s
    rep = ok[-1]["report"]
    stages = {}
    for k in rep.get("seconds", {}):
        stages[k] = median([r["report"]["seconds"].get(k) for r in ok])
    s.update({
        "report": rep,
        "seconds_stages": stages,
        "seconds_total": median([r["report"].get("seconds_total") for r in ok]),
        "wall_s": median([r["wall_s"] for r in ok]),
        "wall_s_all": [round(r["wall_s"], 4) for r in ok],
        "cpu_s": median([r.get("cpu_s") for r in ok]),
        "cpu_s_all": [r.get("cpu_s") for r in ok],
        "loadavg_all": [r.get("loadavg") for r in ok],
        "peak_kb": max([r["peak_kb"] for r in ok if r["peak_kb"] is not None], default=None),
        "warnings": ok[-1]["stderr"],
    })
    return s


def run_check(args, model_stl, supports_stl):
    cmd = [args.bin, "check", "--model", model_stl, "--supports", supports_stl, "--json"]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=args.gen_timeout)
    except subprocess.TimeoutExpired:
        return {"cmd": " ".join(cmd), "rc": "timeout"}
    res = {"cmd": " ".join(cmd), "rc": p.returncode}
    try:
        j = json.loads(p.stdout)
        res["result"] = j
        c = j.get("coverage", {})
        pts = c.get("points") or 0
        res["coverage"] = (c.get("covered", 0) + c.get("exempt", 0)) / pts if pts else 1.0
        res["ok"] = bool(j.get("ok"))
    except ValueError:
        res["error"] = (p.stderr or p.stdout)[-800:]
    return res


# ----------------------------------------------------------------------------------------------
# Slicing
# ----------------------------------------------------------------------------------------------

def run_slice(args, slicer, support, stl):
    cmd = [PY, SLICE_PY, "--slicer", slicer, "--support", support, "--json", "--timeout",
           str(args.slice_timeout), stl]
    # CPU seconds (user + sys) of slice.py and the slicer it waits for: robust to other load on the
    # machine (CuraEngine lowers its own priority to nice 10, so its wall time suffers most).
    load = loadavg()
    p = run_measured(cmd, args.slice_timeout + 120)
    if p.returncode is None:
        return {"error": "timeout", "cmd": " ".join(cmd)}
    cpu = p.cpu_s
    if p.returncode != 0:
        return {"error": f"rc={p.returncode}: {p.stderr.strip()[-600:]}", "cmd": " ".join(cmd)}
    try:
        j = json.loads(p.stdout)
    except ValueError:
        return {"error": "bad json: " + p.stdout[-300:], "cmd": " ".join(cmd)}
    return {k: j.get(k) for k in ("grams", "print_time_s", "filament_mm3", "slice_seconds")} | {"cpu_s": cpu, "cmd": " ".join(cmd),
                                                                                              "loadavg": load}


# The slices of one model: key -> (slicer, support, which stl, timed?)
SLICES = [
    ("cura_none", "cura", "none", "model", True),
    ("cura_tree", "cura", "tree", "model", True),
    ("cura_normal", "cura", "normal", "model", False),
    ("prusa_none", "prusa", "none", "model", False),
    ("prusa_grid", "prusa", "grid", "model", False),
    ("ours_tree_cura", "cura", "none", "tree", False),
    ("ours_tree_prusa", "prusa", "none", "tree", False),
    ("ours_columns_cura", "cura", "none", "columns", False),
    ("ours_columns_prusa", "prusa", "none", "columns", False),
]


class Saver:
    """Keeps results.json up to date while jobs finish. Only the top-level keys this run owns are
    written; the others are re-read from the file at every save, so runs of different sections
    (e.g. --no-main --scaling next to a main run) can share one results dir."""

    def __init__(self, path, data, owned):
        self.path, self.data, self.owned = path, data, set(owned)

    def save(self):
        import fcntl
        import hashlib, tempfile
        lock = os.path.join(tempfile.gettempdir(), "cs-bench-" + hashlib.sha1(self.path.encode()).hexdigest()[:12] + ".lock")
        with _lock, open(lock, "w") as lk:
            fcntl.flock(lk, fcntl.LOCK_EX)
            try:
                merged = json.load(open(self.path))
            except Exception:
                merged = {}
            for k in self.owned:
                if k in self.data:
                    merged[k] = self.data[k]
            tmp = self.path + f".tmp{os.getpid()}"
            with open(tmp, "w") as f:
                json.dump(merged, f, indent=1, default=str)
            os.replace(tmp, self.path)


# ----------------------------------------------------------------------------------------------
# Derived numbers (pure functions of the raw results, so --report-only can redo them)
# ----------------------------------------------------------------------------------------------

def _med_slice(runs, key):
    return median([r.get(key) for r in runs if "error" not in r])


def slice_summary(runs):
    ok = [r for r in runs if "error" not in r]
    if not ok:
        return {"error": runs[0].get("error") if runs else "not run", "cmd": runs[0].get("cmd") if runs else None}
    return {"grams": ok[0]["grams"], "filament_mm3": ok[0]["filament_mm3"], "print_time_s": ok[0]["print_time_s"],
            "slice_seconds": _med_slice(ok, "slice_seconds"), "cpu_s": _med_slice(ok, "cpu_s"),
            "slice_seconds_all": [round(r["slice_seconds"], 3) for r in ok]}


def saving(ours, base):
    if ours is None or base is None or base == 0:
        return None
    return 1.0 - ours / base


def derive_model(m):
    """Per model: support-only grams, savings (within one slicer), ratios, timings."""
    d = {}
    sl = {k: slice_summary(v) for k, v in m.get("slices", {}).items()}
    d["slices"] = sl

    def g(k, f="grams"):
        v = sl.get(k, {})
        return v.get(f) if "error" not in v else None

    for slicer, none_key, systems in (("cura", "cura_none", ["cura_normal", "cura_tree", "ours_columns_cura", "ours_tree_cura"]),
                                      ("prusa", "prusa_none", ["prusa_grid", "ours_columns_prusa", "ours_tree_prusa"])):
        base_g, base_t, base_v = g(none_key), g(none_key, "print_time_s"), g(none_key, "filament_mm3")
        for s in systems:
            tg, tt, tv = g(s), g(s, "print_time_s"), g(s, "filament_mm3")
            d.setdefault("support_g", {})[s] = None if tg is None or base_g is None else tg - base_g
            d.setdefault("support_min", {})[s] = None if tt is None or base_t is None else (tt - base_t) / 60
            d.setdefault("support_mm3", {})[s] = None if tv is None or base_v is None else tv - base_v
        ours = "ours_tree_" + slicer
        for s in systems:
            if s == ours:
                continue
            d.setdefault("saving_total_g", {})[f"{ours}_vs_{s}"] = saving(g(ours), g(s))
            d.setdefault("saving_total_time", {})[f"{ours}_vs_{s}"] = saving(g(ours, "print_time_s"), g(s, "print_time_s"))
            d.setdefault("saving_support_g", {})[f"{ours}_vs_{s}"] = saving(d["support_g"].get(ours), d["support_g"].get(s))
    gen = m.get("gen_tree", {})
    rep = gen.get("report") or {}
    mesh_v = (rep.get("supports") or {}).get("support_volume_mm3")
    cols = (m.get("gen_columns", {}).get("report") or {}).get("supports", {}).get("support_volume_mm3")
    d["mesh_volume_mm3"] = {"tree": mesh_v, "columns": cols}
    d["sliced_over_mesh"] = {}
    for key, mv in (("ours_tree_cura", mesh_v), ("ours_tree_prusa", mesh_v),
                    ("ours_columns_cura", cols), ("ours_columns_prusa", cols)):
        sv = d["support_mm3"].get(key)
        d["sliced_over_mesh"][key] = sv / mv if sv is not None and mv else None
    ct = sl.get("cura_tree", {}).get("slice_seconds")
    cn = sl.get("cura_none", {}).get("slice_seconds")
    d["cura_tree_overhead_s"] = ct - cn if ct is not None and cn is not None else None
    ct, cn = sl.get("cura_tree", {}).get("cpu_s"), sl.get("cura_none", {}).get("cpu_s")
    d["cura_tree_overhead_cpu_s"] = ct - cn if ct is not None and cn is not None else None
    d["generation_cpu_s"] = gen.get("cpu_s")
    d["generation_s"] = gen.get("seconds_total")
    d["generation_wall_s"] = gen.get("wall_s")
    ss = gen.get("seconds_stages") or {}
    d["generation_no_columns_s"] = (gen["seconds_total"] - (ss.get("columns baseline") or 0)
                                    if gen.get("seconds_total") is not None else None)
    d["peak_mb"] = gen["peak_kb"] / 1024 if gen.get("peak_kb") else None
    d["coverage"] = (m.get("check_tree") or {}).get("coverage")
    d["check_ok"] = (m.get("check_tree") or {}).get("ok")
    d["coverage_columns"] = (m.get("check_columns") or {}).get("coverage")
    return d


# ----------------------------------------------------------------------------------------------
# Report writers
# ----------------------------------------------------------------------------------------------

def f_num(x, fmt="{:.2f}", none="–"):
    return none if x is None else fmt.format(x)


def f_pct(x):
    return "–" if x is None else f"{100 * x:.1f}%"


def stats_row(values):
    v = [x for x in values if x is not None]
    if not v:
        return None, None, None
    return sum(v) / len(v), min(v), max(v)


def write_table(out, results):
    st = results.get("stamp", {})
    models = results.get("models", {})
    L = ["# Table 2 analog: clever-support vs the slicers' own supports", "", stamp_md(st) if st else "",
         "Material (g) and print time (min) are the slicers' estimates (bench/slicers, one shared profile). "
         "*ours* = our `<name>.supported.stl` (model + our supports) sliced with the slicer's supports OFF; "
         "*none* = the bare placed model, no supports. Savings compare **within one slicer only** "
         "(slicer notes, pitfall 8). *Saved (total)* is the paper's definition: 1 − total ours / total theirs, "
         "for material and for time; *saved support* is 1 − (ours − none) / (theirs − none) on grams. "
         "*Coverage* is `clever-support check` (share of overhang points with a contact; ✗ = a check failed). "
         "*Sliced/mesh* is the support-only filament the slicer printed (ours − none, mm³) over the support mesh "
         "volume from the report: well below 1 means struts vanish when sliced (pitfall 6).", ""]
    for n in results.get("notes", []):
        L.append(f"- note: {n}")
    L.append("")
    # Headline: support-only grams and minutes, checks, speed.
    L += ["## Headline: support material only (grams = total − bare model, same slicer), checks and speed", "",
          "| model | tris | samples | struts | ours tree (Cura) g | Cura normal g | Cura tree g | ours tree (Prusa) g | Prusa grid g | "
          "+min ours (Cura) | +min Cura normal | +min Cura tree | coverage | sliced/mesh Cura | sliced/mesh Prusa | "
          "columns sliced/mesh Cura | mesh volume saved vs our columns | our generation s (w/o columns) | Cura tree overhead s | our CPU s | Cura tree overhead CPU s | peak MB |",
          "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for name, m in models.items():
        d = m.get("derived") or derive_model(m)
        rep = (m.get("gen_tree") or {}).get("report") or {}
        sg = d.get("support_g", {})
        sm = d.get("support_min", {})
        som = d["sliced_over_mesh"]
        cov = d.get("coverage")
        L.append("| " + " | ".join([
            name, str((rep.get("input") or {}).get("triangles", "–")), str((rep.get("overhangs") or {}).get("samples", "–")),
            str((rep.get("supports") or {}).get("struts", "–")),
            f_num(sg.get("ours_tree_cura")), f_num(sg.get("cura_normal")), f_num(sg.get("cura_tree")),
            f_num(sg.get("ours_tree_prusa")), f_num(sg.get("prusa_grid")),
            f_num(sm.get("ours_tree_cura"), "{:.0f}"), f_num(sm.get("cura_normal"), "{:.0f}"), f_num(sm.get("cura_tree"), "{:.0f}"),
            "–" if cov is None else f"{100 * cov:.2f}%" + ("" if d.get("check_ok") else " ✗"),
            f_num(som.get("ours_tree_cura")), f_num(som.get("ours_tree_prusa")), f_num(som.get("ours_columns_cura")),
            f_pct(saving(d["mesh_volume_mm3"].get("tree"), d["mesh_volume_mm3"].get("columns"))),
            f_num(d.get("generation_s"), "{:.3f}") + " (" + f_num(d.get("generation_no_columns_s"), "{:.3f}") + ")",
            f_num(d.get("cura_tree_overhead_s"), "{:.2f}"),
            f_num(d.get("generation_cpu_s"), "{:.2f}"), f_num(d.get("cura_tree_overhead_cpu_s"), "{:.2f}"),
            f_num(d.get("peak_mb"), "{:.0f}")]) + " |")
    L += ["", "*+min*: print minutes added by the supports (total − bare model, Cura). "
          "*our generation s*: median `seconds_total` of the report (every stage: load, repair, self-intersection count, "
          "overhangs, tree, and the columns baseline the report always computes; in brackets without that baseline; "
          "writing files excluded). *Cura tree overhead*: median slice_seconds with tree support minus without, same "
          "model, same run (Cura's whole support generation; our number does not include slicing). "
          "*CPU s*: user + system seconds (`/usr/bin/time`): ours = the whole generator process incl. output "
          "writing; Cura = CPU of the tree slice minus CPU of the no-support slice (robust to other load on the machine). "
          "Per-stage seconds: the last table and results.json (`models.<name>.gen_tree.seconds_stages`).", ""]
    cura_sys = [("cura_none", "none"), ("cura_normal", "Cura normal"), ("cura_tree", "Cura tree"),
                ("ours_columns_cura", "our columns"), ("ours_tree_cura", "ours (tree)")]
    prusa_sys = [("prusa_none", "none"), ("prusa_grid", "Prusa grid"), ("ours_columns_prusa", "our columns"),
                 ("ours_tree_prusa", "ours (tree)")]
    for title, systems, ours, baselines in (
            ("CuraEngine 4.13", cura_sys, "ours_tree_cura", [("cura_normal", "normal"), ("cura_tree", "tree"), ("ours_columns_cura", "columns")]),
            ("PrusaSlicer 2.5", prusa_sys, "ours_tree_prusa", [("prusa_grid", "grid"), ("ours_columns_prusa", "columns")])):
        L += [f"## {title}", ""]
        head = ["model"] + [f"{lab} g / min" for _, lab in systems]
        head += [f"saved g vs {b}" for _, b in baselines] + [f"saved time vs {b}" for _, b in baselines]
        head += [f"saved support g vs {b}" for _, b in baselines] + ["coverage", "sliced/mesh"]
        L.append("| " + " | ".join(head) + " |")
        L.append("|" + "---|" * len(head))
        cols = {}
        for name, m in models.items():
            d = m.get("derived") or derive_model(m)
            sl = d["slices"]
            row = [name]
            for k, _ in systems:
                s = sl.get(k, {})
                row.append("err" if "error" in s else "–" if s.get("grams") is None
                           else f"{s['grams']:.2f} / {s['print_time_s'] / 60:.0f}")
            for kind in ("saving_total_g", "saving_total_time", "saving_support_g"):
                for b, lab in baselines:
                    v = d.get(kind, {}).get(f"{ours}_vs_{b}")
                    cols.setdefault((kind, b), []).append(v)
                    row.append(f_pct(v))
            cov = d.get("coverage")
            row.append("–" if cov is None else f"{100 * cov:.2f}%" + ("" if d.get("check_ok") else " ✗"))
            row.append(f_num(d["sliced_over_mesh"].get(ours)))
            L.append("| " + " | ".join(row) + " |")
        for label, idx in (("**average**", 0), ("**min**", 1), ("**max**", 2)):
            row = [label] + [""] * len(systems)
            for kind in ("saving_total_g", "saving_total_time", "saving_support_g"):
                for b, _ in baselines:
                    row.append(f_pct(stats_row(cols.get((kind, b), []))[idx]))
            row += ["", ""]
            L.append("| " + " | ".join(row) + " |")
        L.append("")
    # Stage table
    L += ["", "## Generation time per stage (median seconds)", ""]
    stage_names = []
    for m in models.values():
        for k in ((m.get("gen_tree") or {}).get("seconds_stages") or {}):
            if k not in stage_names:
                stage_names.append(k)
    L.append("| model | " + " | ".join(stage_names) + " | total | wall (incl. output) | peak MB |")
    L.append("|---|" + "---:|" * (len(stage_names) + 3))
    for name, m in models.items():
        g = m.get("gen_tree") or {}
        ss = g.get("seconds_stages") or {}
        L.append("| " + " | ".join([name] + [f_num(ss.get(k), "{:.3f}") for k in stage_names] +
                                   [f_num(g.get("seconds_total"), "{:.3f}"), f_num(g.get("wall_s"), "{:.3f}"),
                                    f_num(g["peak_kb"] / 1024 if g.get("peak_kb") else None, "{:.0f}")]) + " |")
    errs = []
    for name, m in models.items():
        for k in ("gen_tree", "gen_columns"):
            if (m.get(k) or {}).get("error"):
                errs.append(f"- {name} {k}: {m[k]['error']} (`{m[k].get('cmd')}`)")
        for k in ("check_tree", "check_columns"):
            c = m.get(k) or {}
            if c and not c.get("ok", False):
                res = c.get("result") or {}
                errs.append(f"- {name} {k} failed (rc {c.get('rc')}): " +
                            json.dumps({kk: res.get(kk) for kk in ("coverage", "penetration", "grounding", "closed", "angles")} if res else c.get("error")) +
                            f". Reproduce: `{(m.get('gen_' + k[6:]) or {}).get('cmd')}` then `{c.get('cmd')}`")
        for k, runs in (m.get("slices") or {}).items():
            for r in runs:
                if "error" in r:
                    errs.append(f"- {name} slice {k}: {r['error'][:300]} (`{r.get('cmd')}`)")
                    break
    if errs:
        L += ["", "## Failures and failed checks", ""] + errs
    open(os.path.join(out, "table.md"), "w").write("\n".join(L) + "\n")


def write_chart(out, results, notes):
    models = results.get("models", {})
    names = list(models)
    if not names:
        return
    systems = [("cura_none", "Cura none"), ("cura_normal", "Cura normal"), ("cura_tree", "Cura tree"),
               ("ours_tree_cura", "ours tree (Cura)"), ("ours_columns_cura", "our columns (Cura)"),
               ("prusa_none", "Prusa none"), ("prusa_grid", "Prusa grid"), ("ours_tree_prusa", "ours tree (Prusa)")]
    data = {}
    for n in names:
        d = models[n].get("derived") or derive_model(models[n])
        sl = d["slices"]
        for k, _ in systems:
            s = sl.get(k, {})
            data[(n, k)] = (s.get("grams"), (s.get("print_time_s") or 0) / 60 if s.get("print_time_s") else None,
                            d.get("support_g", {}).get(k))
    path = os.path.join(out, "chart.png")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except Exception as e:
        notes.append(f"matplotlib unavailable ({e}); trying gnuplot")
        return write_chart_gnuplot(path, names, systems, data, notes)
    fig, axes = plt.subplots(3, 1, figsize=(max(10, 1.1 * len(names) + 4), 13), sharex=True)
    w = 0.8 / len(systems)
    for ax, idx, lab, log_y in ((axes[0], 0, "total material (g)", True),
                                (axes[1], 2, "support material only (g)\n(total − bare model, same slicer)", False),
                                (axes[2], 1, "total print time (min)", True)):
        for i, (k, klab) in enumerate(systems):
            if idx == 2 and k.endswith("_none"):
                continue
            xs = [j + (i - len(systems) / 2 + 0.5) * w for j in range(len(names))]
            ys = [data[(n, k)][idx] or 0 for n in names]
            ax.bar(xs, ys, w, label=klab, hatch="//" if k.startswith("ours") else None, edgecolor="black",
                   linewidth=0.3, color=f"C{i}")
        ax.set_ylabel(lab)
        if log_y:
            ax.set_yscale("log")
        ax.grid(axis="y", alpha=0.3)
    axes[-1].set_xticks(range(len(names)))
    axes[-1].set_xticklabels(names, rotation=30, ha="right")
    axes[0].legend(ncol=4, fontsize=8)
    axes[0].set_title("Material and print time per model and system (compare within one slicer; hatched = ours)")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_chart_gnuplot(path, names, systems, data, notes):
    if not shutil.which("gnuplot"):
        notes.append("no matplotlib and no gnuplot: chart.png not written")
        return
    dat = path + ".dat"
    with open(dat, "w") as f:
        f.write("model " + " ".join(k for k, _ in systems) + "\n")
        for n in names:
            f.write(n + " " + " ".join(str(data[(n, k)][0] or 0) for k, _ in systems) + "\n")
    cols = ", ".join(f"'{dat}' using {i + 2}:xtic(1) title '{lab}'" for i, (_, lab) in enumerate(systems))
    script = (f"set terminal png size 1400,600; set output '{path}'; set style data histogram; "
              f"set style histogram cluster gap 1; set style fill solid; set ylabel 'grams'; "
              f"set xtics rotate by -30; plot {cols}")
    subprocess.run(["gnuplot", "-e", script], check=False)
    os.remove(dat)


def fit_power(xs, ys):
    """Least-squares slope of log y on log x."""
    pts = [(math.log(x), math.log(y)) for x, y in zip(xs, ys) if x and y and x > 0 and y > 0]
    if len(pts) < 2:
        return None
    mx = sum(p[0] for p in pts) / len(pts)
    my = sum(p[1] for p in pts) / len(pts)
    sxx = sum((p[0] - mx) ** 2 for p in pts)
    return sum((p[0] - mx) * (p[1] - my) for p in pts) / sxx if sxx else None


def write_scaling(out, sc):
    L = ["# Scaling", "", stamp_md(sc["stamp"]), ""] + [f"- note: {n}" for n in sc.get("notes", [])] + [""]
    ser = sc.get("series", [])
    L += [f"## {SCALING_MODEL} at benchmark scale, sampling halved three times", "",
          "| sampling mm | samples | struts | tree s | columns s | seconds_total | wall s | CPU s | peak MB | support mm³ |",
          "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for r in ser:
        if r.get("error"):
            L.append(f"| {r['sampling']} | error: {r['error'][:200]} |||||||")
            continue
        L.append(f"| {r['sampling']} | {r['samples']} | {r['struts']} | {r['tree_s']:.3f} | {r['columns_s']:.3f} | "
                 f"{r['seconds_total']:.3f} | {r['wall_s']:.3f} | {f_num(r.get('cpu_s'))} | {r['peak_mb']:.0f} | "
                 f"{r['support_volume_mm3']:.0f} |")
    fit = sc.get("fit", {})
    L += ["", "Power-law fits over the series (least squares on logs; n = overhang samples):", ""]
    for k, v in fit.items():
        L.append(f"- {k}: {f_num(v, '{:.2f}')}")
    L += ["", "An exponent of 1 against n·log n means the stage grows as n log n; against n alone, n log n over "
          "this range shows up as about 1.1.", ""]
    big = sc.get("big")
    if big:
        L += [f"## Large meshes: {BIG_MODEL} with every triangle split in 4 (~1M), and a synthetic 5M-triangle torus", "",
              "The torus (`synthetic_torus_stl`: 2000 x 1250 quads, R 40 mm, r 12 mm, standing on its rim) is a "
              "synthetic 5M-triangle case. The scan is issue 29's limit case: armadillo with every triangle split "
              f"{SCAN_5M_K} x {SCAN_5M_K} (`grid_subdivide_stl`, the same surface), at benchmark scale with default options "
              f"(the orientation search included); the bar is under {SCAN_5M_SECONDS:g} s and {SCAN_5M_GIB:g} GiB peak RSS. "
              "The others run with `--orient keep`.", "",
              "| mesh | triangles | samples | struts | seconds_total | wall s | CPU s | peak MB | load | repair | self-intersections | orient | overhangs | model index | tree | columns |",
              "|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
        for r in big:
            if r.get("error"):
                L.append(f"| {r['mesh']} | error: {r['error'][:200]} ||||||||||||||")
                continue
            s = r["stages"]
            L.append(f"| {r['mesh']} | {r['triangles']} | {r['samples']} | {r['struts']} | {r['seconds_total']:.2f} | "
                     f"{r['wall_s']:.2f} | {f_num(r.get('cpu_s'))} | {r['peak_mb']:.0f} | " +
                     " | ".join(f_num(s.get(k), "{:.2f}") for k in ("load", "repair", "self-intersections", "orient", "overhangs", "model index", "tree", "columns baseline")) + " |")
        L += scan_5m_verdict(big)
        if len(big) >= 2 and not any(r.get("error") for r in big[:2]):
            e = fit_power([big[0]["triangles"], big[1]["triangles"]], [big[0]["seconds_total"], big[1]["seconds_total"]])
            L += ["", f"Time exponent against triangle count (2 points, 4x triangles, same geometry): {f_num(e)}"]
    open(os.path.join(out, "scaling.md"), "w").write("\n".join(L) + "\n")


def cov_str(cov, ok):
    return "–" if cov is None else f"{100 * cov:.2f}%" + ("" if ok else " ✗")


def down_dir(a):
    """The input-frame direction the auto pose points at the bed: R^T (0, 0, -1) = -(third row of R)."""
    R = a.get("rotation")
    if not R:
        return a.get("pose") or "–"
    v = [-R[2][0], -R[2][1], -R[2][2]]
    v = [0.0 if abs(c) < 5e-4 else c for c in v]
    return "(" + ", ".join(f"{c:.3f}" for c in v) + f") ({a.get('pose')})"


def write_orientation(out, orr):
    L = ["# Orientation: `--orient auto` vs `--orient keep`", "", stamp_md(orr["stamp"]), ""] + \
        [f"- note: {n}" for n in orr.get("notes", [])] + ["",
         "Support volume is the support mesh volume from the report; grams are CuraEngine with its supports off on "
         "our `<name>.supported.stl` (model + our tree supports), and support-only grams subtract the bare model "
         "in the same pose. *orient s* is `seconds.orient` of the auto run (median).", "",
         "| model | keep: support mm³ | auto: support mm³ | keep: Cura g (support g) | auto: Cura g (support g) | "
         "auto: input direction put down (decided by) | orient s | auto coverage |",
         "|---|---:|---:|---:|---:|---|---:|---:|"]
    for name, r in orr.get("models", {}).items():
        if r.get("error"):
            L.append(f"| {name} | error: {r['error'][:200]} |||||||")
            continue
        k, a = r.get("keep", {}), r.get("auto", {})

        def gs(x):
            if x.get("grams") is None:
                return "–"
            sup = x.get("support_g")
            return f"{x['grams']:.2f} ({f_num(sup)})"
        L.append(f"| {name} | {f_num(k.get('support_volume_mm3'), '{:.0f}')} | {f_num(a.get('support_volume_mm3'), '{:.0f}')} | "
                 f"{gs(k)} | {gs(a)} | {down_dir(a)} | {f_num(a.get('orient_s'), '{:.2f}')} | "
                 f"{cov_str(a.get('coverage'), a.get('check_ok'))} |")
    open(os.path.join(out, "orientation.md"), "w").write("\n".join(L) + "\n")


# ----------------------------------------------------------------------------------------------
# Sections
# ----------------------------------------------------------------------------------------------

def synthetic_torus_stl(dst, n_major=2000, n_minor=1250, R=40.0, r=12.0):
    """A torus standing on its rim (axis along y), n_major x n_minor quads = 2 n_major n_minor
    triangles (5M by default): a closed surface whose inner ring and lower half overhang.
    Procedural, so the 5M-triangle limit test needs nothing from ../shared."""
    def point(i, j):
        u = 2 * math.pi * (i % n_major) / n_major
        v = 2 * math.pi * (j % n_minor) / n_minor
        w = R + r * math.cos(v)
        return (w * math.cos(u), r * math.sin(v), w * math.sin(u) + R + r)
    with open(dst + ".tmp", "wb") as f:
        f.write(b"binary STL: synthetic torus for the 5M-triangle limit test".ljust(80, b" "))
        f.write(struct.pack("<I", 2 * n_major * n_minor))
        pack = struct.Struct("<12fH").pack
        out = bytearray()
        prev = [point(0, j) for j in range(n_minor + 1)]
        for i in range(n_major):
            cur = [point(i + 1, j) for j in range(n_minor + 1)]
            for j in range(n_minor):
                a, b, c, d = prev[j], cur[j], cur[j + 1], prev[j + 1]
                # Normals are left zero: every reader recomputes them from the winding.
                out += pack(0, 0, 0, *a, *b, *c, 0)
                out += pack(0, 0, 0, *a, *c, *d, 0)
            prev = cur
            if len(out) > 1 << 24:
                f.write(out)
                out = bytearray()
        f.write(out)
    os.replace(dst + ".tmp", dst)
    return 2 * n_major * n_minor


def subdivide_stl(src, dst):
    """Each triangle -> 4 by edge midpoints. Binary STL in, binary STL out."""
    data = open(src, "rb").read()
    n = struct.unpack_from("<I", data, 80)[0]
    with open(dst + ".tmp", "wb") as f:
        hdr = f"binary STL: {os.path.basename(src)} x4 midpoint subdivision".encode()[:80]
        f.write(hdr.ljust(80, b" "))
        f.write(struct.pack("<I", 4 * n))
        out = bytearray()
        pack = struct.Struct("<12fH").pack
        for i in range(n):
            v = struct.unpack_from("<12f", data, 84 + 50 * i)
            nx, ny, nz = v[0:3]
            a, b, c = v[3:6], v[6:9], v[9:12]
            ab = ((a[0] + b[0]) / 2, (a[1] + b[1]) / 2, (a[2] + b[2]) / 2)
            bc = ((b[0] + c[0]) / 2, (b[1] + c[1]) / 2, (b[2] + c[2]) / 2)
            ca = ((c[0] + a[0]) / 2, (c[1] + a[1]) / 2, (c[2] + a[2]) / 2)
            for t in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)):
                out += pack(nx, ny, nz, *t[0], *t[1], *t[2], 0)
            if len(out) > 1 << 24:
                f.write(out)
                out = bytearray()
        f.write(out)
    os.replace(dst + ".tmp", dst)
    return 4 * n


def grid_subdivide_stl(src, dst, k):
    """Each triangle -> k*k on a k-step grid of its edges (the same surface, k*k times the
    triangles): a scan upsampled, for the 5M-triangle limit. A point on an edge is computed from
    the edge's two ends in one canonical order, so neighbouring triangles share it to the bit
    (float32) and the result stays as closed as the source. Binary STL in, binary STL out."""
    data = open(src, "rb").read()
    n = struct.unpack_from("<I", data, 80)[0]
    pack = struct.Struct("<12fH").pack
    rows = [[(i, j) for j in range(k + 1 - i)] for i in range(k + 1)]

    def lattice(corners):
        # weights (k - i - j, i, j) on (a, b, c); the corners taken in sorted order so shared
        # points are computed alike by every triangle that has them
        pts = {}
        order = sorted(range(3), key=lambda t: corners[t])
        for i in range(k + 1):
            for j in range(k + 1 - i):
                w = (k - i - j, i, j)
                x = y = z = 0.0
                for t in order:
                    if w[t]:
                        x += w[t] * corners[t][0]
                        y += w[t] * corners[t][1]
                        z += w[t] * corners[t][2]
                pts[i, j] = (x / k, y / k, z / k)
        return pts

    with open(dst + ".tmp", "wb") as f:
        f.write(f"binary STL: {os.path.basename(src)} x{k * k} grid subdivision".encode()[:80].ljust(80, b" "))
        f.write(struct.pack("<I", k * k * n))
        out = bytearray()
        for t in range(n):
            v = struct.unpack_from("<12f", data, 84 + 50 * t)
            nx, ny, nz = v[0:3]
            pts = lattice((v[3:6], v[6:9], v[9:12]))
            for i in range(k):
                for j in range(k - i):
                    # upright (i, j), (i+1, j), (i, j+1) keeps the source's winding
                    out += pack(nx, ny, nz, *pts[i, j], *pts[i + 1, j], *pts[i, j + 1], 0)
                    if j < k - i - 1:
                        out += pack(nx, ny, nz, *pts[i + 1, j], *pts[i + 1, j + 1], *pts[i, j + 1], 0)
            if len(out) > 1 << 24:
                f.write(out)
                out = bytearray()
        f.write(out)
    os.replace(dst + ".tmp", dst)
    return k * k * n


def scan_5m_case(args, work, scales):
    """The 5M-triangle scan as a user runs it (default options: the orientation search included),
    timed like every generator run: wall, CPU and peak RSS (/usr/bin/time)."""
    src = os.path.join(SHARED, SCAN_5M_MODEL + ".stl")
    dst = os.path.join(work, f"{SCAN_5M_MODEL}_x{SCAN_5M_K * SCAN_5M_K}.stl")
    if not os.path.exists(dst):
        log(f"scaling: writing {dst}")
        grid_subdivide_stl(src, dst, SCAN_5M_K)
    label = f"{os.path.basename(dst)} (scan, orientation search)"
    log(f"scaling: {label}")
    g = timed_generation(args, dst, scales[SCAN_5M_MODEL], os.path.join(work, "scaling", "scan_5m"), [], args.repeats)
    if g.get("error"):
        return {"mesh": label, "error": g["error"], "cmd": g["cmd"]}
    rep = g["report"]
    return {"mesh": label, "cmd": g["cmd"], "triangles": rep["input"]["triangles"],
            "samples": rep["overhangs"]["samples"], "struts": rep["supports"]["struts"],
            "seconds_total": g["seconds_total"], "wall_s": g["wall_s"], "wall_s_all": g["wall_s_all"],
            "cpu_s": g.get("cpu_s"), "cpu_s_all": g.get("cpu_s_all"), "loadavg_all": g.get("loadavg_all"),
            "peak_mb": (g["peak_kb"] or 0) / 1024, "stages": g["seconds_stages"],
            "made_by": f"grid_subdivide_stl(shared/models/{SCAN_5M_MODEL}.stl, k={SCAN_5M_K})"}


def scan_5m_verdict(big):
    """The line saying whether the 5M-triangle scan met issue 29's bar, and how to reproduce it."""
    L = []
    for r in big:
        if "(scan" in r["mesh"] and not r.get("error"):
            gib = r["peak_mb"] / 1024
            ok = r["wall_s"] < SCAN_5M_SECONDS and gib < SCAN_5M_GIB
            L += ["", f"5M-triangle scan ({r['triangles']} triangles): **{r['wall_s']:.1f} s wall** (runs "
                  f"{', '.join(f'{x:.1f}' for x in r.get('wall_s_all') or [])}; CPU {f_num(r.get('cpu_s'))} s), "
                  f"**{gib:.2f} GiB peak RSS**, load average {r.get('loadavg_all')}: the bar (< {SCAN_5M_SECONDS:g} s, "
                  f"< {SCAN_5M_GIB:g} GiB) is {'met' if ok else 'NOT met'}. Command: `{r['cmd']}`. Mesh: {r['made_by']}. "
                  "Reproduce: `python3 bench/run_bench.py --scan-5m` (writes scan_5m.md)."]
    return L


def write_scan_5m(out, sc):
    L = ["# The 5M-triangle scan", "", stamp_md(sc["stamp"]), ""]
    for r in sc["big"]:
        if r.get("error"):
            L.append(f"{r['mesh']}: error: {r['error'][:400]} (`{r.get('cmd')}`)")
            continue
        L += [f"| stage | {r['mesh']} |", "|---|---:|"] + \
             [f"| {k} | {v:.2f} |" for k, v in sorted(r["stages"].items(), key=lambda kv: -kv[1])]
    L += scan_5m_verdict(sc["big"])
    open(os.path.join(out, "scan_5m.md"), "w").write("\n".join(L) + "\n")


def scaling_section(args, work, st):
    sc = {"stamp": st, "series": [], "big": []}
    bj = os.path.join(SHARED, "benchmark.json")
    if not os.path.exists(bj):
        sc["note"] = "shared models absent: scaling skipped"
        return sc
    scales = {os.path.splitext(m["file"])[0]: m["scale"] for m in json.load(open(bj))["models"]}
    path = os.path.join(SHARED, SCALING_MODEL + ".stl")
    for s in SCALING_SAMPLINGS:
        log(f"scaling: {SCALING_MODEL} sampling {s}")
        g = timed_generation(args, path, scales[SCALING_MODEL], os.path.join(work, "scaling", f"s{s}"),
                             ["--orient", "keep", "--sampling", str(s)], args.repeats)
        if g.get("error"):
            sc["series"].append({"sampling": s, "error": g["error"], "cmd": g["cmd"]})
            continue
        rep = g["report"]
        sc["series"].append({"sampling": s, "cmd": g["cmd"], "samples": rep["overhangs"]["samples"],
                             "struts": rep["supports"]["struts"], "tree_s": g["seconds_stages"].get("tree"),
                             "columns_s": g["seconds_stages"].get("columns baseline"),
                             "overhangs_s": g["seconds_stages"].get("overhangs"),
                             "seconds_total": g["seconds_total"], "wall_s": g["wall_s"], "wall_s_all": g["wall_s_all"],
                             "cpu_s": g.get("cpu_s"),
                             "peak_mb": (g["peak_kb"] or 0) / 1024,
                             "support_volume_mm3": rep["supports"]["support_volume_mm3"],
                             "stages": g["seconds_stages"]})
    ok = [r for r in sc["series"] if not r.get("error")]
    if len(ok) >= 2:
        n = [r["samples"] for r in ok]
        nlogn = [x * math.log(x) for x in n]
        sc["fit"] = {
            "tree seconds vs n log n (exponent)": fit_power(nlogn, [r["tree_s"] for r in ok]),
            "tree seconds vs n (exponent)": fit_power(n, [r["tree_s"] for r in ok]),
            "seconds_total vs n log n (exponent)": fit_power(nlogn, [r["seconds_total"] for r in ok]),
            "columns seconds vs n log n (exponent)": fit_power(nlogn, [r["columns_s"] for r in ok]),
            "peak memory vs n (exponent)": fit_power(n, [r["peak_mb"] for r in ok]),
            "process CPU seconds vs n log n (exponent)": fit_power(nlogn, [r.get("cpu_s") for r in ok]),
        }
    # ~1M triangles
    big_src = os.path.join(SHARED, BIG_MODEL + ".stl")
    big_dst = os.path.join(work, f"{BIG_MODEL}_x4.stl")
    log(f"scaling: writing {big_dst}")
    subdivide_stl(big_src, big_dst)
    torus = os.path.join(work, "torus_5m.stl")
    log(f"scaling: writing {torus}")
    synthetic_torus_stl(torus)
    for label, p, scale in ((BIG_MODEL + ".stl", big_src, scales[BIG_MODEL]),
                            (os.path.basename(big_dst), big_dst, scales[BIG_MODEL]),
                            ("torus_5m.stl (synthetic)", torus, 1.0)):
        log(f"scaling: {label}")
        g = timed_generation(args, p, scale, os.path.join(work, "scaling", os.path.splitext(os.path.basename(p))[0]),
                             ["--orient", "keep"], args.repeats)
        if g.get("error"):
            sc["big"].append({"mesh": label, "error": g["error"], "cmd": g["cmd"]})
            continue
        rep = g["report"]
        sc["big"].append({"mesh": label, "cmd": g["cmd"], "triangles": rep["input"]["triangles"],
                          "samples": rep["overhangs"]["samples"], "struts": rep["supports"]["struts"],
                          "seconds_total": g["seconds_total"], "wall_s": g["wall_s"], "cpu_s": g.get("cpu_s"),
                          "peak_mb": (g["peak_kb"] or 0) / 1024, "stages": g["seconds_stages"]})
    sc["big"].append(scan_5m_case(args, work, scales))
    return sc


# ----------------------------------------------------------------------------------------------
# Speed (issue 29): generation with the orientation search against Cura tree's overhead
# ----------------------------------------------------------------------------------------------

SPEED_TARGET_MEDIAN, SPEED_TARGET_EACH = GENERATION_SPEEDUP  # targets.py


def file_sha256(path):
    import hashlib
    h = hashlib.sha256()
    with open(path, "rb") as f:
        for chunk in iter(lambda: f.read(1 << 20), b""):
            h.update(chunk)
    return h.hexdigest()


def speed_generate(args, work, models, previous):
    """Times the generator as a user runs it (the orientation search included: --orient auto) on
    every model, serially, and once more with the benchmark's pose kept: Cura slices that placed
    model (the pose the benchmark set defines; the search may pick one that needs no support at
    all, where Cura's overhead is nil). Returns {name: record} and the Cura slices still to run."""
    recs, jobs = {}, []
    for name, path, scale, src in models:
        d = os.path.join(work, "speed", name)
        shutil.rmtree(d, ignore_errors=True)
        log(f"speed: generate {name} (x{args.repeats} --orient auto, x{args.repeats} --orient keep)")
        g = timed_generation(args, path, scale, os.path.join(d, "auto"), ["--orient", "auto"], args.repeats)
        gk = timed_generation(args, path, scale, os.path.join(d, "keep"), ["--orient", "keep"], args.repeats)
        rep = g.pop("report", None) or {}
        gk.pop("report", None)
        r = {"file": os.path.relpath(path, ROOT) if path.startswith(ROOT) else path, "scale": scale, "gen": g,
             "gen_keep": gk}
        recs[name] = r
        if g.get("error") or gk.get("error"):
            log(f"  {name}: generator FAILED: {(g.get('error') or gk.get('error'))[:300]}")
            continue
        r["triangles"] = (rep.get("input") or {}).get("triangles")
        r["pose"] = (rep.get("placement") or {}).get("decided_by")
        model_stl = os.path.join(d, "keep", name + ".model.stl")
        r["model_sha256"] = file_sha256(model_stl)
        log(f"  {name}: auto CPU {g['cpu_s']:.3f} s (runs {g['cpu_s_all']}), wall {g['wall_s']:.2f} s; keep CPU "
            f"{gk['cpu_s']:.3f} s; load {g['loadavg_all']}")
        prev = previous.get(name) or {}
        if args.reuse_cura and prev.get("model_sha256") == r["model_sha256"] and prev.get("slices"):
            # The same placed model (same bytes) was sliced by an earlier run: its Cura numbers hold.
            r["slices"] = prev["slices"]
            r["cura_from"] = prev.get("cura_from") or previous.get("_stamp_date")
            continue
        r["slices"] = {}
        for key, support in (("cura_none", "none"), ("cura_tree", "tree")):
            for _ in range(args.slice_repeats or args.repeats):
                jobs.append((r["slices"], key, "cura", support, model_stl, name))
    return recs, jobs


def derive_speed(r):
    """Cura tree's overhead (median tree slice - median no-support slice, CPU and wall) over our
    generation (median of the runs, CPU and wall)."""
    sl = {k: slice_summary(v) for k, v in (r.get("slices") or {}).items()}
    g = r.get("gen") or {}
    d = {}
    for unit, field, ours in (("cpu", "cpu_s", g.get("cpu_s")), ("wall", "slice_seconds", g.get("wall_s"))):
        ct, cn = (sl.get("cura_tree") or {}).get(field), (sl.get("cura_none") or {}).get(field)
        over = ct - cn if ct is not None and cn is not None else None
        d[f"cura_tree_overhead_{unit}_s"] = over
        d[f"ratio_{unit}"] = over / ours if over is not None and ours else None
    ok = (r.get("gen_keep") or {}).get("cpu_s")
    over = d.get("cura_tree_overhead_cpu_s")
    d["ratio_keep_cpu"] = over / ok if over is not None and ok else None
    d["slice_load"] = median([x.get("loadavg") for v in (r.get("slices") or {}).values() for x in v])
    d["gen_load"] = median(g.get("loadavg_all") or [])
    return d


def write_speed(out, sp):
    L = ["# Speed: generation (orientation search included) against Cura tree's overhead", "",
         stamp_md(sp["stamp"]), "",
         "Issue 29's target: generation at least "
         f"{SPEED_TARGET_MEDIAN:g}x faster than Cura tree's overhead at the median and at least {SPEED_TARGET_EACH:g}x on "
         "every model of the benchmark set. *Ours*: `clever-support MODEL --scale S --orient auto` (the default: the "
         "orientation search, the tree, the columns baseline and every output written), user + system CPU seconds of "
         "the process (the children's rusage), median of the runs; *pose kept*: the same with `--orient keep`. "
         "*Cura tree overhead*: CuraEngine 4.13 on the placed "
         "`<name>.model.stl` of the `--orient keep` run (the benchmark set's pose: Cura has no orientation search, "
         "and the pose ours picks may need no support at all), CPU of the slice with tree support minus "
         "CPU of the slice without support (medians; slice.py's own start-up cancels), same profile. CPU is the fair "
         "measure on this shared 2-core machine (CuraEngine runs at nice 10; wall times stretch with foreign load); "
         "the wall-time ratio is given beside it. *load*: the 1-minute load average when each run started "
         "(median over the runs).", ""]
    L += [f"- note: {n}" for n in sp.get("notes", [])]
    L += ["", "| model | triangles | our pose | our CPU s | our CPU s, each run | our wall s | load (ours) | our CPU s, pose "
          "kept | Cura tree overhead CPU s | Cura tree overhead wall s | load (Cura) | speed-up (CPU) | speed-up (wall) | "
          "speed-up, pose kept (CPU) |",
          "|---|---:|---|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|"]
    ratios = []
    for name, r in sp.get("models", {}).items():
        g = r.get("gen") or {}
        if g.get("error"):
            L.append(f"| {name} | error: {g['error'][:200]} |||||||||||")
            continue
        d = derive_speed(r)
        if d.get("ratio_cpu") is not None:
            ratios.append((d["ratio_cpu"], name))
        src = f" (sliced {r['cura_from']})" if r.get("cura_from") else ""
        L.append(f"| {name} | {r.get('triangles')} | {r.get('pose') or '–'} | {f_num(g.get('cpu_s'), '{:.3f}')} | "
                 f"{', '.join(f_num(x, '{:.3f}') for x in g.get('cpu_s_all') or [])} | {f_num(g.get('wall_s'))} | "
                 f"{f_num(d.get('gen_load'), '{:.1f}')} | {f_num((r.get('gen_keep') or {}).get('cpu_s'), '{:.3f}')} | "
                 f"{f_num(d.get('cura_tree_overhead_cpu_s'))}{src} | "
                 f"{f_num(d.get('cura_tree_overhead_wall_s'))} | {f_num(d.get('slice_load'), '{:.1f}')} | "
                 f"{f_num(d.get('ratio_cpu'), '{:.1f}x')} | {f_num(d.get('ratio_wall'), '{:.1f}x')} | "
                 f"{f_num(d.get('ratio_keep_cpu'), '{:.1f}x')} |")
    if ratios:
        med = statistics.median([x for x, _ in ratios])
        worst = min(ratios)
        L += ["", f"Speed-up in CPU seconds over {len(ratios)} models: **median {med:.1f}x** (target >= "
              f"{SPEED_TARGET_MEDIAN:g}x: {'met' if med >= SPEED_TARGET_MEDIAN else 'NOT met'}), **worst {worst[0]:.1f}x** "
              f"({worst[1]}; target >= {SPEED_TARGET_EACH:g}x on every model: "
              f"{'met' if worst[0] >= SPEED_TARGET_EACH else 'NOT met on ' + ', '.join(n for x, n in sorted(ratios) if x < SPEED_TARGET_EACH)})."]
    stages = sorted({k for r in sp.get("models", {}).values() for k in ((r.get("gen") or {}).get("seconds_stages") or {})})
    if stages:
        L += ["", "Per-stage wall seconds of our runs (the report's `seconds`, median over the runs; the orientation "
              "search runs its candidate poses on all cores, so its wall seconds are below its CPU seconds):", "",
              "| model | " + " | ".join(stages) + " |", "|---|" + "---:|" * len(stages)]
        for name, r in sp.get("models", {}).items():
            ss = (r.get("gen") or {}).get("seconds_stages") or {}
            L.append(f"| {name} | " + " | ".join(f_num(ss.get(k), "{:.3f}") for k in stages) + " |")
    L += ["", "Reproduce: `nice -n 10 python3 bench/run_bench.py --speed --jobs 1` (add `--models a,b` for a "
          "subset; `--reuse-cura` keeps an earlier run's Cura slices of a byte-identical placed model)."]
    open(os.path.join(out, "speed.md"), "w").write("\n".join(L) + "\n")


def finish_orientation(results, do_main):
    orr = results.get("orientation") or {}
    for name, r in orr.get("models", {}).items():
        if r.get("error"):
            continue
        for pose in ("auto", "keep"):
            x = r.get(pose) or {}
            mm = (results.get("models") or {}).get(name)
            if pose == "keep" and do_main and mm:
                d = mm.get("derived") or derive_model(mm)
                sl = d["slices"]
                x["support_volume_mm3"] = d["mesh_volume_mm3"]["tree"]
                x["grams"] = sl.get("ours_tree_cura", {}).get("grams")
                none = sl.get("cura_none", {}).get("grams")
            else:
                s = {k: slice_summary(v) for k, v in x.get("slices", {}).items()}
                x["grams"] = s.get("ours_tree_cura", {}).get("grams")
                none = s.get("cura_none_model", {}).get("grams")
            x["support_g"] = x["grams"] - none if x.get("grams") is not None and none is not None else None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help="bridge, u_overhang, extruder_idler, arches; no scaling/orient")
    ap.add_argument("--models", help="comma-separated model names (overrides the set)")
    ap.add_argument("--validation", action="store_true",
                    help="only the validation parts (bench/validation/*.stl, scale 1): reported apart from the tuning set")
    ap.add_argument("--out", help="results dir (default bench/results, or bench/results/quick with --quick)")
    ap.add_argument("--work", default=os.path.join(HERE, "work"), help="scratch dir (default bench/work, gitignored)")
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "generator", "clever-support"))
    ap.add_argument("--repeats", type=int, default=3, help="runs per timing (median quoted)")
    ap.add_argument("--slice-repeats", type=int, help="runs of the timed Cura slices (default: --repeats)")
    ap.add_argument("--jobs", type=int, default=2, help="slices at a time (default 2)")
    ap.add_argument("--scaling", action="store_true", help="run the scaling series (on by default in full mode)")
    ap.add_argument("--orient", action="store_true", help="run the orientation comparison (on by default in full mode)")
    ap.add_argument("--no-main", action="store_true", help="skip the per-model table (e.g. --no-main --scaling)")
    ap.add_argument("--no-scaling", action="store_true")
    ap.add_argument("--no-orient", action="store_true")
    ap.add_argument("--slices", help="only these slice keys (e.g. cura_none,cura_tree for a timing run)")
    ap.add_argument("--speed", action="store_true",
                    help="only the speed section (issue 29): generation with --orient auto vs Cura tree's overhead on "
                         "the benchmark set (results/speed.md)")
    ap.add_argument("--scan-5m", action="store_true",
                    help="only the 5M-triangle scan of the scaling section (issue 29: < 60 s, < 4 GiB): results/scan_5m.md")
    ap.add_argument("--reuse-cura", action="store_true",
                    help="with --speed: keep the Cura slices of the last speed run for models whose placed model is "
                         "byte-identical")
    ap.add_argument("--report-only", action="store_true", help="rewrite the .md files and chart from results.json")
    ap.add_argument("--slice-timeout", type=int, default=3600)
    ap.add_argument("--gen-timeout", type=int, default=1800)
    ap.add_argument("--long-run", type=float, default=120,
                    help="generator runs longer than this (s) are not repeated (default 120)")
    args = ap.parse_args()
    args.bin = os.path.abspath(args.bin)
    out = os.path.abspath(args.out or (os.path.join(HERE, "results", "quick") if args.quick else
                                       os.path.join(HERE, "results", "validation") if args.validation else
                                       os.path.join(HERE, "results")))
    os.makedirs(out, exist_ok=True)
    res_path = os.path.join(out, "results.json")

    if args.report_only:
        results = json.load(open(res_path))
        notes = results.setdefault("notes", [])
        for m in (results.get("models") or {}).values():
            m["derived"] = derive_model(m)
        if results.get("orientation"):
            finish_orientation(results, bool(results.get("models")))
        with open(res_path + ".tmp", "w") as f:  # keep the derived numbers next to the raw ones
            json.dump(results, f, indent=1, default=str)
        os.replace(res_path + ".tmp", res_path)
        if results.get("models"):
            write_table(out, results)
            write_chart(out, results, notes)
        if results.get("scaling"):
            write_scaling(out, results["scaling"])
        if results.get("orientation"):
            finish_orientation(results, bool(results.get("models")))
            write_orientation(out, results["orientation"])
        if results.get("speed"):
            write_speed(out, results["speed"])
        if results.get("scan_5m"):
            write_scan_5m(out, results["scan_5m"])
        return 0

    if not os.path.exists(args.bin):
        print(f"generator not found: {args.bin} (build with scripts/build.sh or pass --bin)", file=sys.stderr)
        return 2
    do_main = not args.no_main and not args.speed and not args.scan_5m
    small = args.quick or args.validation or args.speed or args.scan_5m  # the validation run is per model only, like --quick
    do_scaling = (args.scaling or not small) and not args.no_scaling
    do_orient = (args.orient or not small) and not args.no_orient
    t_start = time.perf_counter()
    st = stamp(args)
    notes = []
    models = model_list(args, notes)
    work = os.path.abspath(args.work)
    # No caching across runs: the scratch dir is wiped.
    for sub in ("models", "orient", "scaling", "speed"):
        shutil.rmtree(os.path.join(work, sub), ignore_errors=True)
    os.makedirs(work, exist_ok=True)

    results = {}
    owned = []
    if do_main:
        results.update(stamp=st, models={}, notes=notes, mode="quick" if args.quick else "validation" if args.validation else "full")
        owned += ["stamp", "models", "notes", "mode", "elapsed_s"]
    if do_scaling:
        owned.append("scaling")
    if do_orient:
        owned.append("orientation")
    if args.speed:
        owned.append("speed")
    if args.scan_5m:
        owned.append("scan_5m")
    if not do_main and notes:
        results["notes_" + "_".join(owned)] = notes
        owned.append("notes_" + "_".join(owned))
    saver = Saver(res_path, results, owned)
    log(f"{len(models)} models; main={do_main} scaling={do_scaling} orient={do_orient}; results -> {out}")

    def run_slices(jobs):
        """Slices `jobs` at a time. CuraEngine and PrusaSlicer are essentially single-threaded here
        (user time ~ wall time), so two at a time on two cores do not slow each other much."""
        if not jobs:
            return
        log(f"slicing: {len(jobs)} slices, {args.jobs} at a time")
        done = [0]

        def work_one(job):
            container, key, slicer, support, stl, name = job
            r = run_slice(args, slicer, support, stl)
            with _lock:
                container.setdefault(key, []).append(r)
                done[0] += 1
                k = done[0]
            if "error" in r:
                log(f"  [{k}/{len(jobs)}] {name} {key}: ERROR {r['error'][:200]}")
            else:
                log(f"  [{k}/{len(jobs)}] {name} {key}: {r['grams']:.2f} g, {r['print_time_s'] / 60:.0f} min, "
                    f"slice {r['slice_seconds']:.1f} s")
            saver.save()

        with cf.ThreadPoolExecutor(max_workers=args.jobs) as ex:
            futs = [ex.submit(work_one, j) for j in jobs]
            for f in cf.as_completed(futs):
                if f.exception():
                    log("slice job crashed: " + "".join(traceback.format_exception(f.exception()))[-500:])

    # 1. Per-model table. Generator runs first, serially (no slice of ours running: clean timings),
    #    then the slices.
    if do_main:
        slice_jobs = []  # (container dict, key, slicer, support, stl, model name)
        for name, path, scale, src in models:
            m = {"file": os.path.relpath(path, ROOT) if path.startswith(ROOT) else path, "scale": scale, "source": src,
                 "slices": {}}
            results["models"][name] = m
            d = os.path.join(work, "models", name)
            log(f"generate {name} (x{args.repeats})")
            m["gen_tree"] = timed_generation(args, path, scale, os.path.join(d, "tree"), ["--orient", "keep"], args.repeats)
            m["gen_columns"] = timed_generation(args, path, scale, os.path.join(d, "columns"),
                                                ["--orient", "keep", "--strategy", "columns"], 1)
            for k in ("gen_tree", "gen_columns"):  # drop the bulky per-candidate lists
                rep = (m.get(k) or {}).get("report")
                if rep and "placement" in rep:
                    rep["placement"].pop("candidates", None)
            stl = {}
            for kind in ("tree", "columns"):
                g = m["gen_" + kind]
                if g.get("error"):
                    log(f"  {name} {kind}: generator FAILED: {g['error'][:300]}")
                    continue
                base = os.path.join(d, kind, name)
                stl[kind] = base + ".supported.stl"
                if kind == "tree":
                    stl["model"] = base + ".model.stl"
                m["check_" + kind] = run_check(args, base + ".model.stl", base + ".supports.stl")
                c = m["check_" + kind]
                log(f"  {name} {kind}: {g.get('seconds_total', 0):.3f} s, peak {(g.get('peak_kb') or 0) / 1024:.0f} MB, "
                    f"coverage {c.get('coverage')}, check ok={c.get('ok')}")
            if "columns" in stl and "model" not in stl:
                stl["model"] = os.path.join(d, "columns", name + ".model.stl")
            for key, slicer, support, which, timed in SLICES:
                if which not in stl or (args.slices and key not in args.slices.split(",")):
                    continue
                for _ in range((args.slice_repeats or args.repeats) if timed else 1):
                    slice_jobs.append((m["slices"], key, slicer, support, stl[which], name))
        saver.save()
        # The columns baseline slices last: they are the slowest (hundreds of separate columns) and the
        # least important; an interrupted run then still has every model's main numbers.
        slice_jobs.sort(key=lambda j: j[1].startswith("ours_columns"))
        run_slices(slice_jobs)
        for name, m in results["models"].items():
            m["derived"] = derive_model(m)
        write_table(out, results)
        write_chart(out, results, notes)
        saver.save()

    # 1b. Speed: the benchmark set (shared models) with the orientation search, then Cura's slices.
    if args.speed:
        try:
            old = json.load(open(res_path)).get("speed") or {}
        except Exception:
            old = {}
        previous = dict(old.get("models") or {}, _stamp_date=(old.get("stamp") or {}).get("date"))
        sp = {"stamp": st, "notes": notes}
        results["speed"] = sp
        shared_only = [m for m in models if m[3] == "shared" or args.models]
        sp["models"], jobs = speed_generate(args, work, shared_only, previous)
        saver.save()
        run_slices(jobs)
        for r in sp["models"].values():
            r["derived"] = derive_speed(r)
        write_speed(out, sp)
        saver.save()

    # 1c. The 5M-triangle scan alone.
    if args.scan_5m:
        scales = {os.path.splitext(m["file"])[0]: m["scale"] for m in json.load(open(os.path.join(SHARED, "benchmark.json")))["models"]}
        results["scan_5m"] = {"stamp": st, "big": [scan_5m_case(args, work, scales)]}
        write_scan_5m(out, results["scan_5m"])
        saver.save()

    # 2. Scaling (generator only).
    if do_scaling:
        results["scaling"] = scaling_section(args, work, st)
        write_scaling(out, results["scaling"])
        saver.save()

    # 3. Orientation: generator runs (serial), then their slices.
    if do_orient:
        orr = {"stamp": st, "models": {}}
        results["orientation"] = orr
        slice_jobs = []
        for name, path, scale, src in models:
            r = {}
            orr["models"][name] = r
            log(f"orient auto {name}")
            g = timed_generation(args, path, scale, os.path.join(work, "orient", name), ["--orient", "auto"],
                                 1 if args.quick else args.repeats)
            if g.get("error"):
                r["error"] = g["error"]
                r["cmd"] = g["cmd"]
                continue
            rep = g["report"]
            base = os.path.join(work, "orient", name, name)
            chk = run_check(args, base + ".model.stl", base + ".supports.stl")
            pl = rep.get("placement", {})
            r["auto"] = {"support_volume_mm3": rep["supports"]["support_volume_mm3"],
                         "orient_s": g["seconds_stages"].get("orient"), "orient_s_runs": g["ok_runs"],
                         "seconds_total": g["seconds_total"], "wall_s": g["wall_s"],
                         "pose": pl.get("decided_by") or pl.get("orientation"),
                         "rotation": pl.get("rotation"), "coverage": chk.get("coverage"),
                         "check_ok": chk.get("ok"), "cmd": g["cmd"], "slices": {}}
            log(f"  {name}: orient {r['auto']['orient_s']:.2f} s, support {r['auto']['support_volume_mm3']:.0f} mm3")
            r["keep"] = {"slices": {}}
            slice_jobs.append((r["auto"]["slices"], "cura_none_model", "cura", "none", base + ".model.stl", name))
            slice_jobs.append((r["auto"]["slices"], "ours_tree_cura", "cura", "none", base + ".supported.stl", name))
            if not (do_main and name in results.get("models", {})):  # keep numbers need their own run
                kd = os.path.join(work, "orient", name + "_keep")
                gk = timed_generation(args, path, scale, kd, ["--orient", "keep"], 1)
                if gk.get("error"):
                    r["keep"]["error"] = gk["error"]
                else:
                    r["keep"]["support_volume_mm3"] = gk["report"]["supports"]["support_volume_mm3"]
                    slice_jobs.append((r["keep"]["slices"], "cura_none_model", "cura", "none", os.path.join(kd, name + ".model.stl"), name))
                    slice_jobs.append((r["keep"]["slices"], "ours_tree_cura", "cura", "none", os.path.join(kd, name + ".supported.stl"), name))
            saver.save()
        run_slices(slice_jobs)
        finish_orientation(results, do_main)
        write_orientation(out, orr)
    results["elapsed_s"] = time.perf_counter() - t_start
    saver.save()
    log(f"done in {results['elapsed_s']:.0f} s; see {out}/")
    return 0


if __name__ == "__main__":
    sys.exit(main())

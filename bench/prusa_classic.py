#!/usr/bin/python3
"""Our .prusa.3mf under PrusaSlicer's two perimeter generators: body layers left out, support time and filament.

usage: bench/prusa_classic.py --before OLD_BIN [--bin build/generator/clever-support] [--models SPEC,...]
                              [--validation] [--work DIR] [--out bench/results] [--stem prusa_classic] [--jobs 2]

PrusaSlicer's default perimeter generator is Arachne; many users pick the classic one
(perimeter_generator = classic, a per-object setting, so never ours to set). Per model (SPEC as in
handoff.py: a shared model's name at its benchmark.json scale, PATH, PATH@SCALE or PATH@<N>mm;
--validation: bench/validation's parts and the five examples at 80 mm), both binaries generate
the supports (--orient keep, tree), and PrusaSlicer slices, with bench/slicers/profile.json, under
Arachne and under classic: the bare model, the --before binary's .prusa.3mf and the --bin binary's.
Support time and filament are the 3MF's minus the bare model's, same generator and run;
*dropped* counts the body layers left out (slicers/printed_bodies.py, of all body layers).
--set KEY=VALUE adds a PrusaSlicer setting to every slice (e.g. thin_walls=0, as Prusa's own
printer presets have it). Writes <out>/<stem>.json and .md.
"""
import argparse
import concurrent.futures as cf
import datetime
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
sys.path.insert(0, HERE)
sys.path.insert(0, os.path.join(HERE, "slicers"))
sys.dont_write_bytecode = True
import handoff  # noqa: E402  (model specs and the validation set, as handoff.py reads them)
import printed_bodies  # noqa: E402

GENERATORS = ("arachne", "classic")
BED_MM = handoff.BED_MM


def generate(binary, path, scale, out):
    name = os.path.splitext(os.path.basename(path))[0]
    subprocess.run(["nice", "-n", "10", binary, path, "--scale", repr(scale), "--orient", "keep", "--strategy", "tree",
                    "--out", out, "--no-timings", "-q"], check=True, capture_output=True, timeout=900)
    return os.path.join(out, name)


def slice_prusa(inp, out_dir, generator, settings):
    sets = sum((["--set", "%s=%s" % kv] for kv in dict(settings, perimeter_generator=generator).items()), [])
    p = subprocess.run(["nice", "-n", "10", sys.executable, handoff.SLICE_PY, "--slicer", "prusa", "--support", "none",
                        "--json", "--out-dir", out_dir] + sets + [inp], capture_output=True, text=True)
    if p.returncode:
        raise RuntimeError("%s: %s" % (inp, p.stderr[-500:]))
    return json.loads(p.stdout)


def measure_model(args, name, path, scale, settings):
    work = os.path.join(args.work, name)
    stems = {"before": generate(args.before, path, scale, os.path.join(work, "before")),
             "after": generate(args.bin, path, scale, os.path.join(work, "after"))}
    jobs = {}
    with cf.ThreadPoolExecutor(args.jobs) as ex:
        for gen in GENERATORS:
            jobs[("none", gen)] = ex.submit(slice_prusa, stems["after"] + ".model.stl",
                                            os.path.join(work, "none-" + gen), gen, settings)
            for which, stem in stems.items():
                jobs[(which, gen)] = ex.submit(slice_prusa, stem + ".prusa.3mf",
                                               os.path.join(work, which + "-" + gen), gen, settings)
        res = {k: f.result() for k, f in jobs.items()}
    rows = {}
    for gen in GENERATORS:
        none = res[("none", gen)]
        for which, stem in stems.items():
            r = res[(which, gen)]
            gcode = os.path.join(work, which + "-" + gen, "out.gcode")
            pb = printed_bodies.measure(gcode, stem + ".supports.stl", stem + ".model.stl", float(BED_MM[0]),
                                        float(BED_MM[1]))
            rows[which + "/" + gen] = {"dropped": pb["dropped"], "body_layers": pb["body_layers"],
                                       "support_s": r["print_time_s"] - none["print_time_s"],
                                       "support_g": r["grams"] - none["grams"],
                                       "dropped_examples": pb["dropped_examples"][:3]}
    for d in os.listdir(work):  # keep the commands and settings, not the bulky G-code
        g = os.path.join(work, d, "out.gcode")
        if os.path.exists(g):
            os.remove(g)
    return rows


def report_md(data):
    L = ["# Our .prusa.3mf under PrusaSlicer's Arachne and classic perimeters (bench/prusa_classic.py)", "",
         "_Run %s; before: `%s`, after: `%s` (git commit `%s`)._" % (data["stamp"], data["before"], data["bin"],
                                                                     data["commit"]), "",
         "PrusaSlicer 2.5, bench/slicers/profile.json%s. *Dropped*: body layers left out of all "
         "(slicers/printed_bodies.py). *s*, *g*: support time and filament, the 3MF minus the bare model sliced "
         "under the same generator in the same run." % (
             (" plus " + ", ".join("`%s=%s`" % kv for kv in data["settings"].items())) if data["settings"] else ""),
         "",
         "| model | scale | Arachne dropped before → after | classic dropped before → after | Arachne s | Arachne g "
         "| classic s | classic g |",
         "|---|---:|---|---|---:|---:|---:|---:|"]
    for name, m in data["models"].items():
        r = m["rows"]
        cell = lambda gen: "%d → %d of %d (%.1f %%)" % (  # noqa: E731
            r["before/" + gen]["dropped"], r["after/" + gen]["dropped"], r["after/" + gen]["body_layers"],
            100.0 * r["before/" + gen]["dropped"] / max(1, r["before/" + gen]["body_layers"]))
        nums = lambda gen, k, f: "%s → %s" % (f % r["before/" + gen][k], f % r["after/" + gen][k])  # noqa: E731
        L.append("| %s | %.4g | %s | %s | %s | %s | %s | %s |" % (
            name, m["scale"], cell("arachne"), cell("classic"), nums("arachne", "support_s", "%.0f"),
            nums("arachne", "support_g", "%.2f"), nums("classic", "support_s", "%.0f"),
            nums("classic", "support_g", "%.2f")))
    return "\n".join(L) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--before", required=True, help="the clever-support binary to compare with")
    ap.add_argument("--bin", default=os.path.join(ROOT, "build", "generator", "clever-support"))
    ap.add_argument("--models", default="", help="comma-separated specs, as handoff.py --models")
    ap.add_argument("--validation", action="store_true", help="bench/validation's parts and the examples at 80 mm")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--work", default=os.path.join(ROOT, "build", "bench-prusa-classic"))
    ap.add_argument("--out", default=os.path.join(HERE, "results"))
    ap.add_argument("--stem", default="prusa_classic")
    ap.add_argument("--jobs", type=int, default=2)
    args = ap.parse_args()
    settings = dict(kv.split("=", 1) for kv in args.set)
    bench = {os.path.splitext(m["file"])[0]: (os.path.join(handoff.SHARED, m["file"]), float(m["scale"]))
             for m in json.load(open(os.path.join(handoff.SHARED, "benchmark.json")))["models"]}
    specs = (handoff.validation_specs() if args.validation else []) + [s for s in args.models.split(",") if s]
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "HEAD"], capture_output=True, text=True).stdout.strip()
    data = {"stamp": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"), "commit": commit,
            "before": args.before, "bin": args.bin, "settings": settings, "models": {}}
    os.makedirs(args.out, exist_ok=True)
    for spec in specs:
        name, path, scale, _ = handoff.model_entry(spec, bench)
        data["models"][name] = {"scale": scale, "rows": measure_model(args, name, path, scale, settings)}
        print(report_md(data).splitlines()[-1], flush=True)
        json.dump(data, open(os.path.join(args.out, args.stem + ".json"), "w"), indent=1)
        open(os.path.join(args.out, args.stem + ".md"), "w").write(report_md(data))
    return 0


if __name__ == "__main__":
    sys.exit(main())

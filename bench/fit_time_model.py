#!/usr/bin/env python3
"""Fits the tree prices of the generator's slicer time model (generator/core/slicer_time.hpp) to G-code.

usage: bench/fit_time_model.py TUNING.json [CHECK.json ...]
       bench/fit_time_model.py --walls TUNING.json [CHECK.json ...]
       bench/fit_time_model.py --rest TUNING.json [CHECK.json ...]

TUNING.json is a hand-off run of the tuning set (bench/handoff.py --tuning): for every model it holds
what the generator counted for its tree (report: slicer_estimate island_layers, outline_mm, travel_mm)
and the seconds the supports added in each slicer's G-code (route minus the bare model). Per route
(cura_ours_mesh, prusa_ours_3mf) it fits

    added seconds = island_s * island_layers + outline_s_per_mm * outline_mm + hop_s_per_mm * travel_mm

by least squares on the relative error (every model weighs the same), prints the three prices and,
for TUNING.json and each CHECK.json (e.g. the validation run, never fitted on), the estimate over the
G-code per model with its median and worst.

With --rest the tree's prices are fitted to the G-code's seconds less those it spends on our walls
(the route's "walls" of handoff.py, slicers/wall_time.py): without it, on a walled model the tree's
terms also pay for the walls.

With --walls it fits the price of a wall island instead (SlicerRoute::wall_island_s): per route, the
seconds the G-code spends on our walls (slicers/wall_time.py, recorded by handoff.py as the route's
"walls") against the report's walls (slicer_estimate.walls: their lines' seconds on the route, which
are physics, and their island-layers):

    wall seconds = line_seconds + wall_island_s * island_layers

least squares on the relative error, over the models that have walls.
"""
import json
import math
import statistics
import sys

ROUTES = ("cura_ours_mesh", "prusa_ours_3mf")
TERMS = ("island_layers", "outline_mm", "travel_mm")


def rows(path, route, rest=False):
    """(name, the tree's terms, G-code seconds) per model; with rest, the seconds the G-code spends on
    the walls (slicers/wall_time.py, the route's "walls") are taken out: the tree's own seconds."""
    out = []
    for name, m in json.load(open(path))["models"].items():
        est = m.get("gen", {}).get("tree", {}).get("slicer_estimate")
        d = m.get("derived", {}).get(route)
        if est and d and d.get("support_min"):
            walls = (m.get("slices", {}).get(route) or {}).get("walls") if rest else None
            out.append((name, [est[t] for t in TERMS], d["support_min"] * 60 - (walls["wall_s"] if walls else 0)))
    return out


def solve(a, b):
    """Gauss-Jordan with partial pivoting (no numpy on the bench machine)."""
    n = len(a)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for i in range(n):
        p = max(range(i, n), key=lambda k: abs(m[k][i]))
        m[i], m[p] = m[p], m[i]
        for k in range(n):
            if k != i:
                f = m[k][i] / m[i][i]
                m[k] = [x - f * y for x, y in zip(m[k], m[i])]
    return [m[i][n] / m[i][i] for i in range(n)]


def fit(data):
    k = len(TERMS)
    w = [1 / t for _, _, t in data]
    a = [[sum(wr * wr * x[i] * x[j] for wr, (_, x, _) in zip(w, data)) for j in range(k)] for i in range(k)]
    b = [sum(wr * wr * x[i] * t for wr, (_, x, t) in zip(w, data)) for i in range(k)]
    return solve(a, b)


def report(label, data, prices):
    ratios = [(name, sum(p * v for p, v in zip(prices, x)) / t) for name, x, t in data]
    if not ratios:
        return
    rs = [r for _, r in ratios]
    # a fit with a negative price can estimate below zero: that is the worst
    worst = max(ratios, key=lambda nr: abs(math.log(nr[1])) if nr[1] > 0 else math.inf)
    print(f"  {label}: estimate / G-code median {statistics.median(rs):.2f}, worst {worst[1]:.2f} ({worst[0]})")
    print("    " + ", ".join(f"{n} {r:.2f}" for n, r in ratios))


def wall_rows(path, route):
    out = []
    report_route = {"cura_ours_mesh": "cura_support_mesh", "prusa_ours_3mf": "prusa_3mf"}[route]
    for name, m in json.load(open(path))["models"].items():
        est = (m.get("gen", {}).get("tree", {}).get("slicer_estimate") or {}).get("walls")
        g = (m.get("slices", {}).get(route) or {}).get("walls")
        if est and g and g["wall_s"] > 0 and est["island_layers"] > 0:
            out.append((name, est["routes"][report_route]["line_seconds"], est["island_layers"], g["wall_s"]))
    return out


def fit_walls(paths):
    for route in ROUTES:
        data = wall_rows(paths[0], route)
        if not data:
            print(f"{route}: no model with walls")
            continue
        # minimise sum(((line + b * islands) / t - 1)^2) over b
        b = (sum(y / t * (1 - x / t) for _, x, y, t in data) / sum((y / t) ** 2 for _, x, y, t in data))
        print(f"{route}: {len(data)} models with walls; wall_island_s {b:.4f}")
        for path in paths:
            rows = wall_rows(path, route)
            if not rows:
                continue
            rs = [(n, (x + b * y) / t, x / t) for n, x, y, t in rows]
            print(f"  {path}: wall estimate / G-code median {statistics.median(r for _, r, _ in rs):.2f} "
                  f"(lines alone {statistics.median(r for _, _, r in rs):.2f})")
            print("    " + ", ".join(f"{n} {r:.2f}" for n, r, _ in rs))


def main(paths):
    if paths and paths[0] == "--walls":
        return fit_walls(paths[1:])
    rest = bool(paths) and paths[0] == "--rest"
    if rest:
        paths = paths[1:]
    for route in ROUTES:
        data = rows(paths[0], route, rest)
        if len(data) < len(TERMS):
            print(f"{route}: {len(data)} models, too few to fit")
            continue
        prices = fit(data)
        print(f"{route}: {len(data)} models; island_s {prices[0]:.4f}, outline_s_per_mm {prices[1]:.4f}, "
              f"hop_s_per_mm {prices[2]:.4f}")
        report(paths[0], data, prices)
        for path in paths[1:]:
            report(path, rows(path, route, rest), prices)


if __name__ == "__main__":
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    main(sys.argv[1:])

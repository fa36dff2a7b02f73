#!/usr/bin/python3
"""Where a G-code's minutes go: extrusion, travel, retractions and the starts and stops, from the moves.

usage: gcode_time.py out.gcode[.gz] [SLICER_SECONDS]   (prints one JSON object)

Both slicers' own estimates (CuraEngine 4.13's TimeEstimateCalculator, PrusaSlicer 2.5's GCodeProcessor)
replay the moves through a Marlin-style planner: every move accelerates at the machine's acceleration
and the speed at a corner is limited by the jerk (the largest step in speed the firmware takes without
slowing down). This script replays the moves the same way (trapezoid per move, junction speeds from the
classic jerk rule, a backward and a forward pass over each layer) with the profile's machine
(bench/slicers/profile.json: 1500 mm/s^2, jerk 10 mm/s) and splits the time it finds into

* extrusion_s:    moves that extrude, each timed at its feedrate (length / F);
* travel_s:       moves that do not extrude (XY, with or without Z), at their feedrate;
* retraction_s:   moves of the filament alone (retract and prime), with their own acceleration;
* accel_s:        what acceleration and the corners add to extrusion and travel (time with the planner
                  minus time at feedrate): the starts and stops. A short outline never reaches its
                  feedrate, so this term grows with the number of islands and corners, not with the
                  length printed (accel_extrusion_s + accel_travel_s);
* other_s:        moves of Z alone (layer changes, lifts) and dwells.

The five add up to sim_s. The slicer's own estimate (slicer_s, from the G-code's header) differs from
sim_s by the residual (what the slicer models that this replay does not: Cura's per-layer planning,
PrusaSlicer's firmware limits on E, rounding).
"""
import json
import math
import re
import sys

from gcode_stats import Extruder, open_gcode

# The profile's machine (profile.json) and each slicer's default for what the profile leaves open:
# Cura's fdmprinter.def.json (machine_max_jerk_z 0.4, machine_max_jerk_e 5, feedrates unlimited);
# PrusaSlicer 2.5's machine limits (jerk z 0.2, e 2.5; max feedrate x/y 500, z 12, e 120 mm/s).
MACHINES = {
    "cura": {"accel": 1500.0, "jerk_xy": 10.0, "jerk_z": 0.4, "jerk_e": 5.0,
             "max_feed": (math.inf, math.inf, math.inf, math.inf)},
    "prusa": {"accel": 1500.0, "jerk_xy": 10.0, "jerk_z": 0.2, "jerk_e": 2.5, "max_feed": (500.0, 500.0, 12.0, 120.0)},
}
MIN_PLANNER_SPEED = 0.05  # mm/s: the speed a layer's plan starts and ends at (Marlin's MINIMUM_PLANNER_SPEED)
TERMS = ("extrusion_s", "travel_s", "retraction_s", "accel_extrusion_s", "accel_travel_s", "other_s")
EXTRUDE, TRAVEL, RETRACT, OTHER = range(4)

_WORD = re.compile(r"([GXYZEFPS])(-?[0-9.]+)")
_PRUSA_TIME = re.compile(r"estimated printing time \(normal mode\) = (.*)")




def prusa_seconds(text):
    """'1d 2h 3m 4s' -> seconds."""
    units = {"d": 86400, "h": 3600, "m": 60, "s": 1}
    return sum(float(n) * units[u] for n, u in re.findall(r"([0-9.]+)([dhms])", text))


def trapezoid_time(d, v0, v, v1, a):
    """Time to move d mm starting at v0, cruising at most at v, ending at v1, accelerating at a."""
    up = (v * v - v0 * v0) / (2 * a)
    down = (v * v - v1 * v1) / (2 * a)
    if up + down <= d:
        return (v - v0) / a + (d - up - down) / v + (v - v1) / a
    up = min(max((2 * a * d - v0 * v0 + v1 * v1) / (4 * a), 0.0), d)
    peak = math.sqrt(v0 * v0 + 2 * a * up)
    return (peak - v0) / a + (peak - v1) / a


def plan(blocks, m, terms, labels=None, by_label=None):
    """Times one layer's blocks [(kind, length, speed, (vx, vy, vz, ve))] and adds them to terms; with
    labels (one per block) also to by_label[label] (a dict of TERMS)."""
    n = len(blocks)
    if n == 0:
        return
    a = m["accel"]
    entry = [0.0] * (n + 1)
    entry[n] = MIN_PLANNER_SPEED
    prev = None
    for i, (_, d, v, vel) in enumerate(blocks):
        # classic jerk: from rest at most half a jerk; at a junction, the full speed scaled down so the
        # step in velocity stays within the jerk on XY, Z and E
        if prev is None:
            vj = min(m["jerk_xy"] / 2, v)
            if abs(vel[2]) > m["jerk_z"] / 2:
                vj = min(vj, m["jerk_z"] / 2)
            if abs(vel[3]) > m["jerk_e"] / 2:
                vj = min(vj, m["jerk_e"] / 2)
        else:
            pv, pvel = prev
            factor = 1.0
            xy = math.hypot(vel[0] - pvel[0], vel[1] - pvel[1])
            if xy > m["jerk_xy"]:
                factor = m["jerk_xy"] / xy
            dz, de = abs(vel[2] - pvel[2]), abs(vel[3] - pvel[3])
            if dz > m["jerk_z"]:
                factor = min(factor, m["jerk_z"] / dz)
            if de > m["jerk_e"]:
                factor = min(factor, m["jerk_e"] / de)
            vj = min(pv, v * factor)
        entry[i] = max(vj, MIN_PLANNER_SPEED)
        prev = (v, vel)
    for i in range(n - 1, -1, -1):  # backward: each move can still stop in time for the next
        lim = math.sqrt(entry[i + 1] ** 2 + 2 * a * blocks[i][1])
        if entry[i] > lim:
            entry[i] = lim
    for i in range(n):  # forward: no move ends faster than it could accelerate to
        lim = math.sqrt(entry[i] ** 2 + 2 * a * blocks[i][1])
        if entry[i + 1] > lim:
            entry[i + 1] = lim
    for i, (kind, d, v, _) in enumerate(blocks):
        t = trapezoid_time(d, min(entry[i], v), v, min(entry[i + 1], v), a)
        for into in (terms, by_label.setdefault(labels[i], {k: 0.0 for k in TERMS}) if labels else None):
            if into is None:
                continue
            if kind == EXTRUDE:
                into["extrusion_s"] += d / v
                into["accel_extrusion_s"] += t - d / v
            elif kind == TRAVEL:
                into["travel_s"] += d / v
                into["accel_travel_s"] += t - d / v
            elif kind == RETRACT:
                into["retraction_s"] += t
            else:
                into["other_s"] += t


def split(path, slicer_s=None, label_of=None):
    """The time split of one G-code (see the module's doc). slicer_s: the slicer's own estimate, when the
    G-code does not carry it (CuraEngine's command line leaves ;TIME: at a placeholder; slice.py reads
    the estimate from its log); PrusaSlicer's is read from the G-code's footer.
    label_of(section, (x0, y0), (x1, y1), z): a label for an extruding move (section: its ;TYPE:); each
    other move takes the label of the next extruding move on its layer (the travel, retraction and
    lift that lead to it), or of the last one where none follows. With it the result also holds
    by_label: {label: the TERMS of its moves}."""
    terms = {k: 0.0 for k in TERMS}
    labels, by_label = ([], {}) if label_of else (None, None)
    section = None

    def plan_layer():
        if labels is not None:  # moves before an extrusion take its label; trailing ones the last
            nxt = labels[-1] if labels else None
            for i in range(len(labels) - 1, -1, -1):
                if labels[i] is None:
                    labels[i] = nxt
                nxt = labels[i]
            last = None
            for i, lab in enumerate(labels):
                labels[i] = lab if lab is not None else last
                last = labels[i]
        plan(blocks, m, terms, labels, by_label)
    slicer = None
    x = y = z = 0.0
    f = 1500.0 / 60
    ext = Extruder()
    blocks = []
    m = None
    with open_gcode(path) as fh:
        for raw in fh:
            if raw.startswith(";"):
                if raw.startswith(";LAYER:"):
                    if m is not None and slicer == "cura":  # Cura plans each layer on its own
                        plan_layer()
                        blocks = []
                        labels = [] if label_of else None
                elif raw.startswith(";TYPE:"):
                    section = raw[6:].strip()
                elif raw.startswith(";FLAVOR:") or raw.startswith(";Generated with Cura"):
                    slicer, m = "cura", MACHINES["cura"]
                elif raw.startswith("; generated by PrusaSlicer"):
                    slicer, m = "prusa", MACHINES["prusa"]
                elif raw.startswith("; estimated printing time (normal mode)") and slicer_s is None:
                    slicer_s = prusa_seconds(_PRUSA_TIME.search(raw).group(1))
                continue
            code = raw.split(";", 1)[0].strip()
            if not code or ext.sets_mode(code):
                continue
            if code.startswith("G4"):
                w = dict(_WORD.findall(code))
                terms["other_s"] += float(w.get("S", 0)) + float(w.get("P", 0)) / 1000
                continue
            if not (code.startswith("G0") or code.startswith("G1")) or code.startswith(("G10", "G11")):
                continue
            w = dict(_WORD.findall(code))
            if "F" in w:
                f = float(w["F"]) / 60
            nx = float(w["X"]) if "X" in w else x
            ny = float(w["Y"]) if "Y" in w else y
            nz = float(w["Z"]) if "Z" in w else z
            de = ext.delta(w)
            dx, dy, dz = nx - x, ny - y, nz - z
            x, y, z = nx, ny, nz
            if m is None:
                continue
            xy = math.hypot(dx, dy)
            if xy > 0 or dz != 0:
                d = math.sqrt(xy * xy + dz * dz)
                kind = (EXTRUDE if de > 0 else TRAVEL) if xy > 0 else OTHER
            elif de != 0:
                d, kind = abs(de), RETRACT
            else:
                continue
            v = f
            for comp, limit in zip((dx, dy, dz, de), m["max_feed"]):  # each axis within its feedrate
                if comp != 0 and abs(comp) / d * v > limit:
                    v = limit * d / abs(comp)
            blocks.append((kind, d, v, (dx / d * v, dy / d * v, dz / d * v, de / d * v)))
            if labels is not None:
                labels.append(label_of(section, (x - dx, y - dy), (x, y), z) if kind == EXTRUDE else None)
    if m is not None:
        plan_layer()
    sim = sum(terms.values())
    terms["accel_s"] = terms["accel_extrusion_s"] + terms["accel_travel_s"]
    out = dict(terms, slicer=slicer, sim_s=sim, slicer_s=slicer_s,
               residual_s=(slicer_s - sim) if slicer_s is not None else None)
    if by_label is not None:
        out["by_label"] = by_label
    return out


if __name__ == "__main__":
    if len(sys.argv) not in (2, 3):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        sys.exit(2)
    print(json.dumps(split(sys.argv[1], float(sys.argv[2]) if len(sys.argv) == 3 else None), indent=1))

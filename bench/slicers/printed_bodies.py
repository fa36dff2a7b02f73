#!/usr/bin/python3
"""Which of our support bodies a slicer leaves out, layer by layer.

usage: printed_bodies.py out.gcode supports.stl model.stl BED_X BED_Y [REMOVED_FIRST_LAYERS]
       (prints one JSON object)

The sliced-volume ratio (filament / mesh volume) mixes two things: how much plastic a slicer puts
in a line (PrusaSlicer's rounded bead is 0.91 of width x height for a 0.5 mm wall) and whether a
strut is printed at all. This counts the second. Every body of supports.stl (each is its own
closed shell) is cut at the middle of every layer it spans; the cross-section is *printed* when
some extrusion of that layer passes inside it. A cross-section that meets another body's (a joint)
and has no extrusion inside is not counted against the slicer: the slicer prints the union, and a
strut's end inside a wider strut has no line of its own. What is left, a cross-section on its own
with no extrusion in it, is a strut the slicer dropped on that layer.

Placement: both bench routes put the model and supports, together, with the centre of their
bounding box in XY on the bed's centre (slice.py's place_groups for Cura; PrusaSlicer centres a
3MF object the same way), so G-code XY = mesh XY + (bed centre - that box's centre). The layer
height is slice.py's (0.2 mm, first layer too).

Removed first layers: when the model's first layer slices empty, CuraEngine's
remove_empty_first_layers drops it (and a support mesh's first layer with it) and prints every
later layer one layer lower; slice.py reports how many ("removed_empty_first_layers"). The G-code
layer at height z then holds the meshes' layer at z + that many layers, and the body layers in the
removed layers are counted apart ("in_removed_first_layers"), not as dropped.
"""
import collections
import json
import math
import re
import sys

import slice as S

LAYER_MM = 0.2
SAMPLE_MM = 0.1   # extrusion lines are tested at points this far apart
CELL_MM = 1.0     # hash grid for the points
# A body spans a layer when the layer's middle, where both slicers cut, lies inside it. An end face
# that lies on that middle (a tip standing a gap over a face at a layer's middle: wall_rack's at
# 14.7 mm) has no cross-section there, for any slicer; read back from the STL's 32-bit floats it
# lies a few 1e-7 mm to either side, so without this margin the bottom end of such a body counted
# as a layer the slicers left out and its top end did not.
END_ON_CUT_MM = 1e-4
_WORD = re.compile(r"([GXYZE])(-?[0-9.]+)")


def shells(tris):
    """Triangles grouped by shared vertices: one group per body."""
    parent = {}

    def find(a):
        while parent.setdefault(a, a) != a:
            parent[a] = parent[parent[a]]
            a = parent[a]
        return a
    keys = [[tuple(round(c, 6) for c in p) for p in t] for t in tris]
    for ks in keys:
        for k in ks[1:]:
            ra, rb = find(ks[0]), find(k)
            if ra != rb:
                parent[ra] = rb
    out = collections.defaultdict(list)
    for t, ks in zip(tris, keys):
        out[find(ks[0])].append(t)
    return list(out.values())


def section(tris, z, dx, dy):
    """Segments where the triangles cross the plane at z, moved by (dx, dy)."""
    segs = []
    for t in tris:
        pts = []
        for p, q in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            if (p[2] >= z) != (q[2] >= z):
                s = (z - p[2]) / (q[2] - p[2])
                pts.append((p[0] + s * (q[0] - p[0]) + dx, p[1] + s * (q[1] - p[1]) + dy))
        if len(pts) == 2:
            segs.append((pts[0], pts[1]))
    return segs


def inside(segs, x, y):
    """Even-odd test of a point against closed cross-section segments."""
    c = False
    for (x1, y1), (x2, y2) in segs:
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) / (y2 - y1) * (x2 - x1):
            c = not c
    return c


def extrusions_by_layer(path):
    """Points along every extruding move, keyed by the layer's top z (rounded to 0.01 mm). Moves
    before the first layer (a printer's start G-code, e.g. the purge line an Ender 3 draws at
    z = 0.3) do not count: both slicers mark where the layers begin (";LAYER:0" in Cura,
    ";LAYER_CHANGE" in PrusaSlicer)."""
    layers = collections.defaultdict(list)
    x = y = z = e = 0.0
    relative = False
    with open(path, errors="replace") as f:
        started = not any(line.startswith((";LAYER:", ";LAYER_CHANGE")) for line in f)
        f.seek(0)
        for raw in f:
            started = started or raw.startswith((";LAYER:", ";LAYER_CHANGE"))
            code = raw.split(";", 1)[0].strip()
            if not code:
                continue
            if code.startswith("M83"):
                relative = True
            elif code.startswith("M82"):
                relative = False
            elif code.startswith("G92"):
                m = re.search(r"E(-?[0-9.]+)", code)
                if m:
                    e = float(m.group(1))
            elif code.startswith(("G0", "G1")) and not code.startswith("G10"):
                w = dict(_WORD.findall(code))
                nx, ny = float(w.get("X", x)), float(w.get("Y", y))
                z = float(w.get("Z", z))
                de = 0.0
                if "E" in w:
                    ne = float(w["E"])
                    de = ne if relative else ne - e
                    e = e + ne if relative else ne
                if de > 0 and started:
                    n = max(1, int(math.hypot(nx - x, ny - y) / SAMPLE_MM))
                    pts = layers[round(z, 2)]
                    for i in range(n + 1):
                        pts.append((x + (nx - x) * i / n, y + (ny - y) * i / n))
                x, y = nx, ny
    return layers


def measure(gcode, supports_stl, model_stl, bed_x, bed_y, removed_first_layers=0):
    sup = S.read_stl(supports_stl)
    everything = sup + S.read_stl(model_stl)
    xs = [v[0] for t in everything for v in t]
    ys = [v[1] for t in everything for v in t]
    dx = bed_x / 2 - (min(xs) + max(xs)) / 2
    dy = bed_y / 2 - (min(ys) + max(ys)) / 2
    bodies = shells(sup)
    spans = [(min(v[2] for t in b for v in t), max(v[2] for t in b for v in t)) for b in bodies]
    layers = extrusions_by_layer(gcode)
    shift = removed_first_layers * LAYER_MM
    removed = sum(1 for k in range(removed_first_layers) for lo, hi in spans if lo + END_ON_CUT_MM < (k + 0.5) * LAYER_MM < hi - END_ON_CUT_MM)
    total = printed = joined = 0
    dropped = []
    for top, pts in sorted(layers.items()):
        mid = top - LAYER_MM / 2 + shift
        grid = collections.defaultdict(list)
        for p in pts:
            grid[(math.floor(p[0] / CELL_MM), math.floor(p[1] / CELL_MM))].append(p)
        cut = []
        for i, (lo, hi) in enumerate(spans):
            if lo + END_ON_CUT_MM < mid < hi - END_ON_CUT_MM:
                segs = section(bodies[i], mid, 0, 0)
                if segs:
                    bx = [q[0] for s in segs for q in s]
                    by = [q[1] for s in segs for q in s]
                    cut.append((i, segs, (min(bx), min(by), max(bx), max(by))))
        for i, segs, (x0, y0, x1, y1) in cut:
            total += 1
            hit = False
            for cx in range(math.floor((x0 + dx) / CELL_MM), math.floor((x1 + dx) / CELL_MM) + 1):
                for cy in range(math.floor((y0 + dy) / CELL_MM), math.floor((y1 + dy) / CELL_MM) + 1):
                    for px, py in grid.get((cx, cy), ()):
                        if x0 <= px - dx <= x1 and y0 <= py - dy <= y1 and inside(segs, px - dx, py - dy):
                            hit = True
                            break
                    if hit:
                        break
                if hit:
                    break
            if hit:
                printed += 1
                continue
            # Part of a joint: a corner of it inside another body's cross-section, or one of theirs in it.
            corners = [q for s in segs for q in s]
            if any(j != i and not (bb[0] > x1 or bb[2] < x0 or bb[1] > y1 or bb[3] < y0) and
                   (any(inside(other, *q) for q in corners) or any(inside(segs, *q) for s in other for q in s))
                   for j, other, bb in cut):
                joined += 1
                continue
            dropped.append({"body": i, "z": round(mid, 2), "at": [round((x0 + x1) / 2, 2), round((y0 + y1) / 2, 2)],
                            "width": round(max(x1 - x0, y1 - y0), 2)})
    return {"body_layers": total, "printed": printed, "in_joints_unprinted": joined, "dropped": len(dropped),
            "dropped_share": len(dropped) / total if total else 0.0, "dropped_examples": dropped[:5],
            "removed_first_layers": removed_first_layers, "in_removed_first_layers": removed,
            "offset_xy": [round(dx, 3), round(dy, 3)]}


if __name__ == "__main__":
    if len(sys.argv) not in (6, 7):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        sys.exit(2)
    print(json.dumps(measure(sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4]), float(sys.argv[5]),
                             int(sys.argv[6]) if len(sys.argv) == 7 else 0), indent=1))

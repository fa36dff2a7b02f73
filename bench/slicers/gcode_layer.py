#!/usr/bin/env python3
"""One layer of a G-code as a picture: where a slicer's minutes go, seen from above.

    gcode_layer.py GCODE Z OUT.svg     # the moves at height Z (mm): extrusions coloured by the
                                       # slicer's ;TYPE, travels thin grey, retractions circled
    gcode_layer.py GCODE --heights     # the heights of the layers, one per line

GCODE may be gzipped (bench/handoff.py --keep-gcode keeps them so). Prints a one-line count: paths
(runs of extrusion between two travels), travels and retractions on that layer, and extrusion
moves by type. Reads CuraEngine's and PrusaSlicer's G-code, absolute or relative E. An SVG opens
in any browser; `chromium --headless --screenshot=OUT.png OUT.svg` makes a PNG of it.
"""
import collections
import sys

from gcode_stats import Extruder, open_gcode

SCALE = 12.0  # pixels per mm
PALETTE = ["#d62728", "#1f77b4", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#e377c2", "#17becf"]


def moves(path):
    """(z, kind, type, x0, y0, x1, y1) per move in the XY plane or retraction: kind is 'extrude',
    'travel' or 'retract' (E going back with no XY move)."""
    x = y = z = 0.0
    extruder = Extruder()
    typ = "?"
    with open_gcode(path) as f:
        for raw in f:
            if raw.startswith(";TYPE:"):
                typ = raw[6:].strip()
                continue
            code = raw.split(";", 1)[0].strip()
            if not code or extruder.sets_mode(code) or not code.startswith(("G0 ", "G1 ")):
                continue
            w = {t[0]: t[1:] for t in code.split()[1:] if t[0] in "XYZE"}
            nx, ny, z = float(w.get("X", x)), float(w.get("Y", y)), float(w.get("Z", z))
            de = extruder.delta(w)
            if (nx, ny) != (x, y):
                yield z, "extrude" if de > 0 else "travel", typ, x, y, nx, ny
            elif de < 0:
                yield z, "retract", typ, x, y, x, y
            x, y = nx, ny


def draw(path, z_at, out):
    layer = [m for m in moves(path) if abs(m[0] - z_at) < 1e-3]
    ext = [m for m in layer if m[1] == "extrude"]
    if not ext:
        sys.exit(f"{path}: no extrusion at z = {z_at} (see --heights)")
    xs = [v for m in ext for v in (m[3], m[5])]
    ys = [v for m in ext for v in (m[4], m[6])]
    x0, y0, y1 = min(xs) - 2, min(ys) - 2, max(ys) + 2
    width, height = (max(xs) + 2 - x0) * SCALE, (y1 - y0) * SCALE
    colour = {}
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width:.0f}" height="{height + 20 * 10:.0f}">',
           '<rect width="100%" height="100%" fill="white"/>']
    px = lambda x, y: (f"{(x - x0) * SCALE:.1f}", f"{(y1 - y) * SCALE + 200:.1f}")
    paths = 0
    previous = "travel"
    for _, kind, typ, a, b, c, d in layer:
        if kind == "retract":
            cx, cy = px(a, b)
            svg.append(f'<circle cx="{cx}" cy="{cy}" r="4" fill="none" stroke="black"/>')
            continue
        if kind == "extrude":
            colour.setdefault(typ, PALETTE[len(colour) % len(PALETTE)])
            paths += previous != "extrude"
        previous = kind
        (ax, ay), (bx, by) = px(a, b), px(c, d)
        stroke, w = (colour[typ], 3) if kind == "extrude" else ("#bbbbbb", 0.7)
        svg.append(f'<line x1="{ax}" y1="{ay}" x2="{bx}" y2="{by}" stroke="{stroke}" stroke-width="{w}"/>')
    count = collections.Counter(m[1] for m in layer)
    by_type = collections.Counter(m[2] for m in ext)
    summary = (f"z = {z_at}: {paths} paths, {count['travel']} travels, {count['retract']} retractions; "
               + ", ".join(f"{t} {n}" for t, n in by_type.items()))
    for i, (typ, c) in enumerate(colour.items()):
        svg.append(f'<text x="10" y="{20 + 18 * i}" fill="{c}" font-size="16">{typ}</text>')
    svg.append(f'<text x="10" y="{20 + 18 * len(colour)}" font-size="16">{summary}</text>')
    svg.append("</svg>")
    with open(out, "w") as f:
        f.write("\n".join(svg) + "\n")
    return summary


if __name__ == "__main__":
    if len(sys.argv) == 3 and sys.argv[2] == "--heights":
        for z in sorted({m[0] for m in moves(sys.argv[1]) if m[1] == "extrude"}):
            print(f"{z:g}")
    elif len(sys.argv) == 4:
        print(draw(sys.argv[1], float(sys.argv[2]), sys.argv[3]))
    else:
        sys.exit(__doc__)

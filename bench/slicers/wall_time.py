#!/usr/bin/python3
"""The seconds a slicer spends on our walls, from its G-code: what the generator's price of a wall is
checked against (generator/core/slicer_time.hpp, line_route_seconds; ceilings/ceilings.cpp).

usage: wall_time.py out.gcode[.gz] <name>.scad <name>.supports.stl <name>.model.stl [SLICER_SECONDS]
       (prints one JSON object)

The walls are read from the .scad's `cs_walls` (from, to, foot, top, thickness; the generator's frame,
the frame of <name>.supports.stl). The G-code is placed back into that frame as printed_bodies.py does
(both routes centre the model and its supports together on the bed). gcode_time.py replays the moves;
each extruding move whose middle lies on a wall (within half its thickness and WALL_MARGIN_MM of its
line, between its foot and its top) is labelled "wall", every other one "rest"; a travel, retraction
or lift takes the label of the extrusion it leads to. The result:

  wall_s, rest_s        seconds of the moves of each label (gcode_time's planner, the slicer's machine)
  wall_terms            wall_s split into gcode_time's TERMS
  wall_extruded_mm      length of the wall extrusions (CuraEngine draws each wall as a loop: about
                        twice the walls' length per layer)
  wall_line_mm          the walls' own length summed over the layers they span (0.2 mm layers)
  wall_islands          separate wall runs, summed over the layers (a run ends at a travel longer
                        than gcode_stats.ISLAND_TRAVEL_MM or at a move that is not on a wall)
"""
import json
import math
import os
import re
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True
import gcode_stats  # noqa: E402
import gcode_time  # noqa: E402
import slice as slice_stl  # noqa: E402

BED_MM = (300.0, 300.0)
LAYER_MM = 0.2
# A move is on a wall within this much beyond half the wall's thickness (a slicer's line is centred
# inside the wall's outline, so its middle lies within the wall; the margin takes rounding).
WALL_MARGIN_MM = 0.15
CELL_MM = 2.0

_WALL = re.compile(r"\[\[(-?[0-9.eE+-]+), (-?[0-9.eE+-]+)\], \[(-?[0-9.eE+-]+), (-?[0-9.eE+-]+)\], "
                   r"(-?[0-9.eE+-]+), (-?[0-9.eE+-]+), (-?[0-9.eE+-]+)\]")


def read_walls(scad):
    """[(x0, y0, x1, y1, foot, top, thickness)] of the .scad's cs_walls."""
    text = open(scad).read()
    start = text.find("cs_walls = [")
    if start < 0:
        return []
    end = text.find("];", start)
    return [tuple(float(v) for v in m.groups()) for m in _WALL.finditer(text[start:end])]


class WallIndex:
    def __init__(self, walls):
        self.walls = walls
        self.cells = {}
        for i, (x0, y0, x1, y1, _, _, t) in enumerate(walls):
            r = t / 2 + WALL_MARGIN_MM
            for cx in range(math.floor((min(x0, x1) - r) / CELL_MM), math.floor((max(x0, x1) + r) / CELL_MM) + 1):
                for cy in range(math.floor((min(y0, y1) - r) / CELL_MM), math.floor((max(y0, y1) + r) / CELL_MM) + 1):
                    self.cells.setdefault((cx, cy), []).append(i)

    def on_wall(self, x, y, z):
        for i in self.cells.get((math.floor(x / CELL_MM), math.floor(y / CELL_MM)), ()):
            x0, y0, x1, y1, foot, top, t = self.walls[i]
            if not (foot - 1e-6 <= z <= top + LAYER_MM):
                continue
            dx, dy = x1 - x0, y1 - y0
            ll = dx * dx + dy * dy
            s = 0.0 if ll == 0 else max(0.0, min(1.0, ((x - x0) * dx + (y - y0) * dy) / ll))
            if math.hypot(x - x0 - s * dx, y - y0 - s * dy) <= t / 2 + WALL_MARGIN_MM:
                return True
        return False


def measure(gcode, scad, supports_stl, model_stl, slicer_s=None):
    walls = read_walls(scad)
    everything = slice_stl.read_stl(supports_stl) + slice_stl.read_stl(model_stl)
    xs = [v[0] for t in everything for v in t]
    ys = [v[1] for t in everything for v in t]
    dx = BED_MM[0] / 2 - (min(xs) + max(xs)) / 2
    dy = BED_MM[1] / 2 - (min(ys) + max(ys)) / 2
    index = WallIndex(walls)
    run = {"extruded": 0.0, "islands": 0, "last": None, "z": None}

    def label_of(section, a, b, z):
        x, y = (a[0] + b[0]) / 2 - dx, (a[1] + b[1]) / 2 - dy
        wall = bool(walls) and index.on_wall(x, y, z)
        if wall:
            d = math.hypot(b[0] - a[0], b[1] - a[1])
            run["extruded"] += d
            # a new run: the layer changed, or the last extrusion was elsewhere or far away
            last = run["last"]
            if last is None or run["z"] != z or math.hypot(a[0] - last[0], a[1] - last[1]) > gcode_stats.ISLAND_TRAVEL_MM:
                run["islands"] += 1
            run["last"], run["z"] = b, z
        else:
            run["last"] = None
        return "wall" if wall else "rest"

    t = gcode_time.split(gcode, slicer_s, label_of)
    by = t.pop("by_label", {})
    wall_terms = by.get("wall", {k: 0.0 for k in gcode_time.TERMS})
    line_mm = sum(math.hypot(x1 - x0, y1 - y0) * round((top - foot) / LAYER_MM) for x0, y0, x1, y1, foot, top, _ in walls)
    return {"walls": len(walls), "wall_s": sum(wall_terms.values()),
            "rest_s": sum(sum(v.values()) for k, v in by.items() if k != "wall"),
            "wall_terms": wall_terms, "wall_extruded_mm": run["extruded"], "wall_line_mm": line_mm,
            "wall_islands": run["islands"], "sim_s": t["sim_s"], "slicer_s": t["slicer_s"]}


if __name__ == "__main__":
    if len(sys.argv) not in (5, 6):
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        sys.exit(2)
    print(json.dumps(measure(*sys.argv[1:5], float(sys.argv[5]) if len(sys.argv) == 6 else None), indent=1))

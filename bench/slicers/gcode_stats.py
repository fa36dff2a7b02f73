#!/usr/bin/python3
"""What a G-code does besides extruding: retractions, travel, and islands per layer.

usage: gcode_stats.py out.gcode   (prints one JSON object)

Reads the G-code of CuraEngine 4.13 (";LAYER:n", ";TYPE:SUPPORT") or PrusaSlicer 2.5
(";LAYER_CHANGE", ";TYPE:Support material"), absolute (M82) or relative (M83) extrusion.

* retractions: moves that only pull filament back (E decreases, no XY move), or G10.
* support_to_support_retractions: those on a travel from one support extrusion to the next. With
  CuraEngine's limit_support_retractions these are the travels it could not make in a straight line
  through air (it went around the model), so they say how often islands on opposite sides of a
  model part follow each other in the slicer's order.
* travel_mm: XY length of moves that do not extrude.
* islands: per layer, the separate pieces the nozzle prints (summed; islands_by_layer: per layer). A new island starts at the first
  extrusion of a layer, and at every extrusion reached after more than ISLAND_TRAVEL_MM of travel
  since the previous extrusion (shared notes, slicer-handoff.md). Counted for every extrusion
  (`islands`) and for extrusions inside support sections only (`support_islands`; a support
  extrusion right after a non-support one also starts an island).
* extruded_mm3 by section type: filament length times the filament's cross-section.
"""
import gzip
import json
import math
import re
import sys

ISLAND_TRAVEL_MM = 1.0   # the notes' definition: a gap the nozzle travels over, not a line-to-line step
FILAMENT_DIAMETER_MM = 1.75
SUPPORT_TYPES = ("SUPPORT", "SUPPORT-INTERFACE", "Support material", "Support material interface")

_WORD = re.compile(r"([GXYZEF])(-?[0-9.]+)")


class Extruder:
    """How E counts in a G-code (M82 absolute, M83 relative, G92 E resets it), shared by gcode_time.py."""

    def __init__(self):
        self.e = 0.0
        self.relative = False

    def sets_mode(self, code):
        """Takes M82, M83 and G92 E; True if `code` was one of them (nothing else to do with it)."""
        if code.startswith("M82") or code.startswith("M83"):
            self.relative = code.startswith("M83")
            return True
        if code.startswith("G92"):
            m = re.search(r"E(-?[0-9.]+)", code)
            if m:
                self.e = float(m.group(1))
            return True
        return False

    def delta(self, words):
        """The filament a move's words push (negative: retracted)."""
        if "E" not in words:
            return 0.0
        ne = float(words["E"])
        de = ne if self.relative else ne - self.e
        self.e = self.e + ne if self.relative else ne
        return de



def open_gcode(path):
    """A G-code for reading as text, gzipped (bench/handoff.py --keep-gcode) or not."""
    return gzip.open(path, "rt", errors="replace") if path.endswith(".gz") else open(path, errors="replace")

def is_support(section):
    return section in SUPPORT_TYPES


def parse(path):
    area = math.pi * FILAMENT_DIAMETER_MM ** 2 / 4
    x = y = 0.0
    ext = Extruder()
    section = None
    layers = []          # per layer: [islands, support_islands]
    travel_since = math.inf   # XY travel since the last extrusion (inf: none yet on this layer)
    last_was_support = False
    retractions = 0
    support_to_support = 0
    retracted_since_support = False   # a retraction since the last extrusion, which was support
    travel = 0.0
    by_type = {}
    with open_gcode(path) as f:
        for raw in f:
            line = raw.strip()
            if line.startswith(";"):
                if line.startswith(";LAYER:") or line == ";LAYER_CHANGE":
                    layers.append([0, 0])
                    travel_since = math.inf
                elif line.startswith(";TYPE:"):
                    section = line[6:]
                continue
            code = line.split(";", 1)[0]
            if not code or ext.sets_mode(code):
                continue
            if code.startswith("G10") and not code.startswith("G10 "):
                retractions += 1
                retracted_since_support = last_was_support
                continue
            if not (code.startswith("G0") or code.startswith("G1")) or code.startswith("G10"):
                continue
            words = dict(_WORD.findall(code))
            nx = float(words["X"]) if "X" in words else x
            ny = float(words["Y"]) if "Y" in words else y
            de = ext.delta(words)
            dist = math.hypot(nx - x, ny - y)
            x, y = nx, ny
            if de > 0 and dist > 0:
                by_type[section] = by_type.get(section, 0.0) + de * area
                if layers:
                    support = is_support(section)
                    new_island = travel_since > ISLAND_TRAVEL_MM
                    layers[-1][0] += new_island
                    if support and (new_island or not last_was_support):
                        layers[-1][1] += 1
                    support_to_support += support and retracted_since_support
                    last_was_support = support
                retracted_since_support = False
                travel_since = 0.0
            elif de < 0 and dist == 0:
                retractions += 1
                retracted_since_support = last_was_support
            elif de <= 0 and dist > 0:
                travel += dist
                travel_since += dist
    islands = [l[0] for l in layers]
    support = [l[1] for l in layers]
    return {
        "layers": len(layers),
        "retractions": retractions,
        "support_to_support_retractions": support_to_support,
        "travel_mm": travel,
        "islands": sum(islands),
        "islands_max_per_layer": max(islands, default=0),
        "islands_by_layer": islands,
        "support_islands": sum(support),
        "support_islands_max_per_layer": max(support, default=0),
        "support_islands_by_eighth": by_eighth(support),
        "extruded_mm3_by_type": {str(k): v for k, v in sorted(by_type.items(), key=lambda kv: str(kv[0]))},
        "support_extruded_mm3": sum(v for k, v in by_type.items() if is_support(k)),
    }


def by_eighth(per_layer):
    """Sums over eighths of the layer count, bottom first."""
    n = len(per_layer)
    if n == 0:
        return []
    return [sum(per_layer[i * n // 8:(i + 1) * n // 8]) for i in range(8)]


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__.split("\n\n")[1], file=sys.stderr)
        sys.exit(2)
    print(json.dumps(parse(sys.argv[1]), indent=1))

#!/usr/bin/env python3
"""Sanity checker for STL files (stdlib only).

Usage: check_stl.py [--angle DEG] [--json] [--canonicalize] file.stl ...

For each file prints: triangle count, bounding box, signed volume,
closedness (after welding bit-identical vertices every undirected edge must
be used by exactly two triangles, and every directed edge exactly once, i.e.
consistent orientation), and the share of surface area that overhangs:
faces whose unit normal has n_z < -sin(angle), angle being the critical
overhang angle measured from vertical (default 50 deg).  Downward faces lying
on the bed (all vertices at z == min z) are reported separately since they do
not need support.

--canonicalize first rewrites each (binary) STL in place with its triangles
in a canonical order (each triangle's vertex list rotated to start at its
smallest vertex, orientation kept; triangles sorted; normals recomputed).
OpenSCAD/CGAL emits the same triangles in a run-dependent order, so this
makes re-exports byte-identical.

Exit status is 1 if any file is open, inconsistently oriented, has
non-positive volume, or has min z != 0.
"""
import json
import math
import struct
import sys


def read_stl(path):
    with open(path, "rb") as f:
        data = f.read()
    tris = []
    if len(data) >= 84:
        n = struct.unpack_from("<I", data, 80)[0]
        if 84 + 50 * n == len(data):
            off = 84
            for _ in range(n):
                v = struct.unpack_from("<12f", data, off)
                tris.append((v[3:6], v[6:9], v[9:12]))
                off += 50
            return tris, "binary"
    # ASCII fallback
    text = data.decode("ascii", errors="replace")
    cur = []
    for line in text.splitlines():
        parts = line.split()
        if parts and parts[0] == "vertex":
            cur.append(tuple(float(x) for x in parts[1:4]))
            if len(cur) == 3:
                tris.append(tuple(cur))
                cur = []
    return tris, "ascii"


def canonicalize(path):
    """Rewrite a binary STL with its triangles in a deterministic order."""
    with open(path, "rb") as f:
        data = f.read()
    n = struct.unpack_from("<I", data, 80)[0] if len(data) >= 84 else -1
    if 84 + 50 * n != len(data):
        raise SystemExit("%s: --canonicalize needs a binary STL" % path)
    recs = []
    for i in range(n):
        off = 84 + 50 * i
        vs = struct.unpack_from("<9f", data, off + 12)
        v = [vs[0:3], vs[3:6], vs[6:9]]
        k = v.index(min(v))
        v = v[k:] + v[:k]           # cyclic rotation keeps the orientation
        recs.append((v, data[off + 48:off + 50]))
    recs.sort(key=lambda r: r[0])
    out = [data[:84]]
    for v, attr in recs:
        # recompute the facet normal from the (rotated) vertices so that it
        # does not depend on which vertex the exporter happened to start at
        nx, ny, nz = cross(sub(v[1], v[0]), sub(v[2], v[0]))
        ln = math.sqrt(nx * nx + ny * ny + nz * nz) or 1.0
        out.append(struct.pack("<12f", nx / ln, ny / ln, nz / ln,
                               *(v[0] + v[1] + v[2])) + attr)
    with open(path, "wb") as f:
        f.write(b"".join(out))


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0])


def analyse(path, angle_deg=50.0):
    tris, kind = read_stl(path)
    if not tris:
        raise SystemExit("%s: no triangles" % path)
    idx = {}
    faces = []
    for t in tris:
        f = []
        for v in t:
            key = (float(v[0]), float(v[1]), float(v[2]))
            if key not in idx:
                idx[key] = len(idx)
            f.append(idx[key])
        faces.append(f)
    verts = [None] * len(idx)
    for k, i in idx.items():
        verts[i] = k

    lo = [min(v[i] for v in verts) for i in range(3)]
    hi = [max(v[i] for v in verts) for i in range(3)]

    directed = {}
    undirected = {}
    degenerate = 0
    for f in faces:
        if f[0] == f[1] or f[1] == f[2] or f[0] == f[2]:
            degenerate += 1
        for a, b in ((f[0], f[1]), (f[1], f[2]), (f[2], f[0])):
            directed[(a, b)] = directed.get((a, b), 0) + 1
            k = (a, b) if a < b else (b, a)
            undirected[k] = undirected.get(k, 0) + 1
    bad_edges = sum(1 for c in undirected.values() if c != 2)
    bad_orient = sum(1 for c in directed.values() if c != 1)
    closed = bad_edges == 0
    oriented = bad_orient == 0

    vol6 = 0.0
    area = 0.0
    over = 0.0
    over_bed = 0.0
    thresh = -math.sin(math.radians(angle_deg))
    zmin = lo[2]
    for f in faces:
        a, b, c = verts[f[0]], verts[f[1]], verts[f[2]]
        vol6 += (a[0] * (b[1] * c[2] - b[2] * c[1])
                 - a[1] * (b[0] * c[2] - b[2] * c[0])
                 + a[2] * (b[0] * c[1] - b[1] * c[0]))
        n = cross(sub(b, a), sub(c, a))
        ln = math.sqrt(n[0] ** 2 + n[1] ** 2 + n[2] ** 2)
        if ln == 0.0:
            continue
        ar = 0.5 * ln
        area += ar
        if n[2] / ln < thresh:
            if a[2] == zmin and b[2] == zmin and c[2] == zmin:
                over_bed += ar
            else:
                over += ar
    # Euler characteristic -> genus for a closed, connected surface
    chi = len(verts) - len(undirected) + len(faces)
    res = {
        "file": path,
        "format": kind,
        "triangles": len(faces),
        "vertices": len(verts),
        "bbox_min": lo,
        "bbox_max": hi,
        "size": [hi[i] - lo[i] for i in range(3)],
        "volume": vol6 / 6.0,
        "area": area,
        "closed": closed,
        "non_manifold_or_open_edges": bad_edges,
        "consistently_oriented": oriented,
        "degenerate_triangles": degenerate,
        "euler_characteristic": chi,
        "critical_angle_deg": angle_deg,
        "overhang_area": over,
        "overhang_pct": 100.0 * over / area if area else 0.0,
        "bed_contact_area": over_bed,
    }
    res["ok"] = (closed and oriented and res["volume"] > 0 and lo[2] == 0.0)
    return res


def main(argv):
    angle = 50.0
    as_json = False
    canon = False
    files = []
    it = iter(argv)
    for a in it:
        if a == "--angle":
            angle = float(next(it))
        elif a == "--json":
            as_json = True
        elif a == "--canonicalize":
            canon = True
        elif a in ("-h", "--help"):
            print(__doc__)
            return 0
        else:
            files.append(a)
    if not files:
        print(__doc__)
        return 2
    if canon:
        for f in files:
            canonicalize(f)
    results = [analyse(f, angle) for f in files]
    if as_json:
        print(json.dumps(results, indent=2))
    else:
        for r in results:
            s = r["size"]
            print("%s (%s STL)" % (r["file"], r["format"]))
            print("  triangles  : %d  (vertices %d, degenerate %d)"
                  % (r["triangles"], r["vertices"], r["degenerate_triangles"]))
            print("  bbox       : [%.2f %.2f %.2f] .. [%.2f %.2f %.2f]"
                  % (tuple(r["bbox_min"]) + tuple(r["bbox_max"])))
            print("  size       : %.1f x %.1f x %.1f mm" % tuple(s))
            print("  volume     : %.1f mm^3   area %.1f mm^2"
                  % (r["volume"], r["area"]))
            print("  closed     : %s (bad edges %d), oriented: %s, "
                  "Euler char %d"
                  % (r["closed"], r["non_manifold_or_open_edges"],
                     r["consistently_oriented"], r["euler_characteristic"]))
            print("  overhang   : %.1f%% of area (%.1f mm^2) has n_z < "
                  "-sin(%g deg); bed contact %.1f mm^2"
                  % (r["overhang_pct"], r["overhang_area"], angle,
                     r["bed_contact_area"]))
            print("  status     : %s" % ("OK" if r["ok"] else "PROBLEM"))
    return 0 if all(r["ok"] for r in results) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

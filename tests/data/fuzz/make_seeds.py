#!/usr/bin/env python3
"""Writes the small valid seed files of the fuzz corpora (tests/data/fuzz/<format>/seed-*).

The broken seeds (bad-*) are copies of files in tests/data/bad/; reproducers the fuzzers find
(crash-*, timeout-*, oom-*, leak-*) are added by scripts/fuzz.sh. tests/unit/test_fuzz_replay.cpp
feeds every file here to parse_mesh + repair_mesh. Rerun this script to regenerate the seeds (the
output is byte-identical). The seeds of the other two fuzz targets are written by hand: config/
(--config files) and scad/ (seed-tee.scad is the .scad clever-support wrote for a small T, its
cs_input_path made relative; seed-edited.scad the same with a blocker, a point and an omitted strut).
"""
import os
import shutil
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
BAD = os.path.join(HERE, "..", "bad")

# A 2 x 3 x 4 box (outward faces), a tetrahedron and a quad-faced cube.
BOX_V = [(1 + 2 * (i & 1), 2 + 3 * ((i >> 1) & 1), 3 + 4 * ((i >> 2) & 1)) for i in range(8)]
BOX_F = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4),
         (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
TET_V = [(0, 0, 0), (10, 0, 0), (0, 10, 0), (0, 0, 10)]
TET_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]
QUAD_F = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]


def normal(v, f):
    a, b, c = (v[i] for i in f)
    u = [b[k] - a[k] for k in range(3)]
    w = [c[k] - a[k] for k in range(3)]
    n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
    ln = sum(x * x for x in n) ** 0.5 or 1
    return [x / ln for x in n]


def fmt(x):
    return repr(float(x)) if isinstance(x, float) else str(x)


def ascii_stl(v, f, crlf=False, upper=False):
    nl = "\r\n" if crlf else "\n"
    out = ["solid box"]
    for t in f:
        out.append("  facet normal %s %s %s" % tuple(fmt(x) for x in normal(v, t)))
        out.append("    outer loop")
        for i in t:
            out.append("      vertex %s %s %s" % tuple(fmt(x) for x in v[i]))
        out.append("    endloop")
        out.append("  endfacet")
    out.append("endsolid box")
    s = nl.join(out) + nl
    return (s.upper() if upper else s).encode()


def binary_stl(v, f, header=b"clever-support fuzz seed"):
    out = header.ljust(80, b"\0") + struct.pack("<I", len(f))
    for t in f:
        out += struct.pack("<3f", *normal(v, t))
        for i in t:
            out += struct.pack("<3f", *v[i])
        out += b"\0\0"
    return out


def obj(v, f, extras=False, negative=False):
    out = ["# box"]
    if extras:
        out += ["mtllib box.mtl", "o box", "g side", "s 1", "usemtl grey"]
    out += ["v %s %s %s" % v_ for v_ in v]
    if extras:
        out += ["vt 0 0", "vn 0 0 1"]
    for t in f:
        if negative:
            out.append("f " + " ".join(str(i - len(v)) for i in t))
        elif extras:
            out.append("f " + " ".join("%d/1/1" % (i + 1) for i in t))
        else:
            out.append("f " + " ".join(str(i + 1) for i in t))
    return ("\n".join(out) + "\n").encode()


def off(v, f, color=False, comments=False):
    out = ["COFF" if color else "OFF"]
    if comments:
        out.append("# vertices faces edges")
    out.append("%d %d 0" % (len(v), len(f)))
    for p in v:
        out.append("%s %s %s" % p + (" 255 0 0 255" if color else ""))
    for t in f:
        out.append("%d %s" % (len(t), " ".join(map(str, t))) + (" 0.5 0.5 0.5" if comments else ""))
    return ("\n".join(out) + "\n").encode()


def ply_ascii(v, f):
    head = ["ply", "format ascii 1.0", "comment seed", "element vertex %d" % len(v),
            "property float x", "property float y", "property float z",
            "element face %d" % len(f), "property list uchar int vertex_indices", "end_header"]
    body = ["%s %s %s" % p for p in v] + ["%d %s" % (len(t), " ".join(map(str, t))) for t in f]
    return ("\n".join(head + body) + "\n").encode()


def ply_binary(v, f, big=False, extra=False):
    e = ">" if big else "<"
    head = ["ply", "format binary_%s_endian 1.0" % ("big" if big else "little"),
            "element vertex %d" % len(v), "property double x", "property double y", "property double z"]
    if extra:
        head += ["property uchar red", "property uchar green", "property uchar blue"]
    head += ["element face %d" % len(f), "property list uchar uint vertex_indices"]
    if extra:
        head += ["element edge 1", "property int vertex1", "property int vertex2"]
    head.append("end_header")
    out = ("\n".join(head) + "\n").encode()
    for p in v:
        out += struct.pack(e + "3d", *p)
        if extra:
            out += bytes([200, 100, 50])
    for t in f:
        out += struct.pack(e + "B%dI" % len(t), len(t), *t)
    if extra:
        out += struct.pack(e + "2i", 0, 1)
    return out


SEEDS = {
    "stl": {
        "seed-box-ascii.stl": ascii_stl(BOX_V, BOX_F),
        "seed-box-ascii-crlf-upper.stl": ascii_stl(BOX_V, BOX_F, crlf=True, upper=True),
        "seed-box-binary.stl": binary_stl(BOX_V, BOX_F),
        "seed-tet-binary-solid-header.stl": binary_stl(TET_V, TET_F, header=b"solid tet"),
        "seed-tet-ascii.stl": ascii_stl(TET_V, TET_F),
    },
    "obj": {
        "seed-box.obj": obj(BOX_V, BOX_F),
        "seed-box-extras.obj": obj(BOX_V, BOX_F, extras=True),
        "seed-box-negative.obj": obj(BOX_V, BOX_F, negative=True),
        "seed-box-quads.obj": obj(BOX_V, QUAD_F),
        "seed-tet.obj": obj(TET_V, TET_F),
    },
    "off": {
        "seed-box.off": off(BOX_V, BOX_F),
        "seed-box-color-comments.off": off(BOX_V, BOX_F, color=True, comments=True),
        "seed-box-quads.off": off(BOX_V, QUAD_F),
        "seed-tet.off": off(TET_V, TET_F),
    },
    "ply": {
        "seed-box-ascii.ply": ply_ascii(BOX_V, BOX_F),
        "seed-box-binary-le.ply": ply_binary(BOX_V, BOX_F),
        "seed-box-binary-be.ply": ply_binary(BOX_V, BOX_F, big=True),
        "seed-box-binary-extra.ply": ply_binary(BOX_V, QUAD_F, extra=True),
        "seed-tet-ascii.ply": ply_ascii(TET_V, TET_F),
    },
}

# Broken or awkward files from the bad-input corpus, by the format the fuzzer parses them as.
BAD_COPIES = {
    "stl": ["empty.stl", "truncated.stl", "count_mismatch.stl", "garbage_ascii.stl", "truncated_ascii.stl",
            "nan.stl", "all_degenerate.stl", "flat.stl", "open_mesh.stl", "disjoint_shells.stl",
            "self_intersecting.stl", "inverted_normals.stl"],
    "obj": ["bad_index.obj", "inf.obj", "nonmanifold.obj"],
    "off": ["huge_1e30.off"],
    "ply": ["truncated_binary.ply", "not_a_mesh.ply"],
}

for fmt_, files in SEEDS.items():
    d = os.path.join(HERE, fmt_)
    os.makedirs(d, exist_ok=True)
    for name, data in files.items():
        with open(os.path.join(d, name), "wb") as fh:
            fh.write(data)
    for name in BAD_COPIES[fmt_]:
        shutil.copyfile(os.path.join(BAD, name), os.path.join(d, "bad-" + name))

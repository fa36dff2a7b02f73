#!/usr/bin/env python3
"""Writes the bad-input corpus in tests/data/bad/ (python3 standard library only).

Run from anywhere: python3 tests/data/make_bad_corpus.py
The generated files are committed; rerunning gives byte-identical files.
Two cases cannot live in git and are made by tests/unit/test_cli.cpp at run time:
a directory named like a mesh, and an unreadable (chmod 000) file.
What the CLI must do with each file is in bad/EXPECTED.md (test_cli.cpp reads that table).
"""
import os
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
OUT = os.path.join(HERE, "bad")


def box(lo, hi):
    """Vertices and outward-facing triangles of an axis-aligned box (same layout as tests/support.hpp)."""
    v = [(hi[0] if i & 1 else lo[0], hi[1] if i & 2 else lo[1], hi[2] if i & 4 else lo[2]) for i in range(8)]
    f = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4),
         (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
    return v, f


def soup(v, f):
    return [(v[a], v[b], v[c]) for a, b, c in f]


def binary_stl(tris, count=None, header=b"clever-support bad corpus"):
    out = bytearray(header.ljust(80, b" ")[:80])
    out += struct.pack("<I", len(tris) if count is None else count)
    for t in tris:
        out += struct.pack("<3f", 0, 0, 0)
        for p in t:
            out += struct.pack("<3f", *p)
        out += b"\0\0"
    return bytes(out)


def ascii_stl(tris, name="corpus"):
    lines = ["solid " + name]
    for t in tris:
        lines += ["  facet normal 0 0 0", "    outer loop"]
        lines += ["      vertex %g %g %g" % p for p in t]
        lines += ["    endloop", "  endfacet"]
    lines.append("endsolid " + name)
    return ("\n".join(lines) + "\n").encode()


def obj(v, f, fmt="%r"):
    lines = ["# clever-support bad corpus"]
    lines += ["v " + " ".join(fmt % c for c in p) for p in v]
    lines += ["f %d %d %d" % (a + 1, b + 1, c + 1) for a, b, c in f]
    return ("\n".join(lines) + "\n").encode()


def off(v, f):
    lines = ["OFF", "%d %d 0" % (len(v), len(f))]
    lines += [" ".join(repr(c) for c in p) for p in v]
    lines += ["3 %d %d %d" % t for t in f]
    return ("\n".join(lines) + "\n").encode()


def write(name, data):
    with open(os.path.join(OUT, name), "wb") as fh:
        fh.write(data)


def main():
    os.makedirs(OUT, exist_ok=True)
    cube = soup(*box((0, 0, 0), (20, 20, 10)))

    # --- unusable input: exit 3 ---
    write("empty.stl", b"")
    write("zero_triangles.stl", binary_stl([]))
    write("truncated.stl", binary_stl(cube)[: 84 + 50 * 3 + 17])           # header says 12, 3.3 are there
    write("count_mismatch.stl", binary_stl(cube, count=2))                  # 12 stored, header says 2
    garbage = ascii_stl(cube[:2]).decode().splitlines()
    garbage.insert(4, "      this line is not STL at all")
    write("garbage_ascii.stl", ("\n".join(garbage) + "\n").encode())
    nan_tris = list(cube)
    nan_tris[5] = ((float("nan"), 0.0, 0.0), nan_tris[5][1], nan_tris[5][2])
    write("nan.stl", binary_stl(nan_tris))
    v, f = box((0, 0, 0), (20, 20, 10))
    v_inf = list(v)
    v_inf[3] = (20.0, float("inf"), 0.0)
    write("inf.obj", obj(v_inf, f, "%g"))
    v_huge = list(v)
    v_huge[6] = (0.0, 20.0, 1e30)
    write("huge_1e30.off", off(v_huge, f))
    write("all_degenerate.stl", binary_stl([
        ((0, 0, 0), (0, 0, 0), (1, 1, 1)),      # repeated corner
        ((0, 0, 0), (1, 1, 1), (2, 2, 2)),      # collinear
        ((5, 5, 5), (5, 5, 5), (5, 5, 5)),      # a point
    ]))
    # A single square: zero volume. As exported (away from the origin) and lying in z = 0.
    write("flat.stl", binary_stl([((10, 0, 5), (20, 0, 5), (20, 10, 5)), ((10, 0, 5), (20, 10, 5), (10, 10, 5))]))
    write("flat_on_bed.stl", binary_stl([((0, 0, 0), (10, 0, 0), (10, 10, 0)), ((0, 0, 0), (10, 10, 0), (0, 10, 0))]))
    write("unknown_format.xyz", b"0 0 0\n1 0 0\n0 1 0\n")
    write("not_a_mesh.ply", b"Dear printer,\nthis is a letter, not a mesh.\n42 17 3.5\nend_header? no.\n")
    # A few more readers' edge cases.
    write("truncated_ascii.stl", b"solid t\n facet normal 0 0 -1\n  outer loop\n   vertex 0 0 0\n   vertex 1 0 0\n")
    write("bad_index.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    ply = (b"ply\nformat binary_little_endian 1.0\nelement vertex 8\nproperty float x\nproperty float y\n"
           b"property float z\nelement face 12\nproperty list uchar int vertex_indices\nend_header\n")
    ply += b"".join(struct.pack("<3f", *p) for p in v)
    ply += b"".join(struct.pack("<B3i", 3, *t) for t in f[:5])              # 5 of 12 faces
    write("truncated_binary.ply", ply)

    # --- repaired or carried on with a warning: exit 0 ---
    write("inverted_normals.stl", binary_stl([(a, c, b) for a, b, c in cube]))
    write("open_mesh.stl", binary_stl(cube[:2] + cube[4:]))                 # bottom face (z = 0) missing
    # Two boxes sharing one vertical edge (x = 10, y = 10): that edge has four triangles.
    va, fa = box((0, 0, 0), (10, 10, 10))
    vb, fb = box((10, 10, 0), (20, 20, 10))
    verts = list(va)
    idx_b = []
    for p in vb:
        if p in verts:
            idx_b.append(verts.index(p))
        else:
            idx_b.append(len(verts))
            verts.append(p)
    faces = list(fa) + [(idx_b[a], idx_b[b], idx_b[c]) for a, b, c in fb]
    write("nonmanifold.obj", obj(verts, faces, "%g"))
    # Two overlapping boxes as one soup (an arm pushed through a body, as modellers do): neither
    # box's first corner lies inside the other.
    write("self_intersecting.stl",
          binary_stl(soup(*box((0, 0, 0), (10, 10, 10))) + soup(*box((5, -4, 3), (18, 4, 7)))))
    # Two separate boxes; the second floats next to the first (an overhang whatever the orientation).
    write("disjoint_shells.stl",
          binary_stl(soup(*box((0, 0, 0), (10, 10, 10))) + soup(*box((16, 3, 4), (26, 13, 14)))))


if __name__ == "__main__":
    main()

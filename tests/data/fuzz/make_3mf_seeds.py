#!/usr/bin/env python3
"""Writes the 3MF fuzz corpus (tests/data/fuzz/3mf/): valid seeds (seed-*) and the broken files a
3MF reader must refuse with a clear error (bad-*), one per way a 3MF goes wrong.

tests/unit/test_fuzz_replay.cpp feeds each through parse_mesh(..., "3mf") + repair_mesh: seeds must
be accepted, the rest rejected with InputError. scripts/fuzz.sh starts fuzz_3mf from them. The ZIP
writer is this file's own (stdlib struct + zlib), so the archives are byte-identical run to run
and a header can declare a size its data does not have (the ZIP bomb). Rerun to regenerate.
"""
import os
import struct
import zlib

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "3mf")
CORE = "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"
PROD = "http://schemas.microsoft.com/3dmanufacturing/production/2015/06"

CONTENT_TYPES = ('<?xml version="1.0" encoding="UTF-8"?>\n'
                 '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
                 '<Default Extension="rels" ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
                 '<Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>'
                 '</Types>\n')
RELS = ('<?xml version="1.0" encoding="UTF-8"?>\n'
        '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
        '<Relationship Target="/3D/3dmodel.model" Id="rel0" '
        'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>\n')

BOX_V = [((i & 1) * 20, ((i >> 1) & 1) * 10, ((i >> 2) & 1) * 5) for i in range(8)]
BOX_F = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4),
         (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
TET_V = [(0, 0, 0), (10, 0, 0), (0, 10, 0), (0, 0, 10)]
TET_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def zip_bytes(entries, declared=None, stored=False):
    """A ZIP of (name, text) entries, deflated (or `stored` as they are, so that the fuzzer's
    mutations reach the XML). `declared` maps a name to the uncompressed size its headers claim
    (for the bomb); otherwise the true size."""
    declared = declared or {}
    local, central, offset = b"", b"", 0
    method = 0 if stored else 8
    for name, text in entries:
        data = text.encode() if isinstance(text, str) else text
        comp = zlib.compressobj(9, zlib.DEFLATED, -15)
        packed = data if stored else comp.compress(data) + comp.flush()
        size = declared.get(name, len(data))
        crc = zlib.crc32(data)
        n = name.encode()
        head = struct.pack("<IHHHHHIIIHH", 0x04034B50, 20, 0, method, 0, 0x21, crc, len(packed), size, len(n), 0)
        central += struct.pack("<IHHHHHHIIIHHHHHII", 0x02014B50, 20, 20, 0, method, 0, 0x21, crc, len(packed), size,
                               len(n), 0, 0, 0, 0, 0, offset) + n
        local += head + n + packed
        offset += len(head) + len(n) + len(packed)
    end = struct.pack("<IHHHHIIH", 0x06054B50, 0, 0, len(entries), len(entries), len(central), offset, 0)
    return local + central + end


def mesh_xml(v, f):
    return ("<mesh><vertices>" + "".join(f'<vertex x="{x}" y="{y}" z="{z}"/>' for x, y, z in v) +
            "</vertices><triangles>" + "".join(f'<triangle v1="{a}" v2="{b}" v3="{c}"/>' for a, b, c in f) +
            "</triangles></mesh>")


def model(resources, build, unit="millimeter", ns=""):
    return (f'<?xml version="1.0" encoding="UTF-8"?>\n<model unit="{unit}" xml:lang="en-US" xmlns="{CORE}"{ns}>\n'
            f"<resources>\n{resources}</resources>\n<build>\n{build}</build>\n</model>\n")


def package(model_text, extra=()):
    return zip_bytes([("[Content_Types].xml", CONTENT_TYPES), ("_rels/.rels", RELS),
                      ("3D/3dmodel.model", model_text)] + list(extra))


BOX = f'<object id="1" name="box" type="model">{mesh_xml(BOX_V, BOX_F)}</object>\n'
TET = f'<object id="2" name="tet" type="model">{mesh_xml(TET_V, TET_F)}</object>\n'
MOVE = "1 0 0 0 1 0 0 0 1 30 40 0"


def files():
    yield "seed-box.3mf", package(model(BOX, f'<item objectid="1" transform="{MOVE}"/>\n'))
    # Two objects grouped as components (one turned 90 degrees about z), two build items.
    group = ('<object id="3" name="group" type="model"><components>'
             '<component objectid="1"/><component objectid="2" transform="0 1 0 -1 0 0 0 0 1 50 0 0"/>'
             '</components></object>\n')
    yield "seed-plate.3mf", package(model(BOX + TET + group,
                                         '<item objectid="3"/>\n<item objectid="2" transform="1 0 0 0 1 0 0 0 1 0 60 0"/>\n'))
    yield "seed-inch.3mf", package(model(TET, '<item objectid="2"/>\n', unit="inch"))
    # Bambu Studio / PrusaSlicer 2.6 style: the mesh in its own part, named by p:path.
    part = model(BOX, "").replace("<build>\n</build>\n", "")
    yield "seed-production.3mf", package(
        model('<object id="5" type="model"><components>'
              '<component p:path="/3D/Objects/object_1.model" objectid="1" transform="1 0 0 0 1 0 0 0 1 0 0 2"/>'
              "</components></object>\n", '<item objectid="5"/>\n', ns=f' xmlns:p="{PROD}"'),
        [("3D/Objects/object_1.model", part)])
    yield "seed-no-rels.3mf", zip_bytes([("3D/3dmodel.model", model(BOX, '<item objectid="1"/>\n'))])
    yield "seed-stored.3mf", zip_bytes([("_rels/.rels", RELS), ("3D/3dmodel.model", model(
        BOX + TET, '<item objectid="1"/>\n<item objectid="2" transform="1 0 0 0 1 0 0 0 1 0 30 0"/>\n'))], stored=True)

    yield "bad-not_a_zip.3mf", b"solid box\nfacet normal 0 0 1\n"
    yield "bad-no_model_part.3mf", zip_bytes([("[Content_Types].xml", CONTENT_TYPES), ("_rels/.rels", RELS)])
    yield "bad-broken_xml.3mf", package(model(BOX, '<item objectid="1"/>\n')[:300])
    yield "bad-missing_object.3mf", package(model(BOX, '<item objectid="7"/>\n'))
    yield "bad-transform_not_a_number.3mf", package(model(BOX, '<item objectid="1" transform="1 0 0 0 1 0 0 0 1 x 0 0"/>\n'))
    yield "bad-transform_11_numbers.3mf", package(model(BOX, '<item objectid="1" transform="1 0 0 0 1 0 0 0 1 0 0"/>\n'))
    yield "bad-vertex_index.3mf", package(model(
        '<object id="1" type="model">' + mesh_xml(TET_V, TET_F[:3] + [(1, 2, 99)]) + "</object>\n", '<item objectid="1"/>\n'))
    yield "bad-vertex_nan.3mf", package(model(
        '<object id="1" type="model">' + mesh_xml([("nan", 0, 0)] + TET_V[1:], TET_F) + "</object>\n", '<item objectid="1"/>\n'))
    yield "bad-component_loop.3mf", package(model(
        '<object id="1" type="model"><components><component objectid="2"/></components></object>\n'
        '<object id="2" type="model"><components><component objectid="1"/></components></object>\n',
        '<item objectid="1"/>\n'))
    yield "bad-unit.3mf", package(model(BOX, '<item objectid="1"/>\n', unit="furlong"))
    # Billion laughs: entities are refused before they expand.
    laughs = ('<?xml version="1.0"?>\n<!DOCTYPE model [<!ENTITY a "aaaaaaaaaa">'
              '<!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;"><!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;">]>\n'
              f'<model xmlns="{CORE}"><resources>&c;</resources></model>\n')
    yield "bad-entities.3mf", package(laughs)
    # A ZIP bomb: the model part claims 3.75 GB unpacked (its real data is small): refused before
    # inflating anything.
    yield "bad-zip_bomb.3mf", zip_bytes([("_rels/.rels", RELS), ("3D/3dmodel.model", model(BOX, '<item objectid="1"/>\n'))],
                                        declared={"3D/3dmodel.model": 0xF0000000})


def main():
    os.makedirs(OUT, exist_ok=True)
    for name, data in files():
        with open(os.path.join(OUT, name), "wb") as f:
            f.write(data)
        print(f"{name}: {len(data)} bytes")


if __name__ == "__main__":
    main()

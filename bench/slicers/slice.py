#!/usr/bin/python3
"""Slice STL(s) with CuraEngine 4.13 or PrusaSlicer 2.5 and report grams, print time, volume.

usage: slice.py --slicer cura|prusa --support none|normal|tree|mesh|grid|snug [--out-dir DIR] [--json]
                [--profile profile.json] [--scale S] [--set KEY=VALUE ...] [--timeout SEC]
                [--support-mesh supports.stl ...] model.stl [more.stl ...]

* cura:  --support none | normal (lines, 15%) | tree (support_structure=tree)
         | mesh (the --support-mesh STLs print as a Cura support mesh, the slicer's own supports off)
* prusa: --support none | grid | snug (support_material_style, rectilinear lines)
         A PrusaSlicer 3MF (e.g. clever-support's <name>.prusa.3mf) is sliced as it is, with its
         per-volume settings: give it alone, scale 1; PrusaSlicer centres it on the bed.

Several STLs are merged into ONE mesh (one STL file, one object / mesh group):
a model plus a separate support STL slice together, and both slicers union
overlapping closed bodies (pitfall 5).  The merged mesh is scaled by --scale,
centred in XY on the bed and put on it (min z = 0) before slicing.

Output: one line per field, or with --json one JSON object:
  {slicer, support, models, grams, print_time_s, filament_mm3, slice_seconds,
   filament_mm, scale, model_size_mm, overrides, out_dir}
grams for Cura = filament_mm3 * density (1.24 g/cm3 = 1.24e-3 g/mm3); for
PrusaSlicer the footer's "; filament used [g]".  slice_seconds is the wall time
of the slicer process alone.  On a slicer failure: exit 1 and the tail of the
slicer's stderr on our stderr; on bad usage: exit 2.
"""
import argparse
import json
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
sys.dont_write_bytecode = True  # keep bench/slicers free of __pycache__
import cura_settings  # noqa: E402

CURA_BIN = os.environ.get("CURA_ENGINE", "CuraEngine")
PRUSA_BIN = os.environ.get("PRUSA_SLICER", "prusa-slicer")
SUPPORT_MODES = {"cura": ("none", "normal", "tree", "mesh"), "prusa": ("none", "grid", "snug")}


class SliceError(RuntimeError):
    pass


# --------------------------------------------------------------------------
# STL I/O
# --------------------------------------------------------------------------

def read_stl(path):
    """Return a list of triangles ((x,y,z),(x,y,z),(x,y,z)); binary or ASCII STL."""
    with open(path, "rb") as f:
        data = f.read()
    if len(data) >= 84:
        n = struct.unpack_from("<I", data, 80)[0]
        if 84 + 50 * n == len(data):
            tris = []
            off = 84
            for _ in range(n):
                v = struct.unpack_from("<12f", data, off)
                tris.append((v[3:6], v[6:9], v[9:12]))
                off += 50
            return tris
    text = data.decode("ascii", errors="replace")
    if "facet" not in text:
        raise SliceError("%s: neither a binary STL (size mismatch) nor an ASCII STL" % path)
    nums = re.findall(r"vertex\s+(\S+)\s+(\S+)\s+(\S+)", text)
    if len(nums) % 3:
        raise SliceError("%s: ASCII STL with a vertex count that is not a multiple of 3" % path)
    verts = [tuple(float(c) for c in v) for v in nums]
    return [tuple(verts[i:i + 3]) for i in range(0, len(verts), 3)]


def write_stl(path, tris, name="clever-support merged"):
    with open(path, "wb") as f:
        f.write(("binary STL: " + name).encode("ascii")[:80].ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for a, b, c in tris:
            ux, uy, uz = b[0] - a[0], b[1] - a[1], b[2] - a[2]
            vx, vy, vz = c[0] - a[0], c[1] - a[1], c[2] - a[2]
            nx, ny, nz = uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx
            ln = math.sqrt(nx * nx + ny * ny + nz * nz) or 1.0
            f.write(struct.pack("<12fH", nx / ln, ny / ln, nz / ln, *a, *b, *c, 0))


def merge_and_place(paths, out_path, bed, scale=1.0):
    """Merge STLs into one mesh, scale, centre in XY on the bed, min z = 0."""
    return place_groups([(paths, out_path)], bed, scale)


def place_groups(groups, bed, scale=1.0):
    """Each group [(stl paths, out path)] merged into its own STL, all moved by ONE translation: the
    one that scales, centres the whole set in XY on the bed and puts it on it (min z = 0). A model
    and its support mesh keep their relative position this way."""
    group_tris = []
    for paths, _ in groups:
        group_tris.append([t for p in paths for t in read_stl(p)])
        if not group_tris[-1]:
            raise SliceError("no triangles in %s" % ", ".join(paths))
    tris = [t for g in group_tris for t in g]
    xs = [v[0] for t in tris for v in t]
    ys = [v[1] for t in tris for v in t]
    zs = [v[2] for t in tris for v in t]
    cx = (min(xs) + max(xs)) / 2.0 * scale
    cy = (min(ys) + max(ys)) / 2.0 * scale
    mz = min(zs) * scale
    dx, dy, dz = bed[0] / 2.0 - cx, bed[1] / 2.0 - cy, -mz
    for (_, out_path), g in zip(groups, group_tris):
        write_stl(out_path, [tuple((v[0] * scale + dx, v[1] * scale + dy, v[2] * scale + dz) for v in t) for t in g])
    size = [(max(xs) - min(xs)) * scale, (max(ys) - min(ys)) * scale, (max(zs) - min(zs)) * scale]
    if size[0] > bed[0] or size[1] > bed[1] or size[2] > bed[2]:
        raise SliceError("model %.1f x %.1f x %.1f mm does not fit the %gx%gx%g bed (use --scale)"
                         % (size[0], size[1], size[2], bed[0], bed[1], bed[2]))
    return {"triangles": len(tris), "size_mm": [round(s, 4) for s in size]}


# --------------------------------------------------------------------------
# Helpers
# --------------------------------------------------------------------------

def run_slicer(cmd, cwd, log_prefix, timeout):
    """Run a slicer; return (stdout, stderr, wall seconds). Raise SliceError on failure."""
    t0 = time.monotonic()
    try:
        proc = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                              stdin=subprocess.DEVNULL, timeout=timeout)
    except subprocess.TimeoutExpired as exc:
        raise SliceError("%s timed out after %s s\n%s" % (cmd[0], timeout,
                         tail((exc.stderr or b"").decode("utf-8", "replace"))))
    except FileNotFoundError:
        raise SliceError("slicer binary not found: %s" % cmd[0])
    wall = time.monotonic() - t0
    out = proc.stdout.decode("utf-8", "replace")
    err = proc.stderr.decode("utf-8", "replace")
    with open(log_prefix + ".stdout.log", "w") as f:
        f.write(out)
    with open(log_prefix + ".stderr.log", "w") as f:
        f.write(err)
    if proc.returncode != 0:
        raise SliceError("%s exited with status %d; stderr tail:\n%s"
                         % (os.path.basename(cmd[0]), proc.returncode, tail(err or out)))
    return out, err, wall


def tail(text, lines=25):
    return "\n".join(text.rstrip().splitlines()[-lines:])


def write_cmd(path, cmd):
    """Write the exact command as a re-runnable shell script, one option per line."""
    lines, cur = [], []
    for tok in cmd:
        if tok.startswith("-") and cur:
            lines.append(" ".join(cur))
            cur = []
        cur.append(_shell_quote(tok))
    lines.append(" ".join(cur))
    with open(path, "w") as f:
        f.write("#!/bin/sh\n# written by bench/slicers/slice.py\n")
        f.write(" \\\n  ".join(lines) + "\n")


def _shell_quote(s):
    if s and re.fullmatch(r"[A-Za-z0-9_./=:,+%-]+", s):
        return s
    return "'" + s.replace("'", "'\\''") + "'"


# --------------------------------------------------------------------------
# CuraEngine
# --------------------------------------------------------------------------

# Per-mesh settings that make a mesh print as support ("Print as support" in Cura's GUI). Without
# drop_down=False Cura would add support under the support mesh's own overhangs.
CURA_SUPPORT_MESH = ["support_mesh=True", "support_mesh_drop_down=False"]


def slice_cura(stl, support, profile, work, timeout, extra=None, support_mesh_stl=None):
    overrides = cura_settings.cura_overrides(profile, support)
    overrides.update(extra or {})
    resolver = cura_settings.Resolver()
    glob, ext = resolved(resolver, overrides, work)
    # merged.stl is centred on the profile's bed (common.bed_mm); put that centre on Cura's
    # machine centre.
    bed = (float(profile["common"]["bed_mm"][0]), float(profile["common"]["bed_mm"][1]))
    meshes = [(stl, [])] + ([(support_mesh_stl, CURA_SUPPORT_MESH)] if support_mesh_stl else [])
    density = float(profile["common"]["filament_density_g_cm3"]) * 1e-3  # g/mm3
    return run_cura_engine(resolver.defs_dir, glob, ext, meshes, bed, density, work, timeout)


def resolved(resolver, overrides, work):
    """The resolved global and extruder-0 settings; kept in cura_settings.json."""
    glob, ext, report = resolver.resolve(overrides)
    if report["unknown_overrides"]:
        raise ValueError("unknown Cura setting(s): %s" % ", ".join(report["unknown_overrides"]))
    if report["errors"]:
        raise SliceError("Cura setting formulas did not evaluate: %s" % json.dumps(report["errors"]))
    with open(os.path.join(work, "cura_settings.json"), "w") as f:
        json.dump({"overrides": overrides, "global": glob, "extruder0": ext, "report": report},
                  f, indent=1, sort_keys=True)
    return glob, ext


def run_cura_engine(defs_dir, glob, ext, meshes, bed, density, work, timeout):
    """CuraEngine on resolved settings; `meshes` [(stl, ["key=value" per-mesh settings])], each STL
    in bed coordinates (centred at bed/2)."""
    bed_x, bed_y = bed
    gcode = os.path.join(work, "out.gcode")
    cmd = [CURA_BIN, "slice", "-v",
           "-j", os.path.join(defs_dir, "fdmprinter.def.json")]
    for k in sorted(glob):
        cmd += ["-s", "%s=%s" % (k, cura_settings.to_engine_string(glob[k]))]
    cmd += ["-e0"]
    for k in sorted(ext):
        cmd += ["-s", "%s=%s" % (k, cura_settings.to_engine_string(ext[k]))]
    # The STLs are in bed coordinates (centred at bed_x/2, bed_y/2).  CuraEngine
    # (machine_center_is_zero=false) adds (machine_width/2, machine_depth/2) to every
    # mesh, so shift it back with the per-mesh position settings given after -l.
    for path, settings in meshes:
        cmd += ["-l", path,
                "-s", "mesh_position_x=%s" % (-bed_x / 2.0),
                "-s", "mesh_position_y=%s" % (-bed_y / 2.0),
                "-s", "mesh_position_z=0",
                "-s", "center_object=False"]
        for kv in settings:
            cmd += ["-s", kv]
    cmd += ["-o", gcode]
    write_cmd(os.path.join(work, "cura_cmd.sh"), cmd)
    out, err, wall = run_slicer(cmd, work, os.path.join(work, "cura"), timeout)
    m_t = re.findall(r"Print time \(s\):\s*([0-9.]+)", err)
    m_v = re.findall(r"Filament \(mm\^3\):\s*([0-9.]+)", err)
    if not m_t or not m_v:
        raise SliceError("CuraEngine output had no 'Print time (s)' / 'Filament (mm^3)' lines; stderr tail:\n"
                         + tail(err))
    if not os.path.isfile(gcode) or os.path.getsize(gcode) == 0:
        raise SliceError("CuraEngine wrote no g-code; stderr tail:\n" + tail(err))
    mm3 = float(m_v[-1])
    diameter = float(ext["material_diameter"])
    # remove_empty_first_layers: when the model's first layer slices empty (a scan standing on a
    # few vertices), CuraEngine drops it, support meshes' first layer with it, and prints every
    # later layer one layer lower. printed_bodies.py needs to know to line the G-code up again.
    m_removed = re.findall(r"Removing (\d+) layers because they are empty", err)
    return {
        "grams": mm3 * density,
        "print_time_s": float(m_t[-1]),
        "filament_mm3": mm3,
        "filament_mm": mm3 / (math.pi * diameter * diameter / 4.0),
        "slice_seconds": wall,
        "removed_empty_first_layers": int(m_removed[-1]) if m_removed else 0,
    }


# --------------------------------------------------------------------------
# Cura's 3MF on a printer, as a user's Cura slices it
# --------------------------------------------------------------------------

_NS = {"m": "http://schemas.microsoft.com/3dmanufacturing/core/2015/02"}


def _matrix(text):
    """A 3MF transform (12 numbers, column-major 3x4) as a function on points."""
    v = [float(x) for x in text.split()] if text else [1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0]
    return lambda p: tuple(p[0] * v[i] + p[1] * v[3 + i] + p[2] * v[6 + i] + v[9 + i] for i in range(3))


def read_cura_3mf(path):
    """Objects of a 3MF with a mesh, in build (plate) coordinates: [(name, triangles, {setting: value})].
    The settings are the object's <metadata name="cura:KEY">, as Cura's reader takes them."""
    with zipfile.ZipFile(path) as z:
        root = ET.fromstring(z.read("3D/3dmodel.model"))
    objects = {o.get("id"): o for o in root.iter("{%s}object" % _NS["m"])}
    out = []

    def emit(obj, transforms):
        mesh = obj.find("m:mesh", _NS)
        if mesh is not None:
            verts = [(float(v.get("x")), float(v.get("y")), float(v.get("z"))) for v in mesh.iter("{%s}vertex" % _NS["m"])]
            for t in transforms:
                verts = [t(p) for p in verts]
            tris = [tuple(verts[int(t.get(k))] for k in ("v1", "v2", "v3")) for t in mesh.iter("{%s}triangle" % _NS["m"])]
            settings = {m.get("name")[5:]: (m.text or "") for m in obj.iter("{%s}metadata" % _NS["m"])
                        if (m.get("name") or "").startswith("cura:")}
            out.append((obj.get("name"), tris, settings))
        for c in obj.iter("{%s}component" % _NS["m"]):
            emit(objects[c.get("objectid")], [_matrix(c.get("transform"))] + transforms)
    for item in root.iter("{%s}item" % _NS["m"]):
        emit(objects[item.get("objectid")], [_matrix(item.get("transform"))])
    return out


def slice_cura_3mf(path, printer, curaprofile, work, timeout, extra=None, density=1.24e-3):
    """Our <name>.3mf and a .curaprofile on a Cura printer definition, as the user's Cura gets them:
    the printer's definition, the global quality of the profile's quality_type, the profile's values
    above both, and each object's own settings from the 3MF. The objects keep their relative
    position and are centred on the printer's bed. No profile.json settings."""
    meta, values = cura_settings.read_curaprofile(curaprofile)
    defs_dir = cura_settings.ensure_defs()
    _, quality = cura_settings.global_quality(defs_dir, printer, meta.get("quality_type"))
    probe = cura_settings.Resolver(defs_dir, printer)
    formulas, literals = cura_settings.container_layers(quality, probe.printer.get)
    profile_formulas, profile_literals = cura_settings.container_layers(values, probe.printer.get)
    formulas.update(profile_formulas)
    for key in profile_formulas:
        literals.pop(key, None)
    literals.update(profile_literals)
    literals.update(extra or {})
    resolver = cura_settings.Resolver(defs_dir, printer, formulas)
    glob, ext = resolved(resolver, literals, work)
    bed = (float(glob["machine_width"]), float(glob["machine_depth"]))
    parts = read_cura_3mf(path)
    groups = []
    for i, (name, tris, _) in enumerate(parts):
        raw = os.path.join(work, "object%d.raw.stl" % i)
        write_stl(raw, tris, name or "object")
        groups.append(([raw], os.path.join(work, "object%d.stl" % i)))
    info = place_groups(groups, (bed[0], bed[1], float(glob["machine_height"])))
    meshes = [(g[1], ["%s=%s" % kv for kv in sorted(p[2].items())]) for g, p in zip(groups, parts)]
    res = run_cura_engine(resolver.defs_dir, glob, ext, meshes, bed, density, work, timeout)
    res.update({"printer": printer, "quality_type": meta.get("quality_type"), "bed_mm": list(bed),
                "model_size_mm": info["size_mm"], "objects": [{"name": p[0], "settings": p[2]} for p in parts]})
    return res


# --------------------------------------------------------------------------
# PrusaSlicer
# --------------------------------------------------------------------------

def prusa_config(profile, support):
    prusa = profile["prusa"]
    modes = prusa["support_modes"]
    cfg = {k: v for k, v in prusa["settings"].items() if not k.startswith("_")}
    cfg.update({k: v for k, v in modes[support].items() if not k.startswith("_")})
    return cfg


def _same_value(ours, theirs):
    ours, theirs = ours.strip(), theirs.strip()
    if ours == theirs:
        return True
    try:
        return all(abs(float(x.rstrip("%")) - float(y.rstrip("%"))) < 1e-9
                   for x, y in zip(ours.split(","), theirs.split(","))) and \
            len(ours.split(",")) == len(theirs.split(",")) and ours.endswith("%") == theirs.endswith("%")
    except ValueError:
        return False


def parse_duration(text):
    total = 0.0
    found = False
    for num, unit in re.findall(r"([0-9.]+)\s*([dhms])", text):
        total += float(num) * {"d": 86400, "h": 3600, "m": 60, "s": 1}[unit]
        found = True
    if not found:
        raise ValueError("cannot parse duration %r" % text)
    return total


def slice_prusa(stl, support, profile, work, timeout, extra=None, support_mesh_stl=None):
    cfg = prusa_config(profile, support)
    cfg.update(extra or {})
    ini = os.path.join(work, "prusa_profile.ini")
    with open(ini, "w") as f:
        f.write("# generated by bench/slicers/slice.py from profile.json (support=%s)\n" % support)
        for k in sorted(cfg):
            f.write("%s = %s\n" % (k, cfg[k]))
    datadir = os.path.join(work, "prusa-datadir")  # private: no user preset leaks in
    os.makedirs(datadir, exist_ok=True)
    gcode = os.path.join(work, "out.gcode")
    # A 3MF is not placed by us (it keeps its own parts and settings): PrusaSlicer centres it.
    placement = [] if stl.lower().endswith(".3mf") else ["--dont-arrange"]
    cmd = [PRUSA_BIN, "--datadir", datadir, "--loglevel", "1", "--config-compatibility", "disable",
           "--export-gcode", "--load", ini] + placement + ["-o", gcode, stl]
    write_cmd(os.path.join(work, "prusa_cmd.sh"), cmd)
    out, err, wall = run_slicer(cmd, work, os.path.join(work, "prusa"), timeout)
    if not os.path.isfile(gcode) or os.path.getsize(gcode) == 0:
        raise SliceError("PrusaSlicer wrote no g-code; stderr tail:\n" + tail(err or out))
    with open(gcode, "rb") as f:
        f.seek(0, 2)
        size = f.tell()
        f.seek(max(0, size - 200000))
        foot = f.read().decode("utf-8", "replace")
    def field(pattern):
        m = re.findall(pattern, foot, re.M)
        if not m:
            raise SliceError("PrusaSlicer g-code footer has no %r" % pattern)
        return m[-1]
    # PrusaSlicer ignores unknown .ini keys silently: check that every option we set is in the
    # config dump at the end of the g-code, with our value.
    dumped = dict(re.findall(r"^; ([a-z0-9_]+) = (.*)$", foot, re.M))
    bad = []
    for k, v in cfg.items():
        if k not in dumped:
            bad.append("%s (not a PrusaSlicer option?)" % k)
        elif not _same_value(str(v), dumped[k]):
            bad.append("%s = %s (PrusaSlicer used %s)" % (k, v, dumped[k]))
    if bad:
        raise SliceError("PrusaSlicer did not apply: " + "; ".join(bad))
    mm = float(field(r"^; filament used \[mm\] = ([0-9.]+)"))
    grams = float(field(r"^; filament used \[g\] = ([0-9.]+)"))
    t = parse_duration(field(r"^; estimated printing time \(normal mode\) = (.+)$"))
    diameter = float(cfg["filament_diameter"])
    return {
        "grams": grams,
        "print_time_s": t,
        "filament_mm3": mm * math.pi * diameter * diameter / 4.0,
        "filament_mm": mm,
        "slice_seconds": wall,
    }


# --------------------------------------------------------------------------

def slice_models(slicer, support, models, out_dir=None, profile_path=None, scale=1.0, timeout=3600,
                 overrides=None, support_meshes=None, printer=None, cura_profile=None):
    """Slice; return the result dict.  Raises SliceError / ValueError."""
    support_meshes = list(support_meshes or [])
    threemf = [m for m in models if m.lower().endswith(".3mf")]
    if bool(printer) != bool(cura_profile):
        raise ValueError("--printer and --cura-profile go together (cura, with our <name>.3mf)")
    if printer:
        if slicer != "cura" or support != "mesh" or len(models) != 1 or not threemf or support_meshes or scale != 1.0:
            raise ValueError("--printer slices one Cura 3MF (our <name>.3mf) with --slicer cura --support mesh, at scale 1")
        for m in models + [cura_profile]:
            if not os.path.isfile(m):
                raise ValueError("no such file: %s" % m)
        return in_work_dir(out_dir, lambda work: dict(
            {"slicer": slicer, "support": support, "models": [os.path.abspath(models[0])],
             "cura_profile": os.path.abspath(cura_profile), "overrides": dict(overrides or {}),
             "out_dir": work if out_dir else None},
            **slice_cura_3mf(models[0], printer, cura_profile, work, timeout, overrides)))
    if (support == "mesh") != bool(support_meshes):
        raise ValueError("--support mesh and --support-mesh FILE go together (cura only)")
    if threemf and (slicer != "prusa" or len(models) != 1 or scale != 1.0):
        raise ValueError("a 3MF is sliced by prusa alone, as the only input, at scale 1 (or by cura with --printer)")
    if slicer not in SUPPORT_MODES:
        raise ValueError("--slicer must be cura or prusa")
    if support not in SUPPORT_MODES[slicer]:
        raise ValueError("--support for %s must be one of: %s" % (slicer, ", ".join(SUPPORT_MODES[slicer])))
    for m in models + support_meshes:
        if not os.path.isfile(m):
            raise ValueError("no such file: %s" % m)
    profile = cura_settings.load_profile(profile_path)
    bed = profile["common"]["bed_mm"]

    def sliced(work):
        stl = os.path.join(work, "merged.stl")
        support_stl = os.path.join(work, "support_mesh.stl") if support_meshes else None
        if threemf:
            stl, info = os.path.abspath(models[0]), {"size_mm": None}
        else:
            groups = [(models, stl)] + ([(support_meshes, support_stl)] if support_meshes else [])
            info = place_groups(groups, bed, scale)
        fn = slice_cura if slicer == "cura" else slice_prusa
        res = fn(stl, support, profile, work, timeout, overrides, support_stl)
        result = {"slicer": slicer, "support": support, "models": [os.path.abspath(m) for m in models]}
        if support_meshes:
            result["support_meshes"] = [os.path.abspath(m) for m in support_meshes]
        result.update(res)
        result["scale"] = scale
        result["model_size_mm"] = info["size_mm"]
        result["overrides"] = dict(overrides or {})
        result["out_dir"] = work if out_dir else None
        return result
    return in_work_dir(out_dir, sliced)


def in_work_dir(out_dir, fn):
    """fn(work) in --out-dir (kept, with result.json) or in a temporary folder (deleted)."""
    tmp = None if out_dir else tempfile.mkdtemp(prefix="clever-slice-")
    work = os.path.abspath(out_dir) if out_dir else tmp
    os.makedirs(work, exist_ok=True)
    try:
        result = fn(work)
        if out_dir:
            with open(os.path.join(work, "result.json"), "w") as f:
                json.dump(result, f, indent=1)
        return result
    finally:
        if tmp:
            shutil.rmtree(tmp, ignore_errors=True)


def main(argv=None):
    ap = argparse.ArgumentParser(description="Slice STL(s) with CuraEngine or PrusaSlicer and report "
                                 "grams, print time and extruded volume.")
    ap.add_argument("--slicer", required=True, choices=("cura", "prusa"))
    ap.add_argument("--support", required=True, choices=("none", "normal", "tree", "mesh", "grid", "snug"),
                    help="cura: none|normal|tree|mesh; prusa: none|grid|snug")
    ap.add_argument("--support-mesh", action="append", default=[], metavar="STL",
                    help="with --support mesh (cura): STL(s) printed as a support mesh beside the model(s)")
    ap.add_argument("--out-dir", help="keep merged.stl, out.gcode, the command, logs and settings here")
    ap.add_argument("--json", action="store_true", help="print one JSON object")
    ap.add_argument("--profile", default=None, help="profile.json (default: beside this script)")
    ap.add_argument("--scale", type=float, default=1.0, help="uniform scale applied to the merged mesh (default 1)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="extra slicer setting on top of profile.json (repeatable). Cura: a setting key, "
                         "value as JSON (never re-derived); prusa: an .ini key and value")
    ap.add_argument("--timeout", type=float, default=3600, help="slicer time limit in seconds (default 3600)")
    ap.add_argument("--printer", help="cura, with our <name>.3mf: a Cura machine definition id (e.g. creality_ender3); "
                    "the printer's definition, the quality of --cura-profile and its values replace profile.json")
    ap.add_argument("--cura-profile", help="with --printer: the .curaprofile the user imported")
    ap.add_argument("models", nargs="+", help="STL file(s), several merged into one mesh; or one PrusaSlicer 3MF")
    args = ap.parse_args(argv)
    extra = {}
    for item in args.set:
        key, eq, val = item.partition("=")
        if not eq or not key:
            print("slice.py: error: --set needs KEY=VALUE, got %r" % item, file=sys.stderr)
            return 2
        extra[key.strip()] = cura_settings.parse_cli_value(val) if args.slicer == "cura" else val
    try:
        res = slice_models(args.slicer, args.support, args.models, args.out_dir, args.profile,
                           args.scale, args.timeout, extra, args.support_mesh, args.printer, args.cura_profile)
    except ValueError as exc:
        print("slice.py: error: %s" % exc, file=sys.stderr)
        return 2
    except SliceError as exc:
        print("slice.py: %s failed: %s" % (args.slicer, exc), file=sys.stderr)
        return 1
    if args.json:
        print(json.dumps(res))
    else:
        for k in ("slicer", "support", "models", "grams", "print_time_s", "filament_mm3", "filament_mm",
                  "slice_seconds", "out_dir"):
            v = res[k]
            if isinstance(v, float):
                v = "%.3f" % v
            elif isinstance(v, list):
                v = " ".join(v)
            print("%-14s %s" % (k, v))
        print("%-14s %.1f min" % ("print_time", res["print_time_s"] / 60.0))
    return 0


if __name__ == "__main__":
    sys.exit(main())

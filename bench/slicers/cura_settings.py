#!/usr/bin/python3
"""Resolve Cura 4.13 setting formulas the way the Cura GUI (Uranium) does.

Why: CuraEngine on the command line does NOT evaluate the ``value`` formulas of
fdmprinter.def.json; every derived setting keeps its raw ``default_value``
unless it is passed explicitly (pitfall 1 in shared/notes/slicer-comparison.md).
So we evaluate them here and pass every setting to CuraEngine.

Model (single extruder, extruder 0), following Cura's docs/profiles/
getting_a_setting_value.md and Cura 4.13's GlobalStack / ExtruderStack:

* Two views are computed: the *extruder* view (extruder stack 0: fdmextruder
  definition on top of the global stack) and the *global* view (global stack,
  fdmprinter definition).
* A setting we override explicitly gets that value in both views and is never
  re-derived (like a value in the user container; this also disables
  ``resolve`` for it, like GlobalStack.hasUserValue).
* Extruder view: settings with ``settable_per_extruder: false`` are taken from
  the global view; the others evaluate their ``value`` formula in the extruder
  context (names refer to extruder-view values). fdmextruder.def.json entries
  replace fdmprinter ones for the keys it defines (a definition without
  ``value`` falls back to its ``default_value``).
* Global view: a setting with a ``resolve`` formula returns that formula
  (e.g. ``min(extruderValues('layer_height_0'))``); else a setting with a
  ``limit_to_extruder`` that is settable per extruder is read from extruder 0
  (the only one); else its own ``value`` formula evaluated in the global
  context; else its ``default_value``.
* Helpers: ``extruderValue(n, key)`` -> extruder view; ``extruderValues(key)``
  -> [extruder view]; ``resolveOrValue(key)`` -> global view (resolve applied);
  ``defaultExtruderPosition()`` -> "0"; ``valueFromContainer`` /
  ``extruderValueFromContainer`` -> the value (there is only one container
  here); plus ``math`` and the builtins used by the formulas.
* Evaluation: the settings are ordered topologically by the names their
  formulas use (bare names and quoted keys in helper calls), then evaluated
  pass after pass in that order until no value changes (a fixed point).

Command line:
  cura_settings.py [--defs-dir DIR] [--profile profile.json] [--support MODE]
                   [--set KEY=VALUE ...] [--view global|extruder|both]
prints the flat dict of resolved values as JSON.
"""
import argparse
import ast
import configparser
import glob
import json
import math
import os
import re
import subprocess
import sys
import zipfile

HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_PROFILE = os.path.join(HERE, "profile.json")

# Engine-only settings that the Cura frontend adds in StartSliceJob and that are
# not in fdmprinter.def.json.  They only affect the start g-code text.
FRONTEND_EXTRA = {
    "material_bed_temp_prepend": True,
    "material_print_temp_prepend": True,
}


def default_defs_dir():
    """$CURA_DEFS_DIR, else the definitions in fetch_cura_defs.sh's Cura 4.13 cache."""
    d = os.environ.get("CURA_DEFS_DIR")
    if d:
        return d
    cache = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
    root = os.environ.get("CURA_413_DIR") or os.path.join(cache, "clever-support", "cura-4.13")
    return os.path.join(root, "usr", "share", "cura", "resources", "definitions")


def ensure_defs(defs_dir=None):
    """Return the directory holding the two .def.json files, fetching them if needed."""
    defs_dir = defs_dir or default_defs_dir()
    need = [os.path.join(defs_dir, f) for f in ("fdmprinter.def.json", "fdmextruder.def.json")]
    if all(os.path.isfile(p) and os.path.getsize(p) > 0 for p in need):
        return defs_dir
    env = dict(os.environ, CURA_DEFS_DIR=defs_dir)
    out = subprocess.run(["bash", os.path.join(HERE, "fetch_cura_defs.sh")], env=env,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if out.returncode != 0:
        raise RuntimeError("fetch_cura_defs.sh failed:\n" + out.stderr[-2000:])
    return out.stdout.strip().splitlines()[-1]


# --------------------------------------------------------------------------
# Loading definitions (with inheritance)
# --------------------------------------------------------------------------

def _def_path(defs_dir, def_id):
    """A definition file: printers in the definitions folder, extruders in Cura's extruders/ beside it."""
    for folder in (defs_dir, os.path.join(os.path.dirname(os.path.abspath(defs_dir)), "extruders")):
        path = os.path.join(folder, def_id + ".def.json")
        if os.path.isfile(path):
            return path
    raise ValueError("no Cura definition %r in %s (or its extruders/ folder)" % (def_id, defs_dir))


def _load_def_file(path, defs_dir, metadata=None):
    """Load a .def.json and the chain it inherits from; return flat {key: props}. `metadata`, if
    given, collects the chain's metadata (the child's entries win)."""
    with open(path) as f:
        doc = json.load(f)
    flat = {}
    parent = doc.get("inherits")
    if parent:
        flat = _load_def_file(_def_path(defs_dir, parent), defs_dir, metadata)
    if metadata is not None:
        metadata.update(doc.get("metadata", {}))

    def walk(children):
        for key, props in children.items():
            kids = props.get("children")
            own = {k: v for k, v in props.items() if k != "children"}
            if props.get("type") != "category":
                merged = dict(flat.get(key, {}))
                merged.update(own)
                flat[key] = merged
            if kids:
                walk(kids)

    walk(doc.get("settings", {}))
    # "overrides" (used by machine definitions that inherit) patch properties.
    for key, props in doc.get("overrides", {}).items():
        merged = dict(flat.get(key, {}))
        merged.update(props)
        flat[key] = merged
    return flat


def machine_metadata(defs_dir, machine):
    """A printer definition's metadata, its parents' included (e.g. machine_extruder_trains)."""
    md = {}
    _load_def_file(_def_path(defs_dir, machine), defs_dir, md)
    return md


def load_definitions(defs_dir, machine="fdmprinter"):
    """The printer's and its first extruder's settings (fdmprinter + fdmextruder by default)."""
    printer = _load_def_file(_def_path(defs_dir, machine), defs_dir)
    trains = machine_metadata(defs_dir, machine).get("machine_extruder_trains", {})
    extruder_raw = _load_def_file(_def_path(defs_dir, trains.get("0", "fdmextruder")), defs_dir)
    # Extruder stack: the extruder definition sits above the global stack.  A
    # property it does not define falls through to fdmprinter; "value" does
    # not fall through: a definition without "value" returns its default_value.
    extruder = {}
    for key, props in printer.items():
        if key in extruder_raw:
            merged = dict(props)
            merged.update(extruder_raw[key])
            if "value" not in extruder_raw[key]:
                merged.pop("value", None)
            extruder[key] = merged
        else:
            extruder[key] = props
    for key, props in extruder_raw.items():
        if key not in extruder:
            extruder[key] = props
    return printer, extruder


def read_container(text):
    """A Cura instance container (.inst.cfg, or the .cfg in a .curaprofile): (metadata, values)."""
    cp = configparser.ConfigParser(interpolation=None, strict=False)
    cp.read_string(text)
    meta = dict(cp["general"]) if cp.has_section("general") else {}
    meta.update(dict(cp["metadata"]) if cp.has_section("metadata") else {})
    return meta, dict(cp["values"]) if cp.has_section("values") else {}


def read_curaprofile(path):
    """The global profile of a .curaprofile ZIP (the entry without a position): (metadata, values)."""
    with zipfile.ZipFile(path) as z:
        entries = [read_container(z.read(n).decode("utf-8")) for n in z.namelist()]
    glob = [e for e in entries if "position" not in e[0]]
    if not glob:
        raise ValueError("%s holds no global profile" % path)
    return glob[0]


def global_quality(defs_dir, machine, quality_type):
    """The printer's global quality of that type, as Cura's container tree finds it (MachineNode:
    the quality_definition's global qualities, fdmprinter's when it has none): (metadata, values)."""
    md = machine_metadata(defs_dir, machine)
    has_own = str(md.get("has_machine_quality", "false")).lower() == "true"
    qdef = md.get("quality_definition", machine) if has_own else "fdmprinter"
    quality_dir = os.path.join(os.path.dirname(os.path.abspath(defs_dir)), "quality")
    found = {}
    for path in glob.glob(os.path.join(quality_dir, "**", "*.inst.cfg"), recursive=True):
        with open(path, encoding="utf-8") as f:
            meta, values = read_container(f.read())
        if meta.get("type") == "quality" and str(meta.get("global_quality")) == "True":
            found.setdefault(meta.get("definition"), {})[meta.get("quality_type")] = (meta, values)
    qualities = found.get(qdef) or found.get("fdmprinter", {})
    if quality_type not in qualities:
        raise ValueError("printer %s has no quality %r (it has: %s)" % (machine, quality_type, ", ".join(sorted(qualities))))
    return qualities[quality_type]


def container_layers(values, props_of):
    """Split a container's values as Cura's stack reads them: "=formula" becomes the setting's
    formula (re-derived), anything else a literal of the setting's type (never re-derived).
    Returns (formulas, literals)."""
    formulas, literals = {}, {}
    for key, text in values.items():
        text = text.strip()
        if text.startswith("="):
            formulas[key] = text[1:]
            continue
        kind = (props_of(key) or {}).get("type")
        if kind == "bool":
            literals[key] = text in ("True", "true", "1")
        elif kind in ("float", "int"):
            literals[key] = float(text) if kind == "float" else int(float(text))
        else:
            literals[key] = parse_cli_value(text) if kind not in ("str", "enum") else text
    return formulas, literals


# --------------------------------------------------------------------------
# Formula evaluation
# --------------------------------------------------------------------------

_SAFE_BUILTINS = {
    name: getattr(__builtins__, name) if hasattr(__builtins__, name) else __builtins__[name]
    for name in ("abs", "all", "any", "bool", "dict", "enumerate", "filter", "float", "int",
                 "len", "list", "map", "max", "min", "range", "round", "set", "sorted", "str",
                 "sum", "tuple", "zip", "isinstance", "True", "False", "None")
}


def _referenced_keys(expr, keys):
    """Setting keys an expression uses: bare names and quoted keys."""
    if not isinstance(expr, str):
        return set()
    names = set()
    try:
        tree = ast.parse(expr, mode="eval")
        for node in ast.walk(tree):
            if isinstance(node, ast.Name) and node.id in keys:
                names.add(node.id)
            elif isinstance(node, ast.Constant) and isinstance(node.value, str) and node.value in keys:
                names.add(node.value)
    except SyntaxError:
        names = {t for t in re.findall(r"[A-Za-z_][A-Za-z0-9_]*", expr) if t in keys}
    return names


def _toposort(keys, deps):
    """Kahn's algorithm; members of cycles are appended in definition order."""
    order, seen = [], set()
    indeg = {k: len([d for d in deps[k] if d != k]) for k in keys}
    users = {k: [] for k in keys}
    for k in keys:
        for d in deps[k]:
            if d != k:
                users[d].append(k)
    ready = [k for k in keys if indeg[k] == 0]
    while ready:
        k = ready.pop(0)
        order.append(k)
        seen.add(k)
        for u in users[k]:
            indeg[u] -= 1
            if indeg[u] == 0:
                ready.append(u)
    order += [k for k in keys if k not in seen]
    return order


class Resolver:
    def __init__(self, defs_dir=None, machine="fdmprinter", formulas=None):
        """`machine`: a printer definition id; `formulas`: {key: formula} of containers above the
        definitions (a quality's "=..." values), which replace the definitions' formulas."""
        self.defs_dir = ensure_defs(defs_dir)
        self.printer, self.extruder = load_definitions(self.defs_dir, machine)
        for key, expr in (formulas or {}).items():
            for view in (self.printer, self.extruder):
                if key in view:
                    view[key] = dict(view[key], value=expr)
        self.keys = list(self.printer.keys())
        for k in self.extruder:
            if k not in self.printer:
                self.keys.append(k)
        self._compiled = {}

    # -- properties ------------------------------------------------------
    def _spe(self, key):
        """settable_per_extruder (Uranium default: True)."""
        props = self.extruder.get(key) or self.printer.get(key) or {}
        return props.get("settable_per_extruder", True) is not False

    def _code(self, expr, label):
        c = self._compiled.get(expr)
        if c is None:
            c = compile(expr, "<%s>" % label, "eval")
            self._compiled[expr] = c
        return c

    def resolve(self, overrides=None, max_passes=50):
        """Return (global_view, extruder_view, report) dicts of resolved values."""
        overrides = dict(overrides or {})
        unknown = [k for k in overrides if k not in self.printer and k not in self.extruder]
        keys = self.keys

        glob = {}
        ext = {}
        for k in keys:
            p = self.printer.get(k, self.extruder.get(k))
            e = self.extruder.get(k, p)
            glob[k] = p.get("default_value")
            ext[k] = e.get("default_value")
        for k, v in overrides.items():
            glob[k] = v
            ext[k] = v

        helpers_common = {"math": math, "__builtins__": _SAFE_BUILTINS}

        def extruderValue(extruder_position, key):  # noqa: N802 (Cura's names)
            return ext.get(key)

        def extruderValues(key):  # noqa: N802
            return [ext.get(key)]

        def resolveOrValue(key):  # noqa: N802
            return glob.get(key)

        def defaultExtruderPosition():  # noqa: N802
            return "0"

        def valueFromContainer(key, index):  # noqa: N802
            return glob.get(key)

        def extruderValueFromContainer(extruder_position, key, index):  # noqa: N802
            return ext.get(key)

        helpers = dict(helpers_common, extruderValue=extruderValue, extruderValues=extruderValues,
                       resolveOrValue=resolveOrValue, defaultExtruderPosition=defaultExtruderPosition,
                       valueFromContainer=valueFromContainer,
                       extruderValueFromContainer=extruderValueFromContainer)
        # Namespaces: setting names as globals (so names also work inside
        # comprehensions), helper names on top.
        env_glob = dict(glob)
        env_glob.update(helpers)
        env_ext = dict(ext)
        env_ext.update(helpers)

        deps = {}
        for k in keys:
            d = set()
            for props in (self.printer.get(k, {}), self.extruder.get(k, {})):
                for prop in ("value", "resolve"):
                    d |= _referenced_keys(props.get(prop), set(self.printer) | set(self.extruder))
            deps[k] = d
        order = _toposort(keys, deps)

        errors = {}

        def ev(expr, env, label):
            try:
                return eval(self._code(expr, label), env), None
            except Exception as exc:  # keep previous value, report
                return None, "%s: %s" % (type(exc).__name__, exc)

        def set_val(view, env, k, v):
            view[k] = v
            env[k] = v

        passes = 0
        for passes in range(1, max_passes + 1):
            changed = 0
            for k in order:
                if k in overrides:
                    continue
                p = self.printer.get(k)
                e = self.extruder.get(k, p)
                spe = self._spe(k)
                # -- extruder view
                if spe or p is None:
                    expr = e.get("value")
                    if expr is None:
                        new_e = e.get("default_value")
                    elif isinstance(expr, str):
                        new_e, err = ev(expr, env_ext, k)
                        if err:
                            errors[k] = err
                            new_e = ext[k]
                        else:
                            errors.pop(k, None)
                    else:
                        new_e = expr
                    if new_e != ext[k] or type(new_e) is not type(ext[k]):
                        set_val(ext, env_ext, k, new_e)
                        changed += 1
                # -- global view
                if p is None:
                    new_g = ext[k]
                elif p.get("resolve"):
                    new_g, err = ev(p["resolve"], env_glob, k + "#resolve")
                    if err:
                        errors[k + "#resolve"] = err
                        new_g = glob[k]
                    else:
                        errors.pop(k + "#resolve", None)
                elif p.get("limit_to_extruder") is not None and spe:
                    new_g = ext[k]
                else:
                    expr = p.get("value")
                    if expr is None:
                        new_g = p.get("default_value")
                    elif isinstance(expr, str):
                        new_g, err = ev(expr, env_glob, k + "#global")
                        if err:
                            errors[k + "#global"] = err
                            new_g = glob[k]
                        else:
                            errors.pop(k + "#global", None)
                    else:
                        new_g = expr
                if new_g != glob[k] or type(new_g) is not type(glob[k]):
                    set_val(glob, env_glob, k, new_g)
                    changed += 1
                if not spe and (ext[k] != glob[k] or type(ext[k]) is not type(glob[k])):
                    set_val(ext, env_ext, k, glob[k])
                    changed += 1
            if changed == 0:
                break
        else:
            errors["__fixed_point__"] = "no fixed point after %d passes" % max_passes

        for k, v in FRONTEND_EXTRA.items():
            glob.setdefault(k, v)
            ext.setdefault(k, v)
        report = {"passes": passes, "errors": errors, "unknown_overrides": unknown,
                  "overridden": sorted(overrides), "defs_dir": self.defs_dir}
        return glob, ext, report


# --------------------------------------------------------------------------
# Profile handling
# --------------------------------------------------------------------------

def load_profile(path=None):
    with open(path or DEFAULT_PROFILE) as f:
        return json.load(f)


def cura_overrides(profile, support, bed_override=None):
    """The explicit Cura overrides for a support mode: common + per-mode."""
    cura = profile["cura"]
    modes = cura["support_modes"]
    if support not in modes:
        raise ValueError("Cura support mode must be one of %s" % ", ".join(sorted(modes)))
    out = {k: v for k, v in cura["settings"].items() if not k.startswith("_")}
    out.update({k: v for k, v in modes[support].items() if not k.startswith("_")})
    return out


def to_engine_string(value):
    """How Cura's frontend turns a value into the string CuraEngine receives (str())."""
    return str(value)


def parse_cli_value(text):
    try:
        return json.loads(text)
    except ValueError:
        if text in ("True", "False"):
            return text == "True"
        return text


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--defs-dir", default=None, help="directory with fdmprinter/fdmextruder.def.json "
                    "(default: $CURA_DEFS_DIR or the fetch_cura_defs.sh cache; fetched if absent)")
    ap.add_argument("--profile", default=DEFAULT_PROFILE, help="profile.json (default: beside this script)")
    ap.add_argument("--support", default="none", help="support mode of the profile: none|normal|tree")
    ap.add_argument("--no-profile", action="store_true", help="ignore the profile (raw definitions + --set only)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="extra override (JSON value, e.g. --set infill_sparse_density=15)")
    ap.add_argument("--view", choices=("global", "extruder", "both"), default="global",
                    help="which stack to print (default global; 'both' prints {global, extruder, report})")
    args = ap.parse_args(argv)

    overrides = {}
    if not args.no_profile:
        overrides.update(cura_overrides(load_profile(args.profile), args.support))
    for item in args.set:
        k, _, v = item.partition("=")
        overrides[k] = parse_cli_value(v)
    res = Resolver(args.defs_dir)
    glob, ext, report = res.resolve(overrides)
    if report["errors"] or report["unknown_overrides"]:
        print("warning: %s" % json.dumps({"errors": report["errors"],
                                          "unknown_overrides": report["unknown_overrides"]}),
              file=sys.stderr)
    if args.view == "global":
        out = glob
    elif args.view == "extruder":
        out = ext
    else:
        out = {"global": glob, "extruder": ext, "report": report}
    json.dump(out, sys.stdout, indent=1, sort_keys=True)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

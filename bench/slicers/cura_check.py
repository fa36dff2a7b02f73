#!/usr/bin/python3
"""What Cura 4.13 itself makes of clever-support's <name>.3mf and .curaprofile, on given printers.

usage: cura_check.py [--3mf FILE.3mf] [--profile FILE.curaprofile ...] --printer DEFINITION_ID [...]
       (prints one JSON object; exit 0 when it ran, 1 when Cura's files are missing, 2 on usage)

No GUI and no reimplementation where Cura's own code can run: the Python of Debian's `cura` 4.13
and `python3-uranium`, unpacked by fetch_cura_defs.sh, runs headless here.
* The 3MF is read with python3-savitar (libSavitar, Cura's 3MF parser): the objects, the group and
  each object's "cura:" settings. ThreeMFReader keeps a setting when the object's setting stack
  knows its key (ThreeMFReader.py 168-178, `getAllKeys()`: every setting of the printer's
  definition); the key is checked against each printer's definition, loaded by Uranium's
  DefinitionContainer.
* Each profile is parsed by Uranium's InstanceContainer (the .cfg inside the .curaprofile ZIP, as
  CuraProfileReader does) and judged as CuraContainerRegistry.importProfile/_configureProfile
  (cura/Settings/CuraContainerRegistry.py 419-452) judge it: its quality_type must be one of the
  printer's quality groups, else "Quality type '...' is not compatible" (import fails); a quality
  group not available for the printer's default nozzle and material imports hidden. The quality
  groups come from Cura's own container tree (cura.Machines.MachineNode.getQualityGroups), built
  on Uranium's ContainerRegistry over Cura's definitions, variants, qualities and fdm-materials.
  The default nozzle and material are the ones Cura gives a newly added printer
  (MachineNode.preferred_variant_name, VariantNode.preferredMaterial).
* The layer height after choosing the profile: its own layer_height if it sets one, else the
  quality group's global quality's (a formula is evaluated by Uranium's SettingFunction against the
  definition), else the printer definition's.
What is not run: the Qt import dialog and the container stacks of a whole running Cura.
"""
import argparse
import glob
import json
import os
import subprocess
import sys
import types
import urllib.parse
import warnings
import zipfile

sys.dont_write_bytecode = True
HERE = os.path.dirname(os.path.abspath(__file__))


def cura_root():
    out = subprocess.run(["bash", os.path.join(HERE, "fetch_cura_defs.sh"), "--no-fetch", "--root"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if out.returncode != 0:
        raise SystemExit(out.stderr.strip() or "Cura 4.13 is not unpacked (bench/slicers/fetch_cura_defs.sh)")
    return out.stdout.strip().splitlines()[-1]


def import_cura(root):
    """Put Cura's and Uranium's Python on the path. Modules that need a running Qt application
    (cura.CuraApplication, PyQt5.QtQml) get stand-ins: the code run here only imports them."""
    sys.path[:0] = [os.path.join(root, "usr/lib/python3/dist-packages"), os.path.join(root, "usr/lib/cura/plugins")]
    warnings.simplefilter("ignore")
    qml = types.ModuleType("PyQt5.QtQml")

    class QQmlEngine:
        CppOwnership = 0

        @staticmethod
        def setObjectOwnership(*_):
            pass
    qml.QQmlEngine = QQmlEngine
    sys.modules["PyQt5.QtQml"] = qml
    # Files of Cura 4.13 itself (and our profile, setting_version 19) are at 4.13's versions: the
    # version upgrade that Uranium would run on reading them does nothing; it needs the application.
    upgrade = types.ModuleType("UM.VersionUpgradeManager")

    class VersionUpgradeManager:
        @staticmethod
        def getInstance():
            return VersionUpgradeManager()

        def updateFilesData(self, *_):
            return None
    upgrade.VersionUpgradeManager = VersionUpgradeManager
    sys.modules["UM.VersionUpgradeManager"] = upgrade
    import cura  # noqa: F401
    app = types.ModuleType("cura.CuraApplication")

    class CuraApplication:
        SettingVersion = 19  # cura/CuraApplication.py: SettingVersion of Cura 4.13

        @staticmethod
        def getInstance():
            return None
    app.CuraApplication = CuraApplication
    sys.modules["cura.CuraApplication"] = app
    cura.CuraApplication = app
    # What CuraApplication._initializeSettingDefinitions registers before any definition is read:
    # Cura's own setting properties and types.
    from UM.Settings.SettingDefinition import SettingDefinition, DefinitionPropertyType
    from UM.Settings.Validator import Validator
    for prop in ("settable_per_mesh", "settable_per_extruder", "settable_per_meshgroup", "settable_globally"):
        SettingDefinition.addSupportedProperty(prop, DefinitionPropertyType.Any, default=True, read_only=True)
    for prop, default in (("limit_to_extruder", "-1"), ("resolve", None)):
        SettingDefinition.addSupportedProperty(prop, DefinitionPropertyType.Function, default=default, depends_on="value")
    for kind, validator in (("extruder", Validator), ("optional_extruder", None), ("[int]", None)):
        SettingDefinition.addSettingType(kind, None, str, validator)


class Registry:
    """Uranium's ContainerRegistry holding the metadata of Cura's resource files, found the way
    Uranium's LocalContainerProvider names them (id = file name without its extensions)."""

    def __init__(self, resources):
        from UM.Settings.ContainerRegistry import ContainerRegistry
        from UM.Settings.DefinitionContainer import DefinitionContainer
        from UM.Settings.InstanceContainer import InstanceContainer
        from UM.Resources import Resources
        import cura.Settings.cura_empty_instance_containers as empty
        Resources.addSearchPath(resources)
        class Application:  # the registry's one use of it here: deferred "container added" signals
            @staticmethod
            def callLater(*_):
                pass
        self.registry = ContainerRegistry(Application)
        import UM.Settings.InstanceContainer
        UM.Settings.InstanceContainer.setContainerRegistry(self.registry)  # as UM.Application does
        self.files = {}
        for path in glob.glob(os.path.join(resources, "definitions", "*.def.json")) + \
                glob.glob(os.path.join(resources, "extruders", "*.def.json")):
            self.files[self._id(path, ".def.json")] = (path, DefinitionContainer)
        for sub in ("quality", "variants", "intent"):
            for path in glob.glob(os.path.join(resources, sub, "**", "*.inst.cfg"), recursive=True):
                self.files[self._id(path, ".inst.cfg")] = (path, InstanceContainer)
        for c in (empty.empty_variant_container, empty.empty_material_container, empty.empty_quality_container,
                  empty.empty_intent_container, empty.empty_quality_changes_container):
            self.registry.metadata[c.getId()] = c.getMetaData()
            self.registry._containers[c.getId()] = c
        self.registry._providers.append(self)
        for container_id in list(self.files):
            self.registry.findContainersMetadata(id=container_id)  # lazy-loads through loadMetadata
        self._add_materials(resources)
        self.registry._clearQueryCache()

    @staticmethod
    def _id(path, ext):
        return urllib.parse.unquote_plus(os.path.basename(path)[:-len(ext)])

    def _add_materials(self, resources):
        from UM.PluginRegistry import PluginRegistry
        from XmlMaterialProfile.XmlMaterialProfile import XmlMaterialProfile
        plugins = os.path.dirname(os.path.dirname(sys.modules[XmlMaterialProfile.__module__].__file__))

        class Plugins:  # the one call the material reader makes: where its product_to_id.json is
            @staticmethod
            def getPluginPath(name):
                return os.path.join(plugins, name)
        PluginRegistry.getInstance = staticmethod(lambda: Plugins)
        for path in glob.glob(os.path.join(resources, "materials", "*.xml.fdm_material")):
            with open(path, encoding="utf-8") as f:
                for md in XmlMaterialProfile.deserializeMetadata(f.read(), self._id(path, ".xml.fdm_material")):
                    self.registry.metadata[md["id"]] = md
                    self.registry.source_provider[md["id"]] = None

    # -- the ContainerProvider interface Uranium's registry calls --------------------------------
    def getAllIds(self):
        return self.files.keys()

    def loadMetadata(self, container_id):
        path, kind = self.files[container_id]
        with open(path, encoding="utf-8") as f:
            md = kind.deserializeMetadata(f.read(), container_id)
        return md[0] if md else {}

    def loadContainer(self, container_id):
        path, kind = self.files[container_id]
        c = kind(container_id)
        with open(path, encoding="utf-8") as f:
            c.deserialize(f.read())  # no file name: no signature check (needs the application)
        return c

    def isReadOnly(self, _):
        return True

    def getLastModifiedTime(self, container_id):
        return os.path.getmtime(self.files[container_id][0])

    def definition(self, container_id):
        return self.registry.findDefinitionContainers(id=container_id)[0]

    def quality(self, container_id):
        return self.registry.findInstanceContainers(id=container_id)[0]


def read_3mf(path):
    """The 3MF as Cura's parser (libSavitar) reads it: objects, group, per-object settings."""
    import Savitar
    with zipfile.ZipFile(path) as z:  # ThreeMFReader hands the parser the model part, as here
        scene = Savitar.ThreeMFParser().parse(z.read("3D/3dmodel.model"))

    def node(n):
        return {"name": n.getName(), "triangles": len(n.getMeshData().getFlatVerticesAsBytes()) // 36,
                "settings": {k: v.value for k, v in n.getSettings().items()},
                "children": [node(c) for c in n.getChildren()]}
    return [node(n) for n in scene.getSceneNodes()]


def read_profile(path):
    """The .cfg entries of a .curaprofile ZIP, each parsed by Uranium's InstanceContainer."""
    from UM.Settings.InstanceContainer import InstanceContainer
    profiles = []
    with zipfile.ZipFile(path) as z:
        for entry in z.namelist():
            c = InstanceContainer(entry)
            c.deserialize(z.read(entry).decode("utf-8"))  # no file name: no signature check
            profiles.append(c)
    return profiles


def layer_height_of(reg, quality_container, machine_def):
    """layer_height as a stack of [quality, machine definition] gives it (Uranium evaluates a formula)."""
    from UM.Settings.SettingFunction import SettingFunction
    value = quality_container.getProperty("layer_height", "value") if quality_container else None
    if value is None:
        value = machine_def.getProperty("layer_height", "default_value")
        formula = machine_def.getProperty("layer_height", "value")
        value = formula if formula is not None else value
    if isinstance(value, SettingFunction):
        value = value(machine_def)
    return float(value)


def check_printer(reg, printer, profiles, objects):
    from cura.Machines.MachineNode import MachineNode
    machine = MachineNode(printer)
    machine_def = reg.definition(printer)
    keys = set(machine_def.getAllKeys())
    variant = machine.variants.get(machine.preferred_variant_name) or next(iter(machine.variants.values()))
    # As CuraStackBuilder.createExtruderStack picks them: the preferred nozzle (else the first) and
    # the preferred material at the extruder definition's rounded material_diameter.
    extruder_id = (machine_def.getMetaDataEntry("machine_extruder_trains") or {}).get("0", "fdmextruder")
    diameter = reg.definition(extruder_id).getProperty("material_diameter", "value")
    material = variant.preferredMaterial(round(float(diameter)))
    groups = machine.getQualityGroups([variant.variant_name], [material.base_file], [True])
    out = {"printer": printer, "quality_definition": machine.quality_definition,
           "nozzle": variant.variant_name, "material": material.base_file,
           "quality_types": sorted(groups), "available_quality_types": sorted(t for t, g in groups.items() if g.is_available),
           "preferred_quality_type": machine.preferred_quality_type,
           "minimum_support_area": machine_def.getProperty("minimum_support_area", "value")
           if machine_def.getProperty("minimum_support_area", "value") is not None
           else machine_def.getProperty("minimum_support_area", "default_value"),
           "profiles": {}}
    if not isinstance(out["minimum_support_area"], (int, float)):
        out["minimum_support_area"] = str(out["minimum_support_area"])  # a formula, e.g. "=2"
    # The 3MF's per-object settings that ThreeMFReader keeps on this printer.
    kept, dropped = {}, {}

    def walk(nodes):
        for n in nodes:
            for k, v in n["settings"].items():
                (kept if k in keys else dropped)[n["name"] + ":" + k] = v
            walk(n["children"])
    walk(objects or [])
    out["3mf_settings_kept"], out["3mf_settings_dropped"] = kept, dropped
    for path, containers in profiles.items():
        glob_profile = containers[0] if len(containers) == 1 else next(c for c in containers if not c.getMetaDataEntry("position"))
        qt = glob_profile.getMetaDataEntry("quality_type")
        res = {"name_in_cura": os.path.splitext(os.path.basename(path))[0], "quality_type": qt,
               "unknown_keys": sorted(k for k in glob_profile.getAllKeys() if k not in keys)}
        if qt not in groups:
            res["import"] = "error"
            res["message"] = "Quality type '%s' is not compatible with the current active machine definition '%s'." % (
                qt, machine.quality_definition)
        elif not groups[qt].is_available:
            res["import"] = "hidden"
            res["message"] = "Warning: The profile is not visible because its quality type '%s' is not available " \
                             "for the current configuration." % qt
        else:
            res["import"] = "ok"
        if qt in groups:
            quality = reg.quality(groups[qt].node_for_global.container_id)
            res["quality_layer_height"] = layer_height_of(reg, quality, machine_def)
            own = glob_profile.getProperty("layer_height", "value")
            res["layer_height"] = float(own) if own is not None else res["quality_layer_height"]
        res["values"] = {k: str(glob_profile.getProperty(k, "value")) for k in sorted(glob_profile.getAllKeys())}
        out["profiles"][os.path.basename(path)] = res
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--3mf", dest="threemf", help="clever-support's <name>.3mf")
    ap.add_argument("--profile", action="append", default=[], help="a .curaprofile (repeatable)")
    ap.add_argument("--printer", action="append", default=[], required=True,
                    help="a Cura 4.13 machine definition id, e.g. creality_ender3, prusa_i3_mk3, ultimaker_s5")
    args = ap.parse_args(argv)
    root = cura_root()
    import_cura(root)
    reg = Registry(os.path.join(root, "usr/share/cura/resources"))
    objects = read_3mf(args.threemf) if args.threemf else None
    profiles = {p: read_profile(p) for p in args.profile}
    result = {"cura_version": open(os.path.join(root, "VERSION")).read().strip(), "3mf": objects,
              "printers": [check_printer(reg, p, profiles, objects) for p in args.printer]}
    json.dump(result, sys.stdout, indent=1, sort_keys=True)
    sys.stdout.write("\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

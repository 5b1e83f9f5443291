"""PyBuild: the base class of Python build scripts (seed 004 §4.9, Figure 31).

A build script subclasses PyBuild and overrides ``run()`` (and optionally
``post()``); making an instance builds the rig::

    class HeroBuild(rigel.PyBuild):
        character_file = "tests/data/gltf/rigify_human_metarig.glb"
        rig_name = "hero"

        def run(self):
            hip = self.add("hip", "hip", guides=[rigel.Guide("hip", joint="spine")])
            ...

        def post(self):
            self.scene.set("hero_hip_C_main.visibility", True)

    HeroBuild(output="hero.rigel")

What happens, in order (``execute()``):

1. the character file is opened into ``self.scene`` (``rigel.open``: glTF,
   BVH or .rigel) and an empty ``rigel.Definition`` named ``rig_name`` is
   made, holding a root ``global`` component: ``self.character`` (the
   seed's character instance, which component creation methods take as
   their parent by default);
2. ``run()`` adds components to the definition (``self.add``); it may also
   edit the character scene itself;
3. the definition is checked (``rigel.DefinitionError`` lists every
   problem) and, when ``definition_output`` is given, saved there with the
   character as its geometry, so ``rigel update`` and ``rigel rigs`` find it
   later;
4. ``rigel.RigBuild.open`` plans it on the scene and builds every step (or the
   first ``steps``): the same recorded, undoable, removable procedural build
   as ``rigel build``, with the same component classes;
5. ``post()`` runs with the built rig (``self.build``, ``self.scene``),
   when the build is complete (not after a partial build, ``steps=N``:
   post-build tasks need the whole rig). Its default imports the build's
   hand-made data (below); a script that overrides it calls
   ``super().post()`` to keep that;
6. the scene is saved to ``output`` when given.

The data ``post()`` imports by default (``data_files()``), each file once,
in this order, through the same importer as a definition's ``<data>`` and
``rigel publish`` (``rigel.import_data``):

- ``data``: (kind, file) pairs, files relative to the current folder (as
  ``character_file``), e.g. ``data = [("weights", "data/weights/body.weights.json")]``;
  shapes go onto this rig;
- when the script sits inside an asset (``asset`` None: the folder of the
  file the class, or its ``run()``, is written in; or a folder given;
  False: none), every file
  of the asset's data folders (``rigel.asset_data_files``: weights, then
  shapes): weights onto the scene's skins, a shapes file only when it names
  this rig (the asset's other rigs have their own).

Kinds: weights, shapes (blendshapes, driven_poses and correctives are
refused until their managers exist). A shapes file finds controls by their
component's rigId: a script whose shapes are kept as data gives its
components theirs (``self.add(..., rig_id="...")``, ``root_component =
None`` and its own global), since a component added without one gets a
fresh rigId on every run. The records of what was imported are
kept in ``self.imported``. Unlike a definition's ``<data>`` (the build's
last step, recorded and removable with the rig), this import is a plain
edit of the scene after the build.

So a Python build script produces a real rig definition and a real build:
``rigel rigs``, ``rigel update``, ``rigel remove`` and addresses work on
what it made exactly as on a rig built from a .rig.xml file.
"""

import inspect
import json
import os

from . import _rigel


class PyBuild:
    """Base class of build scripts: override run() (and post())."""

    #: The character to build on (.glb, .gltf, .bvh or .rigel); the first
    #: constructor argument overrides it.
    character_file = None
    #: The rig's name (prefixes every node the build makes).
    rig_name = "rig"
    #: The rig's version.
    rig_version = "1.0"
    #: The root component made before run() as ``self.character``:
    #: (type, name, guide); None makes none (run() adds the roots itself).
    root_component = ("global", "global", "main")
    #: Data the default post() imports, in order: (kind, file) pairs, files
    #: relative to the current folder.
    data = ()
    #: The asset whose data folders the default post() imports: None, the
    #: asset the file defining the class is in (if any); a path, the asset
    #: that folder is in; False, none.
    asset = None

    def __init__(self, character_file=None, rig_name=None, *, output=None, definition_output=None, steps=None,
                 edit_mode=False, execute=True):
        self.character_file = character_file or type(self).character_file
        if not self.character_file:
            raise ValueError(f"{type(self).__name__}: no character file (pass one or set character_file)")
        self.rig_name = rig_name or type(self).rig_name
        self.output = output
        self.definition_output = definition_output
        self.steps = steps
        self.edit_mode = edit_mode
        self.scene = _rigel.open(os.fspath(self.character_file))
        self.definition = _rigel.Definition(self.rig_name, self.rig_version)
        self.character = None
        if self.root_component is not None:
            kind, name, guide = self.root_component
            self.character = self.definition.add_component(kind, name, guides=[_rigel.Guide(guide)])
        self.build = None
        self.imported = []
        if execute:
            self.execute()

    # ---- what a script overrides ------------------------------------------------

    def run(self):
        """Adds the rig's components (self.add); called before the build."""
        raise NotImplementedError(f"{type(self).__name__}.run(): add the rig's components here")

    def post(self):
        """Runs after a complete build (self.build, self.scene). The default
        imports the build's data (data_files()) and keeps the records in
        self.imported; an override calls super().post() to keep that."""
        for kind, file in self.data_files():
            self.imported.append(_rigel.import_data(self.scene, kind, file, self.rig_name))

    def data_files(self):
        """What the default post() imports, as (kind, file) pairs: `data`, then
        the asset's data files (see the module's docstring); each file once."""
        files, seen = [], set()

        def add(kind, file):
            key = os.path.realpath(file)
            if key not in seen:
                seen.add(key)
                files.append((kind, file))

        for kind, file in self.data:
            add(kind, os.fspath(file))
        folder = self.asset_folder()
        if folder is not None:
            for kind, file in _rigel.asset_data_files(folder):
                if kind == "shapes" and self._shapes_rig(file) not in (None, self.rig_name):
                    continue  # another rig's shapes (an unreadable file goes on, for import_data to report)
                add(kind, file)
        return files

    def asset_folder(self):
        """The folder whose asset's data the default post() imports, or None."""
        if self.asset is False:
            return None
        if self.asset is not None:
            return os.fspath(self.asset)
        try:
            script = inspect.getfile(type(self))
        except TypeError:  # its module is not in sys.modules (loaded by hand) or has no file
            try:
                script = inspect.getfile(type(self).run)  # the file its run() is written in
            except TypeError:
                return None
        if not os.path.isfile(script):  # typed at a prompt
            return None
        return os.path.dirname(os.path.abspath(script))

    @staticmethod
    def _shapes_rig(file):
        try:
            with open(file, encoding="utf-8") as f:
                return json.load(f).get("rig")
        except (OSError, ValueError, AttributeError):
            return None  # import_data reports what is wrong with it

    # ---- helpers for run() -----------------------------------------------------------

    def add(self, type, name, side="C", parent=None, **options):
        """Adds a component under `parent` (default: self.character, or a root
        when there is none) and returns it. Options: guides, params,
        controls, attach, version, rig_id (see Definition.add_component)."""
        parent = parent if parent is not None else self.character
        if parent is None:
            return self.definition.add_component(type, name, side, **options)
        return parent.add_component(type, name, side, **options)

    def component(self, key):
        """A component added so far, by full name (arm_L), name or rigId."""
        found = self.definition.find(key)
        if found is None:
            raise _rigel.NotFoundError(f"{self.rig_name}: no component '{key}'")
        return found

    # ---- the build -----------------------------------------------------------------------

    def execute(self):
        """run(), check, build (all steps, or the first `steps`), post() when
        complete, save; returns self."""
        self.run()
        if self.definition_output:
            self.save_definition(self.definition_output)
        self.definition.check()
        self.build = _rigel.RigBuild.open(self.scene, self.definition, edit_mode=self.edit_mode)
        if self.steps is None:
            self.build.build_all()
        else:
            self.build.go_to(self.steps)
        if self.build.position == len(self.build):
            self.post()
        if self.output:
            self.save(self.output)
        return self

    def save_definition(self, path):
        """Saves the definition (.rig.xml / .rig.json) with the character as its
        geometry (relative to the file), and records the path as its source."""
        path = os.fspath(path)
        folder = os.path.dirname(os.path.abspath(path))
        geometry = os.path.relpath(os.path.abspath(os.fspath(self.character_file)), folder)
        self.definition.geometry = [(geometry, "")]
        self.definition.source = path
        self.definition.save(path)

    def save(self, path):
        """Saves the scene (.rigel)."""
        self.scene.save(os.fspath(path))

    def node(self, address):
        """A built node by nameless address relative to this rig: 'arm_L/fk[END]'."""
        return self.scene.resolve(f"{self.rig_name}:{address}")

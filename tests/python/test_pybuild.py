"""PyBuild build scripts: the example end to end, and the base class's rules."""

import importlib.util
import os
import pathlib
import re
import subprocess
import sys

import pytest

import rigel
from conftest import METARIG, REPO, close

EXAMPLE = REPO / "examples" / "pybuild_biped.py"


def load_example():
    spec = importlib.util.spec_from_file_location("pybuild_biped", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_example_script_end_to_end(tmp_path):
    out = tmp_path / "hero.rigel"
    definition = tmp_path / "defs" / "hero.rig.xml"
    definition.parent.mkdir()
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(sys.path))
    run = subprocess.run([sys.executable, str(EXAMPLE), "-o", str(out), "--definition-output", str(definition)],
                         env=env, capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert "built hero: 15 components" in run.stderr

    # the definition is a real one: valid, with the character as geometry
    assert rigel.check_definition(str(definition)) == []
    d = rigel.Definition.load(str(definition))
    [(geo, _)] = d.geometry
    assert os.path.samefile(definition.parent / geo, METARIG)
    assert {c.full_name for c in d.all_components()} >= {"global", "hip", "spine", "arm_L", "hand_R", "foot_L"}

    # the scene holds the built rig, recorded like any build
    scene = rigel.Scene.load(str(out))
    [r] = scene.rigs()
    assert (r.name, r.definition, len(r.components)) == ("hero", str(definition), 15)
    assert r.build_position == len(rigel.RigBuild.reopen(scene, "hero"))
    # post() ran: the pose is in the file
    assert scene.resolve("hero:hand_L/fingerCurl")["curl"] == 20.0
    assert scene.resolve("hero:foot_L/reverseFoot")["roll"] == 10.0
    # the rig drives the character
    wrist = scene.world_matrix("hand.L")
    scene.resolve("hero:arm_L/fk[START]")["rotate"] = (0, 0, 30)
    assert not close(scene.world_matrix("hand.L")[12:15], wrist[12:15], 1e-3)

    # update from the saved definition rebuilds what changed
    d.find("arm_L").set_param("maxStretch", 1.4)
    d.find("arm_L").version = "1.1"
    rebuilt = rigel.RigBuild.reopen(scene, "hero").rebuild_changed(d, when="newer-version")
    assert d.find("arm_L").rig_id in rebuilt and d.find("leg_L").rig_id not in rebuilt

    # and removing the rig gives the character back
    # (byte for byte but the UUIDs, which each import makes afresh)
    def text(s):
        return re.sub(r'"uuid": "[^"]*"', '"uuid": ""', s.to_text())

    fresh = rigel.open(str(METARIG))
    scene.remove_rig("hero")
    assert scene.rigs() == [] and text(scene) == text(fresh)


def test_example_class_in_process(tmp_path):
    module = load_example()
    build = module.BipedBuild(output=str(tmp_path / "a.rigel"))
    assert build.build.position == len(build.build)
    assert build.character.type == "global" and build.character == build.definition.components[0]
    assert build.component("arm_R").parent == build.component("clavicle_R")
    assert (tmp_path / "a.rigel").exists()
    # the same script stepped part of the way (seed 003's VCR); post() needs
    # the whole rig (hand_L is not built yet) and is not run
    partial = module.BipedBuild(steps=10)
    assert partial.build.position == 10 and partial.scene.rigs()[0].build_position == 10
    assert partial.scene.find("hero_hand_L_meta") is None


class TwoArms(rigel.Build):
    character_file = str(METARIG)
    rig_name = "arms"

    def run(self):
        self.ran = True
        for side in "LR":
            self.add("limb", "arm", side, guides=[f"upper_arm.{side}", f"forearm.{side}", f"hand.{side}"],
                     params={"kind": "arm"})

    def post(self):
        self.posted = self.build.position


def test_subclass_order_of_run_build_post():
    b = TwoArms()
    assert b.ran and b.posted == len(b.build)
    assert not hasattr(TwoArms(steps=2), "posted")
    assert [c.full_name for c in b.build.components] == ["global", "arm_L", "arm_R"]
    assert b.node("arm_R/ik").type == "control"


def test_execute_later_and_without_a_root():
    class Bare(TwoArms):
        root_component = None

        def run(self):
            root = self.add("global", "world", guides=[rigel.Guide("main")])
            self.add("limb", "arm", "L", parent=root, guides=["upper_arm.L", "forearm.L", "hand.L"])

    b = Bare(rig_name="bare", execute=False)
    assert b.build is None and b.character is None
    b.execute()
    assert b.scene.find_rig("bare") is not None and b.node("world/main").type == "control"


def test_errors():
    class NoRun(rigel.PyBuild):
        character_file = str(METARIG)

    with pytest.raises(NotImplementedError, match="NoRun.run"):
        NoRun()

    with pytest.raises(ValueError, match="no character file"):
        TwoArms.__bases__[0]()  # PyBuild itself names no character

    class Broken(TwoArms):
        def run(self):
            self.add("limb", "arm", "L", guides=["upper_arm.L"])

    with pytest.raises(rigel.DefinitionError, match=r"component 'arm' \(limb, L\): has 1 guide") as info:
        Broken()
    assert info.value.diagnostics

    class MissingJoint(TwoArms):
        def run(self):
            self.add("limb", "arm", "L", guides=["upper_arm.L", "forearm.L", "wing.L"])

    with pytest.raises(rigel.NotFoundError, match="wing.L"):
        MissingJoint()

    with pytest.raises(rigel.Error, match="nowhere.glb"):
        TwoArms("nowhere.glb")

    with pytest.raises(rigel.NotFoundError, match="no component 'tail'"):
        TwoArms(execute=False).component("tail")


def test_build_is_the_pybuild_base_class():
    assert rigel.Build is rigel.PyBuild
    assert rigel.RigBuild is not rigel.Build


# ---- post()'s default: the build's data ----------------------------------------------

GLOBAL_ID = "6513270e-269e-4d37-b2a7-4de452e6b438"
ARM_ID = "056085bd-f7e6-45bb-8505-54f724ac83a7"
# The components of the scripts below, with rigIds of their own: shapes
# files find controls by rigId, so a script that keeps its shapes as data
# names its components' rigIds (fresh ones each run would match nothing).
ARMS_RUN = f"""
    root_component = None

    def run(self):
        world = self.add("global", "global", guides=[rigel.Guide("main")], rig_id="{GLOBAL_ID}")
        self.add("limb", "arm", "L", parent=world, guides=["upper_arm.L", "forearm.L", "hand.L"],
                 params={{"kind": "arm"}}, rig_id="{ARM_ID}")
"""


class Arms(rigel.PyBuild):
    character_file = str(METARIG)
    rig_name = "arms"
    asset = False
    root_component = None

    def run(self):  # as ARMS_RUN says
        world = self.add("global", "global", guides=[rigel.Guide("main")], rig_id=GLOBAL_ID)
        self.add("limb", "arm", "L", parent=world, guides=["upper_arm.L", "forearm.L", "hand.L"],
                 params={"kind": "arm"}, rig_id=ARM_ID)


def drawn_shapes(path, rig="arms", color=(0.25, 0.5, 1.0)):
    """A shapes file of the Arms rig (named `rig`) with arm_L's ik control recoloured."""
    b = Arms()
    b.node("arm_L/ik")["shapeColor"] = color
    w = rigel.Workspace(b.scene)
    w.export_control_shapes(str(path), "arms")
    if rig != "arms":
        text = path.read_text().replace('"rig": "arms"', f'"rig": "{rig}"')
        path.write_text(text)
    return path


def test_default_post_imports_the_data_the_build_names(tmp_path):
    shapes = drawn_shapes(tmp_path / "arms.shapes.json")

    class WithData(Arms):
        data = [("shapes", str(shapes))]

        def post(self):
            super().post()  # the default import, then the script's own work
            self.posted = [r.kind for r in self.imported]

    b = WithData()
    assert b.posted == ["shapes"]
    assert b.imported[0].shapes_set > 0 and b.imported[0].missing == []
    assert close(b.node("arm_L/ik")["shapeColor"], (0.25, 0.5, 1.0), 1e-12)
    assert not close(Arms().node("arm_L/ik")["shapeColor"], (0.25, 0.5, 1.0), 1e-3), "Arms names no data"

    class Bad(Arms):
        data = [("blendshapes", str(shapes))]

    with pytest.raises(rigel.Error, match="not a rigel blend shapes file"):
        Bad()  # a file of another kind is refused, naming the file

    class Unknown(Arms):
        data = [("muscles", str(shapes))]

    with pytest.raises(rigel.Error, match="unknown data kind 'muscles'"):
        Unknown()

    class Missing(Arms):
        data = [("weights", str(tmp_path / "none.weights.json"))]

    with pytest.raises(rigel.NotFoundError, match="none.weights.json"):
        Missing()


def test_default_post_imports_the_data_of_the_asset_the_script_is_in(tmp_path):
    rigel.create_project(str(tmp_path / "show"))
    asset = pathlib.Path(rigel.create_asset("arms", skeleton=str(METARIG), project=str(tmp_path / "show")).dir)
    drawn_shapes(asset / "data" / "shapes" / "arms.shapes.json")
    drawn_shapes(asset / "data" / "shapes" / "other.shapes.json", rig="other", color=(1.0, 0.0, 0.0))
    assert [k for k, _ in rigel.asset_data_files(str(asset / "build"))] == ["shapes", "shapes"]
    assert rigel.asset_data_files(str(tmp_path)) == []

    # A build script saved in the asset's build/ folder.
    script = asset / "build" / "arms_build.py"
    script.write_text(
        "import rigel\n\n"
        "class ArmsBuild(rigel.PyBuild):\n"
        f"    character_file = {str(METARIG)!r}\n"
        "    rig_name = 'arms'\n" + ARMS_RUN)
    spec = importlib.util.spec_from_file_location("arms_build", script)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    b = module.ArmsBuild()
    assert [os.path.basename(f) for _, f in b.data_files()] == ["arms.shapes.json"], "another rig's shapes are left"
    assert [r.kind for r in b.imported] == ["shapes"]
    assert close(b.node("arm_L/ik")["shapeColor"], (0.25, 0.5, 1.0), 1e-12)

    # The same class told to import no asset's data.
    class NoAsset(module.ArmsBuild):
        asset = False

    assert NoAsset().imported == []

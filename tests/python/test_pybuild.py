"""PyBuild build scripts: the example end to end, and the base class's rules."""

import importlib.util
import os
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

"""mGear guide templates from Python (docs/RIG.md "mGear guides"): the
biped template imported as `rigel import-guides` does, built on the skeleton
it writes; a malformed template raises naming the component."""

import json
import pathlib

import pytest

import rigel

BIPED_SGT = pathlib.Path(__file__).resolve().parents[1] / "data" / "mgear" / "biped.sgt"


def test_the_biped_template_imports_and_builds(tmp_path):
    out = tmp_path / "hero.rig.json"
    report = rigel.import_guides(str(BIPED_SGT), str(out))
    assert report["unmapped"] == [] and len(report["components"]) == 38
    assert report["skeleton"] == str(tmp_path / "hero.glb")
    types = {c["mgear"]: c["rigelType"] for c in report["components"]}
    assert types["arm_L0"] == "limb" and types["mouth_C0"] == "mouth" and types["meta_L0"] == "meta"
    assert types["global_C0"] == "control" and types["foot_R0"] == "foot"
    scene = rigel.open(report["skeleton"])
    definition = rigel.Definition.load(str(out))
    build = rigel.RigBuild.open(scene, definition)
    build.build_all()
    assert build.position == len(build)


def test_a_malformed_template_raises_naming_the_component(tmp_path):
    doc = json.loads(BIPED_SGT.read_text())
    del doc["components_dict"]["leg_R0"]["tra"]["knee"]
    bad = tmp_path / "bad.sgt"
    bad.write_text(json.dumps(doc))
    with pytest.raises(rigel.Error, match="leg_R0"):
        rigel.import_guides(str(bad), str(tmp_path / "bad.rig.xml"))
    assert not (tmp_path / "bad.rig.xml").exists()

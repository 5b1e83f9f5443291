"""Rig definitions: load/save both syntaxes, validation with places, the
component model, and the component schemas."""

import pytest

import rigel
from conftest import BIPED, DATA, arm_definition


def test_load_the_biped():
    d = rigel.Definition.load(str(BIPED))
    assert d.name == "hero" and d.version == "1.0"
    assert d.source == str(BIPED)
    assert d.geometry == [("../tests/data/gltf/rigify_human_metarig.glb", "")]
    assert d.validate() == []
    root = d.components[0]
    assert (root.type, root.name, root.side) == ("global", "global", "C")
    everything = d.all_components()
    assert len(everything) == 21
    arm = d.find("arm_L")
    assert arm.type == "limb" and arm.side == "L" and arm.parent.full_name == "clavicle_L"
    assert [g.joint for g in arm.guides] == ["upper_arm.L", "forearm.L", "hand.L"]
    assert arm.params == {"kind": "arm", "defaultMode": "fk"}
    assert arm.param("maxStretch") == rigel.component_schema("limb")["params"][
        [p["name"] for p in arm.schema["params"]].index("maxStretch")]["default"]
    assert {c.role for c in arm.controls} == {"fk", "ik"}
    assert d.find(arm.rig_id) == arm
    assert d.find("nothing") is None
    foot = d.find("foot_L")
    assert foot.guides[2].translate == (0.098, 0.0, 0.17)


def test_xml_json_round_trip(tmp_path):
    d = rigel.Definition.load(str(DATA / "rig" / "all_types.rig.xml"))
    j = tmp_path / "all.rig.json"
    d.save(str(j))
    back = rigel.Definition.load(str(j))
    assert back.text("xml") == d.text("xml")
    assert back.text("json") == (DATA / "rig" / "all_types.rig.json").read_text()
    parsed = rigel.Definition.parse(d.text("json"), "json")
    assert parsed.diff(d) == []


def test_syntax_errors_raise_with_file_line_column():
    path = DATA / "rig" / "syntax_error.rig.xml"
    with pytest.raises(rigel.DefinitionError) as info:
        rigel.Definition.load(str(path))
    e = info.value
    assert isinstance(e, ValueError)
    assert len(e.diagnostics) == 1
    diag = e.diagnostics[0]
    assert diag.file == str(path) and diag.line > 1 and diag.column >= 1
    assert str(diag).startswith(f"{path}:{diag.line}:{diag.column}: ")
    assert str(diag) in str(e)


def test_check_definition_lists_every_problem_in_order():
    path = DATA / "rig" / "invalid_semantic.rig.xml"
    problems = rigel.check_definition(str(path))
    assert len(problems) >= 8
    assert all(p.file == str(path) and p.line > 0 for p in problems)
    assert [(p.line, p.column) for p in problems] == sorted((p.line, p.column) for p in problems)
    text = "\n".join(str(p) for p in problems)
    assert "unknown component type 'wing'" in text
    assert "tentacle" in text and "maybe" in text
    wing = next(p for p in problems if "wing" in p.message)
    assert wing.line == 5
    assert rigel.check_definition(str(BIPED)) == []
    # loading works (the file parses); check() raises with the same problems
    d = rigel.Definition.load(str(path))
    with pytest.raises(rigel.DefinitionError, match="unknown component type 'wing'") as info:
        d.check()
    assert len(info.value.diagnostics) == len(d.validate())


def test_build_a_definition_in_code(tmp_path):
    d = arm_definition()
    assert d.validate() == []
    arm = d.find("arm_L")
    assert arm.params["maxStretch"] == 1.25
    arm.set_param("maxStretch", 2)  # an int for a double parameter becomes a double
    assert arm.params["maxStretch"] == 2.0 and isinstance(arm.params["maxStretch"], float)
    assert arm.remove_param("maxStretch") and not arm.remove_param("maxStretch")
    arm.set_control("fk", "circle", "blue", 0.2)
    assert [(c.role, c.size) for c in arm.controls] == [("fk", 0.2)]
    arm.version = "1.1"
    arm.set_feature("stretch", False)
    assert arm.features == [{"name": "stretch", "enabled": False, "switches": {}}]
    hand = arm.add_component("hand", "hand", "L", attach="end",
                             guides=[{"name": "hand", "joint": "hand.L"}, {"name": "index.0", "joint": "f_index.01.L"}])
    assert hand.parent == arm and arm.children == [hand]
    assert len(d.all_components()) == 3
    out = tmp_path / "arm.rig.xml"
    d.save(str(out))
    again = rigel.Definition.load(str(out))
    assert again.validate() == [] and again.find("hand_L").guides[1].joint == "f_index.01.L"
    copy = d.copy()
    copy.find("hand_L").remove()
    assert len(copy.all_components()) == 2 and len(d.all_components()) == 3
    assert any("hand" in line for line in d.diff(copy))


def test_component_edits_are_checked():
    d = arm_definition()
    arm = d.find("arm_L")
    with pytest.raises(rigel.InvalidArgumentError, match=r"component 'arm_L' \(limb\): parameter 'stretch' must be a bool"):
        arm.set_param("stretch", "maybe")
    with pytest.raises(rigel.InvalidArgumentError, match="side 'X'"):
        arm.side = "X"
    with pytest.raises(rigel.AlreadyExistsError, match="rigId"):
        d.add_component("global", "g2", rig_id=arm.rig_id)
    with pytest.raises(rigel.InvalidArgumentError, match="unknown guide key 'jont'"):
        arm.guides = [{"jont": "x"}]
    arm.guides = ["upper_arm.L", "forearm.L"]  # joint names
    problems = d.validate()
    assert len(problems) == 1 and "has 2 guides" in problems[0].message
    arm.add_guide("end", joint="hand.L")
    assert d.validate() == []
    arm.remove()
    with pytest.raises(rigel.NotFoundError, match="no component with rigId"):
        arm.name  # noqa: B018
    d.add_component("limb", "leg", "R")  # a limb at the root, without guides
    assert len(d.validate()) >= 1


def test_component_types_and_schemas():
    types = rigel.component_types()
    assert {"global", "limb", "hand", "foot", "spine", "ephemeral"} <= set(types)
    limb = rigel.component_schema("limb")
    assert limb["guides"]["names"] == ["upper", "lower", "end"]
    kind = next(p for p in limb["params"] if p["name"] == "kind")
    assert kind["type"] == "enum" and "arm" in kind["choices"]
    assert rigel.component_schema("global")["root_only"]
    with pytest.raises(rigel.NotFoundError, match="unknown component type 'wing' \\(types: .*limb"):
        rigel.component_schema("wing")
    assert len(rigel.new_rig_id()) == 36

"""Builds: open, stepping forward and back, build_all, failures, rigs and the
metadata network, addresses, update (rebuild_changed), edit mode, remove."""

import pytest

import rigel
from conftest import BIPED, METARIG, arm_definition, close, distance, translation


def test_step_forward_and_back_exactly(metarig):
    original = metarig.to_text()
    b = rigel.RigBuild.open(metarig, arm_definition())
    assert b.position == 0 and b.root is None and len(b) == b.step_count == 10
    labels = [p.label for p in b.plan]
    assert labels[0] == "rig" and "arm_L/fk" in labels and "global/meta" in labels
    assert [c.full_name for c in b.components] == ["global", "arm_L"]
    b.forward()
    assert b.position == 1 and b.root.type == "metaRoot"
    b.go_to(5)
    assert b.position == 5
    after5 = metarig.to_text()
    b.forward()
    b.back()
    assert metarig.to_text() == after5
    b.go_to(0)
    assert b.position == 0 and metarig.to_text() == original
    b.build_all()
    assert b.position == len(b)
    with pytest.raises(rigel.Error):
        b.go_to(len(b) + 1)


def test_each_step_is_one_undo_step(metarig):
    b = rigel.RigBuild.open(metarig, arm_definition())
    b.go_to(3)
    three = metarig.to_text()
    b.forward()
    assert metarig.undo()
    assert metarig.to_text() == three
    reopened = rigel.RigBuild.reopen(metarig, "arm_rig")
    assert reopened.position == 3  # the scene's metaRoot is the truth


def test_built_rig_moves_the_character(metarig):
    b = rigel.RigBuild.open(metarig, arm_definition())
    b.build_all()
    hand = metarig.node("hand.L")
    rest = translation(hand.world_matrix)
    upper = metarig.resolve("arm_rig:arm_L/fk[START]")
    assert upper.type == "control" and upper.address == "arm_rig:arm_L/joint[0]/fk[0]"
    upper["rotate"] = (0, 0, 45)
    moved = translation(hand.world_matrix)
    assert distance(rest, moved) > 0.1
    # the shoulder does not move, and the arm keeps its length
    shoulder = translation(metarig.world_matrix("upper_arm.L"))
    assert close(distance(shoulder, moved), distance(shoulder, rest), 1e-6)


def test_rigs_meta_and_addresses(tmp_path, metarig):
    definition = arm_definition()
    path = tmp_path / "arm.rig.xml"
    definition.save(str(path))
    b = rigel.RigBuild.open(metarig, str(path))  # a file path works too
    b.build_all()
    [r] = metarig.rigs()
    assert (r.name, r.version, r.definition, r.build_position) == ("arm_rig", "1.0", str(path), len(b))
    assert [(c.name, c.type, c.parent) for c in r.components] == [("global", "global", ""), ("arm_L", "limb", "global")]
    assert r.node == b.root == metarig.find_rig("arm_rig")
    assert metarig.find_rig("other") is None
    arm = metarig.find_component("arm_rig", "arm_L")
    assert arm == metarig.find_component(r.node, definition.find("arm_L").rig_id)
    assert arm.get("metaType") == "limb"
    ik = arm.meta_connection("ik")
    assert ik.type == "control" and ik.component == arm and ik.rig == b.root
    assert metarig.resolve(ik.address) == ik
    members = arm.members()
    assert ik in members and all(m.component == arm for m in members)
    glob = r.components[0].node
    assert b.root.meta_children() == [glob]
    assert glob.meta_child(definition.find("arm_L").rig_id) == arm
    assert glob.meta_child(rigel.new_rig_id()) is None
    assert arm.meta_parent == glob
    with pytest.raises(rigel.NotFoundError, match="elbow"):
        metarig.resolve("arm_rig:arm_L/elbow")
    with pytest.raises(rigel.NotFoundError):
        metarig.node("hand.L").address  # noqa: B018  (not part of a rig)
    with pytest.raises(rigel.NotFoundError, match="fk"):
        arm.meta_connection("fk", 7)
    with pytest.raises(rigel.InvalidArgumentError, match="not a meta node"):
        ik.members()
    # renaming built nodes never breaks an address
    ik.name = "renamed"
    assert metarig.resolve("arm_rig:arm_L/ik") == ik


def test_remove_restores_the_character_byte_for_byte(tmp_path, metarig):
    original = metarig.to_text()
    rigel.RigBuild.open(metarig, arm_definition()).build_all()
    out = tmp_path / "built.rigel"
    metarig.save(str(out))
    loaded = rigel.Scene.load(str(out))
    loaded.remove_rig("arm_rig")
    assert loaded.rigs() == [] and loaded.to_text() == original
    with pytest.raises(rigel.NotFoundError, match="no rig 'arm_rig'"):
        loaded.remove_rig("arm_rig")


def test_update_rebuilds_only_what_changed(metarig):
    definition = arm_definition()
    b = rigel.RigBuild.open(metarig, definition)
    b.build_all()
    fk = metarig.resolve("arm_rig:arm_L/fk[1]")
    fk["rotate"] = (0, 30, 0)
    changed = definition.copy()
    changed.find("arm_L").set_param("maxStretch", 1.5)
    changed.find("arm_L").version = "1.1"
    rebuilt = b.rebuild_changed(changed)
    assert rebuilt == [definition.find("arm_L").rig_id]
    assert b.definition.find("arm_L").param("maxStretch") == 1.5
    assert metarig.find_rig("arm_rig").get("version") == "1.0"
    assert b.rebuild_changed(changed) == []  # nothing changed any more
    assert sorted(b.rebuild_changed(changed, when="all", keep_keys="world")) == sorted(
        c.rig_id for c in definition.all_components())
    with pytest.raises(rigel.InvalidArgumentError, match="keep_keys 'global'"):
        b.rebuild_changed(changed, keep_keys="global")
    with pytest.raises(rigel.InvalidArgumentError, match="when 'sometimes'"):
        b.rebuild_changed(changed, when="sometimes")


def test_a_failing_step_raises_and_changes_nothing(metarig):
    d = arm_definition("broken_rig")
    arm = d.find("arm_L")
    arm.guides = [rigel.Guide("upper", joint="upper_arm.X"), rigel.Guide("lower", joint="forearm.L"),
                  rigel.Guide("end", joint="hand.L")]
    assert d.validate() == []  # joints are only known at build time
    b = rigel.RigBuild.open(metarig, d)
    before_pos = None
    with pytest.raises(rigel.Error, match="upper_arm.X"):
        for _ in range(len(b)):
            before_pos = b.position
            before = metarig.to_text()
            b.forward()
    assert b.position == before_pos and metarig.to_text() == before


def test_invalid_definitions_are_refused_with_places(metarig):
    d = arm_definition()
    d.find("arm_L").guides = []
    with pytest.raises(rigel.DefinitionError, match=r"component 'arm' \(limb, L\): has 0 guides") as info:
        rigel.RigBuild.open(metarig, d)
    assert info.value.diagnostics
    with pytest.raises(rigel.DefinitionError, match=r"invalid_semantic\.rig\.xml:\d+:\d+"):
        rigel.RigBuild.open(metarig, str(METARIG.parents[1] / "rig" / "invalid_semantic.rig.xml"))
    with pytest.raises(rigel.NotFoundError, match="no rig 'ghost'"):
        rigel.RigBuild.reopen(metarig, "ghost")


def test_features_switch_steps(metarig):
    b = rigel.RigBuild.open(metarig, str(BIPED))
    assert len(b) == 90
    b.build_all()
    stretch = [p.label for p in b.plan if p.feature == "stretch"]
    assert "arm_L/stretch" in stretch
    b.set_feature("stretch", False)
    assert not any(p.enabled for p in b.plan if p.feature == "stretch")
    assert all(p.enabled for p in b.plan if p.feature == "ik")
    assert b.position == len(b) and b.definition.features[0]["name"] == "stretch"
    b.set_feature("stretch", True)
    assert all(p.enabled for p in b.plan)


def test_edit_mode_writes_moves_back_into_guides(metarig):
    b = rigel.RigBuild.open(metarig, arm_definition(), edit_mode=True)
    b.build_all()
    assert b.edit_mode
    metarig.resolve("arm_rig:arm_L/fk[1]")["translate"] = (0, 0.02, 0)
    edits = b.edits()
    arm_id = b.definition.find("arm_L").rig_id
    assert edits.changed == [arm_id]
    assert edits.definition.version == "1.1" and edits.definition.find("arm_L").version == "1.1"
    committed = b.commit_edits()
    assert committed.changed == [arm_id]
    assert b.edit_mode  # by default edit mode stays on


def test_commit_edits_can_record_the_definition_and_leave_edit_mode(metarig, tmp_path):
    b = rigel.RigBuild.open(metarig, arm_definition(), edit_mode=True)
    b.build_all()
    metarig.resolve("arm_rig:arm_L/fk[1]")["translate"] = (0, 0.02, 0)
    out = str(tmp_path / "moved.rig.xml")
    committed = b.commit_edits(definition_path=out, leave_edit_mode=True)
    assert committed.changed
    assert not b.edit_mode

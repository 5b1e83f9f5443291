"""Ephemeral rigs: setup, relations, the posing Session (modes, select,
drag, release, undo) and keys."""

import math

import pytest

import rigel
from conftest import close, distance, translation


@pytest.fixture
def posed(metarig):
    """The metarig with an ephemeral rig on every joint."""
    result = rigel.setup_ephemeral(metarig)
    return metarig, result


def test_setup(posed):
    scene, result = posed
    assert result.rig.type == "ephemeralRig"
    assert len(result.controls) == len(result.joints) == 159
    hand_ctrl = scene.node("hand.L_ctrl")
    assert hand_ctrl in result.controls and hand_ctrl.type == "control"
    assert rigel.control_of(scene, "hand.L") == hand_ctrl
    assert rigel.control_of(scene, hand_ctrl) == hand_ctrl
    assert scene.source("hand.L.translate") == "hand.L_ctrl.translate"
    assert rigel.ephemeral_rigs(scene) == [result.rig]
    assert rigel.ephemeral_controls(scene, result.rig) == result.controls
    assert rigel.key_scope(scene, result.rig) == "character"
    assert scene.undo_label  # one undo step
    scene.undo()
    assert rigel.ephemeral_rigs(scene) == [] and scene.find("hand.L_ctrl") is None


def test_setup_errors(metarig):
    rigel.setup_ephemeral(metarig, joints=["hand.L"], rig_name="hands")
    with pytest.raises(rigel.Error, match="hand.L"):
        rigel.setup_ephemeral(metarig, joints=["hand.L"])  # already has a control
    with pytest.raises(rigel.NotFoundError, match="no node named 'wing'"):
        rigel.setup_ephemeral(metarig, joints=["wing"])
    with pytest.raises(rigel.InvalidArgumentError, match="not an ephemeralRig"):
        rigel.relations(metarig, "hand.L")
    # The options are checked as the CLI checks them (SetupOptions::validate).
    for kwargs, field in (({"shape_radius": -1.0}, "shape_radius"), ({"shape_radius": math.nan}, "shape_radius"),
                          ({"control_suffix": " c"}, "control_suffix"), ({"rig_name": "my rig"}, "rig_name")):
        with pytest.raises(rigel.InvalidArgumentError) as info:
            rigel.setup_ephemeral(metarig, joints=["hand.R"], **kwargs)
        assert info.value.field == field, kwargs


def test_setup_sizes_circles_from_the_bones(metarig):
    r = rigel.setup_ephemeral(metarig, joints=["hand.L", "f_index.01.L", "f_index.02.L", "f_index.03.L"],
                              shape_radius=0.05, size_from_bones=True)
    radius = {j.name: math.hypot(*c["shapePoints"][0]) for j, c in zip(r.joints, r.controls)}
    assert all(0.005 - 1e-12 <= v <= 0.05 + 1e-12 for v in radius.values()), radius
    assert radius["f_index.03.L"] < 0.02, "a fingertip's short bone: a small circle"


def test_relations(posed):
    scene, result = posed
    rels = rigel.relations(scene, result.rig)
    assert ("forward", scene.node("forearm.L_ctrl"), scene.node("hand.L_ctrl")) in rels
    assert ("inverse", scene.node("hand.L_ctrl"), scene.node("forearm.L_ctrl")) in rels
    rigel.relation_add(scene, result.rig, "magnet", "hand.L_ctrl", "hand.R_ctrl")
    assert ("magnet", scene.node("hand.L_ctrl"), scene.node("hand.R_ctrl")) in rigel.relations(scene, result.rig)
    rigel.relation_remove(scene, result.rig, "magnet", "hand.L_ctrl", "hand.R_ctrl")
    assert len(rigel.relations(scene, result.rig)) == len(rels)
    with pytest.raises(rigel.InvalidArgumentError, match="relation kind 'sideways'"):
        rigel.relation_add(scene, result.rig, "sideways", "hand.L_ctrl", "hand.R_ctrl")


def test_session_forward_rotate(posed):
    scene, _ = posed
    s = rigel.Session(scene)
    assert s.mode == "forward" and "magnet-radius" in rigel.Session.modes()
    s.select(["forearm.L_ctrl"])
    assert s.grabbed == [scene.node("forearm.L_ctrl")]
    elbow = translation(scene.world_matrix("forearm.L"))
    hand = translation(scene.world_matrix("hand.L"))
    s.drag(rotate=(0, 0, 30))  # degrees about the elbow's pivot
    assert s.has_plan and s.plans_built == 1
    assert close(translation(scene.world_matrix("forearm.L")), elbow)  # the pivot stays
    new_hand = translation(scene.world_matrix("hand.L"))
    assert distance(new_hand, hand) > 0.05
    assert close(distance(new_hand, elbow), distance(hand, elbow), 1e-6)
    s.drag(rotate=(0, 0, 0, 1))  # a quaternion: no motion
    assert s.plans_built == 1  # the plan is reused while the selection stays
    s.release()
    assert not s.has_plan


def test_session_inverse_reaches_and_one_gesture_is_one_undo_step(posed):
    scene, _ = posed
    before = scene.to_text()
    s = rigel.Session(scene, mode="inverse")
    s.select(["hand.L_ctrl"])
    chain = ["shoulder.L", "upper_arm.L", "forearm.L", "hand.L"]  # the chain runs up to the clavicle

    def positions():
        return [translation(scene.world_matrix(j)) for j in chain]

    def lengths(p):
        return [distance(a, b) for a, b in zip(p, p[1:])]

    rest = positions()
    # toward the shoulder and down: within reach of the (straight) arm
    step = tuple(0.05 * (a - b) for a, b in zip(rest[1], rest[3]))
    step = (step[0], step[1] - 0.02, step[2])
    for _ in range(3):
        s.drag(translate=step)
    now = positions()
    assert close(now[3], tuple(a + 3 * d for a, d in zip(rest[3], step)), 1e-6)  # the hand reaches
    assert close(now[0], rest[0])  # the top stays
    assert close(lengths(now), lengths(rest), 1e-6)  # bones keep their lengths
    assert not close(now[2], rest[2], 1e-3)  # the elbow moved
    plan = s.plan()
    roles = {e.control.name: e.role for e in plan}
    assert roles["hand.L_ctrl"] == "grabbed" and "forearm.L_ctrl" in roles
    s.release()
    assert scene.undo()
    assert scene.to_text() == before


def test_session_modes_options_and_errors(posed):
    scene, _ = posed
    s = rigel.Session(scene, mode="body", magnet_radius=0.3)
    s.select(["hips_ctrl"] if scene.find("hips_ctrl") else ["spine_ctrl"])
    s.body_pivot = scene.world_matrix(s.grabbed[0])
    assert close(translation(s.body_pivot), translation(scene.world_matrix(s.grabbed[0])))
    head = translation(scene.world_matrix("spine.006"))
    s.drag(translate=(0, 0, 1))
    assert close(translation(scene.world_matrix("spine.006")), (head[0], head[1], head[2] + 1), 1e-9)
    s.body_pivot = None
    assert s.body_pivot is None
    s.mode = "suspended"
    assert s.mode == "suspended"
    with pytest.raises(rigel.InvalidArgumentError, match="mode 'sideways': unknown mode; modes: forward"):
        s.mode = "sideways"
    with pytest.raises(rigel.InvalidArgumentError, match="mode 'x'"):
        rigel.Session(scene, mode="x")
    s.select([])
    with pytest.raises(rigel.Error):
        s.drag(translate=(1, 0, 0))  # nothing grabbed
    s.select(["hand.L_ctrl"])
    with pytest.raises(rigel.Error, match="scale"):
        s.drag(scale=(2, 2, 2))  # scale outside body mode
    world = list(scene.world_matrix("hand.L_ctrl"))
    world[13] += 0.05
    s.drag_to("hand.L_ctrl", world)
    assert close(translation(scene.world_matrix("hand.L")), tuple(world[12:15]), 1e-9)


def test_keys(posed):
    scene, result = posed
    hand = scene.node("hand.L_ctrl")
    assert rigel.key_times(scene, [hand]) == []
    scene.frame = 0
    rigel.set_key(scene, [hand])
    assert rigel.has_key(scene, hand) and rigel.is_keyed(scene, hand)
    # scope 'character': every control of the character was keyed
    assert rigel.has_key(scene, "foot.R_ctrl")
    assert len(rigel.keying_set(scene, [hand])) == 159
    s = rigel.Session(scene)
    s.select([hand])
    scene.frame = 10
    with pytest.raises(rigel.Error, match="auto-key|frame 10"):
        s.drag(rotate=(0, 20, 0))  # keyed, off its keys
    s.auto_key = True
    s.drag(rotate=(0, 20, 0))
    s.release()
    assert [round(t * scene.fps) for t in rigel.key_times(scene, [hand])] == [0, 10]
    assert hand["rotateMode"] == 1  # quaternion (glTF): the rotation is keyed on rotateQuaternion
    posed10 = hand["rotateQuaternion"]
    scene.frame = 0
    assert not close(hand["rotateQuaternion"], posed10, 1e-3)  # the curve plays back the keys
    scene.frame = 10
    assert close(hand["rotateQuaternion"], posed10, 1e-9)
    rigel.delete_key(scene, [hand])
    assert [round(t * scene.fps) for t in rigel.key_times(scene, [hand])] == [0]
    with pytest.raises(rigel.NotFoundError):
        rigel.delete_key(scene, [hand])  # no key there any more
    rigel.set_key_scope(scene, result.rig, "controls")
    assert rigel.key_scope(scene, result.rig) == "controls"
    assert rigel.keying_set(scene, [hand]) == [hand]
    with pytest.raises(rigel.InvalidArgumentError, match="key scope 'all'"):
        rigel.set_key_scope(scene, result.rig, "all")
    assert math.isfinite(scene.time)

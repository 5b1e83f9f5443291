"""rigel.Workspace's rigger actions on the biped (examples/biped.rig.xml on
the metarig): a control's look copied and pasted in parts, shapes mirrored
and flipped in place and onto the opposite control, locators, matching
position and rotation, and joints mirrored with their sides renamed: the
same library calls as `rigel shape`, `rigel align`, `rigel locator`,
`rigel mirror-joints` and the JSON API."""

import pytest

import rigel
from conftest import BIPED, translation


@pytest.fixture
def hero(metarig):
    w = rigel.Workspace(metarig)
    w.add_rig(str(BIPED))
    return w


def test_copy_paste_mirror_flip_and_opposite(hero):
    w = hero
    arm = w.scene.resolve("hero:arm_L/ik[0]")
    leg = w.scene.resolve("hero:leg_L/ik[0]")
    a, l = w.control_look(arm), w.control_look(leg)
    assert a.points != l.points
    w.paste_control_look(a.points, a.closed, a.color, controls=[leg], paste_color=False)
    assert w.control_look(leg).points == a.points and w.control_look(leg).color == l.color
    w.undo()
    assert w.control_look(leg).points == l.points
    w.mirror_control_shape([arm])
    assert w.control_look(arm).points[0] == (-a.points[0][0], a.points[0][1], a.points[0][2])
    w.mirror_control_shape([arm])
    assert w.control_look(arm).points == a.points
    w.flip_control_shape([arm])
    assert w.control_look(arm).points[0] == (-a.points[0][0], a.points[0][1], -a.points[0][2])
    pairs = w.mirror_shape_to_opposite([arm])
    assert pairs == [(arm, w.scene.resolve("hero:arm_R/ik[0]"))]
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.mirror_shape_to_opposite(["hero:hip/main"])
    assert info.value.field == "controls"
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.paste_control_look([(0, 0, 0)], color=(2, 0, 0), controls=[arm])
    assert info.value.field == "shape.color"


def test_locators_align_and_mirror_joints(hero):
    w = hero
    ik = w.scene.resolve("hero:arm_L/ik[0]")
    [loc] = w.create_locators(["hand.L"], size=0.05)
    assert loc.name == "hand.L_loc"
    w.set_channel_values(1.3, controls=[loc], attrs=["translateY"])
    assert w.align([ik], loc) == [ik]
    assert translation(w.scene.world_matrix(ik))[1] == pytest.approx(1.3, abs=1e-9)
    w.undo()
    assert translation(w.scene.world_matrix(ik))[1] != pytest.approx(1.3, abs=1e-3)
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.align([ik], loc, position=False, rotation=False)
    assert info.value.field == "match"
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.mirror_joints(["spine"])
    assert info.value.field == "joints"


def test_mirror_a_new_chain(metarig):
    w = rigel.Workspace(metarig)
    with pytest.raises(rigel.InvalidArgumentError):
        w.mirror_joints(["upper_arm.L"])  # the right arm exists
    report = w.mirror_joints(["upper_arm.L"], update=True)
    assert report.created == [] and report.updated[0].name == "upper_arm.R"

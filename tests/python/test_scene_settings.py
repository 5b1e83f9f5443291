"""rigel.Workspace's playback range and selection sets on the biped
(examples/biped.rig.xml on the metarig), saved with the scene, and keys
moved or copied from a frame that is not the current one: the same library
calls as `rigel playback`, `rigel sets` and POST /api/channel-keys."""

import pytest

import rigel
from conftest import BIPED, METARIG


@pytest.fixture
def hero(metarig):
    w = rigel.Workspace(metarig)
    w.add_rig(str(BIPED))
    return w


def test_playback_range_set_saved_and_undone(hero, tmp_path):
    w = hero
    assert w.playback_range is None and w.summary().playback_range is None
    w.set_playback_range(1, 120)
    assert w.playback_range == (1.0, 120.0)
    assert w.summary().playback_range == (1.0, 120.0)
    path = tmp_path / "shot.rigel"
    w.save(str(path))
    again = rigel.Workspace(rigel.Scene.load(str(path)))
    assert again.playback_range == (1.0, 120.0)
    w.undo()
    assert w.playback_range is None
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.set_playback_range(9, 3)
    assert info.value.field == "range"


def test_selection_sets_save_select_and_remove(hero):
    w = hero
    ik = w.scene.resolve("hero:arm_L/ik[0]")
    fk = w.scene.resolve("hero:arm_L/fk[0]")
    leg = w.scene.resolve("hero:leg_R/ik[0]")
    w.save_selection_set("left_arm", [ik, fk])
    w.select([leg])
    w.save_selection_set("right_leg")
    sets = {s.name: s for s in w.selection_sets()}
    assert sets["left_arm"].members == [ik, fk] and sets["right_leg"].members == [leg]
    assert w.select_set("left_arm") == [ik, fk]
    assert w.select_set("right_leg", add=True) == [ik, fk, leg]
    w.remove_selection_set("left_arm")
    assert [s.name for s in w.selection_sets()] == ["right_leg"]
    with pytest.raises(rigel.NotFoundError) as info:
        w.select_set("left_arm")
    assert info.value.field == "name"
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.save_selection_set("bad name", [ik])
    assert info.value.field == "name"


def test_keys_moved_and_copied_from_another_frame(hero):
    w = hero
    switch = w.scene.resolve("hero:arm_L/fkIkSwitch")
    w.set_frame(4)
    w.set_channel_keys([switch], attrs=["fkIk"], value=1.0)
    w.set_frame(0)
    [k] = w.move_channel_keys(9, [switch], attrs=["fkIk"], from_frame=4, copy=True)
    assert k.frames == [4.0, 9.0]
    [k] = w.move_channel_keys(12, [switch], attrs=["fkIk"], from_frame=9)
    assert k.frames == [4.0, 12.0]
    assert w.frame == 0


def test_picker_groups_by_part_and_side(hero):
    groups = {(g.rig, g.name): g for g in hero.picker()}
    arm = groups[("hero", "arm_L")]
    assert (arm.part, arm.side) == ("arm", "L")
    assert hero.scene.resolve("hero:arm_L/ik[0]") in [c for c, _ in arm.controls]
    assert (groups[("hero", "leg_R")].part, groups[("hero", "leg_R")].side) == ("leg", "R")
    assert groups[("hero", "global")].part == "root"
    parts = [g.part for g in hero.picker() if g.rig == "hero"]
    assert parts.index("head") < parts.index("torso") < parts.index("leg"), "head to toe"
    # An ephemeral rig on the metarig: the face and each hand a group, the rest by part and side.
    fresh = rigel.open(str(METARIG))
    rigel.setup_ephemeral(fresh)
    w = rigel.Workspace(fresh)
    eph = {g.name: g for g in w.picker()}
    assert eph["face_ctrl"].part == "head" and len(eph["face_ctrl"].controls) > 50
    assert (eph["hand.L_ctrl"].part, eph["hand.L_ctrl"].side) == ("hand", "L")
    assert (eph["leg_R"].part, eph["leg_R"].side) == ("leg", "R")
    assert sum(len(g.controls) for g in w.picker()) == 159


def test_motion_trails_and_ghosts(hero):
    w = hero
    ik = w.scene.resolve("hero:arm_L/ik[0]")
    for f in (0, 10):
        w.set_frame(f)
        w.set_channel_values(f * 0.02, [ik], attrs=["translateY"])
        w.set_channel_keys([ik], attrs=["translate"])
    w.set_frame(4)
    [t] = w.motion_trails(0, 10, [ik], step=5)
    assert t.node == ik and t.frames == [0.0, 5.0, 10.0] and t.keys == [0.0, 10.0]
    moved = sum((a - b) ** 2 for a, b in zip(t.points[2], t.points[0])) ** 0.5
    assert moved == pytest.approx(0.2)
    g = w.ghosts(before=1, after=1, step=2)
    assert g.frames == [2.0, 6.0] and len(g.points) == 2 and len(g.points[0]) == len(g.joints)
    assert w.frame == 4
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.motion_trails(5, 1, [ik])
    assert info.value.field == "frames"

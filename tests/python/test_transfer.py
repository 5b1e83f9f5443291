"""rigel.Workspace's transfer keys, move keys and channel values on the
biped (examples/biped.rig.xml on the metarig): the same library calls as
`rigel transfer`, `rigel key --move-to` and `rigel set`."""

import pytest

import rigel
from conftest import BIPED


@pytest.fixture
def hero(metarig):
    w = rigel.Workspace(metarig)
    w.add_rig(str(BIPED))
    return w


def test_transfer_keys_onto_the_other_arm_with_an_offset(hero):
    w = hero
    left = w.scene.resolve("hero:arm_L/fkIkSwitch")
    right = w.scene.resolve("hero:arm_R/fkIkSwitch")
    w.set_frame(0)
    w.set_channel_keys([left], attrs=["fkIk"], value=0.0)
    w.set_frame(10)
    w.set_channel_keys([left], attrs=["fkIk"], value=1.0, tangent="step")
    report = w.transfer_keys("hero:arm_L", "hero:arm_R", offset=5)
    assert (report.channels, report.keys, report.frames) == (1, 2, (0.0, 10.0))
    assert report.set == [right]
    [k] = w.channel_keys([right], attrs=["fkIk"])
    assert (k.frames, k.values, k.out_tangents) == ([5.0, 15.0], [0.0, 1.0], ["auto", "step"])
    # A range: only frame 10's key, onto 25.
    w.transfer_keys("hero:arm_L", "hero:arm_R", frames=(10, 10), offset=15)
    [k] = w.channel_keys([right], attrs=["fkIk"])
    assert k.frames == [5.0, 15.0, 25.0]
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.transfer_keys("hero:arm_L", "hero:foot_L")
    assert info.value.field == "to"
    with pytest.raises(rigel.NotFoundError) as info:
        w.transfer_keys("nobody:arm_L", "hero:arm_R")
    assert info.value.field == "from"
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.transfer_keys("hero:arm_L", "hero:arm_R", frames=(4, 1))
    assert info.value.field == "frames"


def test_move_channel_keys_and_set_channel_values(hero):
    w = hero
    ik = w.scene.resolve("hero:arm_L/ik[0]")
    switch = w.scene.resolve("hero:arm_L/fkIkSwitch")
    w.set_frame(3)
    r = w.set_channel_values(1.0, [ik], attrs=["fkIk"])  # the control stands for its limb's switch
    assert r.channels == [switch.name + ".fkIk"] and r.keys == []
    w.set_channel_keys([switch], attrs=["fkIk"])
    w.set_frame(7)
    [k] = w.set_channel_values(0.5, [switch], attrs=["fkIk"]).keys
    assert (k.frames, k.values) == ([3.0, 7.0], [1.0, 0.5])
    w.set_frame(3)
    [k] = w.move_channel_keys(7, [switch], attrs=["fkIk"])
    assert (k.frames, k.values) == ([7.0], [1.0])
    with pytest.raises(rigel.NotFoundError):
        w.move_channel_keys(9, [switch], attrs=["fkIk"])
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.set_channel_values([1.0, 2.0], [switch], attrs=["fkIk"])
    assert info.value.field == "value"


def test_channel_box_lists_components_switches_and_keyed_state(hero):
    w = hero
    ik = w.scene.resolve("hero:arm_L/ik[0]")
    switch = w.scene.resolve("hero:arm_L/fkIkSwitch")
    w.set_frame(0)
    r = w.set_channel_values(0.2, [ik], attrs=["translateZ"])
    assert r.channels == [ik.name + ".translateZ"]
    w.set_channel_keys([ik], attrs=["translate"])
    [box] = w.channel_box([ik])
    assert box.control == ik
    rows = {c.plug: c for c in box.channels}
    z = rows[ik.name + ".translateZ"]
    assert (z.attr, z.key_attr, z.value, z.keyed) == ("translateZ", "translate", 0.2, "here")
    assert rows[ik.name + ".rotateX"].keyed == "none"
    fk_ik = rows[switch.name + ".fkIk"]
    assert fk_ik.node == switch and fk_ik.attr == "fkIk"
    w.set_frame(5)
    [box] = w.channel_box([ik])
    assert {c.plug: c for c in box.channels}[ik.name + ".translateZ"].keyed == "elsewhere"
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.set_channel_values(1.0, [ik], attrs=["translateW"])
    assert info.value.field == "attrs"

"""rigel.Workspace's graph editor on the biped (examples/biped.rig.xml on the
metarig): curves of a control's channels and its limb's switch, keys moved
in time and value, tangents changed, inserted and deleted, each one undo
step, as GET /api/curves and POST /api/curve-keys do."""

import pytest

import rigel
from conftest import BIPED


@pytest.fixture
def keyed(metarig):
    w = rigel.Workspace(metarig)
    w.add_rig(str(BIPED))
    ik = w.scene.resolve("hero:arm_L/ik[0]")
    switch = w.scene.resolve("hero:arm_L/fkIkSwitch")
    for f in (0, 10):
        w.set_frame(f)
        w.set_channel_values(f * 0.01, [ik], attrs=["translateY"])
        w.set_channel_keys([ik], attrs=["translate"])
    for f, v in ((0, 0.0), (10, 1.0), (20, 0.5)):
        w.set_frame(f)
        w.set_channel_keys([switch], attrs=["fkIk"], value=v)
    return w, ik, switch


def by_plug(curves):
    return {c.plug: c for c in curves}


def test_curves_show_keys_tangents_and_samples(keyed):
    w, ik, switch = keyed
    cs = by_plug(w.curves([ik]))
    ty = cs[ik.name + ".translateY"]
    sw = cs[switch.name + ".fkIk"]
    assert ty.kind == "curve" and ty.frames == [0.0, 10.0]
    assert ty.values[1] == pytest.approx(0.1)
    assert sw.frames == [0.0, 10.0, 20.0] and sw.values == [0.0, 1.0, 0.5]
    assert len(sw.in_tangents) == 3 and len(sw.out_slopes) == 3
    assert len(sw.sample_frames) == 21
    wide = by_plug(w.curves([ik], first=-5, last=30, step=5))[switch.name + ".fkIk"]
    assert (wide.sample_frames[0], wide.sample_frames[-1]) == (-5.0, 30.0)
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.curves([ik], step=0)
    assert info.value.field == "step"


def test_edit_insert_delete_each_one_undo_step(keyed):
    w, ik, switch = keyed
    fkik = switch.name + ".fkIk"
    assert w.edit_curve_keys(fkik, [10.0003], to_frame=15, value=0.75, out_tangent="step") == 1
    sw = by_plug(w.curves([ik]))[fkik]
    assert sw.frames == [0.0, 15.0, 20.0] and sw.values[1] == 0.75 and sw.out_tangents[1] == "step"
    assert w.insert_curve_keys([(ik.name + ".translateX", 5)]) == 1
    assert w.delete_curve_keys([(ik.name + ".translateZ", 0), (ik.name + ".translateZ", 10)]) == 2
    cs = by_plug(w.curves([ik]))
    assert cs[ik.name + ".translateX"].frames == [0.0, 5.0, 10.0]
    assert ik.name + ".translateZ" not in cs
    w.undo()
    assert ik.name + ".translateZ" in by_plug(w.curves([ik]))
    w.undo()
    assert by_plug(w.curves([ik]))[ik.name + ".translateX"].frames == [0.0, 10.0]
    w.undo()
    assert by_plug(w.curves([ik]))[fkik].frames == [0.0, 10.0, 20.0]
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.edit_curve_keys(fkik, [0], tangent="wobbly")
    assert info.value.field == "tangent"
    with pytest.raises(rigel.NotFoundError) as info:
        w.delete_curve_keys([("nosuch.translateX", 0)])
    assert info.value.field == "keys"

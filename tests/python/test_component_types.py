"""Component types written in Python (docs/PYTHON.md, "Component types in
Python"): a plugin's class registered for its metaType builds, steps back
and forth, updates with keys kept and is removed exactly, like a C++ type;
instances come back as the class from the metadata network; a taken type
or a raising class is refused naming the file, with nothing half-built."""

import json
import textwrap

import pytest

import rigel
from conftest import close, distance, translation

ANTENNA = '''
import rigel


class Antenna:
    """A two-joint antenna: a base control turning the root joint and an
    aim control, above the tip, that the tip follows."""

    type = "antenna"
    params = [{"name": "aimDistance", "type": "number", "default": 0.05, "min": 0.0,
               "help": "How far above the tip the aim control floats, m."}]
    guides = {"names": ["root", "tip"], "help": "The root joint and the tip joint, its child."}
    controls = [("base", "circle", "yellow", 0.05, "Turns the antenna."),
                ("aim", "sphere", "red", 0.02, "The tip follows it.")]
    hooks = ["root", "tip"]
    steps = ["controls", "drive"]

    def step_controls(self, build):
        base = build.create_control("base", build.guide_world(0), guide=0)
        build.publish_hook(0, base)  # a step publishes what it made
        above = list(build.guide_world(1))
        above[13] += build.param("aimDistance")  # column-major: translation y
        build.create_control("aim", above, guide=1, parent=base)

    def step_drive(self, build):
        base, aim = build.node("base"), build.node("aim")
        build.drive(base, build.guide_joint(0))
        follow = build.create_group("tipFollow", build.guide_world(1), parent=aim)
        build.drive(follow, build.guide_joint(1))
        build.publish_hook(1, follow)

    def aim_control(self):
        return self.controls[1]


def register_plugin():
    rigel.register_component_type(Antenna)
'''


@pytest.fixture
def antenna(tmp_path):
    folder = tmp_path / "plugins"
    folder.mkdir()
    path = folder / "antenna.py"
    path.write_text(ANTENNA)
    loaded = rigel.load_plugins(str(folder))
    yield path
    rigel.unregister_component_types(str(path))
    assert loaded == {str(path): ["antenna"]}


def normalized(text):
    """A scene's text with each node's uuid replaced by its name (two builds
    make the same nodes with new uuids)."""
    names = {n["uuid"]: n["name"] for n in json.loads(text)["nodes"]}
    for uuid, name in names.items():
        text = text.replace(uuid, name)
    return text


def antenna_definition(distance_above=0.05, type="antenna"):
    d = rigel.Definition("bug")
    root = d.add_component("global", "global", guides=[rigel.Guide("main")])
    root.add_component(type, "antenna", "L", guides=[rigel.Guide("root", joint="ear.L"),
                                                          rigel.Guide("tip", joint="ear.L.001")],
                       params={"aimDistance": distance_above})
    return d


def test_a_python_type_is_a_component_type_like_the_others(antenna):
    assert "antenna" in rigel.component_types()
    assert {"type": "antenna", "origin": str(antenna)} in rigel.registered_component_types()
    d = antenna_definition()
    assert d.validate() == []
    d.find("antenna_L").set_param("aimDistance", -1.0)
    assert any("aimDistance" in str(p) for p in d.validate())


def test_it_builds_steps_back_and_forth_moves_the_joints_and_is_removed_exactly(antenna, metarig):
    original = metarig.to_text()
    b = rigel.RigBuild.open(metarig, antenna_definition())
    labels = [p.label for p in b.plan]
    assert "antenna_L/controls" in labels and "antenna_L/drive" in labels
    b.build_all()
    built = normalized(metarig.to_text())
    rest_tip = translation(metarig.world_matrix("ear.L.001"))
    for position in range(len(b), -1, -1):
        b.go_to(position)
    assert metarig.to_text() == original
    b.build_all()
    assert normalized(metarig.to_text()) == built, "stepping back to the start and forward again gives the straight build"
    assert close(distance(translation(metarig.world_matrix("ear.L.001")), rest_tip), 0.0, 1e-9), "nothing moves at rest"
    aim = metarig.resolve("bug:antenna_L/aim")
    aim["translate"] = (0.03, 0, 0)
    assert close(distance(translation(metarig.world_matrix("ear.L.001")), rest_tip), 0.03, 1e-6)
    moved_tip = translation(metarig.world_matrix("ear.L.001"))
    base = metarig.resolve("bug:antenna_L/base")
    base["rotate"] = (0, 0, 30)
    assert distance(translation(metarig.world_matrix("ear.L.001")), moved_tip) > 0.01, "the base turns the antenna"
    b.remove()
    assert metarig.to_text() == original, "removed exactly"


def test_instances_come_back_as_the_class_from_the_metadata_network(antenna, metarig):
    rigel.RigBuild.open(metarig, antenna_definition()).build_all()
    meta = metarig.find_component("bug", "antenna_L")
    instance = rigel.component_instance(meta)
    assert type(instance).__name__ == "Antenna" and instance.type == "antenna"
    assert [c.name for c in instance.controls] == ["bug_antenna_L_base", "bug_antenna_L_aim"]
    assert instance.aim_control().name == "bug_antenna_L_aim"
    assert len(instance.hooks) == 2 and instance.attach is not None
    assert instance.attach.component == metarig.find_component("bug", "global")
    built_in = rigel.component_instance(metarig.find_component("bug", "global"))
    assert built_in.type == "global" and len(built_in.controls) == 1


def test_an_update_keeps_the_keys(antenna, metarig):
    definition = antenna_definition()
    b = rigel.RigBuild.open(metarig, definition)
    b.build_all()
    ws = rigel.Workspace(metarig)
    aim = metarig.resolve("bug:antenna_L/aim")
    ws.set_frame(0)
    ws.set_channel_keys([aim], attrs=["translate"])
    ws.set_frame(10)
    ws.set_channel_keys([aim], attrs=["translate"])
    ws.set_channel_values(0.04, [aim], attrs=["translateX"])  # keyed: the key at 10 takes it
    changed = definition.copy()
    changed.find("antenna_L").set_param("aimDistance", 0.08)
    changed.find("antenna_L").version = "1.1"
    assert b.rebuild_changed(changed) == [definition.find("antenna_L").rig_id]
    aim = metarig.resolve("bug:antenna_L/aim")
    ws.set_frame(10)
    assert close(aim["translate"][0], 0.04, 1e-12), "the keys stay on the rebuilt control"
    ws.set_frame(0)
    assert close(aim["translate"][0], 0.0, 1e-12)


def test_a_taken_type_and_a_raising_class_are_refused_naming_the_file(antenna, tmp_path, metarig):
    folder = tmp_path / "more"
    folder.mkdir()
    taken = folder / "taken.py"
    taken.write_text(ANTENNA)
    with pytest.raises(rigel.PluginError, match=r"taken\.py.*'antenna'.*antenna\.py"):
        rigel.load_plugin(str(taken))
    limb = folder / "limb.py"
    limb.write_text(ANTENNA.replace('type = "antenna"', 'type = "limb"'))
    with pytest.raises(rigel.PluginError, match=r"limb\.py.*'limb'.*rigel ships it"):
        rigel.load_plugin(str(limb))
    raising = folder / "raising.py"
    raising.write_text(ANTENNA.replace('type = "antenna"', 'type = "raiser"').replace(
        "    def step_controls", "    def __init__(self):\n        raise RuntimeError('no antenna today')\n\n"
        "    def step_controls"))
    with pytest.raises(rigel.PluginError, match=r"raising\.py.*no antenna today"):
        rigel.load_plugin(str(raising))
    assert "raiser" not in rigel.component_types() and "limb" in rigel.component_types()
    # A step that raises fails the build naming the component, the step and
    # the file; the failing step leaves nothing behind.
    broken = folder / "broken.py"
    broken.write_text(ANTENNA.replace('type = "antenna"', 'type = "brokenAntenna"').replace(
        "        build.drive(base, build.guide_joint(0))", "        raise ValueError('the wire is cut')"))
    rigel.load_plugin(str(broken))
    try:
        d = antenna_definition(type="brokenAntenna")
        b = rigel.RigBuild.open(metarig, d)
        before = None
        with pytest.raises(rigel.Error, match=r"antenna_L \(brokenAntenna\) step 'drive' \(.*broken\.py\).*the wire is cut"):
            while True:
                before = metarig.to_text()
                b.forward()
        assert metarig.to_text() == before
    finally:
        rigel.unregister_component_types(str(broken))


def test_declarations_that_do_not_hold_are_refused(tmp_path):
    bad = tmp_path / "bad.py"
    bad.write_text(textwrap.dedent('''
        import rigel

        class NoSteps:
            type = "noSteps"
            steps = ["build"]

        def register_plugin():
            rigel.register_component_type(NoSteps)
    '''))
    with pytest.raises(rigel.PluginError, match=r"bad\.py.*'noSteps'.*step 'build' has no method step_build"):
        rigel.load_plugin(str(bad))
    assert "noSteps" not in rigel.component_types()

"""rigel.Workspace, the service layer from Python (app::Workspace): each
operation once, its answer, and its refusals naming the argument at fault
in Python's spelling (e.field)."""

import pytest

import rigel
from conftest import BIPED, METARIG, arm_definition, close, translation


@pytest.fixture
def ws(metarig):
    """A workspace on the metarig with an ephemeral rig on every joint."""
    rigel.setup_ephemeral(metarig)
    return rigel.Workspace(metarig)


@pytest.fixture
def built(metarig, tmp_path):
    """A workspace on the metarig with the arm rig built from a file."""
    path = tmp_path / "arm.rig.xml"
    arm_definition().save(str(path))
    w = rigel.Workspace(metarig)
    w.add_rig(str(path))
    return w, path


def test_opens_a_file_or_shares_a_scene(tmp_path, metarig):
    w = rigel.Workspace(str(METARIG))
    assert w.scene_path is None  # a character is not where save() writes
    assert w.character == str(METARIG) and w.root is None
    assert w.scene.find("hand.L") is not None
    path = tmp_path / "shot.rigel"
    metarig.save(str(path))
    w = rigel.Workspace(str(path))
    assert w.scene_path == str(path)
    shared = rigel.Workspace(metarig)
    assert shared.scene.node("hand.L") == metarig.node("hand.L")  # the same scene
    with pytest.raises(rigel.IoError, match="ghost.rigel"):
        rigel.Workspace(str(tmp_path / "ghost.rigel"))


def test_nodes_and_reports(ws):
    scene = ws.scene
    hand = scene.node("hand.L_ctrl")
    assert ws.node("hand.L") == scene.node("hand.L") and ws.node(hand.uuid) == hand
    assert ws.control("hand.L") == hand and ws.control(scene.node("hand.L")) == hand
    assert ws.is_control(hand) and not ws.is_control("hand.L")
    assert len(ws.all_controls()) == 159 and hand in ws.all_controls()
    nodes = ws.nodes()
    assert any(e.node == hand and e.parent == scene.node("forearm.L_ctrl") for e in nodes)
    assert [e.parent for e in nodes if e.node == scene.roots()[0]] == [None]
    [entry] = [c for c in ws.controls() if c.node == hand]
    assert entry.rig == "ephemeralRig" and entry.ephemeral and len(entry.color) == 3
    s = ws.summary()
    assert (s.fps, s.frame, s.mode, s.auto_key, s.range) == (24.0, 0.0, "forward", False, (0.0, 0.0))
    assert s.key_scopes == {"ephemeralRig": "character"} and s.can_undo and s.selection == []
    world = {e.node.name: e for e in ws.pose("world")}
    assert close(world["hand.L"].translate, translation(scene.world_matrix("hand.L")))
    assert len(world["hand.L"].rotate) == 4
    assert len(ws.pose()) == len(world)
    with pytest.raises(rigel.NotFoundError) as info:
        ws.control("wing")
    assert info.value.field == "ref"
    scene.create_node("joint", "loose")
    with pytest.raises(rigel.InvalidArgumentError, match="not a control") as info:
        ws.control("loose")
    assert info.value.field == "ref"
    with pytest.raises(rigel.InvalidArgumentError, match="space") as info:
        ws.pose("screen")
    assert info.value.field == "space"


def test_select_mode_options(ws):
    revision = ws.revision
    ws.select(["hand.L"])  # a joint stands for its control
    ws.select(["hand.R_ctrl"], add=True)
    assert ws.selection == [ws.scene.node("hand.L_ctrl"), ws.scene.node("hand.R_ctrl")]
    assert ws.revision > revision
    ws.mode = "magnet"
    assert ws.mode == "magnet" and ws.summary().mode == "magnet"
    with pytest.raises(rigel.InvalidArgumentError, match="mode 'sideways'"):
        ws.mode = "sideways"
    ws.set_options(magnet_fraction=0.5, auto_key=True)
    assert ws.options["magnet_fraction"] == 0.5 and ws.options["auto_key"] and ws.options["magnet_radius"] == 1.0
    with pytest.raises(rigel.InvalidArgumentError, match="^magnet_fraction: ") as info:
        ws.set_options(magnet_fraction=1.5)
    assert info.value.field == "magnet_fraction" and ws.options["magnet_fraction"] == 0.5
    with pytest.raises(rigel.InvalidArgumentError) as info:
        ws.set_options(max_chain=-1)
    assert info.value.field == "max_chain"
    with pytest.raises(rigel.NotFoundError) as info:
        ws.select(["hand.L", "wing"])
    assert info.value.field == "controls[1]"


def test_drag_release_undo_redo(ws):
    scene = ws.scene
    before = scene.to_text()
    with pytest.raises(rigel.StateError) as info:
        ws.drag(translate=(0, 0.1, 0))  # nothing selected
    assert info.value.field == "controls" and isinstance(info.value, RuntimeError)
    ws.mode = "inverse"
    ws.select(["hand.L_ctrl"])
    hand = translation(scene.world_matrix("hand.L_ctrl"))
    r = ws.drag(translate=(0, 0.05, 0))
    assert r.dragged == [scene.node("hand.L_ctrl")] and r.notes == []
    moved = {m.node.name: m for m in r.moved_controls}
    assert close(moved["hand.L_ctrl"].translate, (hand[0], hand[1] + 0.05, hand[2]), 1e-6)
    assert "forearm.L_ctrl" in moved and "foot.L_ctrl" not in moved
    assert any(m.node.name == "forearm.L" for m in r.moved)  # local values of the joints it moved
    ws.drag(translate=(0, 0.05, 0))
    ws.release()
    assert ws.undo() == "ephemeral drag (inverse)"  # both drags: one gesture
    assert scene.to_text() == before
    assert ws.redo() == "ephemeral drag (inverse)"
    assert close(translation(scene.world_matrix("hand.L_ctrl")), (hand[0], hand[1] + 0.1, hand[2]), 1e-6)
    while scene.can_undo:
        ws.undo()
    with pytest.raises(rigel.StateError, match="nothing to undo"):
        ws.undo()


def test_drag_rotations_and_drag_to(ws, metarig):
    scene = ws.scene
    ws.select(["forearm.L_ctrl"])
    by_euler = ws.drag(euler=(0, 0, 30))
    ws.release()
    after_euler = scene.to_text()
    ws.undo()
    ws.select(["forearm.L_ctrl"])
    ws.drag(rotate=(0, 0, 0.25881904510252074, 0.9659258262890683))  # 30 degrees about z
    ws.release()
    assert scene.to_text() == after_euler and by_euler.moved_controls
    with pytest.raises(rigel.InvalidArgumentError) as info:
        ws.drag(rotate=(0, 0, 0, 1), euler=(0, 0, 0))
    assert info.value.field == "euler"
    with pytest.raises(rigel.InvalidArgumentError, match="rotate"):
        ws.drag(rotate=(0, 0, 1))  # a quaternion has 4 numbers
    target = tuple(a + b for a, b in zip(translation(scene.world_matrix("hand.L_ctrl")), (0, 0.03, 0)))
    ws.mode = "inverse"
    r = ws.drag_to("hand.L_ctrl", translate=target)
    assert ws.selection == [scene.node("hand.L_ctrl")]
    assert close(translation(scene.world_matrix("hand.L_ctrl")), target, 1e-6) and r.dragged
    ws.mode = "body"
    ws.select(["spine_ctrl"])
    ws.set_body_pivot("spine_ctrl", at=(0, 0, 0))
    head = translation(scene.world_matrix("spine.006"))
    ws.drag(translate=(0, 0, 1))
    assert close(translation(scene.world_matrix("spine.006")), (head[0], head[1], head[2] + 1), 1e-9)


def test_drag_a_built_rigs_control(built):
    w, _ = built
    scene = w.scene
    ik = scene.resolve("arm_rig:arm_L/ik[0]")
    start = translation(scene.world_matrix(ik))
    w.select([ik])
    r = w.drag(translate=(0, 0.02, 0))
    assert r.dragged == [ik] and r.notes == []
    assert close(translation(scene.world_matrix(ik)), (start[0], start[1] + 0.02, start[2]), 1e-9)
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.drag(scale=(2, 2, 2))
    assert info.value.field == "scale"


def test_channel_keys_on_a_built_rig(built):
    w, _ = built
    scene = w.scene
    ik = scene.resolve("arm_rig:arm_L/ik[0]")
    switch = scene.resolve("arm_rig:arm_L/fkIkSwitch")
    w.set_frame(0)
    keys = w.set_channel_keys([ik])  # the rig's whole character: a key is a pose
    assert keys and all(k.frames == [0.0] for k in keys)
    assert any(k.plug == ik.name + ".translateX" for k in keys)
    w.set_channel_keys([switch], attrs=["fkIk"], value=0.0)
    w.set_frame(24)
    [k] = w.set_channel_keys([switch], attrs=["fkIk"], value=1.0)
    assert (k.plug.endswith(".fkIk"), k.frames, k.values) == (True, [0.0, 24.0], [0.0, 1.0])
    assert w.channel_keys([switch]) == [k]
    [k] = w.set_channel_keys([switch], attrs=["fkIk"], value=1.0, out_tangent="step")
    assert k.out_tangents == ["auto", "step"] and k.in_tangents == ["auto", "auto"]
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.set_channel_keys([switch], attrs=["fkIk"], tangent="curly")
    assert info.value.field == "tangent"
    [k] = w.delete_channel_keys([switch], attrs=["fkIk"])
    assert k.frames == [0.0]
    with pytest.raises(rigel.NotFoundError):
        w.delete_channel_keys([switch], attrs=["fkIk"])
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.set_channel_keys([ik], attrs=["fkIk"])
    assert info.value.field == "attrs"
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.set_channel_keys([ik], attrs=["rotate"], value=1.0)
    assert info.value.field == "value"


def test_match_bakes_a_limbs_fk_to_its_animated_ik(built):
    w, _ = built
    scene = w.scene
    ik = scene.resolve("arm_rig:arm_L/ik[0]")
    switch = scene.resolve("arm_rig:arm_L/fkIkSwitch")
    w.set_frame(0)
    w.set_channel_keys([switch], attrs=["fkIk"], value=1.0)
    scene.set(ik, "translate", (0.05, -0.1, 0.15))  # the IK pose, away from the FK one
    w.set_channel_keys([ik], attrs=["translate"])
    w.set_frame(10)
    w.set_channel_keys([switch], attrs=["fkIk"], value=1.0)
    report = w.match("arm_rig", "arm_L", "fk", frames=(0, 10))
    assert report.frames == 11 and report.max_error < 1e-6
    assert scene.resolve("arm_rig:arm_L/fk[0]") in report.controls
    [k] = w.channel_keys([switch], attrs=["fkIk"])
    assert (k.frames, k.values) == ([0.0, 10.0], [0.0, 0.0])
    # Back to IK at one frame, without keys on the IK side's free pole.
    w.set_frame(5)
    assert w.match("arm_rig", "arm_L", "ik").frames == 1
    with pytest.raises(rigel.InvalidArgumentError):
        w.match("arm_rig", "arm_L", "sideways")
    with pytest.raises(rigel.NotFoundError) as info:
        w.match("arm_rig", "hand_L", "fk")
    assert info.value.field == "component"
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.match("arm_rig", "arm_L", "fk", frames=(8, 2))
    assert info.value.field == "frames"


def test_tween_sets_a_channel_between_its_keys(built):
    w, _ = built
    switch = w.scene.resolve("arm_rig:arm_L/fkIkSwitch")
    w.set_frame(0)
    w.set_channel_keys([switch], attrs=["fkIk"], value=0.0)
    w.set_frame(10)
    w.set_channel_keys([switch], attrs=["fkIk"], value=1.0)
    w.set_frame(4)
    [k] = w.tween([switch], attrs=["fkIk"], fraction=0.25)
    assert k.frames == [0.0, 4.0, 10.0] and abs(k.values[1] - 0.25) < 1e-12
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.tween([switch], attrs=["fkIk"], fraction=float("nan"))
    assert info.value.field == "fraction"
    w.set_frame(20)
    with pytest.raises(rigel.StateError):
        w.tween([switch], attrs=["fkIk"])


def test_mirror_refuses_a_control_without_a_pair_and_flips_the_centre(built):
    w, _ = built
    scene = w.scene
    fk0 = scene.resolve("arm_rig:arm_L/fk[0]")
    with pytest.raises(rigel.InvalidArgumentError, match="has no pair") as info:
        w.mirror([fk0])
    assert info.value.field == "controls"
    main = scene.resolve("arm_rig:global/main")
    report = w.mirror([main], flip=True)
    assert report.frames == 1 and report.set == [main]
    with pytest.raises(rigel.InvalidArgumentError):
        w.mirror([main], side="Q")


def test_spaces_add_switch_and_bake(built):
    w, _ = built
    scene = w.scene
    ik = scene.resolve("arm_rig:arm_L/ik")
    spaces = w.spaces(ik)
    # The arm rig has a global but no chest or head: those spaces are left out.
    assert [s.name for s in spaces.spaces] == ["parent", "world", "global"]
    assert spaces.current == "parent" and spaces.spaces[1].target is None
    added = w.add_space(ik, "forearm", scene.resolve("arm_rig:arm_L/fk[1]"))
    assert added.spaces[-1].name == "forearm"
    w.set_frame(0)
    w.set_channel_keys([ik], attrs=["translate"])
    w.set_frame(10)
    w.set_channel_keys([ik], attrs=["translate"])
    w.select([ik])
    w.drag(translate=(0.05, 0.1, 0.0))  # moves the key at frame 10
    w.release()
    w.set_frame(5)
    before = scene.world_matrix(ik)
    report = w.switch_space(ik, "world", frame=5)
    assert report.from_space == "parent" and report.to_space == "world"
    assert report.frames == 1 and report.max_error < 1e-9
    w.set_frame(5)
    assert close(scene.world_matrix(ik), before, 1e-9)
    assert w.spaces(ik).current == "world"
    baked = w.switch_space(ik, "global", frames=(0, 10))
    assert baked.frames == 11 and baked.max_error < 1e-6
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.switch_space(ik, "moon")
    assert info.value.field == "space"
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.add_space(ik, "self", ik)
    assert info.value.field == "target"
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.switch_space(scene.resolve("arm_rig:arm_L/fk[0]"), "world")
    assert info.value.field == "control"


def test_deform_only_export_writes_the_skin_joints_and_the_mesh(built, tmp_path):
    w, _ = built
    scene = w.scene
    full = scene.export_gltf(str(tmp_path / "all.glb"))
    report = scene.export_gltf(str(tmp_path / "game.glb"), frames=(0, 4), deform_only=True)
    assert report["baked"] and report["skins"] == 1
    assert report["nodes"] < full["nodes"]
    back = rigel.open(str(tmp_path / "game.glb"))
    names = {n.name for n in back.nodes()}
    assert "hand.L" in names and not any(name.startswith("arm_rig_") for name in names)


def test_time_and_keys(ws):
    scene = ws.scene
    ws.set_frame(10)
    assert ws.frame == 10 and scene.frame == 10
    ws.time = 0.5
    assert ws.frame == 12 and ws.time == 0.5
    ws.frame = 0
    with pytest.raises(rigel.InvalidArgumentError) as info:
        ws.set_frame(2e6)
    assert info.value.field == "frame"
    with pytest.raises(rigel.InvalidArgumentError) as info:
        ws.set_time(float("inf"))
    assert info.value.field == "time"
    with pytest.raises(rigel.StateError) as info:
        ws.set_key()  # nothing selected, no controls
    assert info.value.field == "controls"
    k = ws.set_key(["hand.L_ctrl"])
    assert k.scope == "character" and len(k.set) == 159 and k.frames == [0.0] and k.times == [0.0]
    ws.set_frame(5)
    ws.select(["hand.L_ctrl"])
    assert ws.set_key().frames == [0.0, 5.0]  # the selection's
    assert ws.keys(["foot.R_ctrl"]).frames == [0.0, 5.0]
    assert ws.delete_key(["hand.L_ctrl"]).frames == [0.0]
    assert ws.summary().range == (0.0, 0.0)
    with pytest.raises(rigel.Error):
        ws.delete_key(["hand.L_ctrl"])  # no key at frame 5 any more


def test_save_and_root(tmp_path, metarig):
    w = rigel.Workspace(metarig)
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.save()  # no file yet
    assert info.value.field == "path"
    out = tmp_path / "a" / "shot.rigel"
    assert w.save(str(out)) == str(out) and w.scene_path == str(out)
    assert rigel.Scene.load(str(out)).to_text() == metarig.to_text()
    assert w.save() == str(out)
    confined = rigel.Workspace(metarig, root=str(tmp_path))
    assert confined.root == str(tmp_path)
    assert confined.save("b/shot.rigel") == str(tmp_path / "b" / "shot.rigel")
    for bad in [str(tmp_path / "abs.rigel"), "../out.rigel"]:
        with pytest.raises(rigel.InvalidArgumentError) as info:
            confined.save(bad)
        assert info.value.field == "path"


def test_rigs_add_step_feature_remove(metarig, tmp_path):
    path = tmp_path / "biped.rig.xml"
    rigel.Definition.load(str(BIPED)).save(str(path))
    w = rigel.Workspace(metarig)
    added = w.add_rig(str(path))
    assert added.name == "hero" and added.steps == 90 and "arm_L" in added.components
    [entry] = w.rigs()
    assert (entry.name, entry.unbuilt, entry.steps, entry.definition) == ("hero", False, 90, str(path))
    assert any(f.feature == "stretch" for f in entry.features)
    f = w.set_feature("hero", "stretch", False)
    assert [x.enabled for x in f.features if x.feature == "stretch" and x.switch == ""] == [False]
    assert f.position == f.steps == 90
    with pytest.raises(rigel.NotFoundError) as info:
        w.set_feature("hero", "wings", True)
    assert info.value.field == "feature"
    step = w.step_rig("hero", to=3)
    assert (step.rig, step.position, step.steps) == ("hero", 3, 90) and step.step
    assert w.step_rig("hero", by=-10).position == 0
    [entry] = w.rigs()
    assert entry.unbuilt and entry.version == "1.0"  # at step 0: kept by the workspace
    with pytest.raises(rigel.StateError) as info:
        w.update_rig("hero")
    assert info.value.field == "rig"
    assert w.step_rig("hero", by=90).position == 90
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.step_rig("hero", to=99)
    assert info.value.field == "to"
    assert w.definition("hero").name == "hero"
    assert "limb" in w.component_types()
    w.remove_rig("hero")
    assert w.rigs() == [] and metarig.find_rig("hero") is None
    with pytest.raises(rigel.NotFoundError) as info:
        w.remove_rig("hero")
    assert info.value.field == "rig"
    with pytest.raises(rigel.NotFoundError) as info:
        w.add_rig(str(tmp_path / "ghost.rig.xml"))
    assert info.value.field == "definition"


def test_update_rig(built, tmp_path):
    w, path = built
    d = rigel.Definition.load(str(path))
    d.version = "1.1"
    d.find("arm_L").version = "1.1"
    d.find("arm_L").set_param("maxStretch", 1.5)
    d.save(str(path))
    r = w.update_rig("arm_rig")
    assert (r.rig, r.from_version, r.to_version, r.updated) == ("arm_rig", "1.0", "1.1", True)
    assert r.rebuilt == ["arm_L"]
    assert w.update_rig("arm_rig").updated is False
    with pytest.raises(rigel.InvalidArgumentError, match="keep_keys 'global'"):
        w.update_rig("arm_rig", keep_keys="global")


def test_edit_mode_and_commit(built, tmp_path):
    w, path = built
    assert w.set_edit_mode("arm_rig", True) is True
    w.scene.resolve("arm_rig:arm_L/fk[1]")["translate"] = (0, 0.02, 0)
    out = tmp_path / "moved.rig.xml"
    c = w.commit_edits("arm_rig", definition_out=str(out))
    assert c.rig == "arm_rig" and c.version == "1.1" and c.changed == [c.definition.find("arm_L").rig_id]
    assert c.definition_path == str(out) and not c.edit_mode
    assert rigel.Definition.load(str(out)).version == "1.1"
    assert w.rigs()[0].definition == str(out)
    with pytest.raises(rigel.NotFoundError) as info:
        w.commit_edits("ghost")
    assert info.value.field == "rig"


def test_definitions_check_build_save(metarig, tmp_path):
    w = rigel.Workspace(metarig)
    checked = w.check_definition(arm_definition().text("json"), "json", "arm.rig.json")
    assert checked.problems == [] and checked.definition.name == "arm_rig"
    bad = w.check_definition("<rig", "xml", "bad.rig.xml")
    assert bad.problems and "bad.rig.xml:1" in str(bad.problems[0])
    with pytest.raises(rigel.InvalidArgumentError, match="syntax 'yaml'"):
        w.check_definition("{}", "yaml")
    d = arm_definition()
    r = w.build_definition(d)
    assert r.rig == "arm_rig" and len(r.rebuilt) == 2
    hand = translation(metarig.world_matrix("hand.L"))
    d.find("arm_L").set_param("maxStretch", 1.5)
    assert w.build_definition(d).rebuilt == [d.find("arm_L").rig_id]  # a live rebuild of what changed
    assert close(translation(metarig.world_matrix("hand.L")), hand, 1e-9)
    out = tmp_path / "arm.rig.xml"
    assert (w.save_definition(d, str(out)).version, w.save_definition(d, str(out)).version) == ("1.0", "1.0")
    d.find("arm_L").set_param("maxStretch", 1.75)
    saved = w.save_definition(d, str(out))
    assert saved.path == str(out) and saved.version == "1.1"  # other content over the file: next version
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.save_definition(d, str(tmp_path / "arm.txt"))
    assert info.value.field == "path"
    d.find("arm_L").guides = []
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.build_definition(d)
    assert info.value.field == "definition"


def test_revision_counts_changes(ws):
    r = ws.revision
    ws.summary()
    ws.pose()
    assert ws.revision == r
    ws.set_frame(3)
    assert ws.revision == r + 1


def test_state_error_and_field(ws):
    assert issubclass(rigel.StateError, rigel.Error) and issubclass(rigel.StateError, RuntimeError)
    assert rigel.StateError.code == "failed precondition" and rigel.StateError.__module__ == "rigel"
    with pytest.raises(rigel.StateError) as info:
        ws.redo()  # nothing to redo: no input at fault
    assert info.value.field is None
    with pytest.raises(rigel.NotFoundError) as info:
        ws.scene.get("ghost.translate")  # errors that name no input
    assert info.value.field is None


def test_pose_library_saves_applies_lists_and_removes(built, tmp_path):
    w, path = built
    scene = w.scene
    fk0 = scene.resolve("arm_rig:arm_L/fk[0]")
    fk0["rotate"] = (10.0, 20.0, 30.0)
    library = str(tmp_path / "poses")
    saved = w.save_pose(library, "wave")
    assert saved.name == "wave" and saved.entries > 3
    assert (tmp_path / "poses" / "wave.pose.json").exists()
    posed = translation(scene.resolve("arm_rig:arm_L/fk[2]").world_matrix)
    # A second character built from the same definition takes the pose.
    other = rigel.Workspace(str(METARIG))
    other.add_rig(str(path))
    report = other.apply_pose(library, "wave")
    assert other.scene.resolve("arm_rig:arm_L/fk[0]") in report.set
    assert close(translation(other.scene.resolve("arm_rig:arm_L/fk[2]").world_matrix), posed)
    # Half way, keyed, on a selection.
    other.undo()
    other.set_frame(5)
    half = other.apply_pose(library, "wave", controls=["arm_rig:arm_L/fk[0]"], fraction=0.5, key=True)
    assert half.keyed == half.channels and len(half.set) == 1
    assert [p.name for p in w.list_poses(library)] == ["wave"]
    assert w.list_poses(library)[0].rig == "arm_rig" and w.list_poses(library)[0].error is None
    # The thumbnail saved beside it: the skeleton in the pose, as SVG.
    assert w.list_poses(library)[0].thumbnail
    svg = w.pose_thumbnail(library, "wave")
    assert svg.startswith("<svg ") and "<line " in svg
    assert svg == (tmp_path / "poses" / "wave.pose.svg").read_text()
    w.remove_pose(library, "wave")
    assert w.list_poses(library) == []
    assert not (tmp_path / "poses" / "wave.pose.svg").exists()
    with pytest.raises(rigel.NotFoundError):
        w.pose_thumbnail(library, "wave")


def test_pose_library_refusals_name_the_argument(built, tmp_path):
    w, _ = built
    library = str(tmp_path / "poses")
    for name in ["../escape", "a/b", ""]:
        with pytest.raises(rigel.InvalidArgumentError) as info:
            w.save_pose(library, name)
        assert info.value.field == "name"
    assert not (tmp_path / "escape.pose.json").exists()
    with pytest.raises(rigel.NotFoundError) as info:
        w.apply_pose(library, "nope")
    assert info.value.field == "name"
    w.save_pose(library, "wave")
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.apply_pose(library, "wave", fraction=2)
    assert info.value.field == "fraction"
    with pytest.raises(rigel.NotFoundError):
        w.apply_pose(library, "wave", controls=["nobody"])
    with pytest.raises(rigel.NotFoundError) as info:
        w.apply_pose(library, "wave", rig="nobody")
    assert info.value.field == "rig"
    # A pose of another rig: its rigIds are not this rig's.
    text = (tmp_path / "poses" / "wave.pose.json").read_text()
    (tmp_path / "poses" / "other.pose.json").write_text(text.replace('"rigId": "', '"rigId": "f'))
    with pytest.raises(rigel.InvalidArgumentError, match="no component has rigId f") as info:
        w.apply_pose(library, "other")
    assert info.value.field == "rig"
    with pytest.raises(rigel.NotFoundError):
        w.remove_pose(library, "nope")

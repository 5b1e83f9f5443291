"""The pipeline from Python: a project with an asset, settings layered
project over user over defaults, and the data managers (skin weights,
control shapes and blend shapes exported and imported back): the same library calls as
`rigel project`, `rigel asset`, `rigel config` and `rigel data`."""

import re

import pytest

import rigel
from conftest import BIPED, DATA


UUID = re.compile(r"[0-9a-fA-F]{8}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{12}")


@pytest.fixture
def user_settings(tmp_path, monkeypatch):
    home = tmp_path / "user"
    monkeypatch.setenv("RIGEL_CONFIG_HOME", str(home))
    return home / "config.json"


def test_project_assets_and_settings(tmp_path, user_settings, monkeypatch):
    project = rigel.create_project(str(tmp_path / "show"))
    assert project.name == "show" and project.format == 1
    monkeypatch.chdir(tmp_path / "show")
    hero = rigel.create_asset("hero", skeleton=str(DATA / "gltf" / "rigify_human_metarig.glb"))
    assert hero.skeleton == "skeleton/rigify_human_metarig.glb" and hero.published == []
    rigel.create_asset("sword", type="prop")
    assert [a.name for a in rigel.assets()] == ["hero", "sword"]
    monkeypatch.chdir(tmp_path / "show" / "characters" / "hero" / "data")
    assert rigel.open_asset().name == "hero"
    assert rigel.open_project().name == "show"
    with pytest.raises(rigel.InvalidArgumentError) as info:
        rigel.create_asset("hero")
    assert info.value.field == "name"

    rigel.set_setting("log.level", "info")
    rigel.set_setting("log.level", "error", file=str(tmp_path / "show" / "rigel.config.json"))
    settings = rigel.settings()
    assert settings["log.level"].value == "error" and settings["log.level"].source == "project"
    assert settings["batch.jobs"].value == 0 and settings["batch.jobs"].source == "default"
    rigel.set_setting("log.level", None, file=str(tmp_path / "show" / "rigel.config.json"))
    assert rigel.settings()["log.level"].source == "user"
    with pytest.raises(rigel.InvalidArgumentError) as info:
        rigel.set_setting("log.level", "loud")
    assert info.value.field == "value"
    with pytest.raises(rigel.InvalidArgumentError):
        rigel.set_log_level("loud")


def test_weights_and_shapes_round_trip(tmp_path, user_settings):
    w = rigel.Workspace(str(DATA / "gltf" / "rigify_human_body.glb"))
    path = w.export_skin_weights(str(tmp_path / "body.weights.json"))
    text = open(path).read()
    report = w.import_skin_weights(path)
    assert report.skins == 1 and report.vertices > 10000 and report.remapped == []
    again = w.export_skin_weights(str(tmp_path / "again.weights.json"))
    assert open(again).read() == text
    mirrored = w.import_skin_weights(path, mirror=True)
    assert mirrored.remapped  # the left joints onto the right
    w.undo()
    assert open(w.export_skin_weights(str(tmp_path / "back.weights.json"))).read() == text
    # The arrays in a binary side file beside it (what data.weights = binary does).
    binary = w.export_skin_weights(str(tmp_path / "bin" / "body.weights.json"), format="binary")
    sides = [p.name for p in (tmp_path / "bin").iterdir() if p.suffix == ".bin"]
    assert len(sides) == 1 and '"binary"' in open(binary).read()
    assert w.import_skin_weights(binary).vertices == report.vertices
    assert open(w.export_skin_weights(str(tmp_path / "back2.weights.json"))).read() == text
    # No format: the setting data.weights (the user's here).
    rigel.set_setting("data.weights", "binary")
    by_setting = w.export_skin_weights(str(tmp_path / "set" / "body.weights.json"))
    assert '"binary"' in open(by_setting).read()
    rigel.set_setting("data.weights", None)
    with pytest.raises(rigel.InvalidArgumentError) as info:
        w.export_skin_weights(str(tmp_path / "x.weights.json"), format="xml")
    assert info.value.field == "format"

    hero = rigel.Workspace(str(DATA / "gltf" / "rigify_human_metarig.glb"))
    hero.add_rig(str(BIPED))
    shapes = hero.export_control_shapes(str(tmp_path / "hero.shapes.json"))
    r = hero.import_control_shapes(shapes)
    assert r.set > 50 and r.missing == []
    with pytest.raises(rigel.NotFoundError) as info:
        hero.import_control_shapes(str(tmp_path / "none.json"))
    assert info.value.field == "file"


def test_driven_keys_and_driven_poses_round_trip(tmp_path):
    hero = rigel.Workspace(str(DATA / "gltf" / "rigify_human_metarig.glb"))
    hero.add_rig(str(BIPED))
    driver = "hero_arm_L_fk0.rotateX"
    r = hero.set_driven_key(driver, {"hero_arm_L_fk1.rotateZ": 0.0, "hero_arm_R_fk1.rotateZ": None}, at=0)
    assert r.created == 2 and r.at == 0
    r = hero.set_driven_key(driver, {"hero_arm_L_fk1.rotateZ": -45.0}, at=90, tangent="linear")
    assert r.created == 0
    curves = hero.driven_poses()
    assert [c.driven for c in curves] == ["hero_arm_L_fk1.rotateZ", "hero_arm_R_fk1.rotateZ"]
    assert curves[0].driver == driver and curves[0].at == [0, 90] and curves[0].values == [0, -45]
    assert hero.driven_poses(correctives=True) == []
    path = hero.export_driven_poses(str(tmp_path / "hero.drivenposes.json"))
    text = open(path).read()
    hero.remove_driven_keys(["hero_arm_L_fk1.rotateZ", "hero_arm_R_fk1.rotateZ"])
    assert hero.driven_poses() == []
    report = hero.import_driven_poses(path)
    assert report.curves == 2 and report.created == 2 and report.keys == 3
    assert open(hero.export_driven_poses(str(tmp_path / "again.json"))).read() == text
    hero.undo()
    assert hero.driven_poses() == []
    with pytest.raises(rigel.InvalidArgumentError) as info:
        hero.set_driven_key("nobody.rotateX", {"hero_arm_L_fk1.rotateZ": 1.0})
    assert info.value.field == "driver"
    with pytest.raises(rigel.InvalidArgumentError) as info:
        hero.set_driven_key(driver, {"hero_arm_L_fk1.rotateZ": 1.0}, tangent="wobbly")
    assert info.value.field == "tangent"
    with pytest.raises(rigel.ParseError) as info:
        hero.import_driven_poses(path, correctives=True)
    assert info.value.field == "file"


def test_blend_shapes_round_trip(tmp_path):
    w = rigel.Workspace(str(DATA / "gltf" / "SimpleMorph.gltf"))
    w.time = 2.0  # the file's animated weights: (1, 1)
    path = w.export_blend_shapes(str(tmp_path / "tri.blendshapes.json"))
    text = open(path).read()
    assert '"rigelBlendShapes": 1' in text and "[2, 1.0, 1.0, 0.0]" in text
    edited = text.replace("[2, 1.0, 1.0, 0.0]", "[2, 1.0, 2.0, 0.0]")  # target 1 sculpted further
    with open(path, "w") as f:
        f.write(edited)
    mesh = w.scene.nodes(type="mesh")[0].name
    before = w.scene.get(mesh + ".points")
    r = w.import_blend_shapes(path)
    assert r.blend_shapes == 1 and r.targets == 2 and r.created == [] and r.added == []
    assert r.driven == []  # the animated weights are the file's
    after = w.scene.get(mesh + ".points")
    assert abs(after[2][1] - before[2][1] - 1) < 1e-6
    assert open(w.export_blend_shapes(str(tmp_path / "again.blendshapes.json"))).read() == edited
    w.undo()
    assert open(w.export_blend_shapes(str(tmp_path / "back.blendshapes.json"))).read() == text

    (tmp_path / "bad.blendshapes.json").write_text('{"rigelBlendShapes": 1,\n "blendShapes": [}')
    with pytest.raises(rigel.ParseError) as info:
        w.import_blend_shapes(str(tmp_path / "bad.blendshapes.json"))
    assert info.value.field == "file" and "bad.blendshapes.json:2:" in str(info.value)
    with pytest.raises(rigel.StateError):
        rigel.Workspace(str(DATA / "gltf" / "rigify_human_metarig.glb")).export_blend_shapes(str(tmp_path / "x.json"))


def test_publish_from_python(tmp_path, user_settings, monkeypatch):
    rigel.create_project(str(tmp_path / "show"))
    monkeypatch.chdir(tmp_path / "show")
    hero = rigel.create_asset("hero", skeleton=str(DATA / "gltf" / "rigify_human_metarig.glb"))
    (tmp_path / "show" / "characters" / "hero" / "build" / "biped.rig.xml").write_text(BIPED.read_text())
    v1 = rigel.publish("hero")
    assert v1.version == 1 and v1.rigs == ["hero"] and v1.rest_error < 1e-9
    monkeypatch.chdir(hero.dir)
    assert rigel.publish().version == 2
    assert rigel.open_asset().published == [1, 2]
    scene = rigel.Workspace(rigel.Scene.load(v1.scene))
    assert scene.rigs()[0].name == "hero"


def test_batch_from_python(tmp_path, user_settings, rigel_cli):
    """rigel.batch: the shots baked two at a time by `rigel` processes, the
    broken one failed with its log while the others succeed, progress
    reported, the report written; a retry reruns only the failed shot and
    updates the report; a request that cannot run is refused naming the
    field."""
    import json
    import shutil
    import subprocess

    hero = tmp_path / "hero.rigel"
    subprocess.run([str(rigel_cli), "build", str(BIPED), "-o", str(hero)], check=True, capture_output=True)
    shots = []
    for i in range(4):
        shots.append(tmp_path / "shots" / f"s{i}.rigel")
        shots[-1].parent.mkdir(exist_ok=True)
        shutil.copy(hero, shots[-1])
    shots[2].write_text("{ not a scene")
    seen = []
    out = tmp_path / "baked"
    r = rigel.batch("bake", [str(s) for s in shots], output=str(out), frames="0:4", jobs=2, program=str(rigel_cli),
                    progress=seen.append)
    assert r.operation == "bake" and r.jobs == 2 and r.ran == 4 and r.failed == 1
    assert [s.status for s in r.shots] == ["ok", "ok", "failed", "ok"]
    assert "s2.rigel" in open(r.shots[2].log).read() and not (out / "s2.rigel").exists()
    assert all((out / f"s{i}.rigel").is_file() for i in (0, 1, 3))
    assert seen and seen[-1].done == 4 and seen[-1].failed == 1 and "4/4 done" in seen[-1].line
    report = json.loads((out / "batch-report.json").read_text())
    assert [s["status"] for s in report["shots"]] == ["ok", "ok", "failed", "ok"]
    # Baked by hand: the same scene as the batch's (the made nodes' uuids aside, they are random).
    by_hand = tmp_path / "by_hand" / "s0.rigel"  # (beside the batch's: the scene names its definition relative to itself)
    by_hand.parent.mkdir()
    subprocess.run([str(rigel_cli), "bake", str(shots[0]), "--frames", "0:4", "-o", str(by_hand)], check=True, capture_output=True)
    kept = set(UUID.findall(shots[0].read_text()))

    def numbered(text):  # each uuid the bake made numbered by its first appearance; the shot's kept
        made = {}
        return UUID.sub(lambda m: m[0] if m[0] in kept else made.setdefault(m[0], f"<made {len(made)}>"), text)

    assert numbered(by_hand.read_text()) == numbered((out / "s0.rigel").read_text())

    shutil.copy(hero, shots[2])
    again = rigel.batch("bake", output=str(out), frames="0:4", retry_failed=str(out / "batch-report.json"), program=str(rigel_cli))
    assert again.ran == 1 and again.failed == 0 and [s.status for s in again.shots] == ["ok"] * 4
    assert (out / "s2.rigel").is_file()

    for kwargs, field in [(dict(operation="dance", shots=[str(shots[0])]), "operation"),
                          (dict(operation="bake", shots=[str(shots[0])], output=str(out)), "frames"),
                          (dict(operation="bake", shots=[str(shots[0])], frames="0:4"), "output"),
                          (dict(operation="update", shots=[str(shots[0]), str(shots[0])], output=str(out)), "shots"),
                          (dict(operation="update", shots=[str(shots[0])], output=str(out), partition="p"), "partition")]:
        with pytest.raises(rigel.InvalidArgumentError) as info:
            rigel.batch(program=str(rigel_cli), **kwargs)
        assert info.value.field == field, kwargs

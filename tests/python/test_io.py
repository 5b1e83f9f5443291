"""Files: .rigel load/save, glTF and BVH import, glTF export, and their errors."""

import pytest

import rigel
from conftest import DATA, METARIG, assert_valid_gltf, close, translation


def test_load_save_round_trip(tmp_path):
    path = DATA / "scenes" / "two_joint_chain.rigel"
    s = rigel.Scene.load(str(path))
    assert s.fps == 24 and s.time == 0.125
    tip = s.node("tip")
    assert tip.parent == s.node("root")
    assert s.source("aim.offsetParentMatrix") == "tip.worldMatrix"
    out = tmp_path / "copy.rigel"
    s.save(str(out))
    again = rigel.Scene.load(str(out))
    assert again.to_text() == s.to_text()
    assert again.node("root").uuid == s.node("root").uuid
    assert close(translation(again.world_matrix("tip")), translation(s.world_matrix("tip")))


def test_edits_survive_a_save(tmp_path, scene):
    j = scene.create_node("joint", "j")
    j["rotate"] = (10, 20, 30)
    j["rotateOrder"] = "zyx"
    out = tmp_path / "s.rigel"
    scene.save(str(out))
    text = out.read_text()
    assert '"rotateOrder": "zyx"' in text  # enums by name, angles in degrees
    again = rigel.Scene.load(str(out))
    assert again.node("j")["rotate"] == (10.0, 20.0, 30.0) and again.node("j")["rotateOrder"] == 5


def test_import_gltf_and_open(metarig):
    assert len(metarig.nodes("joint")) == 159
    hand = metarig.node("hand.L")
    assert hand.parent == metarig.node("forearm.L")
    scaled = rigel.Scene.import_gltf(str(METARIG), scale=2.0)
    a = translation(metarig.world_matrix("hand.L"))
    b = translation(scaled.world_matrix("hand.L"))
    assert close(tuple(2 * x for x in a), b, 1e-9)
    # imported scenes hold every node type (an ephemeral rig can be made on them)
    assert "ephemeralRig" in metarig.node_types()
    assert not metarig.can_undo


def test_import_bvh():
    s = rigel.Scene.import_bvh(str(DATA / "bvh" / "cmu_131_01.bvh"), scale=0.0254)
    assert s.fps == 120
    joints = s.nodes("joint")
    assert len(joints) > 20
    skipped = rigel.open(str(DATA / "bvh" / "cmu_131_01.bvh"))
    assert len(skipped.nodes("joint")) == len(joints)
    fewer = rigel.Scene.import_bvh(str(DATA / "bvh" / "cmu_131_01.bvh"), skip_end_sites=True)
    assert len(fewer.nodes("joint")) < len(joints)
    # the motion plays: a joint moves between frames
    root = joints[0]
    s.frame = 0
    p0 = translation(root.world_matrix)
    s.frame = 100
    assert translation(root.world_matrix) != p0


def test_export_gltf_round_trip(tmp_path, metarig):
    metarig.node("forearm.L")["rotateQuaternion"] = (0, 0, 0.3826834323650898, 0.9238795325112867)
    out = tmp_path / "out.glb"
    report = metarig.export_gltf(str(out))
    # The imported mesh node goes back on the glTF node it came from (tag gltf.node).
    assert report["nodes"] == len(metarig.hierarchy()) - 1 and not report["baked"]
    assert_valid_gltf(out)
    back = rigel.open(str(out))
    assert close(translation(back.world_matrix("hand.L")), translation(metarig.world_matrix("hand.L")), 1e-6)
    baked = metarig.export_gltf(str(tmp_path / "baked.gltf"), frames=(0, 2))
    assert baked["baked"] and baked["last_frame"] == 2
    assert_valid_gltf(tmp_path / "baked.gltf")


def test_file_errors_name_the_file(tmp_path):
    with pytest.raises(rigel.Error, match="missing.rigel"):
        rigel.Scene.load(str(tmp_path / "missing.rigel"))
    with pytest.raises(rigel.ParseError, match=r"malformed_truncated\.rigel:\d+:\d+"):
        rigel.Scene.load(str(DATA / "scenes" / "malformed_truncated.rigel"))
    with pytest.raises(rigel.Error, match="unknown_type"):
        rigel.Scene.load(str(DATA / "scenes" / "malformed_unknown_type.rigel"))
    bad = tmp_path / "bad.glb"
    bad.write_bytes(b"glTF not really")
    with pytest.raises(rigel.Error, match="bad.glb"):
        rigel.open(str(bad))
    with pytest.raises(rigel.Error, match="nope.bvh"):
        rigel.Scene.import_bvh(str(tmp_path / "nope.bvh"))
    with pytest.raises(rigel.Error, match="extension|obj"):
        rigel.Scene().export_gltf(str(tmp_path / "x.obj"))
    with pytest.raises(rigel.Error):
        rigel.Scene().save(str(tmp_path / "no" / "such" / "dir" / "x.rigel"))

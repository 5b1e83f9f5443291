"""Scene and Node: nodes, attributes of every value kind, connections,
evaluation, time, undo/redo, hierarchy."""

import math

import pytest

import rigel
from conftest import close, translation


# ---- nodes -------------------------------------------------------------------------


def test_create_find_list_and_identity(scene):
    a = scene.create_node("joint", "hip")
    b = scene.create_node("joint", "hip")  # a taken name gets a suffix
    assert a.name == "hip" and b.name == "hip1"
    assert a.type == "joint"
    assert len(a.uuid) == 36 and a.uuid != b.uuid
    assert scene.node("hip") == a and scene.node(a.uuid) == a
    assert scene.find("nothing") is None
    assert "hip1" in scene and "nothing" not in scene
    assert len(scene) == 2
    assert scene.nodes() == [a, b]
    scene.create_node("locator", "loc")
    assert [n.name for n in scene.nodes("locator")] == ["loc"]
    assert "ikTwoBone" in scene.node_types() and "ephemeralRig" in scene.node_types()
    assert hash(a) == hash(scene.node("hip"))
    assert "hip" in repr(a)


def test_rename_and_delete(scene):
    n = scene.create_node("transform", "a")
    n.name = "b"
    assert n.name == "b" and scene.find("a") is None
    n.rename("c")
    scene.rename("c", "d")
    assert n.name == "d"
    scene.create_node("transform", "taken")
    with pytest.raises(rigel.AlreadyExistsError, match="taken"):
        n.rename("taken")
    n.delete()
    assert not n.exists
    with pytest.raises(rigel.NotFoundError, match="'d'.*no longer exists"):
        n.get("translate")
    with pytest.raises(rigel.NotFoundError, match="no node named 'zzz'"):
        scene.delete("zzz")


def test_unknown_type_raises_with_the_type(scene):
    with pytest.raises(rigel.Error, match="wing"):
        scene.create_node("wing", "w")


# ---- attributes --------------------------------------------------------------------


def test_scalar_values_of_every_kind(scene):
    j = scene.create_node("joint", "j")
    # double3, by node+attr and by "node.attr"
    j.set("translate", (1, 2, 3))
    assert j.get("translate") == (1.0, 2.0, 3.0)
    scene.set("j.translate", [4.5, 5, 6])
    assert scene.get("j.translate") == (4.5, 5.0, 6.0)
    scene.set("j", "scale", (2, 2, 2))
    assert scene.get("j", "scale") == (2.0, 2.0, 2.0)
    # a component of a double3
    scene.set("j.translateY", 7.0)
    assert scene.get("j.translateY") == 7.0 and j["translate"] == (4.5, 7.0, 6.0)
    # bool
    j["visibility"] = False
    assert j["visibility"] is False
    # enum: index, or name on input
    j["rotateOrder"] = "zxy"
    assert j["rotateOrder"] == 2
    j["rotateOrder"] = 4
    assert j["rotateOrder"] == 4
    # quaternion (x, y, z, w)
    s = math.sqrt(0.5)
    j["rotateQuaternion"] = (0, 0, s, s)
    assert close(j["rotateQuaternion"], (0, 0, s, s))
    # matrix: 16 floats column-major; 4 rows of 4 accepted
    m = list(range(16))
    j["offsetParentMatrix"] = [float(x) for x in m]
    assert j["offsetParentMatrix"] == tuple(float(x) for x in m)
    rows = [[1, 0, 0, 10], [0, 1, 0, 20], [0, 0, 1, 30], [0, 0, 0, 1]]
    j["offsetParentMatrix"] = rows
    assert translation(j["offsetParentMatrix"]) == (10.0, 20.0, 30.0)
    # double, int, string
    t = scene.create_node("twistShare", "t")
    t["count"] = 3
    assert t["count"] == 3 and isinstance(t["count"], int)
    r = scene.create_node("metaRoot", "r")
    r["rigName"] = "hero"
    assert r["rigName"] == "hero"
    f = scene.create_node("fingerCurl", "f")
    f["curl"] = 12.5
    assert f["curl"] == 12.5


def test_array_values_of_every_kind(scene):
    f = scene.create_node("fingerCurl", "f")
    f["fingerCurl"] = [1.0, 2, 3.5]
    assert f["fingerCurl"] == [1.0, 2.0, 3.5]
    f["fingerNames"] = ["index", "middle"]
    assert f["fingerNames"] == ["index", "middle"]
    f["finger"] = [0, 0, 1]
    assert f["finger"] == [0, 0, 1]
    f["bendAxis"] = [(1, 0, 0), (0, 1, 0)]
    assert f["bendAxis"] == [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0)]
    ident = tuple(float(i % 5 == 0) for i in range(16))
    f["restOffsetParentMatrix"] = [ident, ident]
    assert f["restOffsetParentMatrix"] == [ident, ident]
    c = scene.create_node("animCurveQuat", "c")
    c["keyValues"] = [(0, 0, 0, 1), (1, 0, 0, 0)]
    assert c["keyValues"] == [(0.0, 0.0, 0.0, 1.0), (1.0, 0.0, 0.0, 0.0)]
    # one element by "node.attr[i]" or element=
    scene.set("f.fingerCurl[1]", 9.0)
    assert scene.get("f.fingerCurl[1]") == 9.0
    f.set("fingerCurl", 4.0, element=4)  # grows the array with zeros
    assert f.get("fingerCurl") == [1.0, 9.0, 3.5, 0.0, 4.0]
    assert f.get("fingerCurl", element=2) == 3.5
    # a message attribute holds nothing
    assert f["metaParent"] is None


def test_attribute_metadata(scene):
    j = scene.create_node("joint", "j")
    assert "jointOrient" in j.attributes()
    assert "parentMatrix" not in j.attributes(hidden=False)
    info = j.attribute("rotate")
    assert info.type == "double3" and info.angle and info.keyable and info.input and not info.output
    assert j.attribute("rotateOrder").enum_names[:2] == ["xyz", "yzx"]
    assert j.attribute("scale").default == (1.0, 1.0, 1.0)
    assert j.attribute("worldMatrix").output
    assert j.plug("translate") == "j.translate"
    with pytest.raises(rigel.NotFoundError, match="no attribute 'nope'"):
        j.attribute("nope")


def test_bad_values_raise_naming_the_plug(scene):
    j = scene.create_node("joint", "j")
    with pytest.raises(rigel.InvalidArgumentError, match=r"j\.translate: expected 3 numbers"):
        j["translate"] = (1, 2)
    with pytest.raises(ValueError, match=r"j\.visibility: expected a bool"):
        j["visibility"] = 1
    with pytest.raises(rigel.InvalidArgumentError, match="'sideways' is not one of xyz"):
        j["rotateOrder"] = "sideways"
    with pytest.raises(rigel.InvalidArgumentError, match="j.offsetParentMatrix: expected 16 numbers"):
        j["offsetParentMatrix"] = [1, 2, 3]
    with pytest.raises(rigel.InvalidArgumentError, match="expected a number, got str"):
        j["translate"] = ("a", 0, 0)
    with pytest.raises(rigel.NotFoundError, match="nope"):
        scene.get("j.nope")
    with pytest.raises(rigel.InvalidArgumentError):
        j["worldMatrix"] = [0.0] * 16  # an output cannot be set


# ---- connections and evaluation -----------------------------------------------------


def test_connect_evaluate_disconnect(scene):
    a = scene.create_node("transform", "a")
    b = scene.create_node("transform", "b")
    a["translate"] = (1, 2, 3)
    scene.connect("a.translate", "b.translate")
    assert scene.source("b.translate") == "a.translate"
    assert ("a.translate", "b.translate") in scene.connections()
    assert b.inputs() == [("a.translate", "b.translate")]
    assert a.outputs() == [("a.translate", "b.translate")]
    assert b["translate"] == (1.0, 2.0, 3.0)
    a["translate"] = (5, 0, 0)
    scene.evaluate()
    assert translation(scene.world_matrix(b)) == (5.0, 0.0, 0.0)
    with pytest.raises(rigel.InvalidArgumentError):
        b["translate"] = (0, 0, 0)  # connected: not settable
    scene.disconnect("a.translate", "b.translate")
    assert scene.source("b.translate") is None
    assert b["translate"] == (5.0, 0.0, 0.0)  # keeps the pulled value (Maya's rule)
    scene.connect("a.translateX", "b.translateZ")
    scene.disconnect_input("b.translateZ")
    assert scene.connections() == []


def test_connection_errors_name_the_nodes(scene):
    a = scene.create_node("transform", "a")
    b = scene.create_node("transform", "b")
    scene.connect("a.worldMatrix", "b.offsetParentMatrix")
    with pytest.raises(rigel.CycleError, match="a"):
        scene.connect("b.worldMatrix", "a.offsetParentMatrix")
    with pytest.raises(rigel.Error, match="b.translate"):
        scene.connect("a.rotateQuaternion", "b.translate")  # type mismatch
    assert a != b


def test_world_matrix_time_and_frames(scene):
    root = scene.create_node("joint", "root")
    tip = scene.create_node("joint", "tip", parent=root)
    root["translate"] = (1, 0, 0)
    root["rotate"] = (0, 0, 90)  # degrees
    tip["translate"] = (1, 0, 0)
    assert close(translation(tip.world_matrix), (1, 1, 0))
    assert close(translation(scene.local_matrix(tip)), (1, 0, 0))
    scene.fps = 30
    scene.frame = 15
    assert scene.time == 0.5 and scene.frame == 15
    scene.time = 1.0
    assert scene.frame == 30
    with pytest.raises(rigel.Error):
        scene.fps = 0


def test_serial_and_parallel_evaluation_agree(metarig):
    for j in metarig.nodes("joint")[:40]:
        j["translate"] = tuple(v + 0.01 for v in j["translate"])
    metarig.evaluate(parallel=False)
    serial = [n.world_matrix for n in metarig.nodes("joint")]
    metarig.evaluate(parallel=True)
    assert serial == [n.world_matrix for n in metarig.nodes("joint")]


def test_compiled_evaluation_equals_the_interpreted(metarig):
    assert metarig.evaluation == "compiled", "the default"
    metarig.evaluation = "interpreted"
    assert metarig.evaluation == "interpreted"
    joints = metarig.nodes("joint")[:40]
    for i, j in enumerate(joints):
        j["rotate"] = (i * 0.5, -i * 0.25, 3.0)
    metarig.evaluate()
    interpreted = [n.world_matrix for n in metarig.nodes("joint")]
    metarig.evaluation = "compiled"
    assert metarig.evaluation == "compiled"
    for j in joints:
        j["rotate"] = (0.0, 0.0, 0.0)
    metarig.evaluate()
    for i, j in enumerate(joints):
        j["rotate"] = (i * 0.5, -i * 0.25, 3.0)
    joints[0]["rotate"] = (90.0, 0.0, 0.0)
    metarig.evaluate()
    metarig.undo()  # joints[0] back
    metarig.evaluate()
    assert [n.world_matrix for n in metarig.nodes("joint")] == interpreted
    with pytest.raises(rigel.InvalidArgumentError, match="'fast'.*interpreted or compiled"):
        metarig.evaluation = "fast"
    assert metarig.evaluation == "compiled"


# ---- undo ------------------------------------------------------------------------------


def test_undo_redo_and_handles_survive(scene):
    n = scene.create_node("joint", "j")
    n["translate"] = (1, 2, 3)
    assert scene.can_undo
    assert scene.undo() and n["translate"] == (0.0, 0.0, 0.0)
    assert scene.redo() and n["translate"] == (1.0, 2.0, 3.0)
    n.delete()
    assert not n.exists
    assert scene.undo()
    assert n.exists and n["translate"] == (1.0, 2.0, 3.0)  # same UUID, new handle inside
    while scene.undo():
        pass
    assert len(scene) == 0 and not scene.can_undo and scene.can_redo
    scene.redo()
    assert scene.find("j") is not None
    scene.clear_history()
    assert not scene.can_undo and not scene.undo()


def test_transaction_groups_and_rolls_back(scene):
    before = scene.undo_count
    with scene.transaction("two nodes"):
        scene.create_node("joint", "a")
        scene.create_node("joint", "b")
    assert scene.undo_count == before + 1 and scene.undo_label == "two nodes"
    scene.undo()
    assert len(scene) == 0
    with pytest.raises(rigel.AlreadyExistsError):
        with scene.transaction("fails"):
            scene.create_node("joint", "c")
            scene.create_node("joint", "d").rename("c")
    assert scene.find("c") is None and scene.find("d") is None


# ---- hierarchy -----------------------------------------------------------------------------


def test_hierarchy_and_reparent(scene):
    a = scene.create_node("joint", "a")
    b = scene.create_node("joint", "b", parent="a")
    c = scene.create_node("joint", "c")
    assert b.parent == a and a.children == [b] and a.parent is None
    assert scene.roots() == [a, c]
    assert scene.hierarchy() == [a, b, c]
    a["translate"] = (0, 5, 0)
    c["translate"] = (1, 0, 0)
    before = translation(c.world_matrix)
    scene.reparent(c, b)  # keep_world
    assert c.parent == b and close(translation(c.world_matrix), before)
    assert close(c["translate"], (1, -5, 0))
    c.set_parent(None, keep_world=False)
    assert c.parent is None and close(translation(c.world_matrix), (1, -5, 0))
    with pytest.raises(rigel.CycleError):
        scene.reparent(a, b)


def test_selection_and_tags(scene):
    a = scene.create_node("joint", "a")
    scene.selection = [a, "a"]
    assert scene.selection[0] == a
    a.set_tag("side", "L")
    assert a.tags == {"side": "L"}
    a.remove_tag("side")
    assert a.tags == {}


def test_nodes_of_another_scene_are_refused(scene):
    other = rigel.Scene()
    n = other.create_node("joint", "x")
    with pytest.raises(rigel.InvalidArgumentError, match="another scene"):
        scene.world_matrix(n)

"""Errors: every failing rigel call raises a rigel.Error subclass chosen by
its ErrorCode (also a standard exception), with rigel's message naming the
place."""

import pytest

import rigel
from conftest import DATA


def test_exception_hierarchy():
    expected = {
        rigel.InvalidArgumentError: (ValueError, "invalid argument"),
        rigel.NotFoundError: (LookupError, "not found"),
        rigel.AlreadyExistsError: (ValueError, "already exists"),
        rigel.CycleError: (ValueError, "cycle"),
        rigel.ParseError: (ValueError, "parse error"),
        rigel.IoError: (OSError, "i/o error"),
        rigel.UnsupportedError: (NotImplementedError, "unsupported"),
        rigel.DefinitionError: (ValueError, "definition"),
    }
    for cls, (builtin, code) in expected.items():
        assert issubclass(cls, rigel.Error) and issubclass(cls, builtin), cls
        assert cls.code == code
        assert cls.__module__ == "rigel"
    assert issubclass(rigel.Error, Exception)


@pytest.mark.parametrize("call, cls, place", [
    (lambda s: s.get("ghost.translate"), rigel.NotFoundError, "ghost"),
    (lambda s: s.set("j.rotate", "up"), rigel.InvalidArgumentError, "j.rotate"),
    (lambda s: s.connect("j.worldMatrix", "j.offsetParentMatrix"), rigel.CycleError, "j"),
    (lambda s: s.create_node("joint", "bad name"), rigel.InvalidArgumentError, "bad name"),
    (lambda s: rigel.Scene.load(str(DATA / "scenes" / "malformed_wrong_type.rigel")), rigel.Error,
     "malformed_wrong_type.rigel"),
    (lambda s: rigel.Scene.load(str(DATA / "scenes" / "malformed_dangling_connection.rigel")), rigel.Error,
     "malformed_dangling_connection.rigel"),
    (lambda s: rigel.Definition.load(str(DATA / "rig" / "invalid_structure.rig.json")), rigel.DefinitionError,
     "invalid_structure.rig.json:"),
    (lambda s: rigel.Definition.parse("<rig", "xml", "inline.rig.xml"), rigel.DefinitionError, "inline.rig.xml:1"),
    (lambda s: rigel.Definition.parse("{}", "yaml"), rigel.InvalidArgumentError, "syntax 'yaml'"),
    (lambda s: s.resolve("hero:arm_L/fk"), rigel.NotFoundError, "hero"),
    (lambda s: rigel.Session(s).drag_to("j", [1, 2]), rigel.InvalidArgumentError, "drag_to world"),
])
def test_failures_raise_naming_the_place(scene, call, cls, place):
    scene.create_node("joint", "j")
    with pytest.raises(cls) as info:
        call(scene)
    assert place in str(info.value)


def test_a_failure_changes_nothing(scene):
    j = scene.create_node("joint", "j")
    text = scene.to_text()
    count = scene.undo_count
    for bad in [lambda: j.set("translate", (1, "x", 3)), lambda: scene.connect("j.translate", "j.rotateQuaternion"),
                lambda: scene.reparent(j, j)]:
        with pytest.raises(rigel.Error):
            bad()
    assert scene.to_text() == text and scene.undo_count == count


def test_unsupported_scene_version(tmp_path):
    path = tmp_path / "future.rigel"
    path.write_text('{"rigel": "scene", "version": 99, "nodes": [], "connections": []}')
    with pytest.raises(rigel.UnsupportedError, match="future.rigel") as info:
        rigel.Scene.load(str(path))
    assert isinstance(info.value, NotImplementedError)

"""Build graphs from Python (docs/BUILD_GRAPH.md): a graph converted from
the example biped, grown by hand with a function node from a Python plugin
and a variable read by two later nodes, built, stepped, rebuilt and
removed like a definition; plugins that raise or take a taken id refused
with their file named."""

import json

import pytest

import rigel
from conftest import BIPED, METARIG

PLUGIN = '''
import rigel

def scale_shapes(call, component, factor):
    """Scales each control shape of a component."""
    count = 0
    for control in call.controls("component"):
        control["shapePoints"] = [[p * factor for p in point] for point in control["shapePoints"]]
        count += 1
    return count

def register_plugin():
    rigel.register_function(scale_shapes, "studio.scaleShapes",
                            inputs=[("component", "component"), ("factor", "number")],
                            outputs=[("count", "int")], nice_name="Scale control shapes",
                            category="Controls", defaults={"factor": 1.0})
'''


def write(path, text):
    path.write_text(text)
    return path


def grown_graph(tmp_path):
    """The biped's graph, then: factor = 2 in a variable, scaling the left
    arm's and the right arm's control shapes (two readers of one variable)."""
    graph = tmp_path / "biped.build.json"
    made = rigel.convert_definition(str(BIPED), str(graph))
    assert made.nodes == 22 and made.links == 41
    doc = json.loads(graph.read_text())
    g = doc["buildGraph"]
    g["variables"] = [{"name": "factor", "type": "number", "value": 1.0}]
    last = "foot_R"
    g["nodes"] += [
        {"id": "two", "kind": "constant:number", "value": 2.0},
        {"id": "setFactor", "kind": "variable:set", "variable": "factor"},
        {"id": "f1", "kind": "variable:get", "variable": "factor"},
        {"id": "f2", "kind": "variable:get", "variable": "factor"},
        {"id": "scaleL", "kind": "function:studio.scaleShapes"},
        {"id": "scaleR", "kind": "function:studio.scaleShapes"},
    ]
    g["links"] += [
        {"from": f"{last}.then", "to": "setFactor.exec"},
        {"from": "two.value", "to": "setFactor.value"},
        {"from": "setFactor.then", "to": "scaleL.exec"},
        {"from": "scaleL.then", "to": "scaleR.exec"},
        {"from": "arm_L.component", "to": "scaleL.component"},
        {"from": "arm_R.component", "to": "scaleR.component"},
        {"from": "f1.value", "to": "scaleL.factor"},
        {"from": "f2.value", "to": "scaleR.factor"},
    ]
    graph.write_text(json.dumps(doc, indent=2))
    return graph


@pytest.fixture
def plugin(tmp_path):
    folder = tmp_path / "plugins"
    folder.mkdir()
    write(folder / "shapes.py", PLUGIN)
    loaded = rigel.load_plugins(str(folder))
    assert list(loaded.values()) == [["studio.scaleShapes"]]
    yield folder / "shapes.py"
    rigel.unregister_functions(str(folder / "shapes.py"))


def test_a_python_function_node_builds_steps_rebuilds_and_removes_like_a_component(tmp_path, metarig, plugin):
    graph = grown_graph(tmp_path)
    report = rigel.validate_graph(str(graph))
    assert report.valid, report.errors
    assert report.order[-3:] == ["setFactor", "scaleL", "scaleR"]
    entry = [f for f in rigel.build_functions() if f["id"] == "studio.scaleShapes"][0]
    assert entry["origin"] == str(plugin) and entry["category"] == "Controls"

    # The shapes the plain definition makes, to compare with.
    ref_scene = rigel.open(str(METARIG))
    rigel.RigBuild.open(ref_scene, str(BIPED)).build_all()
    before = metarig.to_text()
    b = rigel.RigBuild.open(metarig, str(graph))
    b.build_all()
    for side in ("L", "R"):
        scaled = metarig.resolve(f"hero:arm_{side}/fk[0]")["shapePoints"]
        plain_points = ref_scene.resolve(f"hero:arm_{side}/fk[0]")["shapePoints"]
        assert [list(p) for p in scaled] == [[2.0 * p for p in point] for point in plain_points]
    calls = {c.name: c for c in metarig.rigs()[0].components if c.type == "call"}
    assert set(calls) == {"scaleL", "scaleR"}
    # Stepped back over the calls and forward again: the same shapes, the
    # same nodes (the C++ tests compare whole scenes, uuids aside).
    scaled = metarig.resolve("hero:arm_R/fk[0]")["shapePoints"]
    count = len(metarig.nodes())
    for k in range(len(b) - 1, len(b) - 4, -1):
        b.go_to(k)
        b.build_all()
        assert metarig.resolve("hero:arm_R/fk[0]")["shapePoints"] == scaled
        assert len(metarig.nodes()) == count
    b.remove()
    assert metarig.to_text() == before


def test_plugins_that_raise_or_take_a_taken_id_are_refused_naming_their_file(tmp_path, plugin):
    folder = tmp_path / "more"
    folder.mkdir()
    broken = write(folder / "broken.py", "def register_plugin():\n    raise RuntimeError('no licence')\n")
    with pytest.raises(rigel.PluginError) as e:
        rigel.load_plugin(str(broken))
    assert str(broken) in str(e.value) and "no licence" in str(e.value)
    twice = write(folder / "twice.py", PLUGIN)
    with pytest.raises(rigel.PluginError) as e:
        rigel.load_plugin(str(twice))
    assert str(twice) in str(e.value) and str(plugin) in str(e.value)
    half = write(folder / "half.py", "import rigel\n"
                                     "def register_plugin():\n"
                                     "    rigel.register_function(lambda call: None, 'studio.half')\n"
                                     "    raise ValueError('stopped half way')\n")
    with pytest.raises(rigel.PluginError):
        rigel.load_plugin(str(half))
    assert "studio.half" not in [f["id"] for f in rigel.build_functions()]


def test_a_python_function_that_raises_stops_the_build_naming_the_call(tmp_path, metarig):
    rigel.register_function(lambda call: 1 / 0, "test.divide", outputs=[("x", "number")], origin="test")
    try:
        graph = tmp_path / "g.build.json"
        rigel.convert_definition(str(BIPED), str(graph))
        doc = json.loads(graph.read_text())
        doc["buildGraph"]["nodes"].append({"id": "oops", "kind": "function:test.divide"})
        doc["buildGraph"]["links"].append({"from": "foot_R.then", "to": "oops.exec"})
        graph.write_text(json.dumps(doc))
        b = rigel.RigBuild.open(metarig, str(graph))
        with pytest.raises(rigel.Error) as e:
            b.build_all()
        assert "call 'oops' (test.divide)" in str(e.value) and "ZeroDivisionError" in str(e.value)
        assert b.position == len(b) - 1
    finally:
        rigel.unregister_functions("test")

"""The graph editor's side from Python (docs/PYTHON.md "Build graphs"):
Workspace's graph calls, and rigel.serve, the server in this process, so a
graph with a function node from a Python plugin (loaded from the root's
plugins/ folder) and a variable read by two later nodes builds in the
editor's API as it builds headless: the same controls, shapes and world
matrices."""

import json
import os
import subprocess
import sys
import urllib.error
import urllib.request

import pytest

import rigel
from conftest import METARIG
from test_build_graph import PLUGIN, grown_graph, write


def call(server, method, path, body=None):
    """A request as the page sends it (JSON, same origin)."""
    base = server.url.split("?")[0].rstrip("/")
    data = None if body is None else json.dumps(body).encode()
    req = urllib.request.Request(base + path, data=data, method=method,
                                 headers={"Content-Type": "application/json", "Origin": base})
    try:
        with urllib.request.urlopen(req, timeout=120) as res:
            return res.status, json.loads(res.read())
    except urllib.error.HTTPError as e:
        return e.code, json.loads(e.read())


def controls(scene):
    """Every control of the scene's rig by name: (world matrix, shape points)."""
    out = {}
    for node in scene.nodes():
        if node.type == "control":
            out[node.name] = (list(node.world_matrix), [list(p) for p in node["shapePoints"]])
    return out


@pytest.fixture
def root(tmp_path):
    """A served root: the grown biped graph and a plugins/ folder."""
    os.makedirs(tmp_path / "plugins")
    write(tmp_path / "plugins" / "shapes.py", PLUGIN)
    grown_graph(tmp_path)
    yield tmp_path
    rigel.unregister_functions(str(tmp_path / "plugins" / "shapes.py"))


def test_a_graph_with_a_python_function_builds_the_same_in_the_editor_as_headless(root):
    server = rigel.serve(str(METARIG), root=str(root))
    try:
        # The root's plugin is loaded: its function is in the palette.
        status, palette = call(server, "GET", "/api/graph/palette")
        assert status == 200
        kind = [k for k in palette["kinds"] if k["id"] == "function:studio.scaleShapes"]
        assert kind and kind[0]["category"] == "Controls"
        assert [i["name"] for i in kind[0]["inputs"]] == ["exec", "component", "factor"]

        status, files = call(server, "GET", "/api/graph/files")
        assert files["files"] == ["biped.build.json"]
        status, opened = call(server, "GET", "/api/graph?path=biped.build.json")
        graph = opened["graph"]
        status, checked = call(server, "POST", "/api/graph/validate", {"graph": graph})
        assert checked["ok"], checked["problems"]
        status, built = call(server, "POST", "/api/graph/build", {"graph": graph})
        assert status == 200, built
        assert {"scaleL", "scaleR"} <= set(built["rigIds"].values())
        status, saved = call(server, "POST", "/api/save", {"path": "editor.rigel"})
        assert status == 200, saved
    finally:
        server.stop()
    assert not server.running

    # Headless, through Workspace: the same rig.
    ws = rigel.Workspace(str(METARIG))
    report = ws.check_graph(str(root / "biped.build.json"))
    assert report.ok and report.order[-3:] == ["setFactor", "scaleL", "scaleR"]
    built = ws.build_graph(str(root / "biped.build.json"))
    assert built.rig == "hero" and set(built.rig_ids.values()) >= {"scaleL", "scaleR"}
    headless = controls(ws.scene)
    editor = controls(rigel.open(str(root / "editor.rigel")))
    assert set(headless) == set(editor) and len(headless) > 50
    for name, (matrix, points) in headless.items():
        assert editor[name][1] == points, name
        assert max(abs(a - b) for a, b in zip(editor[name][0], matrix)) < 1e-9, name


def test_workspace_graph_calls_save_list_and_report_problems_on_nodes(root, metarig):
    assert list(rigel.load_root_plugins(str(root)).values()) == [["studio.scaleShapes"]]
    ws = rigel.Workspace(metarig)
    text = (root / "biped.build.json").read_text()
    doc = json.loads(text)
    doc["buildGraph"]["links"].append({"from": "global.component", "to": "spine.name"})
    report = ws.check_graph(json.dumps(doc))
    assert not report.ok
    assert (report.problems[0].node, report.problems[0].socket) == ("spine", "name")
    # A graph being drawn is saved, with its problems; the version stays on
    # the same content and moves on another.
    saved = ws.save_graph(json.dumps(doc), str(root / "wip.build.json"))
    assert saved.version == "1.0" and saved.problems[0].node == "spine"
    assert ws.save_graph(json.dumps(doc), str(root / "wip.build.json")).version == "1.0"
    doc["buildGraph"]["nodes"][1]["position"] = [999.0, 0.0]
    assert ws.save_graph(json.dumps(doc), str(root / "wip.build.json")).version == "1.1"
    with pytest.raises(rigel.InvalidArgumentError):
        ws.build_graph(json.dumps(doc))
    assert metarig.rigs() == []
    with pytest.raises(rigel.InvalidArgumentError):
        ws.save_graph(text, str(root / "out.rig.json"))
    ws.build_graph(str(root / "biped.build.json"))
    # Built through build_graph, as the editor builds: no file is recorded, so it opens converted.
    assert ws.rig_graph("hero").converted
    with pytest.raises(rigel.NotFoundError):
        ws.rig_graph("villain")


def test_python_m_rigel_names_its_commands():
    env = dict(os.environ)
    res = subprocess.run([sys.executable, "-m", "rigel"], capture_output=True, text=True, env=env, timeout=60)
    assert res.returncode == 2 and "serve" in res.stderr and "graph run" in res.stderr

"""Build graphs' lists and for-each nodes from Python (docs/BUILD_GRAPH.md
"For-each"): one arm drawn on the left joints, in the body of a for-each
over ["L", "R"], builds both arms (the right one mirrored), with a Python
function node called once per item; the file keeps the list."""

import json

import pytest

import rigel
from conftest import METARIG
from test_build_graph import PLUGIN, write


def sides_graph(sides=("L", "R"), scale=True):
    """For each side, the arm; then (with `scale`) its control shapes scaled
    by the Python plugin's function, once per item."""
    arm = {"type": "fkChain", "name": "arm", "side": "L", "version": "1.0",
           "guides": [{"joint": j} for j in ("upper_arm.L", "forearm.L", "hand.L")]}
    nodes = [
        {"id": "start", "kind": "start"},
        {"id": "global", "kind": "component:global",
         "component": {"type": "global", "name": "global", "side": "C", "version": "1.0",
                       "guides": [{"name": "main"}]}},
        {"id": "list", "kind": "variable:get", "variable": "sides"},
        {"id": "each", "kind": "forEach:string"},
        {"id": "arm", "kind": "component:fkChain", "component": arm},
    ]
    links = [
        {"from": "start.then", "to": "global.exec"},
        {"from": "global.then", "to": "each.exec"},
        {"from": "list.value", "to": "each.list"},
        {"from": "each.body", "to": "arm.exec"},
        {"from": "each.element", "to": "arm.side"},
        {"from": "global.component", "to": "arm.parent"},
    ]
    if scale:
        nodes.append({"id": "scale", "kind": "function:studio.scaleShapes", "values": {"factor": 2.0}})
        links += [{"from": "arm.then", "to": "scale.exec"}, {"from": "arm.component", "to": "scale.component"}]
    return {"buildGraph": {
        "format": 1,
        "rig": {"name": "sides", "version": "1.0"},
        "variables": [{"name": "sides", "type": "list:string", "value": list(sides)}],
        "nodes": nodes,
        "links": links,
    }}


@pytest.fixture
def plugin(tmp_path):
    path = write(tmp_path / "shapes.py", PLUGIN)
    assert rigel.load_plugin(str(path)) == ["studio.scaleShapes"]
    yield path
    rigel.unregister_functions(str(path))


def fk_controls(scene):
    return {n.name: n for n in scene.nodes() if n.type == "control" and "_arm_" in n.name}


def test_a_for_each_over_sides_builds_both_arms_from_one_node(tmp_path, plugin):
    ws = rigel.Workspace(str(METARIG))
    report = ws.check_graph(json.dumps(sides_graph()))
    assert report.ok, [p.message for p in report.problems]
    assert report.order == ["global", "each", "arm", "scale", "arm", "scale"]
    built = ws.build_graph(json.dumps(sides_graph()))
    assert built.rig == "sides"
    ids = {}
    for rig_id, node in built.rig_ids.items():
        ids.setdefault(node, []).append(rig_id)
    assert len(ids["arm"]) == 2 and len(set(ids["arm"])) == 2 and len(set(ids["scale"])) == 2
    controls = fk_controls(ws.scene)
    left = sorted(n for n in controls if "_arm_L_" in n)
    right = sorted(n for n in controls if "_arm_R_" in n)
    assert len(left) == 3 and [n.replace("_arm_L_", "_arm_R_") for n in left] == right
    # The right arm stands on the right joints: its controls mirror the left's.
    for name in left:
        a = controls[name].world_matrix
        b = controls[name.replace("_arm_L_", "_arm_R_")].world_matrix
        assert abs(a[12] + b[12]) < 1e-6 and abs(a[13] - b[13]) < 1e-6 and abs(a[14] - b[14]) < 1e-6, name

    # The file keeps the list.
    path = tmp_path / "sides.build.json"
    saved = ws.save_graph(json.dumps(sides_graph()), str(path))
    assert saved.problems == []
    assert '"value": ["L", "R"]' in path.read_text()


def test_lists_of_the_wrong_type_are_refused_naming_the_node(plugin):
    ws = rigel.Workspace(str(METARIG))
    doc = sides_graph()
    doc["buildGraph"]["nodes"].append({"id": "numbers", "kind": "constant:list:number", "value": [1, "two"]})
    report = ws.check_graph(json.dumps(doc))
    assert not report.ok and "item 1 is not a number" in report.problems[0].message
    assert report.problems[0].node == "numbers"
    doc = sides_graph(("L", "L"))
    report = ws.check_graph(json.dumps(doc))
    assert not report.ok and any("duplicate component name 'arm' on side L" in p.message for p in report.problems)
    assert report.problems[0].node == "arm"
    with pytest.raises(rigel.InvalidArgumentError):
        ws.build_graph(json.dumps(doc))
    assert ws.scene.rigs() == []


ARM = {"buildGraph": {
    "format": 1, "rig": {"name": "arm", "version": "1.0"},
    "variables": [{"name": "side", "type": "string", "value": "L"},
                  {"name": "parent", "type": "component", "value": None}],
    "nodes": [
        {"id": "start", "kind": "start"},
        {"id": "arm", "kind": "component:fkChain",
         "component": {"type": "fkChain", "name": "arm", "side": "L", "version": "1.0",
                       "guides": [{"joint": j} for j in ("upper_arm.L", "forearm.L", "hand.L")]}},
        {"id": "side", "kind": "variable:get", "variable": "side"},
        {"id": "parent", "kind": "variable:get", "variable": "parent"},
    ],
    "links": [
        {"from": "start.then", "to": "arm.exec"},
        {"from": "side.value", "to": "arm.side"},
        {"from": "parent.value", "to": "arm.parent"},
    ],
}}


def test_a_sub_graph_used_twice_builds_two_arms_and_is_in_the_palette(tmp_path):
    (tmp_path / "lib").mkdir()
    write(tmp_path / "lib" / "arm.build.json", json.dumps(ARM))
    hero = sides_graph(scale=False)
    g = hero["buildGraph"]
    g["nodes"] = [n for n in g["nodes"] if n["id"] != "arm"] + [{"id": "arm", "kind": "graph:lib/arm.build.json"}]
    path = write(tmp_path / "hero.build.json", json.dumps(hero))

    ws = rigel.Workspace(str(METARIG))
    report = ws.check_graph(str(path))
    assert report.ok, [p.message for p in report.problems]
    assert report.order == ["global", "each", "arm", "arm/arm", "arm", "arm/arm"]
    ws.build_graph(str(path))
    controls = fk_controls(ws.scene)
    assert len([n for n in controls if "_arm_L_" in n]) == 3 and len([n for n in controls if "_arm_R_" in n]) == 3

    # The served root's graph files are sub-graph nodes of the palette.
    from test_graph_editor import call
    server = rigel.serve(str(METARIG), root=str(tmp_path))
    try:
        status, palette = call(server, "GET", "/api/graph/palette")
        assert status == 200
        kind = [k for k in palette["kinds"] if k["id"] == "graph:lib/arm.build.json"]
        assert kind and kind[0]["category"] == "Graphs"
        assert [s["name"] for s in kind[0]["inputs"]] == ["exec", "side", "parent"]
        # A graph sent by the editor finds its sub-graphs under the root.
        status, answer = call(server, "POST", "/api/graph/validate", {"graph": hero})
        assert status == 200 and answer["ok"], answer
    finally:
        server.stop()


def test_a_python_function_takes_a_components_controls_joints_and_hooks(tmp_path):
    seen = {}

    def made(call, controls, joints, hooks):
        seen["controls"] = sorted(c.name for c in controls)
        seen["joints"] = [j.name for j in joints]
        return len(hooks)

    rigel.register_function(made, "test.made", origin=str(tmp_path / "made.py"),
                            inputs=[("controls", "list:control"), ("joints", "list:joint"), ("hooks", "list:node")],
                            outputs=[("hooks", "int")])
    try:
        doc = sides_graph(("L",), scale=False)
        g = doc["buildGraph"]
        g["nodes"].append({"id": "made", "kind": "function:test.made"})
        g["links"] += [{"from": "arm.then", "to": "made.exec"}] + [
            {"from": f"arm.{what}", "to": f"made.{what}"} for what in ("controls", "joints", "hooks")]
        ws = rigel.Workspace(str(METARIG))
        ws.build_graph(json.dumps(doc))
        assert seen["joints"] == ["upper_arm.L", "forearm.L", "hand.L"]
        assert seen["controls"] == sorted(fk_controls(ws.scene))
    finally:
        rigel.unregister_functions(str(tmp_path / "made.py"))


WEIGHTS_PLUGIN = '''
import rigel

def measure(call, component):
    """A weight map of the component's controls: any JSON value."""
    return {c.name: 1.0 / (i + 1) for i, c in enumerate(call.controls("component"))}

def total(call, weights):
    return sum(weights.values())

def register_plugin():
    rigel.register_data_type("studio.weights", "#336699", help="a weight per control")
    rigel.register_function(measure, "studio.measure", inputs=[("component", "component")],
                            outputs=[("weights", "studio.weights")])
    rigel.register_function(total, "studio.total", inputs=[("weights", "studio.weights")],
                            outputs=[("total", "number")])
'''


def test_a_plugins_data_type_carries_any_value_between_its_functions(tmp_path):
    path = write(tmp_path / "weights.py", WEIGHTS_PLUGIN)
    assert rigel.load_plugin(str(path)) == ["studio.measure", "studio.total"]
    try:
        types = {t["name"]: t for t in rigel.data_types()}
        assert types["studio.weights"]["origin"] == str(path) and types["number"]["origin"] == ""
        # A second plugin with the type's name is refused, naming its file; nothing of it stays.
        other = write(tmp_path / "other.py", "import rigel\n\ndef register_plugin():\n"
                                             "    rigel.register_data_type('studio.weights', '#000000')\n")
        with pytest.raises(rigel.PluginError) as refused:
            rigel.load_plugin(str(other))
        assert str(other) in str(refused.value) and str(path) in str(refused.value)

        doc = sides_graph(("L",), scale=False)
        g = doc["buildGraph"]
        g["nodes"] += [{"id": "measure", "kind": "function:studio.measure"}, {"id": "total", "kind": "function:studio.total"}]
        g["links"] += [
            {"from": "arm.then", "to": "measure.exec"}, {"from": "measure.then", "to": "total.exec"},
            {"from": "arm.component", "to": "measure.component"}, {"from": "measure.weights", "to": "total.weights"}]
        ws = rigel.Workspace(str(METARIG))
        built = ws.build_graph(json.dumps(doc))
        # In the for-each's body: one call per item, named by its index.
        outputs = json.loads(ws.scene.find_component(built.rig, "total_0")["outputs"])
        assert abs(outputs["total"] - (1 + 1 / 2 + 1 / 3)) < 1e-12
        # A weights output into a number input is refused by type.
        g["links"].append({"from": "measure.weights", "to": "arm.name"})
        report = ws.check_graph(json.dumps(doc))
        assert not report.ok and "a studio.weights output cannot feed a string input" in report.problems[0].message
    finally:
        rigel.unregister_functions(str(path))
    assert "studio.weights" not in {t["name"] for t in rigel.data_types()}


def test_python_m_rigel_graph_runs_a_graph_with_its_folders_plugins(tmp_path):
    """The rigel binary runs the shipped functions only; python3 -m rigel graph
    loads the graph's folder's plugins/ and builds it headless."""
    import subprocess
    import sys
    (tmp_path / "plugins").mkdir()
    write(tmp_path / "plugins" / "shapes.py", PLUGIN)
    graph = write(tmp_path / "sides.build.json", json.dumps(sides_graph()))
    out = tmp_path / "sides.rigel"
    cmd = [sys.executable, "-m", "rigel", "graph"]
    try:
        res = subprocess.run(cmd + ["run", str(graph), "--character", str(METARIG), "-o", str(out), "--json"],
                             capture_output=True, text=True, timeout=120)
        assert res.returncode == 0, res.stderr
        report = json.loads(res.stdout)
        assert report["rig"] == "sides" and sorted(set(report["rigIds"].values())) == ["arm", "global", "scale"]
        scene = rigel.open(str(out))
        assert len([n for n in scene.nodes() if n.type == "control" and "_arm_R_" in n.name]) == 3
        valid = subprocess.run(cmd + ["validate", str(graph), "--json"], capture_output=True, text=True, timeout=120)
        assert valid.returncode == 0 and json.loads(valid.stdout)["valid"], valid.stderr
        # Without the plugin the graph names the function it lacks.
        (tmp_path / "plugins" / "shapes.py").unlink()
        missing = subprocess.run(cmd + ["validate", str(graph)], capture_output=True, text=True, timeout=120)
        assert missing.returncode == 1 and "studio.scaleShapes" in missing.stderr
        usage = subprocess.run(cmd + ["run", str(tmp_path / "x.json"), "--character", str(METARIG), "-o", str(out)],
                               capture_output=True, text=True, timeout=120)
        assert usage.returncode == 2
    finally:
        rigel.unregister_functions(str(tmp_path / "plugins" / "shapes.py"))


def test_pure_functions_name_each_items_component_while_the_graph_compiles(tmp_path):
    def shout(call, text):
        assert call.scene is None  # a pure function runs while the graph compiles
        return text.upper()

    rigel.register_function(shout, "test.shout", inputs=[("text", "string")], outputs=[("text", "string")],
                            origin=str(tmp_path / "shout.py"), pure=True)
    try:
        doc = sides_graph(scale=False)
        g = doc["buildGraph"]
        # name = shout(joinText("arm", intText(index, digits=2), separator="_"))
        g["nodes"] += [
            {"id": "index", "kind": "function:rigel.intText", "values": {"digits": 2}},
            {"id": "join", "kind": "function:rigel.joinText", "values": {"a": "arm", "separator": "_"}},
            {"id": "loud", "kind": "function:test.shout"},
        ]
        g["links"] += [
            {"from": "each.index", "to": "index.value"}, {"from": "index.text", "to": "join.b"},
            {"from": "join.text", "to": "loud.text"}, {"from": "loud.text", "to": "arm.name"},
        ]
        ws = rigel.Workspace(str(METARIG))
        report = ws.check_graph(json.dumps(doc))
        assert report.ok, [p.message for p in report.problems]
        assert report.order == ["global", "each", "arm", "arm"]
        ws.build_graph(json.dumps(doc))
        # Each item's controls carry its name (RIG_NAME_SIDE_fkN).
        names = sorted({n.name.split("_fk")[0] for n in ws.scene.nodes() if n.type == "control" and "_ARM_" in n.name})
        assert names == ["sides_ARM_00_L", "sides_ARM_01_R"]
    finally:
        rigel.unregister_functions(str(tmp_path / "shout.py"))

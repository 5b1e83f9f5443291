"""Node kinds written in Python and lists through function nodes
(docs/BUILD_GRAPH.md "Node kinds from plugins", "Lists"): a plugin's flow
node runs a body once per side and builds both arms; a plugin that raises,
a node kind that goes through an exit it does not have and a taken id are
refused with the file named; Python functions take and give lists, a pure
function's list feeding a for-each."""

import json

import pytest

import rigel
from conftest import METARIG
from test_build_graph import write
from test_graph_loops import fk_controls, sides_graph

FLOWS = '''
import rigel

@rigel.node_kind("studio.perSide", inputs=[("sides", "list:string")], outputs=[("side", "string")],
                 exits=["body", "done"], repeats=["body"], category="Studio")
def per_side(call, sides):
    """Runs its body once per side."""
    for side in sides:
        call.go("body", side=side)
    call.go("done")

def register_plugin():
    pass
'''


def per_side_graph(kind="flow:studio.perSide", sides=("L", "R")):
    """sides_graph's arm, in the body of a flow node instead of a for-each
    (given no sides: the arm in its body, no side linked)."""
    doc = sides_graph(scale=False)
    g = doc["buildGraph"]
    g["variables"] = []
    g["nodes"] = [n for n in g["nodes"] if n["id"] not in ("list", "each")]
    g["nodes"].append({"id": "each", "kind": kind, "values": {"sides": list(sides)}} if sides else
                      {"id": "each", "kind": kind})
    g["links"] = [lk for lk in g["links"] if lk["from"] != "list.value" and (sides or lk["from"] != "each.element")]
    for lk in g["links"]:
        if lk["from"] == "each.element":
            lk["from"] = "each.side"
    return doc


@pytest.fixture
def flows(tmp_path):
    path = write(tmp_path / "flows.py", FLOWS)
    assert rigel.load_plugin(str(path)) == ["studio.perSide"]
    yield path
    rigel.unregister_functions(str(path))


def test_a_python_node_kind_runs_its_body_per_side_and_is_in_the_palette(flows):
    kinds = {k["id"]: k for k in rigel.node_kinds()}
    assert kinds["studio.perSide"]["exits"] == ["body", "done"] and kinds["studio.perSide"]["origin"] == str(flows)
    palette = {k["id"]: k for k in rigel.graph_palette()["kinds"]}
    kind = palette["flow:studio.perSide"]
    assert kind["category"] == "Studio" and [o["type"] for o in kind["outputs"]] == ["exec", "exec", "string"]
    ws = rigel.Workspace(str(METARIG))
    report = ws.check_graph(json.dumps(per_side_graph()))
    assert report.ok, [p.message for p in report.problems]
    assert report.order == ["global", "each", "arm", "arm"]
    built = ws.build_graph(json.dumps(per_side_graph()))
    assert list(built.rig_ids.values()).count("arm") == 2
    controls = fk_controls(ws.scene)
    assert len([n for n in controls if "_arm_L_" in n]) == 3 and len([n for n in controls if "_arm_R_" in n]) == 3


def test_node_kinds_that_raise_stray_or_take_a_taken_id_are_refused_naming_their_file(tmp_path, flows):
    ws = rigel.Workspace(str(METARIG))
    raises = write(tmp_path / "raises.py", "import rigel\n"
                                           "def register_plugin():\n"
                                           "    rigel.register_node_kind(lambda call: 1 / 0, 'studio.broken', exits=['body'])\n")
    rigel.load_plugin(str(raises))
    try:
        doc = per_side_graph("flow:studio.broken", sides=())
        report = ws.check_graph(json.dumps(doc))
        assert not report.ok
        message = " ".join(p.message for p in report.problems)
        assert "node 'each'" in message and str(raises) in message and "ZeroDivisionError" in message, message
    finally:
        rigel.unregister_functions(str(raises))
    stray = write(tmp_path / "stray.py", "import rigel\n"
                                         "def register_plugin():\n"
                                         "    rigel.register_node_kind(lambda call: 'elsewhere', 'studio.stray', exits=['body'])\n")
    rigel.load_plugin(str(stray))
    try:
        doc = per_side_graph("flow:studio.stray", sides=())
        message = " ".join(p.message for p in ws.check_graph(json.dumps(doc)).problems)
        assert "'elsewhere', which is not one of its exits" in message, message
    finally:
        rigel.unregister_functions(str(stray))
    again = write(tmp_path / "again.py", "import rigel\n"
                                         "def register_plugin():\n"
                                         "    rigel.register_node_kind(lambda call: None, 'studio.perSide')\n")
    with pytest.raises(rigel.PluginError) as e:
        rigel.load_plugin(str(again))
    assert str(again) in str(e.value) and str(flows) in str(e.value)
    assert "studio.perSide" in {k["id"] for k in rigel.node_kinds()}, "the first plugin's kind stays"
    # A graph naming a kind no plugin registered is refused at the node.
    message = " ".join(p.message for p in ws.check_graph(json.dumps(per_side_graph("flow:studio.none"))).problems)
    assert "unknown node kind 'flow:studio.none'" in message


def test_python_functions_take_and_give_lists(tmp_path):
    seen = []

    def letters(call, text):
        return list(text)

    def total(call, xs):
        seen.append(xs)
        return {"sum": sum(xs), "doubled": [2 * x for x in xs]}

    origin = str(tmp_path / "lists.py")
    rigel.register_function(letters, "test.letters", inputs=[("text", "string")], outputs=[("items", "list:string")],
                            origin=origin, pure=True)
    rigel.register_function(total, "test.total", inputs=[("xs", "list:number")],
                            outputs=[("sum", "number"), ("doubled", "list:number")], origin=origin)
    try:
        doc = sides_graph(scale=False)
        g = doc["buildGraph"]
        g["variables"] = []
        g["nodes"] = [n for n in g["nodes"] if n["id"] != "list"]
        g["nodes"] += [
            {"id": "letters", "kind": "function:test.letters", "values": {"text": "LR"}},
            {"id": "t1", "kind": "function:test.total", "values": {"xs": [1, 2.5]}},
            {"id": "t2", "kind": "function:test.total"},
        ]
        g["links"] = [lk for lk in g["links"] if lk["from"] != "list.value"]
        g["links"] += [
            {"from": "letters.items", "to": "each.list"},
            {"from": "each.completed", "to": "t1.exec"},
            {"from": "t1.then", "to": "t2.exec"},
            {"from": "t1.doubled", "to": "t2.xs"},
        ]
        ws = rigel.Workspace(str(METARIG))
        report = ws.check_graph(json.dumps(doc))
        assert report.ok, [p.message for p in report.problems]
        assert report.order == ["global", "each", "arm", "arm", "t1", "t2"]
        ws.build_graph(json.dumps(doc))
        assert seen == [[1.0, 2.5], [2.0, 5.0]]
        assert len([n for n in fk_controls(ws.scene) if "_arm_R_" in n]) == 3
    finally:
        rigel.unregister_functions(origin)


def test_rigel_buildgraph_is_the_plugin_api_in_one_place(tmp_path):
    from rigel import buildgraph

    @buildgraph.node_kind("test.twice", outputs=[("index", "int")], exits=["body"], repeats=["body"])
    def twice(call):
        call.go("body", index=0)
        call.go("body", index=1)

    @buildgraph.function("test.half", inputs=[("x", "number")], outputs=[("y", "number")], pure=True)
    def half(call, x):
        return x / 2

    try:
        assert {"test.twice"} <= {k["id"] for k in buildgraph.node_kinds()}
        assert {"test.half"} <= {f["id"] for f in buildgraph.build_functions()}
        kinds = {k["id"] for k in buildgraph.palette()["kinds"]}
        assert {"flow:test.twice", "function:test.half", "flow:rigel.repeat", "function:rigel.range"} <= kinds
    finally:
        buildgraph.unregister("")
    assert "test.twice" not in {k["id"] for k in buildgraph.node_kinds()}
    assert "test.half" not in {f["id"] for f in buildgraph.build_functions()}

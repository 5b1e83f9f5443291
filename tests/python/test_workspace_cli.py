"""rigel.Workspace and the `rigel` CLI give the same answer for the same
input: one table, each row an operation done through the CLI on a file and
through a Workspace opened on the same file, requiring the same scene (its
.rigel text), the same definition files and, where the CLI prints one, the
same report; and a table of refusals, requiring both to refuse alike."""

import json
import pathlib
import re
import subprocess

import pytest

import rigel
from conftest import arm_definition, close


@pytest.fixture
def files(tmp_path, metarig):
    """Scene files: the metarig with an ephemeral rig (also keyed at frame
    0), and the metarig with the arm rig built from a definition file."""
    rigel.setup_ephemeral(metarig)
    metarig.save(str(tmp_path / "ephemeral.rigel"))
    rigel.set_key(metarig, ["hand.L_ctrl"])
    metarig.save(str(tmp_path / "keyed.rigel"))
    built = rigel.Scene.load(str(tmp_path / "ephemeral.rigel"))
    definition = tmp_path / "arm.rig.xml"
    arm_definition().save(str(definition))
    rigel.Workspace(built).add_rig(str(definition))
    built.save(str(tmp_path / "built.rigel"))
    editing = rigel.Scene.load(str(tmp_path / "ephemeral.rigel"))
    rigel.Workspace(editing).add_rig(str(definition), edit_mode=True)
    editing.save(str(tmp_path / "editing.rigel"))
    return tmp_path


def same_scene_text(scene):
    """The scene's .rigel text with the UUIDs of nodes made by the operation
    (fresh ones: a new key's curves, rebuilt components) numbered in order
    of appearance."""
    numbers = {}
    return re.sub(r"[0-9a-f]{8}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{4}-[0-9a-f]{12}",
                  lambda m: "uuid-%d" % numbers.setdefault(m.group(0), len(numbers)), scene.to_text())


def ik_control(ws):
    return ws.scene.resolve("arm_rig:arm_L/ik[0]").name


def pose_inverse(ws):
    ws.mode = "inverse"
    ws.select(["hand.L_ctrl"])
    r = ws.drag(translate=(0, 0.05, -0.02))
    ws.release()
    return r


def pose_euler(ws):
    ws.select(["forearm.L_ctrl"])
    r = ws.drag(euler=(0, 0, 30))
    ws.release()
    return r


def pose_magnet_keyed(ws):
    ws.set_frame(5)
    ws.mode = "magnet"
    ws.set_options(magnet_fraction=0.5, auto_key=True)
    ws.select(["hand.L_ctrl", "hand.R_ctrl"])
    r = ws.drag(translate=(0.02, 0, 0))
    ws.release()
    ws.set_key(r.dragged)
    return r


def pose_built(ws):
    ws.select([ik_control(ws)])
    r = ws.drag(translate=(0, 0.03, 0))
    ws.release()
    return r


def key(ws):
    ws.set_frame(5)
    return ws.set_key(["hand.L"])


def delete_key(ws):
    ws.set_frame(0)
    return ws.delete_key(["hand.L_ctrl"])


def remove(ws):
    ws.remove_rig("arm_rig")


def update(ws):
    return ws.update_rig("arm_rig", force=True)


def edit(ws):
    ws.scene.resolve("arm_rig:arm_L/fk[1]")["translate"] = (0, 0.02, 0)
    return ws.commit_edits("arm_rig", definition_out=str(pathlib.Path(ws.scene_path).parent / "moved.rig.xml"))


CASES = [
    # (name, scene file, CLI arguments (IN, OUT replaced), Workspace operation, report kind)
    ("pose inverse", "ephemeral.rigel",
     ["pose", "IN", "-o", "OUT", "--control", "hand.L_ctrl", "--mode", "inverse", "--translate", "0,0.05,-0.02", "--json"],
     pose_inverse, "pose"),
    ("pose euler", "ephemeral.rigel",
     ["pose", "IN", "-o", "OUT", "--control", "forearm.L_ctrl", "--mode", "forward", "--rotate", "0,0,30", "--json"],
     pose_euler, "pose"),
    ("pose magnet, key", "keyed.rigel",
     ["pose", "IN", "-o", "OUT", "--control", "hand.L_ctrl", "--select", "hand.R_ctrl", "--mode", "magnet",
      "--magnet-fraction", "0.5", "--translate", "0.02,0,0", "--frame", "5", "--auto-key", "--key", "--json"],
     pose_magnet_keyed, "pose"),
    ("pose a built rig", "built.rigel",
     ["pose", "IN", "-o", "OUT", "--control", "IK", "--mode", "forward", "--translate", "0,0.03,0", "--json"],
     pose_built, "pose"),
    ("ephemeral key", "ephemeral.rigel",
     ["ephemeral", "key", "IN", "-o", "OUT", "--control", "hand.L", "--frame", "5", "--json"], key, "key"),
    ("ephemeral key --delete", "keyed.rigel",
     ["ephemeral", "key", "IN", "-o", "OUT", "--control", "hand.L_ctrl", "--frame", "0", "--delete", "--json"],
     delete_key, "key"),
    ("remove", "built.rigel", ["remove", "IN", "--rig", "arm_rig", "-o", "OUT"], remove, None),
    ("update --force", "built.rigel", ["update", "IN", "--rig", "arm_rig", "--force", "-o", "OUT"], update, None),
    ("edit", "editing.rigel",
     ["edit", "IN", "--rig", "arm_rig", "--move", "arm_rig:arm_L/fk[1]=0,0.02,0", "--definition-out", "MOVED", "-o", "OUT"],
     edit, None),
]


@pytest.mark.parametrize("name, source, args, operation, report", CASES, ids=[c[0] for c in CASES])
def test_cli_and_workspace_agree(files, rigel_cli, name, source, args, operation, report):
    ws = rigel.Workspace(str(files / source))
    out = files / "cli_out.rigel"
    substitutions = {"IN": str(files / source), "OUT": str(out), "MOVED": str(files / "moved.rig.xml"),
                     "IK": ik_control(ws) if "built" in source else "IK"}
    run = subprocess.run([str(rigel_cli)] + [substitutions.get(a, a) for a in args], capture_output=True, text=True)
    assert run.returncode == 0, f"{name}: {run.stderr}"
    definitions = {p.name: p.read_text() for p in files.glob("*.rig.xml")}
    answer = operation(ws)
    assert same_scene_text(ws.scene) == same_scene_text(rigel.Scene.load(str(out))), name
    assert {p.name: p.read_text() for p in files.glob("*.rig.xml")} == definitions, name  # the same definitions written
    if report == "pose":
        printed = json.loads(run.stdout)
        assert printed["grabbed"] == [n.name for n in answer.dragged]
        assert printed["notes"] == answer.notes
        moved = {m.node.name: m for m in answer.moved_controls}
        assert sorted(printed["moved"]) == sorted(moved) and moved
        for control, value in printed["moved"].items():
            assert close(value["t"], moved[control].translate, 1e-12), control
            assert close(value["q"], moved[control].rotate, 1e-12), control
    elif report == "key":
        printed = json.loads(run.stdout)
        assert printed["keyed"] == [n.name for n in answer.set]
        assert printed["times"] == answer.frames and printed["frame"] == ws.frame


def pose_off_keys(ws):
    ws.set_frame(5)
    ws.select(["hand.L_ctrl"])
    ws.drag(translate=(0, 0.01, 0))


REFUSALS = [
    # (name, scene file, CLI arguments, Workspace operation, exception class, the CLI prints app's message)
    ("a keyed control off its keys", "keyed.rigel",
     ["pose", "IN", "-o", "OUT", "--control", "hand.L_ctrl", "--mode", "forward", "--translate", "0,0.01,0", "--frame", "5"],
     pose_off_keys, rigel.StateError, True),
    ("remove: no such rig", "built.rigel", ["remove", "IN", "--rig", "ghost", "-o", "OUT"],
     lambda ws: ws.remove_rig("ghost"), rigel.NotFoundError, True),
    # `rigel update` looks the rig up itself ("no rig 'ghost'").
    ("update: no such rig", "built.rigel", ["update", "IN", "--rig", "ghost", "-o", "OUT"],
     lambda ws: ws.update_rig("ghost"), rigel.NotFoundError, False),
]


@pytest.mark.parametrize("name, source, args, operation, error, same_message", REFUSALS, ids=[c[0] for c in REFUSALS])
def test_cli_and_workspace_refuse_alike(files, rigel_cli, name, source, args, operation, error, same_message):
    ws = rigel.Workspace(str(files / source))
    undo_count = ws.scene.undo_count
    out = files / "cli_out.rigel"
    substitutions = {"IN": str(files / source), "OUT": str(out)}
    run = subprocess.run([str(rigel_cli)] + [substitutions.get(a, a) for a in args], capture_output=True, text=True)
    with pytest.raises(error) as info:
        operation(ws)
    assert run.returncode != 0 and not out.exists(), name
    if same_message:
        assert str(info.value) in run.stderr, (name, run.stderr)
    assert "ghost" in run.stderr or "auto-key" in run.stderr
    assert ws.scene.undo_count == undo_count  # the refusal changed nothing

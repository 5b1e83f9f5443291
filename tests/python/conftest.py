"""Shared fixtures of the Python module's tests (run by CTest as `python`:
/usr/bin/python3 -m pytest tests/python with PYTHONPATH at the built
package, build/<dir>/apps/python)."""

import math
import os
import pathlib
import shutil
import subprocess

import pytest

import rigel

REPO = pathlib.Path(__file__).resolve().parents[2]
DATA = REPO / "tests" / "data"
METARIG = DATA / "gltf" / "rigify_human_metarig.glb"
BIPED = REPO / "examples" / "biped.rig.xml"


def gltf_validator_errors(path):
    """What the Khronos glTF-Validator (tools/validate-gltf.mjs, the npm
    package gltf-validator in web/) finds wrong in `path`: "" when nothing,
    None when the validator is not installed (node or the package missing)."""
    node = shutil.which("node")
    if node is None:
        return None
    run = subprocess.run([node, str(REPO / "tools" / "validate-gltf.mjs"), str(path)],
                         capture_output=True, text=True)
    if run.returncode == 3:
        return None
    return "" if run.returncode == 0 else (run.stdout + run.stderr or f"exit {run.returncode}")


def assert_valid_gltf(path):
    errors = gltf_validator_errors(path)
    assert errors in (None, ""), f"the Khronos glTF-Validator finds errors in {path}:\n{errors}"


@pytest.fixture
def rigel_cli():
    """The `rigel` command-line binary (CTest passes it as RIGEL_CLI; else the
    release build's)."""
    path = pathlib.Path(os.environ.get("RIGEL_CLI", REPO / "build" / "release" / "apps" / "cli" / "rigel"))
    if not path.is_file():
        pytest.skip(f"the rigel binary is not built ({path})")
    return path


@pytest.fixture
def scene():
    return rigel.Scene()


@pytest.fixture
def metarig():
    """Rigify's human metarig (159 joints), imported fresh for each test."""
    return rigel.open(str(METARIG))


def translation(matrix):
    """The translation of a column-major 4x4 matrix (16 floats)."""
    return tuple(matrix[12:15])


def close(a, b, tol=1e-9):
    if isinstance(a, (int, float)):
        return abs(a - b) <= tol
    return len(a) == len(b) and all(close(x, y, tol) for x, y in zip(a, b))


def distance(a, b):
    return math.sqrt(sum((x - y) ** 2 for x, y in zip(a, b)))


def arm_definition(name="arm_rig"):
    """A small valid definition: global + a left arm limb on the metarig."""
    d = rigel.Definition(name)
    root = d.add_component("global", "global", guides=[rigel.Guide("main")])
    root.add_component("limb", "arm", "L",
                       guides=[rigel.Guide("upper", joint="upper_arm.L"), rigel.Guide("lower", joint="forearm.L"),
                               rigel.Guide("end", joint="hand.L")],
                       params={"kind": "arm", "defaultMode": "fk", "maxStretch": 1.25})
    return d

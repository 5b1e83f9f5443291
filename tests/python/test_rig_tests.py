"""Rig regression tests from Python (docs/RIG.md "Regression poses"):
the biped recorded and checked as `rigel check` does; a changed parameter
fails naming the poses and joints; bad input raises naming the file."""

import pytest

import rigel
from conftest import BIPED


def test_the_biped_is_recorded_and_holds_its_poses(tmp_path):
    out = tmp_path / "biped.rigtest.json"
    recorded = rigel.record_rig_tests(str(BIPED), str(out))
    assert recorded.rig == "hero" and recorded.output == str(out) and recorded.joints > 100
    names = [p.name for p in recorded.poses]
    assert names[0] == "rest" and names[-1] == "all" and "arm_L" in names and "eyes" in names
    checked = rigel.check_rig(str(BIPED), str(out))
    assert checked.ok and checked.poses == len(names) and checked.max_error < 1e-9
    # The shipped file beside the definition is the default.
    assert rigel.check_rig(str(BIPED)).ok


def test_a_changed_parameter_fails_naming_poses_and_joints(tmp_path):
    changed = tmp_path / "changed.rig.xml"
    changed.write_text(BIPED.read_text().replace('<param name="aimDistance" value="0.4"/>',
                                                 '<param name="aimDistance" value="0.6"/>'))
    tests = BIPED.parent / "biped.rigtest.json"
    report = rigel.check_rig(str(changed), str(tests))
    assert not report.ok
    assert {m.joint for m in report.mismatches} == {"eye.L", "eye.R"}
    assert {"eyes", "all"} <= {m.pose for m in report.mismatches}
    assert all(m.error > 1e-6 for m in report.mismatches)
    assert rigel.check_rig(str(changed), str(tests), tolerance=1.0).ok


def test_bad_input_raises_naming_the_file(tmp_path):
    with pytest.raises(rigel.Error, match="no such rig tests file"):
        rigel.check_rig(str(BIPED), str(tmp_path / "none.rigtest.json"))
    bad = tmp_path / "bad.rigtest.json"
    bad.write_text('{"format": "rigel rig tests", "version": 1, "rig": "hero", "character": "", "base": {"x": [1]}}')
    with pytest.raises(rigel.Error, match="bad.rigtest.json: base.x: expected 16 numbers"):
        rigel.check_rig(str(BIPED), str(bad))
    with pytest.raises(rigel.Error, match="tolerance"):
        rigel.check_rig(str(BIPED), tolerance=-1)

#!/usr/bin/env python3
"""Every kind of file `rigel export` writes passes the Khronos glTF-Validator.

Imports each bundled character (tests/data/gltf), builds the biped from
examples/biped.rig.xml and imports a BVH, exports each scene direct and with
--bake, as .glb and as .gltf, adds the skeleton `rigel import-guides` writes
for mGear's biped template, and validates all of them in one run of
tools/validate-gltf.mjs. Exit 0 when every file passes, 1 when a command
fails or a file has an error (each named), 77 when node or the validator
package is missing (ctest reports the test as skipped).
"""
import argparse
import pathlib
import subprocess
import sys
import tempfile


def run(command):
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"FAILED (exit {done.returncode}): {' '.join(map(str, command))}\n{done.stdout}{done.stderr}")


def main():
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--rigel", required=True, help="the rigel binary")
    parser.add_argument("--source", required=True, help="the repository root")
    args = parser.parse_args()
    root = pathlib.Path(args.source)
    validator = root / "tools" / "validate-gltf.mjs"
    try:
        probe = subprocess.run(["node", str(validator), str(root / "tests/data/gltf/RiggedSimple.glb")],
                               capture_output=True, text=True)
    except FileNotFoundError:
        probe = None
    if probe is None or probe.returncode in (3, 127):
        print("skipped: the Khronos glTF-Validator is not installed (node and `npm ci` in web/ provide it)")
        return 77

    with tempfile.TemporaryDirectory(prefix="rigel_validator_sweep_") as tmp:
        tmp = pathlib.Path(tmp)
        scenes = []
        for source in sorted((root / "tests/data/gltf").iterdir()):
            if source.suffix not in (".glb", ".gltf"):
                continue
            scene = tmp / (source.stem + ".rigel")
            run([args.rigel, "import", source, "-o", scene])
            scenes.append((source.stem, scene))
        if len(scenes) < 8:
            sys.exit(f"FAILED: expected every bundled character (8 or more), found {len(scenes)}")
        run([args.rigel, "build", root / "examples/biped.rig.xml", "-o", tmp / "hero.rigel"])
        scenes.append(("biped", tmp / "hero.rigel"))
        run([args.rigel, "import", root / "tests/data/bvh/cmu_131_01.bvh", "-o", tmp / "walk.rigel"])
        scenes.append(("bvh", tmp / "walk.rigel"))

        outputs = []
        for name, scene in scenes:
            for bake in (False, True):
                for ext in (".glb", ".gltf"):
                    out = tmp / f"{name}{'_baked' if bake else ''}{ext}"
                    run([args.rigel, "export", scene, "-o", out] + (["--bake"] if bake else []))
                    outputs.append(out)
        # The skeleton `rigel import-guides` writes (joints in a skin no mesh uses).
        run([args.rigel, "import-guides", root / "tests/data/mgear/biped.sgt", "-o", tmp / "guides.rig.xml",
             "--skeleton", tmp / "guides.glb"])
        outputs.append(tmp / "guides.glb")
        checked = subprocess.run(["node", str(validator)] + [str(o) for o in outputs], capture_output=True, text=True)
        if checked.returncode != 0:
            print(checked.stdout + checked.stderr)
            print(f"FAILED: the validator finds errors (exit {checked.returncode})")
            return 1
        print(f"{len(outputs)} exports of {len(scenes)} scenes pass the Khronos glTF-Validator")
        return 0


if __name__ == "__main__":
    sys.exit(main())

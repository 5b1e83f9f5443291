#!/usr/bin/env python3
"""A PyBuild build script (seed 004 §4.9): a biped on Rigify's human metarig
(tests/data/gltf, CC0), made in Python with rigel's definition and build
machinery.

    PYTHONPATH=build/release/apps/python python3 examples/pybuild_biped.py -o hero.rigel \\
        [--definition-output hero.rig.xml]

run() adds the components (the same types and guides as examples/biped.rig.xml,
fewer of them); the base class checks the definition, builds it on the
character, calls post() and saves. With --definition-output the definition
is saved too, so `rigel rigs`, `rigel update` and `rigel remove` work on the
result as on any built rig.
"""

import argparse
import os
import sys

import rigel

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
METARIG = os.path.join(REPO, "tests", "data", "gltf", "rigify_human_metarig.glb")

FINGERS = ("thumb", "index", "middle", "ring", "pinky")


def finger_guides(side):
    """The hand's guides: the hand joint, then FINGER.N for each finger joint."""
    guides = [rigel.Guide("hand", joint=f"hand.{side}")]
    for finger in FINGERS:
        for n in range(3):
            joint = f"thumb.0{n + 1}.{side}" if finger == "thumb" else f"f_{finger}.0{n + 1}.{side}"
            guides.append(rigel.Guide(f"{finger}.{n}", joint=joint))
    return guides


class BipedBuild(rigel.Build):
    character_file = METARIG
    rig_name = "hero"

    def run(self):
        # self.character is the rig's `global` component (made by PyBuild).
        self.character.set_control("main", "fourArrowCircle", "yellow", 0.8)
        hip = self.add("hip", "hip", guides=[rigel.Guide("hip", joint="spine")],
                       controls=[{"role": "main", "shape": "circle", "color": "orange", "size": 0.35}])
        spine = self.add("spine", "spine", parent=hip, guides=["spine.001", "spine.002", "spine.003"],
                         params={"kinematicType": "splineIK"})
        neck = self.add("neck", "neck", parent=spine, attach="END", guides=["spine.004", "spine.005", "spine.006"])
        self.add("eye", "eyes", parent=neck, attach="END", guides=["eye.L", "eye.R"], params={"aimDistance": 0.4})
        for side, color, sign in (("L", "blue", 1.0), ("R", "red", -1.0)):
            clavicle = self.add("fkChain", "clavicle", side, parent=spine, attach="END", guides=[f"shoulder.{side}"],
                                controls=[{"role": "fk", "shape": "circle", "color": color, "size": 0.1}])
            arm = self.add("limb", "arm", side, parent=clavicle,
                           guides=[rigel.Guide("upper", joint=f"upper_arm.{side}"),
                                   rigel.Guide("lower", joint=f"forearm.{side}"),
                                   rigel.Guide("end", joint=f"hand.{side}")],
                           params={"kind": "arm", "defaultMode": "fk"},
                           controls=[{"role": "fk", "shape": "circle", "color": color, "size": 0.1},
                                     {"role": "ik", "shape": "cube", "color": color, "size": 0.08}])
            self.add("hand", "hand", side, parent=arm, attach="end", guides=finger_guides(side),
                     controls=[{"role": "finger", "shape": "circle", "color": color, "size": 0.02}])
            leg = self.add("limb", "leg", side, parent=hip,
                           guides=[rigel.Guide("upper", joint=f"thigh.{side}"),
                                   rigel.Guide("lower", joint=f"shin.{side}"),
                                   rigel.Guide("end", joint=f"foot.{side}")],
                           params={"kind": "leg", "defaultMode": "ik"})
            self.add("foot", "foot", side, parent=leg, attach="end",
                     guides=[rigel.Guide("ankle", joint=f"foot.{side}"),
                             rigel.Guide("ball", joint=f"toe.{side}"),
                             rigel.Guide("toe", translate=(sign * 0.098, 0, 0.17)),
                             rigel.Guide("heel", joint=f"heel.02.{side}"),
                             rigel.Guide("inner", translate=(sign * 0.05, 0, 0.05)),
                             rigel.Guide("outer", translate=(sign * 0.145, 0, 0.05))],
                     params={"rollBreak": 30.0})

    def post(self):
        # After the build: a starting pose through the rig's own controls,
        # found by address (names play no part).
        self.node("hand_L/fingerCurl")["curl"] = 20.0
        self.node("foot_L/reverseFoot")["roll"] = 10.0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--output", required=True, help="scene file to write (.rigel)")
    parser.add_argument("--definition-output", help="also save the definition (.rig.xml / .rig.json)")
    parser.add_argument("--character", default=METARIG, help="character to build on (default: the Rigify metarig)")
    args = parser.parse_args(argv)
    build = BipedBuild(args.character, output=args.output, definition_output=args.definition_output)
    print(f"built {build.rig_name}: {len(build.definition.all_components())} components, "
          f"{build.build.position} steps, into {args.output}", file=sys.stderr)
    return build


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Writes quadruped.rigel: a horse-sized quadruped skeleton (metres, y up,
facing +z, joints in world orientation) and the cart it pulls, the character
examples/quadruped.rig.xml is built on.

    python3 make_quadruped.py > quadruped.rigel

The skeleton: hips; a spine of three joints to the chest; neck, neck.001 and
head; jaw and lips, eyes and lids (at the eyes: their pivot), brows, ears; a tail of four joints; two hind legs (femur,
tibia, metatarsus, hoof: three segments with the hock between tibia and
metatarsus) and two front legs (scapula, then humerus, radius, metacarpus,
fhoof; an elbowFix corrective joint beside the elbow). The cart: cart_root
on the ground, an axle with two wheels, two shock absorbers (a cylinder on
the axle, a rod on the cart body) and a sign on the cart: a quad mesh with
a blendShape of two targets (lift, tilt).
"""
import json
import sys
import uuid

NAMESPACE = uuid.UUID("0b7a4f1e-52d3-4c8a-9e61-3f2d8c5a7b90")

# name: (parent, world position)
CENTRE = {
    "hips": (None, (0.0, 1.30, -0.55)),
    "spine": ("hips", (0.0, 1.33, -0.25)),
    "spine.001": ("spine", (0.0, 1.35, 0.05)),
    "chest": ("spine.001", (0.0, 1.36, 0.35)),
    "neck": ("chest", (0.0, 1.45, 0.60)),
    "neck.001": ("neck", (0.0, 1.65, 0.85)),
    "head": ("neck.001", (0.0, 1.85, 1.00)),
    "jaw": ("head", (0.0, 1.78, 1.05)),
    "lip.T": ("head", (0.0, 1.70, 1.45)),
    "lip.B": ("jaw", (0.0, 1.62, 1.40)),
    "tail": ("hips", (0.0, 1.35, -0.80)),
    "tail.001": ("tail", (0.0, 1.20, -0.95)),
    "tail.002": ("tail.001", (0.0, 1.00, -1.02)),
    "tail.003": ("tail.002", (0.0, 0.80, -1.04)),
    "cart_root": (None, (0.0, 0.0, -2.40)),
    "axle": ("cart_root", (0.0, 0.55, -2.40)),
    "cart": ("cart_root", (0.0, 1.00, -2.40)),
}
# Left side (x > 0); the right side mirrors it.
LEFT = {
    "lip.L": ("head", (0.07, 1.66, 1.36)),
    "eye.L": ("head", (0.11, 1.92, 1.15)),
    "lid.T.L": ("head", (0.11, 1.92, 1.15)),
    "lid.B.L": ("head", (0.11, 1.92, 1.15)),
    "brow.L": ("head", (0.06, 1.99, 1.16)),
    "brow.L.001": ("brow.L", (0.12, 1.99, 1.13)),
    "ear.L": ("head", (0.07, 2.00, 1.02)),
    "ear.L.001": ("ear.L", (0.07, 2.18, 1.02)),
    "femur.L": ("hips", (0.18, 1.20, -0.60)),
    "tibia.L": ("femur.L", (0.19, 0.80, -0.42)),
    "metatarsus.L": ("tibia.L", (0.19, 0.50, -0.75)),
    "hoof.L": ("metatarsus.L", (0.19, 0.08, -0.70)),
    "scapula.L": ("chest", (0.15, 1.45, 0.40)),
    "humerus.L": ("scapula.L", (0.20, 1.10, 0.55)),
    "radius.L": ("humerus.L", (0.20, 0.80, 0.40)),
    "elbowFix.L": ("humerus.L", (0.20, 0.80, 0.40)),
    "metacarpus.L": ("radius.L", (0.20, 0.40, 0.47)),
    "fhoof.L": ("metacarpus.L", (0.20, 0.08, 0.50)),
    "wheel.L": ("axle", (0.75, 0.55, -2.40)),
    "shock.L": ("axle", (0.45, 0.55, -2.40)),
    "shock.L.001": ("cart", (0.45, 0.95, -2.40)),
}


def mirrored(name):
    return name.replace(".L", ".R")


def main():
    joints = dict(CENTRE)
    for name, (parent, (x, y, z)) in LEFT.items():
        joints[name] = (parent, (x, y, z))
        joints[mirrored(name)] = (mirrored(parent), (-x, y, z))
    nodes = []
    for name, (parent, position) in joints.items():
        base = joints[parent][1] if parent else (0.0, 0.0, 0.0)
        translate = [round(p - b, 6) for p, b in zip(position, base)]
        side = "L" if name.endswith((".L", ".L.001")) else "R" if name.endswith((".R", ".R.001")) else "C"
        node = {"name": name, "type": "joint", "uuid": str(uuid.uuid5(NAMESPACE, name))}
        if parent:
            node["parent"] = parent
        node["attrs"] = {"translate": translate}
        node["tags"] = {"side": side}
        nodes.append(node)
    # The cart's sign: a quad (mesh space: the cart joint's) and its shapes.
    base = [[-0.2, 0.2, 0.3], [0.2, 0.2, 0.3], [0.2, 0.5, 0.3], [-0.2, 0.5, 0.3]]
    lift = [[0, 0, 0], [0, 0, 0], [0, 0.1, 0], [0, 0.1, 0]]
    tilt = [[0, 0, 0], [0, 0, 0], [0, 0, 0.1], [0, 0, 0.1]]
    nodes.append({"name": "sign", "type": "mesh", "uuid": str(uuid.uuid5(NAMESPACE, "sign")), "parent": "cart",
                  "attrs": {"triangles": [0, 1, 2, 0, 2, 3]}})
    nodes.append({"name": "sign_blendShape", "type": "blendShape", "uuid": str(uuid.uuid5(NAMESPACE, "sign_blendShape")),
                  "attrs": {"basePoints": base, "targetDeltas": lift + tilt, "targetOffsets": [0, 4, 8],
                            "targetNames": ["lift", "tilt"], "weights": [0.0, 0.0]}})
    # One node per line: diffable, and short.
    lines = ",\n  ".join(json.dumps(n) for n in nodes)
    sys.stdout.write('{"rigel": "scene", "version": 1, "fps": 24, "time": 0,\n "nodes": [\n  ' + lines +
                     '\n ],\n "connections": [{"src": "sign_blendShape.outPoints", "dst": "sign.points"}]}\n')


main()

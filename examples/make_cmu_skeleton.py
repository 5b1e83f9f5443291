#!/usr/bin/env python3
"""Writes cmu_131_skeleton.rigel: the skeleton of CMU motion-capture subject
131 (cgspeed BVH conversion, see LICENSE-data.md) posed at one frame of its
"start walk stop" take, under a circular world control.

Until rigel imports BVH itself (`rigel import`), this script is how the
bundled example was made: python3 make_cmu_skeleton.py data/cmu_131_01.bvh 300 > cmu_131_skeleton.rigel.
BVH units (the conversion's scaled inches) are kept, as rigel's importers do.
"""
import json
import math
import sys
import uuid

NAMESPACE = uuid.UUID("6f1d2a64-8c1e-4c55-9a57-0f3b1b0c2e11")


def parse(path):
    tokens = open(path).read().split()
    joints, stack, i = [], [], 1  # after "HIERARCHY"
    while tokens[i] != "MOTION":
        t = tokens[i]
        if t in ("ROOT", "JOINT"):
            joints.append({"name": tokens[i + 1], "parent": stack[-1] if stack else None, "channels": []})
            i += 2
        elif t == "End":
            joints.append({"name": None, "parent": stack[-1], "channels": [], "end": True})
            i += 2
        elif t == "{":
            stack.append(len(joints) - 1)
            i += 1
        elif t == "}":
            stack.pop()
            i += 1
        elif t == "OFFSET":
            joints[-1]["offset"] = [float(x) for x in tokens[i + 1:i + 4]]
            i += 4
        elif t == "CHANNELS":
            n = int(tokens[i + 1])
            joints[-1]["channels"] = tokens[i + 2:i + 2 + n]
            i += 2 + n
        else:
            raise SystemExit(f"unexpected token {t}")
    frames = int(tokens[i + 2])
    values = [float(x) for x in tokens[i + 6:]]
    width = len(values) // frames
    return joints, [values[f * width:(f + 1) * width] for f in range(frames)]


def main():
    path = sys.argv[1]
    frame = int(sys.argv[2]) if len(sys.argv) > 2 else 300
    joints, motion = parse(path)
    row = motion[frame]
    cursor = 0
    sides = {}
    nodes = [{
        "name": "world_ctrl", "type": "control",
        "uuid": str(uuid.uuid5(NAMESPACE, "world_ctrl")),
        "attrs": {
            "shapePoints": [[20 * math.cos(a * math.pi / 8), 0, 20 * math.sin(a * math.pi / 8)] for a in range(16)],
            "shapeColor": [1.0, 0.8, 0.1],
        },
        "tags": {"role": "world"},
    }]
    for index, j in enumerate(joints):
        if j.get("end"):
            continue
        attrs = {}
        translate = list(j["offset"])
        rotate = {"X": 0.0, "Y": 0.0, "Z": 0.0}
        axes = []
        for ch in j["channels"]:
            v = row[cursor]
            cursor += 1
            if ch.endswith("position"):
                translate["XYZ".index(ch[0])] += v
            else:
                rotate[ch[0]] = v
                axes.append(ch[0])
        # BVH lists rotations outermost first: "Z Y X" means R = Rz*Ry*Rx,
        # applied X first: rigel's rotate order "xyz".
        order = "".join(reversed(axes)).lower() or "xyz"
        if any(translate):
            attrs["translate"] = translate
        if any(rotate.values()):
            attrs["rotate"] = [rotate["X"], rotate["Y"], rotate["Z"]]
        if order != "xyz":
            attrs["rotateOrder"] = order
        name = j["name"]
        parent = joints[j["parent"]]["name"] if j["parent"] is not None else "world_ctrl"
        node = {"name": name, "type": "joint", "uuid": str(uuid.uuid5(NAMESPACE, name)), "parent": parent, "attrs": attrs}
        side = "L" if name.startswith(("Left", "LHip", "LFing", "LThu")) else \
               "R" if name.startswith(("Right", "RHip", "RFing", "RThu")) else \
               sides.get(parent, "C")
        sides[name] = side
        node["tags"] = {"side": side, "source": f"bvh:{index}"}
        nodes.append(node)
    scene = {"rigel": "scene", "version": 1, "fps": 120, "time": 0, "nodes": nodes, "connections": []}
    json.dump(scene, sys.stdout, indent=1)
    sys.stdout.write("\n")


main()

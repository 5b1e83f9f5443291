#!/usr/bin/env python3
"""How `rigel bake` and `rigel export` scale with the frame count: time and
peak memory (RSS, /usr/bin/time) per frame at 1,000 and 10,000 frames, and
the 10,000 / 1,000 ratios (linear work gives 10).

    python3 bench/bake_scaling.py [--rigel build/release/apps/cli/rigel] [--frames 1000,10000] [--json OUT]

Cases, each run by the command line in a scratch folder:
- bake mocap: a 38-joint BVH (tests/data/bvh/cmu_131_01.bvh's rows repeated
  to the length, bench/long_bvh.py) imported, then `rigel bake` of every
  frame (every joint);
- bake biped: examples/biped.rig.xml built on the bundled metarig (163
  joints), 24 controls keyed every 24 frames over the shot (a slow sine per
  channel), then `rigel bake` of every frame (every joint);
- export mocap: `rigel export` of the imported BVH to .glb (its Euler
  rotations are baked, every frame).
Per frame figures: the wall time and the peak RSS divided by the frames,
the memory also per 40 joints, and the marginal memory per frame (the
difference of the two peaks over the difference of the frames), which
leaves out what a run needs whatever its length.
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def timed(cmd, cwd):
    """Runs cmd under /usr/bin/time; returns (seconds, peak RSS in KiB)."""
    stats = Path(cwd) / "time.txt"
    r = subprocess.run(["/usr/bin/time", "-o", str(stats), "-f", "%e %M"] + cmd, cwd=cwd,
                       stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit(f"bake_scaling.py: {' '.join(cmd)} failed ({r.returncode}):\n{r.stderr}")
    wall, rss = stats.read_text().split()[-2:]
    return float(wall), int(rss)


def run(cmd, cwd):
    r = subprocess.run(cmd, cwd=cwd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if r.returncode != 0:
        sys.exit(f"bake_scaling.py: {' '.join(cmd)} failed ({r.returncode}):\n{r.stderr}")


# Controls of the built biped keyed in the biped case, and the channels.
BIPED_KEYS = [
    ("hero_hip_main", "translate", 0.05), ("hero_hip_main", "rotate", 10),
    ("hero_spine_fk0", "rotate", 8), ("hero_spine_fk1", "rotate", 8), ("hero_spine_fk2", "rotate", 8),
    ("hero_neck_neck0", "rotate", 10), ("hero_neck_head", "rotate", 15),
    ("hero_clavicle_L_fk0", "rotate", 10), ("hero_arm_L_fk0", "rotate", 30), ("hero_arm_L_fk1", "rotate", 30),
    ("hero_arm_L_fk2", "rotate", 20), ("hero_clavicle_R_fk0", "rotate", 10), ("hero_arm_R_fk0", "rotate", 30),
    ("hero_arm_R_fk1", "rotate", 30), ("hero_arm_R_fk2", "rotate", 20), ("hero_leg_L_fk0", "rotate", 25),
    ("hero_leg_L_fk1", "rotate", 25), ("hero_leg_L_fk2", "rotate", 15), ("hero_leg_R_fk0", "rotate", 25),
    ("hero_leg_R_fk1", "rotate", 25), ("hero_leg_R_fk2", "rotate", 15), ("hero_hand_L_finger0", "rotate", 20),
    ("hero_hand_R_finger0", "rotate", 20), ("hero_eyes_master", "translate", 0.02),
]


def keyed_biped(built, out, frames, fps):
    """The built biped with BIPED_KEYS keyed every 24 frames over [0, frames - 1]."""
    scene = json.loads(Path(built).read_text())
    names = {n["name"] for n in scene["nodes"]}
    key_frames = list(range(0, frames, 24))
    if key_frames[-1] != frames - 1:
        key_frames.append(frames - 1)
    times = [f / fps for f in key_frames]
    for k, (control, channel, amplitude) in enumerate(BIPED_KEYS):
        if control not in names:
            sys.exit(f"bake_scaling.py: the built biped has no control {control}")
        for a, axis in enumerate("XYZ"):
            curve = f"bench_{control}_{channel}{axis}"
            phase = 0.7 * k + 2.1 * a
            values = [amplitude * math.sin(2 * math.pi * f / 96 + phase) for f in key_frames]
            scene["nodes"].append({"name": curve, "type": "animCurve", "attrs": {"keyTimes": times, "keyValues": values}})
            scene["connections"].append({"src": f"{curve}.output", "dst": f"{control}.{channel}{axis}"})
    Path(out).write_text(json.dumps(scene))


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--rigel", default=str(ROOT / "build/release/apps/cli/rigel"))
    p.add_argument("--frames", default="1000,10000")
    p.add_argument("--json", help="also write the figures here")
    args = p.parse_args()
    rigel = str(Path(args.rigel).resolve())
    counts = [int(x) for x in args.frames.split(",")]
    rows = []
    with tempfile.TemporaryDirectory(prefix="rigel_bake_scaling_") as tmp:
        run([rigel, "build", str(ROOT / "examples/biped.rig.xml"), "-o", "hero.rigel"], tmp)
        for n in counts:
            run([sys.executable, str(ROOT / "bench/long_bvh.py"), f"m{n}.bvh", str(n)], tmp)
            run([rigel, "import", f"m{n}.bvh", "-o", f"m{n}.rigel"], tmp)
            wall, rss = timed([rigel, "bake", f"m{n}.rigel", "--frames", f"0:{n - 1}", "-o", f"mb{n}.rigel"], tmp)
            rows.append({"case": "bake mocap", "joints": 38, "frames": n, "seconds": wall, "peak_kib": rss})
            os.remove(Path(tmp) / f"mb{n}.rigel")
            wall, rss = timed([rigel, "export", f"m{n}.rigel", "-o", f"m{n}.glb"], tmp)
            rows.append({"case": "export mocap", "joints": 38, "frames": n, "seconds": wall, "peak_kib": rss})
            fps = json.loads((Path(tmp) / "hero.rigel").read_text()).get("fps", 24)
            keyed_biped(Path(tmp) / "hero.rigel", Path(tmp) / f"h{n}.rigel", n, fps)
            wall, rss = timed([rigel, "bake", f"h{n}.rigel", "--frames", f"0:{n - 1}", "-o", f"hb{n}.rigel"], tmp)
            rows.append({"case": "bake biped", "joints": 163, "frames": n, "seconds": wall, "peak_kib": rss})
            os.remove(Path(tmp) / f"hb{n}.rigel")

    print("| case | joints | frames | time | peak RSS | time/frame | peak/frame | per 40 joints |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for r in rows:
        per_frame_kib = r["peak_kib"] / r["frames"]
        print(f"| {r['case']} | {r['joints']} | {r['frames']:,} | {r['seconds']:.2f} s | {r['peak_kib'] / 1024:.0f} MiB | "
              f"{1e6 * r['seconds'] / r['frames']:.0f} us | {per_frame_kib:.1f} KiB | {per_frame_kib * 40 / r['joints']:.1f} KiB |")
    if len(counts) >= 2:
        lo, hi = counts[0], counts[-1]
        print()
        print(f"| case | time {hi:,} / {lo:,} | peak {hi:,} / {lo:,} | marginal memory per frame | per 40 joints |")
        print("| --- | ---: | ---: | ---: | ---: |")
        for case in dict.fromkeys(r["case"] for r in rows):
            a = next(r for r in rows if r["case"] == case and r["frames"] == lo)
            b = next(r for r in rows if r["case"] == case and r["frames"] == hi)
            marginal = (b["peak_kib"] - a["peak_kib"]) / (hi - lo)
            print(f"| {case} | {b['seconds'] / a['seconds']:.1f} | {b['peak_kib'] / a['peak_kib']:.1f} | "
                  f"{marginal:.1f} KiB | {marginal * 40 / a['joints']:.1f} KiB |")
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=2) + "\n")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Writes a BVH of FRAMES frames made of a source BVH's motion rows repeated
(tests/data/bvh/cmu_131_01.bvh by default), for scaling benchmarks: big
files are generated, not committed.

    python3 bench/long_bvh.py OUT.bvh FRAMES [SOURCE.bvh]

The hierarchy and frame time are the source's; rows cycle forward then
backward (ping-pong), so the motion stays continuous where it repeats.
"""

import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def main() -> int:
    if len(sys.argv) not in (3, 4):
        print(__doc__.strip(), file=sys.stderr)
        return 2
    out, frames = Path(sys.argv[1]), int(sys.argv[2])
    source = Path(sys.argv[3]) if len(sys.argv) == 4 else ROOT / "tests/data/bvh/cmu_131_01.bvh"
    if frames < 1:
        print("long_bvh.py: FRAMES must be at least 1", file=sys.stderr)
        return 2
    lines = source.read_text().splitlines()
    at = next(i for i, line in enumerate(lines) if line.strip().startswith("Frames:"))
    header, frame_time = lines[:at], lines[at + 1]
    rows = [line for line in lines[at + 2 :] if line.strip()]
    if not rows:
        print(f"long_bvh.py: {source}: no motion rows", file=sys.stderr)
        return 1
    cycle = rows + rows[-2:0:-1] if len(rows) > 2 else rows
    with out.open("w") as f:
        f.write("\n".join(header) + "\n")
        f.write(f"Frames: {frames}\n{frame_time}\n")
        for k in range(frames):
            f.write(cycle[k % len(cycle)] + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Batch bake throughput: 50 generated shots (the biped with different keys)
baked over 48 frames three ways, timed as whole processes in one run:

  loop   one `rigel bake` after another (what a shell loop does): the anchor
  local  `rigel batch bake --jobs N` (N = the cores)
  slurm  `rigel batch bake --slurm` on a single-node cluster started here
         (tests/support/slurm_cluster.sh), when Slurm can run

and prints shots per second, the ratio to the loop, and Slurm's overhead
per shot against the local batch. Usage: bench/batch_throughput.py
[--rigel build/release/apps/cli/rigel] [--shots 50] [--frames 0:48]"""

import argparse
import os
import pathlib
import subprocess
import sys
import tempfile
import time

REPO = pathlib.Path(__file__).resolve().parents[1]


def run(args, **kw):
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, **kw)


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--rigel", default=str(REPO / "build" / "release" / "apps" / "cli" / "rigel"))
    p.add_argument("--shots", type=int, default=50)
    p.add_argument("--frames", default="0:48")
    a = p.parse_args()
    rigel = a.rigel
    cores = os.cpu_count() or 1
    with tempfile.TemporaryDirectory(prefix="rigel-batch-bench-") as tmp:
        tmp = pathlib.Path(tmp)
        env = dict(os.environ, RIGEL_CONFIG_HOME=str(tmp / "nocfg"))
        run([rigel, "build", str(REPO / "examples" / "biped.rig.xml"), "-o", str(tmp / "hero.rigel")], env=env)
        (tmp / "shots").mkdir()
        shots = []
        for i in range(a.shots):
            shot = tmp / "shots" / f"s{i:03d}.rigel"
            run([rigel, "key", str(tmp / "hero.rigel"), "--control", "hero_arm_L_fkIkSwitch", "--attr", "fkIk",
                 "--frame", str(2 + i % 40), "--value", str((i % 10) / 10), "-o", str(shot)], env=env)
            shots.append(str(shot))
        results = {}
        (tmp / "loop").mkdir()
        t = time.perf_counter()
        for s in shots:
            run([rigel, "bake", s, "--frames", a.frames, "-o", str(tmp / "loop" / pathlib.Path(s).name)], env=env)
        results["loop"] = time.perf_counter() - t
        t = time.perf_counter()
        run([rigel, "batch", "bake", *shots, "--frames", a.frames, "-o", str(tmp / "local"), "--jobs", str(cores)], env=env)
        results["local"] = time.perf_counter() - t
        cluster = tmp / "cluster"
        started = subprocess.run([str(REPO / "tests" / "support" / "slurm_cluster.sh"), "start", str(cluster)],
                                 capture_output=True, text=True)
        if started.returncode == 0:
            senv = dict(env, SLURM_CONF=started.stdout.strip())
            try:
                t = time.perf_counter()
                run([rigel, "batch", "bake", *shots, "--frames", a.frames, "-o", str(tmp / "slurm"), "--slurm"], env=senv)
                results["slurm"] = time.perf_counter() - t
            finally:
                subprocess.run([str(REPO / "tests" / "support" / "slurm_cluster.sh"), "stop", str(cluster)])
        else:
            print(f"slurm: not run ({started.stderr.strip()})", file=sys.stderr)
    n = a.shots
    print(f"{n} shots, frames {a.frames}, {cores} cores (whole-process timings)")
    print("| run | seconds | shots/s | vs loop |")
    print("| --- | --- | --- | --- |")
    for k, v in results.items():
        print(f"| {k} | {v:.2f} | {n / v:.1f} | {results['loop'] / v:.2f}x |")
    if "slurm" in results:
        print(f"Slurm overhead per shot against the local batch: {(results['slurm'] - results['local']) / n * 1000:.0f} ms")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Merges several rigel_bench JSON outputs and prints the better run of each
benchmark as a Markdown table.

    rigel_bench --benchmark_min_time=0.2 --benchmark_out=run1.json --benchmark_out_format=json
    rigel_bench --benchmark_min_time=0.2 --benchmark_out=run2.json --benchmark_out_format=json
    python3 bench/summarize.py run1.json run2.json

For every benchmark the run with the lowest measured time is kept ("better
of N": the machine is shared, and interference only ever adds time). The
spread column is (worst / best - 1) over the runs, a rough noise figure.
Counters named ns_per_* hold seconds per item (see bench_util.h) and are
printed in nanoseconds. For benchmarks timed in wall-clock time with
UseRealTime(), the "cpu per item" column gives the lowest main-thread CPU
time per item over the runs: for serial code it is immune to time slices
lost to other processes (not to their cache pollution); for parallel code it
leaves out the worker threads, so it means little there.
"""

import json
import sys

UNIT_NS = {"ns": 1.0, "us": 1e3, "ms": 1e6, "s": 1e9}


def measured_ns(bench):
    # Google Benchmark stores the manual time (UseManualTime) or the real
    # time (UseRealTime) in real_time; otherwise CPU time is the measure.
    name = bench["name"]
    key = "real_time" if name.endswith(("/real_time", "/manual_time")) else "cpu_time"
    return bench[key] * UNIT_NS[bench["time_unit"]]


def format_ns(ns):
    if ns >= 1e6:
        return f"{ns / 1e6:.2f} ms"
    if ns >= 1e3:
        return f"{ns / 1e3:.1f} us"
    if ns >= 100:
        return f"{ns:.0f} ns"
    return f"{ns:.1f} ns"


def main(paths):
    runs = {}
    order = []
    context = None
    for path in paths:
        with open(path) as f:
            data = json.load(f)
        context = context or data.get("context", {})
        for bench in data["benchmarks"]:
            if bench.get("run_type", "iteration") != "iteration" or bench.get("error_occurred"):
                continue
            name = bench["name"]
            if name not in runs:
                runs[name] = []
                order.append(name)
            runs[name].append(bench)
    if context:
        print(f"<!-- {context.get('date', '')}, {context.get('num_cpus', '?')} CPUs at "
              f"{context.get('mhz_per_cpu', '?')} MHz, {len(paths)} run(s) -->")
    print("| benchmark | time | per item | cpu per item | extra | iterations | spread |")
    print("| --- | ---: | ---: | ---: | --- | ---: | ---: |")
    for name in order:
        results = runs[name]
        best = min(results, key=measured_ns)
        worst = max(results, key=measured_ns)
        spread = measured_ns(worst) / measured_ns(best) - 1.0
        per_item = ""
        cpu_per_item = ""
        extra = []
        for key, value in best.items():
            if key.startswith("ns_per"):
                per_item = format_ns(value * 1e9)
                if name.endswith("/real_time"):
                    # items per iteration = time per iteration / time per item
                    cpu = min(r["cpu_time"] * UNIT_NS[r["time_unit"]] * r[key] * 1e9 / measured_ns(r)
                              for r in results)
                    cpu_per_item = format_ns(cpu)
            elif key in ("dirtied", "levels"):
                extra.append(f"{key}={value:g}")
        short = name.removesuffix("/real_time").removesuffix("/manual_time")
        print(f"| {short} | {format_ns(measured_ns(best))} | {per_item} | {cpu_per_item} | {' '.join(extra)} | "
              f"{best['iterations']} | {spread * 100:.0f}% |")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])

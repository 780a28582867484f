#!/usr/bin/env python3
"""Issue 19's goals over many complete runs of the terrain benchmark group, each reading split
by the machine's moment (docs/terrain_shadow.md, "Where it stands").

    python3 scripts/terrain_goals.py SUMMARY.json ...      # runs already made
    python3 scripts/terrain_goals.py --run N [--dir DIR]   # N more runs first (build/release)

A SUMMARY is what `bench_terrain --summary_out` writes (`./penumbra bench terrain` leaves one in
build/bench/terrain_summary.json); --run calls build/release/tests/bench/bench_terrain N times
(`./penumbra bench terrain` builds it) and keeps their summaries in DIR (default
build/bench/terrain_runs; its other outputs in DIR/scratch). Each goal is a ratio to the case's floor measured in the same run.
A reading is quiet when the probes just before and after its case (the "machine moment" row's
note) both read the slower vCPU's one-thread sweep at most QUIET_RATIO times its floor and an
L2 latency of at most QUIET_L2_NS (docs/terrain_shadow_log.md, "Thirteenth round"); otherwise
slow. Prints, per goal, the met count and range of the quiet and of the slow readings, the
median of all, and in how many runs all six goals were met. Exits 2 naming the file and the
reason for a summary that is not one of this group's.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys
import time

# (label, case name prefix in the summary, goal: ratio to the floor at most, probe before it)
GOALS = [
    ("environment update", "env update 256^2 sweep", 5.0, "env update"),
    ("horizons", "horizons alone, sweep", 10.0, "horizons"),
    ("transfer", "transfer alone (exact", 3.0, "transfer"),
    ("one light", "1 spherical light (default", 15.0, "lights"),
    ("16x16 edit", "local edit 16x16", 15.0, "edit"),
    ("1024^2, n_phi 64", "env update 1024^2", 6.0, "1024^2"),
]
QUIET_RATIO = 10.0
QUIET_L2_NS = 5.2
PROBE_ROW = "machine moment"
PROBE = re.compile(r"(before: |after |, )([^,;:]+?) ([\d.]+)x ([\d.]+) ns")


def fail(path, why):
    sys.exit(f"terrain_goals: {path}: {why}")


def probes_of(path, note):
    """The probes in the order they ran: [(label, ratio, l2_ns)]; 'after X' is labelled 'after'."""
    found = []
    for lead, label, ratio, ns in PROBE.findall(note):
        found.append(("after" if lead == "after " else label.strip(), float(ratio), float(ns)))
    if not found:
        fail(path, f"the '{PROBE_ROW}' row's note names no probe")
    return found


def read_run(path):
    """One run: {goal label: (ratio, quiet)}."""
    try:
        with open(path) as f:
            summary = json.load(f)
        rows = summary["rows"]
    except (OSError, ValueError, KeyError, TypeError) as e:
        fail(path, f"not a benchmark summary ({e.__class__.__name__}: {e})")
    probe_rows = [r for r in rows if str(r.get("name", "")).startswith(PROBE_ROW)]
    if not probe_rows:
        fail(path, f"no '{PROBE_ROW}' row (a run of bench_terrain before the probes, or another group)")
    probes = probes_of(path, str(probe_rows[0].get("note", "")))
    labels = [p[0] for p in probes]
    run = {}
    for label, prefix, goal, before in GOALS:
        case = [r for r in rows if str(r.get("name", "")).startswith(prefix)]
        if not case or not isinstance(case[0].get("floor_ratio"), (int, float)):
            fail(path, f"no floor ratio for '{prefix}'")
        if before not in labels or labels.index(before) + 1 >= len(labels):
            fail(path, f"no probe before and after '{before}' in the '{PROBE_ROW}' note")
        i = labels.index(before)
        quiet = all(r <= QUIET_RATIO and ns <= QUIET_L2_NS for _, r, ns in probes[i:i + 2])
        run[label] = (float(case[0]["floor_ratio"]), quiet, goal)
    return run


def report(paths):
    runs = [read_run(p) for p in paths]
    print(f"{len(runs)} runs; quiet: both probes around a case at most {QUIET_RATIO:g}x and "
          f"{QUIET_L2_NS:g} ns")
    print(f"{'goal':24} {'all runs: median (range)':28} {'quiet: met (range)':26} slow: met (range)")
    for label, _, goal, _ in GOALS:
        values = [run[label] for run in runs]

        def part(quiet):
            sel = [v for v, q, _ in values if q == quiet]
            if not sel:
                return "none"
            met = sum(v <= goal for v in sel)
            return f"{met} of {len(sel)} ({min(sel):.2f}-{max(sel):.2f})"

        every = [v for v, _, _ in values]
        middle = f"{statistics.median(every):.2f} ({min(every):.2f}-{max(every):.2f})"
        print(f"{label + ' <= ' + format(goal, 'g'):24} {middle:28} {part(True):26} {part(False)}")
    all_six = sum(all(v <= g for v, _, g in run.values()) for run in runs)
    print(f"all six goals met in {all_six} of {len(runs)} runs")
    if any(not q for run in runs for _, q, _ in run.values()):
        print("slow: a probe around the case read the machine slower than a quiet moment (another "
              "tenant on the vCPU's core, or a vCPU stopped; docs/terrain_shadow.md, \"What a slow "
              "moment is\"); the issue measured its start on a quiet machine")


def run_bench(count, directory):
    exe = os.path.join("build", "release", "tests", "bench", "bench_terrain")
    if not os.access(exe, os.X_OK):
        sys.exit(f"terrain_goals: {exe}: not built (run ./penumbra bench terrain once)")
    os.makedirs(directory, exist_ok=True)
    stamp = time.strftime("%Y%m%d-%H%M%S", time.gmtime())
    paths = []
    for i in range(count):
        path = os.path.join(directory, f"{stamp}_{i + 1}.json")
        scratch = os.path.join(directory, "scratch", "last")  # outputs the goals do not read
        os.makedirs(os.path.dirname(scratch), exist_ok=True)
        done = subprocess.run([exe, f"--summary_out={path}",
                               f"--benchmark_out={scratch}_gbench.json",
                               "--benchmark_out_format=json",
                               f"--records_out={scratch}_records.json", f"--chart_out={scratch}.svg"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if done.returncode != 0:
            sys.exit(f"terrain_goals: {exe} exited {done.returncode}:\n{done.stderr}")
        load = os.getloadavg()[0]
        print(f"run {i + 1} of {count}: {path} ({time.strftime('%H:%M:%S', time.gmtime())} UTC, "
              f"load {load:.2f})", flush=True)
        paths.append(path)
    return paths


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("summaries", nargs="*", help="bench_terrain summary JSON files")
    parser.add_argument("--run", type=int, default=0, help="make this many complete runs first")
    parser.add_argument("--dir", default=os.path.join("build", "bench", "terrain_runs"),
                        help="where --run keeps its summaries")
    args = parser.parse_args()
    paths = list(args.summaries)
    if args.run > 0:
        paths += run_bench(args.run, args.dir)
    if not paths:
        parser.error("no summaries: name some, or --run N")
    report(paths)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Writes a benchmark group's summary table from its record (build/bench/GROUP_summary.json).

    ./penumbra bench render                 # -> build/bench/render_summary.json
    python3 scripts/bench_table.py render [--write README.md ...]

Prints the table (markdown); with --write, replaces the text between
<!-- bench-table:GROUP:begin --> and <!-- bench-table:GROUP:end --> in each file named. Every
number comes from the record, measured in one run (the play group has its own script,
scripts/play_table.py). The blockers group adds a table of its frames from build/bench/blockers.json
(Google Benchmark's output: medians and counters) and the load average's three values.
"""
import json
import sys

from doc_markers import write_between


def fmt(v):
    if v is None:
        return "-"
    return f"{v:,.0f}" if abs(v) >= 1000 else f"{v:.3g}" if abs(v) < 10 else f"{v:.1f}"


def table(r):
    load = r.get("load_avg") or [None]
    lines = [
        f"Measured {r['date']} on {r['num_cpus']} CPUs, load average {load[0]:.2f} at the start "
        f"(`./penumbra bench {r['group']}`, build/bench/{r['group']}_summary.json).",
        "",
        "| case | value | ratio | floor (value / floor) | goal | note |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for row in r["rows"]:
        goal = row.get("goal")
        goal_text = "-"
        if goal:
            goal_text = f"{goal['metric']} {goal['op']} {fmt(goal['target'])}: {row['status']}"
        ratio = row.get("ratio")
        ratio_text = "-" if ratio is None else f"{ratio:.3g} ({row.get('ratio_def') or 'baseline/value'})"
        floor = row.get("floor")
        floor_text = "-" if floor is None else f"{fmt(floor)} ({fmt(row.get('floor_ratio'))}x)"
        lines.append(f"| {row['name'].strip()} | {fmt(row.get('value'))} {row['unit']} | "
                     f"{ratio_text} | {floor_text} | {goal_text} | {row.get('note', '')} |")
    if r["group"] == "blockers":
        lines[0] = lines[0].replace(
            f"load average {load[0]:.2f} at the start",
            "load average " + " / ".join(f"{x:.2f}" for x in load) + " (1, 5, 15 min, as `uptime` "
            "prints it) at the start")
        lines += blocker_frames()
    return "\n".join(lines)


def blocker_frames(path="build/bench/blockers.json"):
    """The blockers group's frames: median ms, speed-up, pairs and irradiance difference."""
    with open(path) as f:
        runs = json.load(f)["benchmarks"]
    med, cv = {}, {}  # (scene, method) -> median aggregate (in run order), its cv
    for b in runs:
        if b.get("aggregate_name") in ("median", "cv") and b["run_name"].startswith("BM_Frame/"):
            _, scene, method = b["run_name"].split("/")[:3]
            if b["aggregate_name"] == "cv":
                cv[(scene, method)] = b["real_time"]
                continue
            assert b["time_unit"] == "ms"
            med[(scene, method)] = b
    lines = [
        "",
        f"Frames ({fmt(next(iter(med.values()))['receivers']) if med else '-'} receivers, 2 "
        "threads, median of the repetitions; build/bench/blockers.json):",
        "",
        "| scene | method | ms / frame (cv) | speed-up vs all pairs | view_blocker calls / receiver "
        "| log-SH adds / receiver | HYB squares (mean) | irradiance vs all pairs: rel RMS, max |",
        "| --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for (scene, method), b in med.items():
        base = med.get((scene, "all_pairs"))
        speed = base["real_time"] / b["real_time"] if base else None
        diff = "-" if method == "all_pairs" else (
            f"{100 * b['rel_rms_vs_all_pairs']:.2f}%, {100 * b['max_rel_vs_all_pairs']:.2f}%")
        spread = f" ({100 * cv[(scene, method)]:.1f}%)" if (scene, method) in cv else ""
        lines.append(f"| {scene} | {method} | {fmt(b['real_time'])}{spread} | {fmt(speed)} | "
                     f"{fmt(b['views_per_receiver'])} | {fmt(b['added_per_receiver'])} | "
                     f"{b['squares_mean']:.2f} | {diff} |")
    return lines


def main(argv):
    if not argv:
        sys.exit("usage: bench_table.py GROUP [--write FILE...]")
    group = argv.pop(0)
    targets = argv[1:] if argv[:1] == ["--write"] else []
    path = f"build/bench/{group}_summary.json"
    with open(path) as f:
        record = json.load(f)
    text = table(record)
    print(text)
    begin, end = f"<!-- bench-table:{group}:begin -->", f"<!-- bench-table:{group}:end -->"
    for target in targets:
        write_between(target, begin, end, text)


if __name__ == "__main__":
    main(sys.argv[1:])

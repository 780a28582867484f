#!/usr/bin/env python3
"""Writes a benchmark group's summary table from its record (build/bench/GROUP_summary.json).

    ./penumbra bench render                 # -> build/bench/render_summary.json
    python3 scripts/bench_table.py render [--write README.md ...]

Prints the table (markdown); with --write, replaces the text between
<!-- bench-table:GROUP:begin --> and <!-- bench-table:GROUP:end --> in each file named. Every
number comes from the record, measured in one run (the play group has its own script,
scripts/play_table.py).
"""
import json
import os
import sys


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
    return "\n".join(lines)


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
        with open(target) as f:
            doc = f.read()
        if begin not in doc or end not in doc:
            sys.exit(f"{target}: no {begin} ... {end} markers")
        head, rest = doc.split(begin, 1)
        _, tail = rest.split(end, 1)
        with open(target + ".tmp", "w") as f:
            f.write(head + begin + "\n" + text + "\n" + end + tail)
        os.replace(target + ".tmp", target)


if __name__ == "__main__":
    main(sys.argv[1:])

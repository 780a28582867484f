#!/usr/bin/env python3
"""Writes the valley game's performance table from its `play` benchmark record.

    ./penumbra bench play                # -> build/bench/play_game.json (the recorded session)
    python3 scripts/game_table.py [build/bench/play_game.json] [--write docs/game.md README.md]

Prints the table (markdown); with --write, replaces the text between <!-- game-table:begin -->
and <!-- game-table:end --> in each file named. Every number comes from the record, measured in
one run (issue 16's goal: at least 30 fps at 960x540 on lavapipe with every system on).
"""
import json
import sys

from doc_markers import write_between

BEGIN, END = "<!-- game-table:begin -->", "<!-- game-table:end -->"


def table(r):
    f, m, run = r["frame"], r["machine"], r["run"]
    lines = [
        f"Measured {r['date']} on {m['cpu']} ({m['cores']} cores), load average "
        f"{m['load_average_start']:.2f} at the start; {run['device']}, {run['width']}x{run['height']} "
        f"headless, the recorded session ({run['frames']} frames, {run['timed_frames']} timed; "
        f"`./penumbra bench play`, build/bench/play_game.json).",
        "",
        "| valley game, every system on | measured | goal |",
        "| --- | --- | --- |",
        f"| frame rate | {f['fps']:.1f} fps (mean {f['mean_ms']:.2f} ms) | >= 30 fps |",
        f"| frame time median / p95 | {f['median_ms']:.2f} / {f['p95_ms']:.2f} ms | - |",
        f"| headroom to 30 fps (33.3 ms - p95) | {1000 / 30 - f['p95_ms']:.2f} ms | >= 0 |",
        f"| empty frame, same run (clear + tonemap) | {f['empty_frame_ms']:.2f} ms: the median frame is "
        f"{f['x_empty_frame']:.2f}x | - |",
        f"| simulation / render record + submit (mean) | {f['simulation_ms']:.2f} / "
        f"{f['render_ms']:.2f} ms | - |",
        f"| GPU frame (timestamps, {run['gpu_timed_frames']} frames) | {f['gpu_frame_ms']:.2f} ms | - |",
        "",
        "Per system (mean ms per frame over the timed frames; systems on the job graph overlap in "
        "time, so the column does not add up to the frame):",
        "",
        "| system | mean ms | max ms |",
        "| --- | --- | --- |",
    ]
    systems = sorted(r["systems"], key=lambda s: -s["mean_ms"])
    shown = [s for s in systems if s["mean_ms"] >= 0.05 or s["name"].startswith("game_")]
    for s in shown:
        lines.append(f"| {s['name']} | {s['mean_ms']:.2f} | {s['max_ms']:.2f} |")
    passes = sorted(r["gpu_pass_ms"].items(), key=lambda kv: -kv[1])
    lines += ["", "GPU passes (mean ms): " + ", ".join(f"{k} {v:.2f}" for k, v in passes)]
    return "\n".join(lines)


def main(argv):
    args = [a for a in argv if a != "--write"]
    path = "build/bench/play_game.json"
    files = []
    if "--write" in argv:
        i = argv.index("--write")
        files = argv[i + 1:]
        args = argv[:i]
    if args:
        path = args[0]
    with open(path) as f:
        text = table(json.load(f))
    print(text)
    for name in files:
        write_between(name, BEGIN, END, text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

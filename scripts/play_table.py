#!/usr/bin/env python3
"""Writes the main job's performance tables from the `play` benchmark record.

    ./penumbra bench play                 # -> build/bench/play.json, play_terrain.json
    python3 scripts/play_table.py [build/bench/play.json] [--write README.md docs/play.md]

play_terrain.json (beside the record: the same main job with --boulders 0 --probe-objects 0, run right after) adds
the terrain demo alone, so the tables show what the blocker system's boulders cost.

Prints the tables (markdown); with --write, replaces the text between the markers
<!-- play-table:begin --> and <!-- play-table:end --> in each file named. Every number comes from
the record, measured in one run: no figure in those tables is typed by hand.
"""
import json
import os
import sys

from doc_markers import write_between

BEGIN, END = "<!-- play-table:begin -->", "<!-- play-table:end -->"


def tables(r, alone=None):
    f, m, t, lights = r["frame"], r["machine"], r["terrain"], r["lights"]
    th = r["threads"]
    lines = [
        f"Measured {r['date']} on {m['cpu']} ({m['cores']} cores), load average "
        f"{m['load_average_start']:.2f} at the start; {r['run']['device']}, "
        f"{r['run']['width']}x{r['run']['height']} headless, {r['run']['timed_frames']} timed frames "
        f"(`./penumbra bench play`, build/bench/play.json).",
        "",
        "| main job (terrain demo) | measured | goal |",
        "| --- | --- | --- |",
        f"| frame rate | {f['fps']:.1f} fps (mean {f['mean_ms']:.2f} ms) | >= 30 fps |",
        f"| frame time median / p95 | {f['median_ms']:.2f} / {f['p95_ms']:.2f} ms | - |",
        f"| empty frame, same run (clear + tonemap; before / after the run) | "
        f"{f['empty_frame_ms']:.2f} ms ({f.get('empty_frame_before_ms', 0):.2f} / "
        f"{f.get('empty_frame_after_ms', 0):.2f}) | - |",
        f"| median frame / empty frame | {f['x_empty_frame']:.2f}x | <= 4x |",
        f"| headroom for later systems: to 30 fps / to 4x the empty frame | "
        f"{1000 / 30 - f['median_ms']:.2f} / {4 * f['empty_frame_ms'] - f['median_ms']:.2f} ms | - |",
        f"| simulation / render record + submit (mean) | {f['simulation_ms']:.2f} / "
        f"{f['render_ms']:.2f} ms | - |",
    ]
    if alone:
        a = alone["frame"]
        lines += [
            f"| the terrain demo alone (`--boulders 0 --probe-objects 0`, run right after; load average "
            f"{alone['machine']['load_average_start']:.2f}): frame rate, median / empty frame | "
            f"{a['fps']:.1f} fps, {a['median_ms']:.2f} / {a['empty_frame_ms']:.2f} ms = "
            f"{a['x_empty_frame']:.2f}x | >= 30 fps, <= 4x |",
            f"| what the boulders and probe floaters cost (blocker and probe systems, mesh pass): median frame, simulation | "
            f"+{f['median_ms'] - a['median_ms']:.2f} ms, +{f['simulation_ms'] - a['simulation_ms']:.2f} "
            f"ms | - |",
        ]
    lines += [
        f"| GPU frame (timestamps, timed frames) | {f['gpu_frame_ms']:.2f} ms | - |",
        f"| terrain triangles per frame | {t['triangles']:,.0f} (full detail: "
        f"{t['triangles_full_detail']:,}) at {t['lod_pixels']:g} px | - |",
        f"| last frame against full detail | {100 * t['lod_differing_fraction']:.2f}% of pixels off "
        f"by more than 24/255 (largest {t['lod_max_difference']}) | - |",
        f"| light tiles re-shaded per frame | {lights['tiles_per_frame']:.1f} of {lights['tiles']} | "
        f"<= 1/4 |",
        f"| re-shaded texels that had changed visibly while waiting | "
        f"{100 * lights['visible_fraction']:.1f}% (largest change "
        f"{100 * lights['worst_observed_relative']:.0f}% of the texel's irradiance) | - |",
        *([f"| environment tiles re-shaded per frame (turning sky) | "
           f"{r['environment']['tiles_per_frame']:.1f} of {lights['tiles']} "
           f"({r['environment']['stale_per_frame']:.1f} over the tolerance) | <= 1/4 |"]
          if "environment" in r else []),
        f"| threads | simulation {th['simulation']}, lavapipe {th['lavapipe'] or 'default'} | - |",
    ]
    passes = r.get("gpu_pass_ms", {})
    if passes:
        timed = r["run"].get("gpu_timed_frames")
        over = f" over {timed} timed frames before the measured ones" if timed else ""
        lines += ["", f"GPU passes (mean ms{over}): " + ", ".join(
            f"{k} {v:.2f}" for k, v in sorted(passes.items(), key=lambda kv: -kv[1]))]
    splits = r.get("splits", [])
    if splits:
        lines += ["", "| thread split (simulation : LP_NUM_THREADS) | fps | median ms | p95 ms | "
                  "simulation ms | render ms |", "| --- | --- | --- | --- | --- | --- |"]
        for s in splits:
            sf, st = s["frame"], s["threads"]
            lines.append(f"| {st['simulation']} : {st['lavapipe'] or 'default'} | {sf['fps']:.1f} | "
                         f"{sf['median_ms']:.2f} | {sf['p95_ms']:.2f} | {sf['simulation_ms']:.2f} | "
                         f"{sf['render_ms']:.2f} |")
    return "\n".join(lines)


def main(argv):
    path = "build/bench/play.json"
    targets = []
    if argv and not argv[0].startswith("--"):
        path = argv.pop(0)
    if argv[:1] == ["--write"]:
        targets = argv[1:]
    with open(path) as f:
        record = json.load(f)
    if record.get("format") != "penumbra-play" or record.get("version") != 1:
        sys.exit(f"{path}: not a penumbra-play version 1 record")
    alone = None
    alone_path = os.path.join(os.path.dirname(path), "play_terrain.json")
    if os.path.exists(alone_path):
        with open(alone_path) as f:
            alone = json.load(f)
    text = tables(record, alone)
    print(text)
    for target in targets:
        write_between(target, BEGIN, END, text)


if __name__ == "__main__":
    main(sys.argv[1:])

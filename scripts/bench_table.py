#!/usr/bin/env python3
"""Writes a benchmark group's summary table from its record (build/bench/GROUP_summary.json).

    ./penumbra bench render                 # -> build/bench/render_summary.json
    python3 scripts/bench_table.py render [--write README.md ...]

Prints the table (markdown); with --write, replaces the text between
<!-- bench-table:GROUP:begin --> and <!-- bench-table:GROUP:end --> in each file named. Every
number comes from the record, measured in one run (the play group has its own script,
scripts/play_table.py). The blockers group adds a table of its frames from
build/bench/blockers_gbench.json (Google Benchmark's output: medians, spread and counters), the
speed-versus-accuracy sweep from its records (build/bench/blockers.json) and the load average's
three values; in a file with <!-- bench-table:blockers-brief:begin/end --> markers instead (the
README), a short table of the 400-blocker frames and the sweep's best trade-offs, from the records.
The probes group likewise adds, from its records (build/bench/probes.json), the
tetrahedralization against tetgen, the frames and the speed-versus-accuracy sweep; with
<!-- bench-table:probes-brief:begin/end --> markers, a short table of them.
The spherical_lights group adds, from its records (build/bench/spherical_lights.json), a table of
every frame (ms, floor, goal, counted work per receiver, error against the reference and, for
clusters, against per receiver); with <!-- bench-table:spherical_lights-brief:begin/end -->
markers, a short table of the goal frames.
The probe_bake group's text is its own tables, from the summary and its records
(build/bench/probe_bake.json): the bakes, the ray-rate floor, placement per method and the
placement sweep (speed against accuracy in the room), with the load average at start and end.
"""
import json
import sys

from doc_markers import write_between


def fmt(v):
    if v is None:
        return "-"
    return f"{v:,.0f}" if abs(v) >= 1000 else f"{v:.3g}" if abs(v) < 10 else f"{v:.1f}"


def ratio_and_floor(row):
    """A summary row's same-run ratio and floor cells: "1.23 (baseline/value)", "4.5 (6.7x)"."""
    ratio = row.get("ratio")
    ratio_text = "-" if ratio is None else f"{ratio:.3g} ({row.get('ratio_def') or 'baseline/value'})"
    floor = row.get("floor")
    floor_text = "-" if floor is None else f"{fmt(floor)} ({fmt(row.get('floor_ratio'))}x)"
    return ratio_text, floor_text


def table(r):
    if r["group"] == "probe_bake":
        return probe_bake_table(r, probe_bake_records())
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
        ratio_text, floor_text = ratio_and_floor(row)
        lines.append(f"| {row['name'].strip()} | {fmt(row.get('value'))} {row['unit']} | "
                     f"{ratio_text} | {floor_text} | {goal_text} | {row.get('note', '')} |")
    if r["group"] == "blockers":
        lines[0] = lines[0].replace(
            f"load average {load[0]:.2f} at the start",
            "load average " + " / ".join(f"{x:.2f}" for x in load) + " (1, 5, 15 min, as `uptime` "
            "prints it) at the start")
        lines += blocker_frames()
        lines += blocker_sweep(blocker_records())
    if r["group"] == "spherical_lights":
        lines[0] = lines[0].replace(
            f"load average {load[0]:.2f} at the start",
            "load average " + " / ".join(f"{x:.2f}" for x in load) + " (1, 5, 15 min) at the start")
        lines += sl_frames(sl_records())
    if r["group"] == "probes":
        lines[0] = lines[0].replace(
            f"load average {load[0]:.2f} at the start",
            "load average " + " / ".join(f"{x:.2f}" for x in load) + " (1, 5, 15 min) at the start")
        lines += probe_tables(probe_records())
    return "\n".join(lines)


def blocker_frames(path="build/bench/blockers_gbench.json"):
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
        "threads, median of the repetitions; build/bench/blockers_gbench.json):",
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


def pct(v):
    return "-" if v is None else f"{100 * v:.2f}%"


def blocker_records(path="build/bench/blockers.json"):
    with open(path) as f:
        return json.load(f)


def blocker_sweep(rec):
    """The blockers group's speed-versus-accuracy sweep from its records: one row per
    configuration, one column per band count."""
    sweep = [x for x in rec["records"] if x["kind"] == "sweep"]
    if not sweep:
        return []
    rows = {}  # (scene, method, min_sin, far_error) -> {bands: record}, in run order
    for x in sweep:
        p = x["params"]
        rows.setdefault((x["scene"], x["method"], p["min_sin"], p.get("far_error")), {})[x["bands"]] = x
    bands = sorted({x["bands"] for x in sweep})
    best = set(rec.get("best_tradeoff", {}).values())
    load = rec.get("load_avg_at_end")
    lines = [
        "",
        f"Speed versus accuracy ({fmt(sweep[0]['receivers'])} receivers: the central quarter of "
        "the frames' grid, 2 threads, median of 3 frames; build/bench/blockers.json, chart "
        "build/bench/blockers.svg; load average " + ("-" if load is None else f"{load:.2f}") +
        " at the end). Each cell: ms / frame, then the irradiance's relative RMS difference against "
        "all pairs at the same bands and, in brackets, against all pairs at 5 bands; **bold**: the "
        f"best trade-off ({rec['best_tradeoff_rule']}, error_budget {pct(rec['error_budget'])}):",
        "",
        "| scene | method | min_sin | far_error | " + " | ".join(f"{b} bands" for b in bands) + " |",
        "| --- | --- | --- | --- | " + " | ".join("---" for _ in bands) + " |",
    ]
    for (scene, method, min_sin, far_error), by_bands in rows.items():
        cells = []
        for b in bands:
            x = by_bands.get(b)
            if x is None:
                cells.append("-")
                continue
            cell = f"{fmt(x['ms'])} ms, {pct(x['rel_rms_error'])} ({pct(x['rel_rms_error_vs_5_bands'])})"
            cells.append(f"**{cell}**" if x["case"] in best else cell)
        lines.append(f"| {scene} | {method} | {fmt(min_sin) if method != 'all_pairs' else '0'} | "
                     f"{'-' if far_error is None else fmt(far_error)} | " + " | ".join(cells) + " |")
    return lines


def blocker_brief(summary, rec):
    """The README's short blockers table: the 400-blocker frames and the sweep's best trade-offs."""
    load = summary.get("load_avg") or [None]
    frames = [x for x in rec["records"] if x["kind"] == "frame" and x["blockers"] == 400]
    lines = [
        f"Measured {summary['date']} on {summary['num_cpus']} CPUs, load average "
        + " / ".join(f"{x:.2f}" for x in load if x is not None)
        + " at the start (`./penumbra bench blockers`, build/bench/blockers.json).",
        "",
        "| frame: 400 spheres, 4 bands | receivers | ms / frame | speed-up vs all pairs "
        "| irradiance vs all pairs: rel RMS, max | goal |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for x in frames:
        goal = "-"
        if x.get("goal_ms") is not None and x["method"] != "all_pairs":
            goal = f"<= {fmt(x['goal_ms'])} ms: {'met' if x['goal_met'] else 'missed'}"
        err = "-" if x["method"] == "all_pairs" else f"{pct(x['rel_rms_error'])}, {pct(x['max_rel_error'])}"
        lines.append(f"| {x['scene']} {x['method']} | {fmt(x['receivers'])} | {fmt(x['ms'])} | "
                     f"{fmt(x['speedup_vs_all_pairs'])} | {err} | {goal} |")
    by_key = {x["case"]: x for x in rec["records"]}
    for scene, key in rec.get("best_tradeoff", {}).items():
        x = by_key[key]
        p = x["params"]
        what = f"{x['method']}, {x['bands']} bands, min_sin {fmt(p['min_sin'])}" + (
            f", far_error {fmt(p['far_error'])}" if "far_error" in p else "")
        base = fmt(x["baseline_ms"])
        lines.append(
            f"\nSweep, {scene} ({fmt(x['receivers'])} receivers), fastest within "
            f"{pct(rec['error_budget'])} of all pairs: {what}: {fmt(x['ms'])} ms against all pairs' "
            f"{base} ms, rel RMS {pct(x['rel_rms_error'])} (vs 5 bands {pct(x['rel_rms_error_vs_5_bands'])}).")
    return "\n".join(lines)


def sl_records(path="build/bench/spherical_lights.json"):
    with open(path) as f:
        return json.load(f)


def sl_frames(rec):
    """The spherical_lights group's frames: every record, goal frames first."""
    load = rec.get("load_avg_at_end")
    lines = [
        "",
        "Frames (2 threads, median of the repetitions; build/bench/spherical_lights.json, chart "
        "build/bench/spherical_lights.svg; load average " + ("-" if load is None else f"{load:.2f}")
        + " at the end; errors: indirect irradiance against the reference's one bounce, "
        "RGB, at every 100th or 21st receiver; sum: ours / reference):",
        "",
        "| kind | scene | blocking | method | min_sin | far_ratio | ms | floor (ms / floor) | goal | "
        "views, log caps, exps, far SLs per receiver | rel RMS, max vs reference | sum | "
        "rel RMS vs per receiver |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for x in rec["records"]:
        p = x["params"]
        goal = "-"
        if x.get("goal_ms") is not None:
            goal = f"<= {fmt(x['goal_ms'])} ms: {'met' if x['goal_met'] else 'missed'}"
        blocking, method = x["method"].split(" ")
        far = fmt(p["far_ratio"]) if p.get("clusters") else "-"
        floor = "-" if x.get("floor_ms") is None else f"{fmt(x['floor_ms'])} ({fmt(x['ratio_to_floor'])}x)"
        work = ", ".join(fmt(x.get(k)) for k in ("views_per_receiver", "logs_per_receiver",
                                                  "exponentials_per_receiver", "far_per_receiver"))
        lines.append(
            f"| {x['kind']} | {x['scene']} | {blocking} | {method} | {fmt(p['min_sin'])} | {far} | "
            f"{fmt(x['ms'])} | {floor} | {goal} | {work} | "
            f"{pct(x.get('rel_rms_error'))}, {pct(x.get('max_rel_error'))} | "
            f"{fmt(x.get('sum_vs_reference'))} | {pct(x.get('rel_rms_vs_per_receiver'))} |")
    return lines


def sl_brief(summary, rec):
    """The README's short spherical_lights table: the goal frames."""
    load = summary.get("load_avg") or [None]
    lines = [
        f"Measured {summary['date']} on {summary['num_cpus']} CPUs, load average "
        + " / ".join(f"{x:.2f}" for x in load if x is not None)
        + " at the start (`./penumbra bench spherical_lights`, build/bench/spherical_lights.json).",
        "",
        "| frame, 2 threads | receivers x SLs | ms / frame | speed-up vs per receiver | floor "
        "(ms / floor) | indirect vs reference: rel RMS | goal |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    frames = [x for x in rec["records"] if x["kind"] == "frame"]
    per_receiver = {(x["scene"], x["params"]["blocking"]): x["ms"] for x in frames
                    if not x["params"].get("clusters")}
    for x in frames:
        goal = f"<= {fmt(x['goal_ms'])} ms: {'met' if x['goal_met'] else 'missed'}"
        base = per_receiver.get((x["scene"], x["params"]["blocking"]))
        speed = fmt(base / x["ms"]) if base and x.get("ms") else "-"
        floor = "-" if x.get("floor_ms") is None else f"{fmt(x['floor_ms'])} ({fmt(x['ratio_to_floor'])}x)"
        lines.append(f"| {x['scene']} {x['method']} | {x['receivers']:,.0f} x {x['lights']:.0f} | "
                     f"{fmt(x['ms'])} | {speed} | {floor} | {pct(x.get('rel_rms_error'))} | {goal} |")
    return "\n".join(lines)


def probe_records(path="build/bench/probes.json"):
    with open(path) as f:
        return json.load(f)


def probe_tetra(rec):
    """The probes group's tetrahedralizations: ours against tetgen, time and tetrahedra."""
    ours = [x for x in rec["records"] if x["kind"] == "tetrahedralize" and x["method"] == "ours"]
    lines = [
        "",
        "Tetrahedralization against Debian `tetgen -QNEF` on the same points in the same run "
        "(tetgen: process wall time, start and .node read included; CPU: ours the thread's, "
        "tetgen the process's user + system time; build/bench/probes.json):",
        "",
        "| points | count | ours, ms | tetgen, ms | tetgen / ours | CPU ms: ours, tetgen (tetgen / ours) "
        "| tetrahedra: ours, tetgen |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for x in ours:
        t, b = x.get("tetrahedra"), x.get("baseline_tetrahedra")
        same = "-" if t is None or b is None else ("equal" if t == b else "differ")
        c, bc = x.get("cpu_ms"), x.get("baseline_cpu_ms")
        cpu_ratio = bc / c if c and bc is not None else None
        lines.append(f"| {x['scene']} | {fmt(x['size'])} | {fmt(x['ms'])} | {fmt(x['baseline_ms'])} | "
                     f"{fmt(x['speedup_vs_baseline'])} | {fmt(c)}, {fmt(bc)} ({fmt(cpu_ratio)}) | "
                     f"{fmt(t)}, {fmt(b)} ({same}) |")
    return lines


def probe_frames(rec):
    frames = [x for x in rec["records"] if x["kind"] == "frame" and x["method"] != "no_cache"]
    lines = [
        "",
        "Frames: entities moving 8 cm per frame through 10,000 random probes (100 x 100 x 20 m, "
        "3 bands), walk from the cached cell + interpolation, 2 threads; `walk`: locate_batch in a "
        "2-thread arena (baseline: the same without a cache), `system`: probes.walk on "
        "jobs::Executor(2) (baseline: the walk row):",
        "",
        "| entities | method | ms / frame | baseline, ms | speed-up | floor ms (ms / floor) | "
        "steps / entity | bytes / entity | goal |",
        "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
    ]
    for x in frames:
        goal = "-" if x.get("goal_ms") is None else (
            f"<= {fmt(x['goal_ms'])} ms: {'met' if x['goal_met'] else 'missed'}")
        lines.append(f"| {fmt(x['size'])} | {x['method']} | {fmt(x['ms'])} | {fmt(x['baseline_ms'])} | "
                     f"{fmt(x['speedup_vs_baseline'])} | {fmt(x['floor_ms'])} ({fmt(x['ratio_to_floor'])}x) | "
                     f"{fmt(x['steps_per_entity'])} | {fmt(x['bytes_per_entity'])} | {goal} |")
    return lines


def probe_sweep(rec):
    sweep = [x for x in rec["records"] if x["kind"] == "sweep"]
    if not sweep:
        return []
    load = rec.get("load_avg_at_end")
    lines = [
        "",
        "Speed versus accuracy (the accuracy tests' scene: ground, two boxes, lobe sky; a frame of "
        f"{fmt(sweep[0]['size'])} moving entities, 2 threads; the interpolated irradiance against "
        "the reference at 800 points x 6 normals; load average "
        + ("-" if load is None else f"{load:.2f}") + " at the end; **bold**: the best trade-off, "
        f"{rec['best_tradeoff_rule']}; chart build/bench/probes.svg):",
        "",
        "| cloud | bands | probes | ms / frame | rel RMS (interior, edge, outside) | max | "
        "reference noise |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for x in sweep:
        cell = (f"{pct(x['rel_rms_error'])} ({pct(x['rel_rms_error_interior'])}, "
                f"{pct(x['rel_rms_error_edge'])}, {pct(x['rel_rms_error_outside'])})")
        if x["case"] == rec.get("best_tradeoff"):
            cell = f"**{cell}**"
        probes = "-" if x.get("probes") is None else f"{x['probes']:,.0f}"
        lines.append(f"| {x['method']} | {x['bands']} | {probes} | {fmt(x['ms'])} | {cell} | "
                     f"{pct(x['max_rel_error'])} | {pct(x['reference_rel_se'])} |")
    return lines


def probe_tables(rec):
    return probe_tetra(rec) + probe_frames(rec) + probe_sweep(rec)


def probe_brief(summary, rec):
    """The README's short probes table: tetrahedralization against tetgen (uniform points), the
    10k / 100k frames and the best trade-off."""
    load = summary.get("load_avg") or [None]
    by = {(x["kind"], x["scene"], x["method"], x["size"]): x for x in rec["records"]}
    lines = [
        f"Measured {summary['date']} on {summary['num_cpus']} CPUs, load average "
        + " / ".join(f"{x:.2f}" for x in load if x is not None)
        + " at the start (`./penumbra bench probes`, build/bench/probes.json).",
        "",
        "| case | ours | same-run baseline | ratio | goal |",
        "| --- | --- | --- | --- | --- |",
    ]
    for x in rec["records"]:
        if x["kind"] == "tetrahedralize" and x["method"] == "ours" and x["scene"] == "uniform":
            ok = x["speedup_vs_baseline"] is not None and x["speedup_vs_baseline"] >= 1
            lines.append(f"| tetrahedralize {fmt(x['size'])} uniform points | {fmt(x['ms'])} ms | "
                         f"tetgen {fmt(x['baseline_ms'])} ms | {fmt(x['speedup_vs_baseline'])}x | "
                         f"at least tetgen's speed: {'met' if ok else 'missed'} |")
        if x["kind"] == "frame" and x["method"] != "no_cache":
            goal = "-" if x.get("goal_ms") is None else (
                f"<= {fmt(x['goal_ms'])} ms: {'met' if x['goal_met'] else 'missed'}")
            base = "no cache" if x["method"] == "walk" else "locate_batch"
            what = "locate_batch" if x["method"] == "walk" else "the system (probes.walk)"
            lines.append(f"| frame, {fmt(x['size'])} moving entities, {what}, 2 threads | {fmt(x['ms'])} ms | "
                         f"{base} {fmt(x['baseline_ms'])} ms | {fmt(x['speedup_vs_baseline'])}x | {goal} |")
    for row in summary["rows"]:
        if row["name"].startswith("anchor:") and row.get("value") is not None:
            lines.append(f"| 2,000 queries (walk + interpolation), 1 thread | {fmt(row['value'])} ms | "
                         f"Unity anchor: < 1 ms on an iPad 2 | {fmt(row.get('ratio'))}x | "
                         f"<= 1 ms: {'met' if row['status'] == 'PASS' else 'missed'} |")
    best = {x["case"]: x for x in rec["records"]}.get(rec.get("best_tradeoff"))
    if best:
        lines.append(
            f"\nBest trade-off of the sweep: {best['method']}, {best['bands']} bands: "
            f"{fmt(best['ms'])} ms per {fmt(best['size'])}-entity frame, irradiance rel RMS "
            f"{pct(best['rel_rms_error'])} against the reference.")
    return "\n".join(lines)


def probe_bake_records(path="build/bench/probe_bake.json"):
    with open(path) as f:
        return json.load(f)


def mega(v):
    return "-" if v is None else f"{v / 1e6:.3g} M"


def count(v):
    return "-" if v is None else f"{v:,.0f}"


def metres(v):
    return "-" if v is None else f"{v:g} m"


def loads(values):
    return " / ".join(f"{x:.2f}" for x in values if x is not None) or "-"


def probe_bake_table(summary, rec):
    """The probe_bake group (docs/probe_bake.md, "Benchmarks"): the bakes, the floor (bare ray
    rates and the summary's ratios), placement per method, and the placement sweep."""
    records = rec["records"]
    by = {x["case"]: x for x in records}

    def c(case, name):
        x = by.get(case)
        return None if x is None else x["counters"].get(name)

    lines = [
        f"Measured {summary['date']} on {summary['num_cpus']} CPUs, load average "
        f"{loads(summary.get('load_avg') or [])} at the start and {loads(rec.get('load_avg_at_end') or [])} "
        "at the end (1, 5, 15 min, as `uptime` prints them; `./penumbra bench probe_bake`, "
        "build/bench/probe_bake_summary.json and build/bench/probe_bake.json).",
        "",
        "| case | probes | rays | time | per probe | per ray | rays/s |",
        "| --- | --- | --- | --- | --- | --- | --- |",
    ]
    for x in records:
        if x["kind"] != "bake":
            continue
        k = x["case"]
        lines.append(
            f"| bake {x['scene']}, {metres(x['params'].get('spacing'))} | {count(x['probes'])} "
            f"({count(c(k, 'placed'))} placed) | "
            f"{mega(c(k, 'rays'))} ({fmt(c(k, 'rays_per_probe'))} / probe) | {fmt(x['ms'])} ms | "
            f"{fmt(c(k, 'us_per_probe'))} us | {fmt(c(k, 'ns_per_ray'))} ns | "
            f"{mega(x['rays_per_s'])} (capture {mega(c(k, 'capture_rays_per_s'))}) |")

    scenes = [x["scene"] for x in records if x["kind"] == "bake"]
    cols = [(s, t) for s in scenes for t in (1, 2)]
    lines += [
        "",
        "| floor (random rays) | " + " | ".join(f"{s}, {t} thread{'s' if t > 1 else ''}" for s, t in cols)
        + " |",
        "| --- |" + " --- |" * len(cols),
    ]
    floor_key = {"occluded": "BM_RaysOccluded", "first_hit": "BM_RaysFirstHit"}
    for method, prefix in floor_key.items():
        cells = [mega(by.get(f"{prefix}/{s}/threads:{t}", {}).get("rays_per_s")) + "/s" for s, t in cols]
        lines.append(f"| `{method}` | " + " | ".join(cells) + " |")
    rows = {row["name"]: row for row in summary["rows"]}
    for label, what in (("bake rays/s / `first_hit` floor", "bake rays/s vs first_hit"),
                        ("bake capture rays/s / `occluded` floor", "bake capture rays/s vs occluded")):
        cells = [fmt((rows.get(f"{s}: {what} threads:{t}") or {}).get("ratio")) for s, t in cols]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    hits = ", ".join(f"{s} {pct(c(f'BM_RaysFirstHit/{s}/threads:1', 'hit_fraction'))}" for s in scenes)
    lines += ["", f"Share of the random rays that hit (`first_hit`, 1 thread): {hits}."]

    lines += ["", "| placement (room) | time | counts |", "| --- | --- | --- |"]
    g1, g2 = by.get("BM_PlaceGrid/100"), by.get("BM_PlaceGrid/25")
    if g1 and g2:
        lines.append(f"| grid 1 m / 0.25 m | {fmt(g1['ms'] * 1e3)} us / {fmt(g2['ms'] * 1e3)} us | "
                     f"{count(g1['probes'])} / {count(g2['probes'])} points |")
    for key, what in (("BM_PlaceSpawnMerge", "spawn-merge (1.5 m, cap 500, 2 iterations)"),
                      ("BM_PlaceGradient", "gradient (1.5 m, 3 iterations)")):
        x = by.get(key)
        if not x:
            continue
        lines.append(f"| {what} | {fmt(x['ms'])} ms | {count(c(key, 'initial'))} -> "
                     f"{count(c(key, 'placed'))} probes, {count(c(key, 'iterations'))} iterations, "
                     f"{count(c(key, 'captured'))} captures, {mega(c(key, 'placement_rays_per_s'))} rays/s |")
    e1, e2 = by.get("BM_EdgeRays/150"), by.get("BM_EdgeRays/100")
    if e1 and e2:
        k1, k2 = e1["case"], e2["case"]
        lines.append(f"| edge rays, one round, 1.5 m / 1 m grid | {fmt(e1['ms'])} ms / {fmt(e2['ms'])} ms | "
                     f"{count(c(k1, 'edges'))} / {count(c(k2, 'edges'))} edges, {count(c(k1, 'hits'))} / "
                     f"{count(c(k2, 'hits'))} hits, {count(c(k1, 'added'))} / {count(c(k2, 'added'))} added |")

    sweep = [x for x in records if x["kind"] == "sweep"]
    if sweep:
        ref = rec.get("reference_seconds")
        p0 = sweep[0]["params"]
        lines += [
            "",
            f"Placement sweep in the room (each point baked with {p0['samples']} samples, validity "
            f"{'on' if p0['validity'] else 'off'}, edge rays only where the method names them; "
            f"bake: its wall time, median of {rec.get('sweep_repetitions', 1)}, placement: the adaptive placement in it; rel. RMS over "
            "the 120 free-space points of the accuracy tests, dark / lit side: over the 60 points on "
            "each side of the inner wall (dark: the leak metric); reference computed once in "
            + ("-" if ref is None else f"{ref:.1f} s") + "; **bold**: on the Pareto front of bake time "
            "and rel. RMS; chart build/bench/probe_bake.svg; load average at the end "
            + loads(rec.get("load_avg_at_end") or []) + "):",
            "",
            "| method | start spacing | spawn threshold | probes | rel. RMS | dark side | lit side | "
            "placement | bake |",
            "| --- | --- | --- | --- | --- | --- | --- | --- | --- |",
        ]
        for x in sweep:
            p = x["params"]
            err = fmt(x["rel_rms_error"])
            if x.get("pareto_front"):
                err = f"**{err}**"
            place = "-" if x.get("placement_ms") is None else f"{fmt(x['placement_ms'])} ms"
            lines.append(f"| {x['method']} | {metres(p['spacing'])} | {fmt(p.get('spawn_contrast'))} | "
                         f"{count(x['probes'])} | {err} | {fmt(x['dark_side'])} | {fmt(x['lit_side'])} | "
                         f"{place} | {fmt(x['ms'])} ms |")
        grids = [x for x in sweep if x["method"] == "grid"]
        adaptive = [x for x in sweep if not x["method"].startswith("grid")]
        checks = []
        for g in grids:
            met = [a for a in adaptive if a["rel_rms_error"] is not None and g["rel_rms_error"] is not None
                   and a["rel_rms_error"] <= g["rel_rms_error"] and 2 * a["probes"] <= g["probes"]]
            checks.append(f"{metres(g['params']['spacing'])} ({count(g['probes'])} probes, "
                          f"{fmt(g['rel_rms_error'])}): "
                          + (", ".join(f"{a['method']} {count(a['probes'])}" for a in met) if met else "no"))
        lines += ["", "An adaptive cloud with at most half a grid's probes and at most its error "
                  "(issue 14's hypothesis), per grid: " + "; ".join(checks) + "."]
    return "\n".join(lines)


# The terrain group's headline rows for the README (<!-- bench-table:terrain-brief:begin/end -->):
# name prefix in the summary -> label.
TERRAIN_BRIEF = [
    ("env update 256^2 sweep", "environment update (sweep horizons + transfer), 256^2, n_phi 32"),
    ("horizons alone, sweep", "horizons alone, sweep"),
    ("transfer alone", "transfer alone"),
    ("1 spherical light (default", "one spherical light (cap horizon, default)"),
    ("local edit 16x16", "brush edit, 16x16 texels"),
    ("shading only", "rotating environment (re-shade from stored transfer)"),
    ("env update 1024^2", "1024x1024, n_phi 64"),
    ("machine moment", "the machine's moment: one-thread sweep on the slower vCPU, worst of the "
     "probes before each case (each in the note)"),
]


def terrain_brief(summary):
    load = summary.get("load_avg") or [None]
    lines = [
        f"Measured {summary['date']} on {summary['num_cpus']} CPUs, load average {load[0]:.2f} at the "
        "start (`./penumbra bench terrain`, build/bench/terrain_summary.json).",
        "",
        "| case | ms | floor (ms / floor) | same-run ratio | goal | note |",
        "| --- | --- | --- | --- | --- | --- |",
    ]
    for prefix, label in TERRAIN_BRIEF:
        row = next((r for r in summary["rows"] if r["name"].strip().startswith(prefix)), None)
        if row is None:
            continue
        goal = row.get("goal")
        goal_text = f"{goal['op']} {fmt(goal['target'])}: {row['status']}" if goal else "-"
        ratio_text, floor_text = ratio_and_floor(row)
        lines.append(f"| {label} | {fmt(row.get('value'))} | {floor_text} | {ratio_text} | "
                     f"{goal_text} | {row.get('note', '')} |")
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
        brief = f"<!-- bench-table:{group}-brief:begin -->"
        if group == "terrain":
            with open(target) as f:
                if "<!-- bench-table:terrain-brief:begin -->" in f.read():
                    write_between(target, "<!-- bench-table:terrain-brief:begin -->",
                                  "<!-- bench-table:terrain-brief:end -->", terrain_brief(record))
                    continue
        if group in ("blockers", "probes", "spherical_lights"):
            with open(target) as f:
                if brief in f.read():
                    short = (blocker_brief(record, blocker_records()) if group == "blockers"
                             else probe_brief(record, probe_records()) if group == "probes"
                             else sl_brief(record, sl_records()))
                    write_between(target, brief, brief.replace(":begin", ":end"), short)
                    continue
        write_between(target, begin, end, text)


if __name__ == "__main__":
    main(sys.argv[1:])

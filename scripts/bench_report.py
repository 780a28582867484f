#!/usr/bin/env python3
"""Writes one self-contained HTML report of every benchmark group from its JSON in build/bench.

    ./penumbra bench            # all groups, then this script -> build/bench/report.html
    ./penumbra bench report     # this script alone, from the JSON already there
    python3 scripts/bench_report.py [--dir build/bench] [-o build/bench/report.html]

Viewable offline: inline CSS, the groups' SVG charts embedded inline, no script, font or link
to anything outside the file. At the top, one row per group: date, CPUs, load average and the
goal counts (PASS / MISS / N/A); groups with no GROUP_summary.json are listed as "not run". Then
per group: the machine as its JSON records it, the summary table (cases, values, ratios,
floors and value / floor, goals and their status), its charts (GROUP.svg, GROUP_*.svg; the
Pareto front is drawn by the chart writer), and the tables scripts/bench_table.py writes from
the group's records. Then the main job's headline numbers from play.json (scripts/play_table.py)
with its systems' CPU time and work done / skipped per frame,
and last the stability table from stability.json (scripts/stability_table.py, `./penumbra
stability`) when it is there.
Every text taken from the JSON is escaped. Standard library only.
"""
import argparse
import datetime
import html
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_table  # noqa: E402  (fmt, loads and the records' tables)
import play_table  # noqa: E402

# The groups `./penumbra bench` runs, in its order (play is the main job's record, last). Any
# other GROUP_summary.json found in the folder is reported too.
GROUPS = ["ecs", "sh", "reference", "render", "terrain", "blockers", "probes", "spherical_lights",
          "probe_bake", "environment"]

# The play record's goals, as scripts/play_table.py's table states them (docs/play.md).
PLAY_GOALS = [
    ("frame rate", lambda r: r["frame"]["fps"], ">=", 30.0, "fps"),
    ("median frame / empty frame", lambda r: r["frame"]["x_empty_frame"], "<=", 4.0, "x"),
    ("light tiles re-shaded per frame / tiles", lambda r: r["lights"]["tiles_per_frame"] / r["lights"]["tiles"],
     "<=", 0.25, ""),
]

CSS = """
body { font-family: sans-serif; font-size: 14px; margin: 1.5em; color: #222; max-width: 1400px; }
h1 { font-size: 1.5em; } h2 { font-size: 1.25em; margin-top: 2em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; margin: 0.6em 0; }
th, td { border: 1px solid #ccc; padding: 2px 6px; text-align: left; vertical-align: top; }
th { background: #f0f0f0; }
td.num { text-align: right; white-space: nowrap; }
.PASS { background: #d9f2d9; } .MISS { background: #f7d4d4; } .NA { background: #f5ecc8; }
.notrun { color: #888; font-style: italic; }
.machine { color: #444; }
figure { margin: 1em 0; } figcaption { color: #666; font-size: 0.9em; }
figure svg { max-width: 100%; height: auto; border: 1px solid #ddd; }
details { margin: 0.8em 0; } summary { cursor: pointer; color: #335; }
code { background: #f4f4f4; padding: 0 2px; }
"""


def esc(v):
    return html.escape("" if v is None else str(v), quote=True)


def read_json(path):
    with open(path) as f:
        return json.load(f)


def load_text(values):
    """A load average: a list (1, 5, 15 min) or one number."""
    if values is None:
        return "-"
    if isinstance(values, (int, float)):
        return f"{values:.2f}"
    return bench_table.loads(values)


def status_class(status):
    return {"PASS": "PASS", "MISS": "MISS", "N/A": "NA"}.get(status, "")


def counts(rows):
    out = {"PASS": 0, "MISS": 0, "N/A": 0}
    for row in rows:
        if row.get("status") in out:
            out[row["status"]] += 1
    return out


def cpu_model(*objs):
    """A CPU model string from records that hold one (cpu_model, cpu or machine.cpu)."""
    for o in objs:
        if not isinstance(o, dict):
            continue
        for k in ("cpu_model", "cpu"):
            if isinstance(o.get(k), str):
                return o[k]
        m = o.get("machine")
        if isinstance(m, dict) and isinstance(m.get("cpu"), str):
            return m["cpu"]
        c = o.get("context")
        if isinstance(c, dict) and isinstance(c.get("cpu_model"), str):
            return c["cpu_model"]
    return None


def md_inline(text):
    t = esc(text)
    t = re.sub(r"\*\*(.+?)\*\*", r"<strong>\1</strong>", t)
    return re.sub(r"`([^`]+)`", r"<code>\1</code>", t)


def md_to_html(text):
    """The markdown scripts/bench_table.py and play_table.py write (paragraphs and pipe tables)
    as HTML."""
    out, lines, i = [], text.split("\n"), 0
    while i < len(lines):
        if lines[i].startswith("|"):
            rows = []
            while i < len(lines) and lines[i].startswith("|"):
                rows.append([c.strip() for c in lines[i].strip().strip("|").split("|")])
                i += 1
            head, body = rows[0], [r for r in rows[1:] if not all(re.fullmatch(r":?-+:?", c) for c in r)]
            out.append("<table>\n<tr>" + "".join(f"<th>{md_inline(c)}</th>" for c in head) + "</tr>")
            out += ["<tr>" + "".join(f"<td>{md_inline(c)}</td>" for c in r) + "</tr>" for r in body]
            out.append("</table>")
        elif lines[i].strip():
            para = []
            while i < len(lines) and lines[i].strip() and not lines[i].startswith("|"):
                para.append(lines[i])
                i += 1
            out.append(f"<p>{md_inline(' '.join(para))}</p>")
        else:
            i += 1
    return "\n".join(out)


def embed_svg(path):
    """The chart's markup, inline: no XML prolog, no namespace URL (HTML puts <svg> in its
    namespace), nothing active."""
    with open(path) as f:
        text = f.read()
    start, end = text.find("<svg"), text.rfind("</svg>")
    if start < 0 or end < 0:
        return None, "not an SVG document"
    text = text[start:end + len("</svg>")]
    text = re.sub(r'\s+xmlns(:\w+)?\s*=\s*"[^"]*"', "", text)
    if re.search(r"<script|<foreignObject|<[^>]*\son\w+\s*=", text, re.I):
        return None, "holds script or event attributes"
    if re.search(r"https?://", text, re.I):
        return None, "references an external URL"
    return text, None


def charts_by_group(folder, groups):
    """Each .svg in the folder under the group whose name is its longest prefix (GROUP.svg,
    GROUP_*.svg), GROUP.svg first."""
    out = {g: [] for g in groups}
    try:
        names = sorted(os.listdir(folder))
    except OSError:
        names = []
    for name in names:
        if not name.endswith(".svg"):
            continue
        stem = name[:-4]
        owners = [g for g in groups if stem == g or stem.startswith(g + "_")]
        if owners:
            g = max(owners, key=len)
            out[g].append(name)
    for g in out:
        out[g].sort(key=lambda n: (n != f"{g}.svg", n))
    return out


def record_tables(group, folder, summary):
    """The markdown tables bench_table.py writes from the group's records, or None."""
    p = lambda name: os.path.join(folder, name)  # noqa: E731
    if group == "blockers":
        return "\n".join(bench_table.blocker_frames(p("blockers_gbench.json"))
                         + bench_table.blocker_sweep(bench_table.blocker_records(p("blockers.json"))))
    if group == "spherical_lights":
        return "\n".join(bench_table.sl_frames(bench_table.sl_records(p("spherical_lights.json"))))
    if group == "probes":
        return "\n".join(bench_table.probe_tables(bench_table.probe_records(p("probes.json"))))
    if group == "probe_bake":
        return bench_table.probe_bake_table(summary, bench_table.probe_bake_records(p("probe_bake.json")))
    return None


def summary_table(rows):
    fmt = bench_table.fmt
    out = ["<table class=\"summary\">",
           "<tr><th>case</th><th>value</th><th>ratio</th><th>floor</th><th>value / floor</th>"
           "<th>goal</th><th>status</th><th>note</th></tr>"]
    for row in rows:
        ratio = row.get("ratio")
        ratio_text = "-" if ratio is None else f"{ratio:.3g} ({row.get('ratio_def') or 'baseline/value'})"
        floor = row.get("floor")
        goal = row.get("goal")
        goal_text = f"{goal.get('metric')} {goal.get('op')} {fmt(goal.get('target'))}" if goal else "-"
        status = row.get("status", "")
        out.append(
            f"<tr><td>{esc(str(row.get('name', '')).strip())}</td>"
            f"<td class=\"num\">{esc(fmt(row.get('value')))} {esc(row.get('unit', ''))}</td>"
            f"<td>{esc(ratio_text)}</td>"
            f"<td class=\"num\">{esc('-' if floor is None else fmt(floor))}</td>"
            f"<td class=\"num\">{esc('-' if floor is None else fmt(row.get('floor_ratio')) + 'x')}</td>"
            f"<td>{esc(goal_text)}</td><td class=\"{status_class(status)}\">{esc(status)}</td>"
            f"<td>{esc(row.get('note', ''))}</td></tr>")
    out.append("</table>")
    return "\n".join(out)


def group_section(group, folder, charts, play_cpu):
    """(top summary row, section HTML) for one group."""
    path = os.path.join(folder, f"{group}_summary.json")
    anchor = f"g-{esc(group)}"
    head = f"<section id=\"{anchor}\">\n<h2>{esc(group)}</h2>"
    if not os.path.exists(path):
        row = (f"<tr><td><a href=\"#{anchor}\">{esc(group)}</a></td>"
               f"<td class=\"notrun\" colspan=\"7\">not run (no {esc(path)})</td></tr>")
        return row, f"{head}\n<p class=\"notrun\">not run: no {esc(path)}</p>\n</section>"
    try:
        summary = read_json(path)
        rows = summary["rows"]
    except (OSError, ValueError, KeyError, TypeError) as e:
        row = (f"<tr><td><a href=\"#{anchor}\">{esc(group)}</a></td>"
               f"<td class=\"MISS\" colspan=\"7\">unreadable summary: {esc(e)}</td></tr>")
        return row, f"{head}\n<p class=\"MISS\">unreadable {esc(path)}: {esc(e)}</p>\n</section>"

    records = gbench = None
    for name in (f"{group}.json", f"{group}_gbench.json"):
        try:
            obj = read_json(os.path.join(folder, name))
        except (OSError, ValueError):
            continue
        if isinstance(obj, dict) and "benchmarks" in obj and "context" in obj:
            gbench = obj
        else:
            records = obj
    context = (gbench or {}).get("context") or {}
    end_load = records.get("load_avg_at_end") if isinstance(records, dict) else None
    model = cpu_model(summary, records, gbench)
    model_text = (esc(model) if model else
                  "not in this group's records" + (f" (the play record: {esc(play_cpu)})" if play_cpu else ""))
    c = counts(rows)
    cpus = summary.get("num_cpus", "-")
    mhz = summary.get("mhz_per_cpu")
    machine = (f"<p class=\"machine\">Measured {esc(summary.get('date', '-'))} on {esc(cpus)} CPUs"
               + (f" at {esc(mhz)} MHz" if mhz else "")
               + (f", host {esc(context['host_name'])}" if context.get("host_name") else "")
               + f"; CPU model: {model_text}; load average {esc(load_text(summary.get('load_avg')))} "
               "(1, 5, 15 min) at the start"
               + (f", {esc(load_text(end_load))} at the end" if end_load is not None else "")
               + f". Goals: PASS {c['PASS']}, MISS {c['MISS']}, N/A {c['N/A']}; "
               f"<code>{esc(path)}</code>.</p>")
    parts = [head, machine, summary_table(rows)]
    for name in charts:
        svg, why = embed_svg(os.path.join(folder, name))
        caption = esc(os.path.join(folder, name))
        if svg is None:
            parts.append(f"<p class=\"notrun\">chart {caption} not embedded: {esc(why)}</p>")
        else:
            parts.append(f"<figure>\n{svg}\n<figcaption>{caption}</figcaption>\n</figure>")
    try:
        tables = record_tables(group, folder, summary)
        if tables:
            parts.append("<details><summary>Tables from the records (scripts/bench_table.py)</summary>\n"
                         + md_to_html(tables) + "\n</details>")
    except Exception as e:  # a record of another shape: the rest of the report still stands
        parts.append(f"<p class=\"notrun\">record tables not rendered: {esc(type(e).__name__)}: {esc(e)}</p>")
    parts.append("</section>")
    row = (f"<tr><td><a href=\"#{anchor}\">{esc(group)}</a></td><td>{esc(summary.get('date', '-'))}</td>"
           f"<td class=\"num\">{esc(cpus)}</td><td>{esc(load_text(summary.get('load_avg')))}</td>"
           f"<td class=\"num {'PASS' if c['PASS'] else ''}\">{c['PASS']}</td>"
           f"<td class=\"num {'MISS' if c['MISS'] else ''}\">{c['MISS']}</td>"
           f"<td class=\"num\">{c['N/A']}</td><td class=\"num\">{len(charts)}</td></tr>")
    return row, "\n".join(parts)


def play_goal_rows(record):
    out = []
    for label, get, op, target, unit in PLAY_GOALS:
        try:
            v = get(record)
        except (KeyError, TypeError, ZeroDivisionError):
            out.append((label, None, op, target, unit, "N/A"))
            continue
        ok = v >= target if op == ">=" else v <= target
        out.append((label, v, op, target, unit, "PASS" if ok else "MISS"))
    return out


def play_section(folder):
    path = os.path.join(folder, "play.json")
    anchor = "g-play"
    head = f"<section id=\"{anchor}\">\n<h2>play (the main job)</h2>"
    if not os.path.exists(path):
        row = (f"<tr><td><a href=\"#{anchor}\">play</a></td>"
               f"<td class=\"notrun\" colspan=\"7\">not run (no {esc(path)})</td></tr>")
        return row, f"{head}\n<p class=\"notrun\">not run: no {esc(path)}</p>\n</section>", None
    try:
        record = read_json(path)
    except (OSError, ValueError) as e:
        row = (f"<tr><td><a href=\"#{anchor}\">play</a></td>"
               f"<td class=\"MISS\" colspan=\"7\">unreadable record: {esc(e)}</td></tr>")
        return row, f"{head}\n<p class=\"MISS\">unreadable {esc(path)}: {esc(e)}</p>\n</section>", None
    alone = None
    try:
        alone = read_json(os.path.join(folder, "play_terrain.json"))
    except (OSError, ValueError):
        pass
    m = record.get("machine") or {}
    run = record.get("run") or {}
    goals = play_goal_rows(record)
    c = counts([{"status": g[-1]} for g in goals])
    parts = [head, f"<p class=\"machine\">Measured {esc(record.get('date', '-'))} on {esc(m.get('cpu', '-'))} "
             f"({esc(m.get('cores', '-'))} cores), load average {esc(load_text(m.get('load_average_start')))} "
             f"at the start; {esc(run.get('device', '-'))}, {esc(run.get('width', '-'))}x{esc(run.get('height', '-'))}, "
             f"{esc(run.get('timed_frames', '-'))} timed frames; <code>{esc(path)}</code>.</p>",
             "<table class=\"summary\">\n<tr><th>headline</th><th>measured</th><th>goal</th><th>status</th></tr>"]
    fmt = bench_table.fmt
    for label, v, op, target, unit, status in goals:
        parts.append(f"<tr><td>{esc(label)}</td><td class=\"num\">{esc(fmt(v))} {esc(unit)}</td>"
                     f"<td>{esc(op)} {esc(fmt(target))} {esc(unit)}</td>"
                     f"<td class=\"{status_class(status)}\">{esc(status)}</td></tr>")
    f = record.get("frame") or {}
    for label, key in (("frame time median", "median_ms"), ("frame time p95", "p95_ms"),
                       ("empty frame", "empty_frame_ms"), ("simulation", "simulation_ms"),
                       ("render record + submit", "render_ms"), ("GPU frame", "gpu_frame_ms")):
        if key in f:
            parts.append(f"<tr><td>{esc(label)}</td><td class=\"num\">{esc(fmt(f[key]))} ms</td>"
                         "<td>-</td><td></td></tr>")
    parts.append("</table>")
    systems = record.get("systems") or []
    if systems:  # per system: CPU ms and the work it did and skipped per frame (jobs::report_work)
        parts.append("<details><summary>Per system: CPU time and items done / skipped as unchanged, "
                     "per frame</summary>\n<table>\n<tr><th>system</th><th>mean ms</th><th>max ms</th>"
                     "<th>done / frame</th><th>skipped / frame</th></tr>")
        for r in systems:
            cells = [fmt(r.get(k)) if r.get(k) is not None else "-"
                     for k in ("mean_ms", "max_ms", "done_per_frame", "skipped_per_frame")]
            parts.append(f"<tr><td>{esc(r.get('name'))}</td>"
                         + "".join(f"<td class=\"num\">{esc(c)}</td>" for c in cells) + "</tr>")
        parts.append("</table>\n</details>")
    try:
        parts.append("<details><summary>All the play tables (scripts/play_table.py)</summary>\n"
                     + md_to_html(play_table.tables(record, alone)) + "\n</details>")
    except Exception as e:  # a record of another shape
        parts.append(f"<p class=\"notrun\">play tables not rendered: {esc(type(e).__name__)}: {esc(e)}</p>")
    parts.append("</section>")
    row = (f"<tr><td><a href=\"#{anchor}\">play</a></td><td>{esc(record.get('date', '-'))}</td>"
           f"<td class=\"num\">{esc(m.get('cores', '-'))}</td><td>{esc(load_text(m.get('load_average_start')))}</td>"
           f"<td class=\"num {'PASS' if c['PASS'] else ''}\">{c['PASS']}</td>"
           f"<td class=\"num {'MISS' if c['MISS'] else ''}\">{c['MISS']}</td>"
           f"<td class=\"num\">{c['N/A']}</td><td class=\"num\">0</td></tr>")
    return row, "\n".join(parts), m.get("cpu")


def stability_section(folder):
    """The stability table (scripts/stability_table.py's stability.json), or a line saying how to
    make it."""
    path = os.path.join(folder, "stability.json")
    head = "<section id=\"stability\">\n<h2>Stability</h2>"
    try:
        table = read_json(path)
    except (OSError, ValueError):
        table = None
    if not isinstance(table, dict) or table.get("format") != "penumbra-stability-table":
        return (f"{head}\n<p class=\"notrun\">No stability table ({esc(path)}): "
                "<code>./penumbra stability</code> writes it.</p>\n</section>")
    rows = table.get("rows", [])
    out = [head,
           f"<p>{len(rows)} failure-mode, bad-input and degenerate cases, from the tests' "
           f"PENUMBRA_STABILITY records ({esc(table.get('date', '-'))}; docs/stability.md).</p>",
           "<table>",
           "<tr><th>system</th><th>input</th><th>what happens</th><th>error (measured)</th>"
           "<th>mitigation</th><th>test</th></tr>"]
    for r in rows:
        if r.get("input") is None:
            out.append(f"<tr><td>{esc(r.get('system'))}</td><td class=\"notrun\" colspan=\"4\">"
                       f"no record: run the test</td><td>{esc(r.get('test'))}</td></tr>")
            continue
        out.append("<tr>" + "".join(f"<td>{esc(r.get(k) or '-')}</td>" for k in (
            "system", "input", "behaviour", "error", "mitigation", "test")) + "</tr>")
    out += ["</table>", "</section>"]
    return "\n".join(out)


def report(folder):
    groups = list(GROUPS)
    try:
        found = sorted(n[:-len("_summary.json")] for n in os.listdir(folder) if n.endswith("_summary.json"))
    except OSError:
        found = []
    groups += [g for g in found if g not in groups and g != "play"]
    charts = charts_by_group(folder, groups)
    play = play_section(folder)
    play_cpu = play[2]
    rows, sections = [], []
    for g in groups:
        row, section = group_section(g, folder, charts[g], play_cpu)
        rows.append(row)
        sections.append(section)
    rows.append(play[0])
    sections.append(play[1])
    sections.append(stability_section(folder))
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%dT%H:%M:%SZ")
    return "\n".join([
        "<!DOCTYPE html>",
        "<html lang=\"en\">",
        "<head>",
        "<meta charset=\"utf-8\">",
        "<title>Penumbra benchmark report</title>",
        f"<style>{CSS}</style>",
        "</head>",
        "<body>",
        "<h1>Penumbra benchmark report</h1>",
        f"<p>From the JSON in <code>{esc(folder)}</code> (written by <code>./penumbra bench</code>), "
        f"rendered {now} by <code>scripts/bench_report.py</code>; regenerate with "
        "<code>./penumbra bench report</code>. CPU model as the play record states it: "
        f"{esc(play_cpu or 'not recorded')}.</p>",
        "<h2>Summary</h2>",
        "<table class=\"summary\">",
        "<tr><th>group</th><th>date</th><th>CPUs</th><th>load average at the start (1, 5, 15 min)</th>"
        "<th>PASS</th><th>MISS</th><th>N/A</th><th>charts</th></tr>",
        *rows,
        "</table>",
        *sections,
        "</body>",
        "</html>",
        "",
    ])


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--dir", default="build/bench", help="folder of the groups' JSON (build/bench)")
    ap.add_argument("-o", "--output", default=None, help="the HTML file (DIR/report.html)")
    args = ap.parse_args(argv)
    out = args.output or os.path.join(args.dir, "report.html")
    text = report(args.dir)
    os.makedirs(os.path.dirname(out) or ".", exist_ok=True)
    tmp = out + ".tmp"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, out)
    print(out)


if __name__ == "__main__":
    main(sys.argv[1:])

#!/usr/bin/env python3
"""Renders the benchmark report from the fixture JSON and checks it (ctest bench_report_fixture).

    python3 tests/bench/check_bench_report.py scripts/bench_report.py tests/bench/report_fixture OUT.html

The fixture (tests/bench/report_fixture/) holds two groups' summaries (terrain with a chart and
Google Benchmark's context, environment without), a play record and a stability table (one row
without a record); every other group is missing. Checked: html/head/body present and every element closed (tables included), each
fixture group's heading and a known value from its JSON (the stability rows too), the chart's markup embedded inline,
text from the JSON escaped, the missing groups shown as "not run", and no http(s):// URL, script
or external resource anywhere in the file.
"""
import re
import subprocess
import sys
from html.parser import HTMLParser

VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source",
        "track", "wbr"}


class Report(HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.stack, self.errors, self.seen = [], [], set()
        self.section = None
        self.text = {}  # section id -> its text
        self.headings = {}  # section id -> its h2 text
        self.in_h2 = False
        self.svg_in = {}  # section id -> number of <svg>

    def handle_starttag(self, tag, attrs):
        self.seen.add(tag)
        a = dict(attrs)
        if tag == "section":
            self.section = a.get("id")
        if tag == "h2":
            self.in_h2 = True
        if tag == "svg":
            self.svg_in[self.section] = self.svg_in.get(self.section, 0) + 1
        for k, v in attrs:
            if k in ("src", "href") and v and not v.startswith("#"):
                self.errors.append(f"<{tag} {k}={v!r}>: a reference outside the file")
        if tag not in VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag, attrs):
        self.seen.add(tag)

    def handle_endtag(self, tag):
        if tag in VOID:
            return
        if not self.stack or self.stack[-1] != tag:
            self.errors.append(f"</{tag}> closes <{self.stack[-1] if self.stack else 'nothing'}>")
            if tag in self.stack:
                while self.stack.pop() != tag:
                    pass
            return
        self.stack.pop()
        if tag == "h2":
            self.in_h2 = False
        if tag == "section":
            self.section = None

    def handle_data(self, data):
        self.text[self.section] = self.text.get(self.section, "") + data
        if self.in_h2:
            self.headings[self.section] = self.headings.get(self.section, "") + data


def main(argv):
    script, fixture, out = argv
    subprocess.run([sys.executable, script, "--dir", fixture, "-o", out], check=True)
    with open(out, encoding="utf-8") as f:
        raw = f.read()
    r = Report()
    r.feed(raw)
    r.close()
    fails = list(r.errors)
    if r.stack:
        fails.append(f"elements left open: {r.stack}")
    for tag in ("html", "head", "body", "title", "style", "table"):
        if tag not in r.seen:
            fails.append(f"no <{tag}>")
    if raw.count("<table") != raw.count("</table>"):
        fails.append(f"{raw.count('<table')} tables opened, {raw.count('</table>')} closed")
    if not raw.lstrip().lower().startswith("<!doctype html>"):
        fails.append("no <!DOCTYPE html>")

    # Each fixture group: its heading and a value from its JSON, formatted as bench_table.fmt does.
    expect = {
        "g-terrain": ("terrain", ["12.5 ms", "2.25 ms", "MISS", "PASS", "fixture-host",
                                  "1.25 / 2.50 / 3.75", "1.50 / 2.50 / 3.50 at the end"]),
        "g-environment": ("environment", ["3.88 ms", "62.0x", "2026-01-02T03:10:00+0000"]),
        "g-play": ("play", ["48.5 fps", "Fixture CPU Model 9000", "MISS",
                            "terrain_shadow.lights", "216", "demo_clock"]),
        "stability": ("Stability", ["3 failure-mode", "a thin spike between the sampled azimuths",
                                    "rel. RMS, 8 azimuths = 0.0312", "more azimuths",
                                    "no record: run the test"]),
    }
    for sid, (heading, values) in expect.items():
        if heading not in r.headings.get(sid, ""):
            fails.append(f"section {sid}: no heading {heading!r} (got {r.headings.get(sid)!r})")
        for v in values:
            if v not in r.text.get(sid, ""):
                fails.append(f"section {sid}: {v!r} missing")
    # The summary at the top: terrain's goal counts (1 PASS, 1 MISS) in its row.
    if not re.search(r'href="#g-terrain">terrain</a></td><td>2026-01-02T03:04:05\+0000</td>'
                     r'.*?>1</td><td[^>]*>1</td>', raw):
        fails.append("summary table: no terrain row with PASS 1, MISS 1")

    # The chart: inline, in the terrain section only, without the namespace URL.
    if r.svg_in.get("g-terrain") != 1 or sum(r.svg_in.values()) != 1:
        fails.append(f"SVG charts per section: {r.svg_in} (want one, in g-terrain)")
    if "Fixture chart: time against error" not in r.text.get("g-terrain", ""):
        fails.append("the chart's title is not in the terrain section")

    # Escaping: the note 'escaped: a <b> & "c"' from terrain_summary.json, and a stability row.
    if "escaped: a &lt;b&gt; &amp; &quot;c&quot;" not in raw or "a <b> &" in raw:
        fails.append("the note with <, & and \" is not escaped")
    if "a cloud of &lt;0&gt; probes" not in raw:
        fails.append("the stability table's text is not escaped")

    # Missing groups are listed, not skipped.
    for g in ("ecs", "blockers", "probes", "spherical_lights", "probe_bake"):
        if "not run" not in r.text.get(f"g-{g}", ""):
            fails.append(f"group {g}: not shown as 'not run'")
        if not re.search(rf'href="#g-{g}">{g}</a></td><td class="notrun"[^>]*>not run', raw):
            fails.append(f"summary table: group {g} not listed as 'not run'")

    # Offline: nothing to fetch.
    for pattern in (r"https?://", r"<script", r"<link", r"@import", r"url\("):
        if re.search(pattern, raw, re.I):
            fails.append(f"{pattern!r} in the report")

    for f in fails:
        print("FAIL:", f)
    print(f"{out}: {len(raw)} bytes, {len(fails)} failures")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

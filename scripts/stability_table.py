#!/usr/bin/env python3
"""The stability table (issue 17), generated from the tests themselves.

    ./penumbra stability     # checked build, runs the stability tests without a fresh record,
                             # then writes docs/stability.md and build/bench/stability.json
    python3 scripts/stability_table.py [--build build/checked] [--records DIR] [--source ROOT]
        [--run-missing] [--check] [--json PATH] [--markdown PATH] [--write docs/stability.md]

Every failure-mode, bad-input and degenerate-case test calls PENUMBRA_STABILITY(input, what
happens, mitigation) and, where it measures one, PENUMBRA_STABILITY_MEASURE(what, value)
(tests/common/stability.h). Running the test writes one record per call into the build's
tests/stability folder. This script finds every call in the sources (tests/**/*.cpp, the
registry's own folder tests/common left out), matches it to its record and writes one table:
system (the test's folder), input, what happens, error (the measured values), mitigation, test.

A call whose record is missing, unreadable (bad CRC, format, version) or older than its source
file is "stale": --run-missing runs those tests (their ctest commands, from `ctest
--show-only=json-v1` in the build folder) and reads again; --check exits 1 naming every call
still without a fresh record, so the table cannot go stale silently (calls of tests the build
does not have, e.g. the renderer's without Vulkan, are named and left out). Records of calls
that are no longer in the sources are ignored. Standard library only.
"""
import argparse
import datetime
import json
import os
import re
import subprocess
import sys
import zlib

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import doc_markers  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BEGIN = "<!-- stability table: scripts/stability_table.py --write docs/stability.md -->"
END = "<!-- end of the stability table -->"
FORMAT, VERSION = "penumbra-stability", 1
# Table order of the systems (a test's folder under tests/); others follow alphabetically.
SYSTEMS = ["terrain_shadow", "blocker_accumulation", "spherical_lights", "probe_cloud",
           "probe_cloud_tool", "probe_bake", "environment", "assets", "sh", "reference", "render",
           "scene", "jobs", "ecs", "game"]
TEST_RE = re.compile(r"^\s*TEST(_F|_P)?\(\s*(\w+)\s*,\s*(\w+)\s*\)", re.M)
CALL_RE = re.compile(r"\bPENUMBRA_STABILITY\(")


class RecordError(Exception):
    """A record file that cannot be used; the message names the file and the reason."""


class Site:
    """One PENUMBRA_STABILITY call in the sources."""

    def __init__(self, path, first, last, suite, test, param):
        self.path, self.first, self.last = path, first, last  # path relative to the root
        self.suite, self.test, self.param = suite, test, param
        self.records = []

    @property
    def name(self):
        return f"{self.suite}.{self.test}"

    @property
    def system(self):
        parts = self.path.split("/")
        return parts[1] if len(parts) > 2 and parts[0] == "tests" else parts[0]

    def is_test(self, name):
        """Whether `name` (gtest's Suite.Test) is this call's test or, parameterised, one of its
        instances (Prefix/Suite.Test/N)."""
        if not self.param:
            return name == self.name
        return re.match(rf"^(\w+/)?{re.escape(self.name)}/\w+$", name) is not None

    def where(self):
        return f"{self.path}:{self.first}"


def _call_end(text, start):
    """Index just past the parenthesis closing the call whose '(' is at start - 1."""
    depth, i, quote = 1, start, None
    while i < len(text) and depth:
        c = text[i]
        if quote:
            if c == "\\":
                i += 1
            elif c == quote:
                quote = None
        elif c in "\"'":
            quote = c
        elif c == "(":
            depth += 1
        elif c == ")":
            depth -= 1
        i += 1
    return i


def scan_sources(root):
    """Every PENUMBRA_STABILITY call under root/tests, with its enclosing test."""
    sites = []
    tests_dir = os.path.join(root, "tests")
    for folder, dirs, files in os.walk(tests_dir):
        dirs.sort()
        rel_folder = os.path.relpath(folder, root).replace(os.sep, "/")
        if any(rel_folder == f or rel_folder.startswith(f + "/")
               for f in ("tests/common", "tests/bench")):
            continue
        for name in sorted(files):
            if not name.endswith(".cpp"):
                continue
            path = os.path.join(folder, name)
            with open(path, encoding="utf-8", errors="replace") as f:
                text = f.read()
            tests = [(m.start(), m.group(1) == "_P", m.group(2), m.group(3))
                     for m in TEST_RE.finditer(text)]
            for m in CALL_RE.finditer(text):
                if text.rfind("#define", text.rfind("\n", 0, m.start()) + 1, m.start()) >= 0:
                    continue
                enclosing = [t for t in tests if t[0] < m.start()]
                if not enclosing:
                    continue
                _, param, suite, test = enclosing[-1]
                first = text.count("\n", 0, m.start()) + 1
                last = text.count("\n", 0, _call_end(text, m.end())) + 1
                sites.append(Site(f"{rel_folder}/{name}", first, last, suite, test, param))
    return sites


def read_record(path):
    """The record in `path` as a dict; RecordError naming the file and the reason otherwise."""
    try:
        with open(path, "rb") as f:
            data = f.read()
    except OSError as e:
        raise RecordError(f"{path}: cannot read: {e.strerror}")
    lines = data.split(b"\n")
    if len(lines) < 2 or not lines[1].startswith(b"crc32 "):
        raise RecordError(f"{path}: no 'crc32' line after the record")
    try:
        stated = int(lines[1][6:].decode("ascii"), 16)
    except (UnicodeDecodeError, ValueError):
        raise RecordError(f"{path}: the crc32 line is not hexadecimal")
    if zlib.crc32(lines[0]) != stated:
        raise RecordError(f"{path}: CRC-32 mismatch (corrupt or truncated)")
    try:
        r = json.loads(lines[0].decode("utf-8"))
    except (UnicodeDecodeError, ValueError) as e:
        raise RecordError(f"{path}: not JSON: {e}")
    if not isinstance(r, dict) or r.get("format") != FORMAT:
        raise RecordError(f"{path}: not a {FORMAT} record")
    if r.get("version") != VERSION:
        raise RecordError(f"{path}: version {r.get('version')!r}, this script reads {VERSION}")
    for key in ("test", "file", "input", "behaviour", "mitigation"):
        if not isinstance(r.get(key), str):
            raise RecordError(f"{path}: '{key}' is missing or not a string")
    if not isinstance(r.get("line"), int) or not isinstance(r.get("measured"), list):
        raise RecordError(f"{path}: 'line' or 'measured' is missing or of the wrong type")
    for m in r["measured"]:
        if (not isinstance(m, dict) or not isinstance(m.get("what"), str)
                or not (m.get("value") is None or isinstance(m.get("value"), (int, float)))):
            raise RecordError(f"{path}: a 'measured' entry is not {{what, value}}")
    return r


def _same_file(recorded, site_path):
    """Whether the record's file (__FILE__: absolute in a build, maybe another checkout) is the
    site's file, relative to the source root."""
    p = recorded.replace(os.sep, "/")
    return p == site_path or p.endswith("/" + site_path)


def match_records(sites, records_dir):
    """Attaches each readable record to its call; returns the unreadable ones' errors."""
    errors = []
    if not os.path.isdir(records_dir):
        return errors
    for name in sorted(os.listdir(records_dir)):
        if not name.endswith(".json"):
            continue
        path = os.path.join(records_dir, name)
        try:
            r = read_record(path)
        except RecordError as e:
            errors.append(str(e))
            continue
        for s in sites:
            if (s.first <= r["line"] <= s.last and s.is_test(r["test"])
                    and _same_file(r["file"], s.path)):
                r["_mtime"] = os.path.getmtime(path)
                s.records.append(r)
                break
    return errors


def stale(site, root):
    """Why `site` has no fresh record, or None."""
    if not site.records:
        return "no record"
    source = os.path.getmtime(os.path.join(root, site.path))
    if max(r["_mtime"] for r in site.records) < source:
        return "record older than its source"
    return None


def ctest_commands(build):
    """Test name -> (command, working directory) from ctest's JSON listing of `build`."""
    out = subprocess.run(["ctest", "--test-dir", build, "--show-only=json-v1"],
                         capture_output=True, text=True, check=True).stdout
    tests = {}
    for t in json.loads(out).get("tests", []):
        props = {p["name"]: p["value"] for p in t.get("properties", [])}
        if t.get("command"):
            tests[t["name"]] = (t["command"], props.get("WORKING_DIRECTORY"))
    return tests


def run_tests(sites, build, log):
    """Runs the ctest entries of `sites` (each instance of a parameterised test); returns the
    sites whose test this build does not have (not built here, e.g. no Vulkan)."""
    try:
        tests = ctest_commands(build)
    except (OSError, subprocess.CalledProcessError, ValueError) as e:
        log(f"stability: cannot list the tests of {build}: {e}")
        return []
    if not tests:
        log(f"stability: {build} has no tests (not a build folder?)")
        return []
    done, absent = set(), []
    for s in sites:
        names = [n for n in tests if s.is_test(n)]
        if not names:
            log(f"stability: {s.name} ({s.where()}) is not a test of {build}: left out of the check")
            absent.append(s)
        for n in names:
            if n in done:
                continue
            done.add(n)
            command, cwd = tests[n]
            log(f"stability: running {n}")
            try:
                p = subprocess.run(command, cwd=cwd, capture_output=True, text=True, timeout=900)
                if p.returncode != 0:
                    log(f"stability: {n} exited with {p.returncode} (its own ctest entry fails too)")
            except (OSError, subprocess.TimeoutExpired) as e:
                log(f"stability: {n}: {e}")
    return absent


def fmt_value(v):
    if v is None:
        return "non-finite"
    if isinstance(v, int) or (isinstance(v, float) and v.is_integer() and abs(v) < 1e9):
        return str(int(v))
    return f"{v:.3g}"


def measured_text(site):
    parts = []
    many = len(site.records) > 1
    for r in sorted(site.records, key=lambda r: r["test"]):
        for m in r["measured"]:
            label = f"{m['what']} = {fmt_value(m['value'])}"
            parts.append(f"{label} ({r['test'].split('/')[-1]})" if many else label)
    return "; ".join(parts)


def rows_of(sites):
    order = {s: i for i, s in enumerate(SYSTEMS)}
    rows = []
    for s in sorted(sites, key=lambda s: (order.get(s.system, len(SYSTEMS)), s.system, s.path,
                                          s.first)):
        r = s.records[0] if s.records else None
        rows.append({
            "system": s.system,
            "test": s.name,
            "file": s.path,
            "line": s.first,
            "input": r["input"] if r else None,
            "behaviour": r["behaviour"] if r else None,
            "mitigation": r["mitigation"] if r else None,
            "error": measured_text(s) if r else None,
            "measured": [{"test": x["test"], "what": m["what"], "value": m["value"]}
                         for x in s.records for m in x["measured"]],
        })
    return rows


def cell(text):
    return (text or "").replace("|", "\\|").replace("\n", " ")


def markdown(rows):
    out = [f"{len(rows)} cases from {len({r['test'] for r in rows})} tests "
           f"(generated by scripts/stability_table.py from PENUMBRA_STABILITY calls; do not edit).",
           "",
           "| system | input | what happens | error (measured) | mitigation | test |",
           "| --- | --- | --- | --- | --- | --- |"]
    for r in rows:
        if r["input"] is None:
            out.append(f"| {cell(r['system'])} | (no record: run the test) | | | | "
                       f"`{cell(r['test'])}` |")
            continue
        out.append(f"| {cell(r['system'])} | {cell(r['input'])} | {cell(r['behaviour'])} | "
                   f"{cell(r['error']) or '-'} | {cell(r['mitigation'])} | `{cell(r['test'])}` |")
    return "\n".join(out)


def write_atomic(path, text):
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    with open(path + ".tmp", "w") as f:
        f.write(text)
    os.replace(path + ".tmp", path)


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", default="build/checked", help="build folder (records, ctest)")
    ap.add_argument("--records", help="records folder (default BUILD/tests/stability)")
    ap.add_argument("--source", default=ROOT, help="source root holding tests/")
    ap.add_argument("--run-missing", action="store_true",
                    help="run the tests of calls without a fresh record first")
    ap.add_argument("--check", action="store_true",
                    help="exit 1 when a call has no fresh, readable record")
    ap.add_argument("--json", help="write the table as JSON (build/bench/stability.json)")
    ap.add_argument("--markdown", help="write the table as Markdown")
    ap.add_argument("--write", metavar="DOC", help="put the table between DOC's markers")
    ap.add_argument("--list-tests", action="store_true",
                    help="print the tests holding calls, ';'-separated (ctest DEPENDS), and stop")
    a = ap.parse_args(argv)
    if a.list_tests:
        print(";".join(sorted({s.name for s in scan_sources(a.source) if not s.param})), end="")
        return 0
    records = a.records or os.path.join(a.build, "tests", "stability")
    log = lambda m: print(m, file=sys.stderr)  # noqa: E731
    sites = scan_sources(a.source)
    if not sites:
        sys.exit(f"stability: no PENUMBRA_STABILITY call under {a.source}/tests")
    errors = match_records(sites, records)
    absent = []
    if a.run_missing:
        todo = [s for s in sites if stale(s, a.source)]
        if todo:
            log(f"stability: {len(todo)} calls without a fresh record: running their tests")
            absent = run_tests(todo, a.build, log)
            for s in sites:
                s.records = []
            errors = match_records(sites, records)
    rows = rows_of(sites)
    if a.json:
        write_atomic(a.json, json.dumps({
            "format": "penumbra-stability-table", "version": 1,
            "date": datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC"),
            "rows": rows}, indent=1) + "\n")
    md = markdown(rows)
    if a.markdown:
        write_atomic(a.markdown, md + "\n")
    if a.write:
        doc_markers.write_between(a.write, BEGIN, END, md)
    bad = [(s, stale(s, a.source)) for s in sites if stale(s, a.source) and s not in absent]
    for e in errors:
        log(f"stability: unreadable record: {e}")
    print(f"stability: {len(sites)} calls, {len(sites) - len(bad) - len(absent)} with a fresh "
          f"record" + (f", {len(absent)} of tests this build does not have" if absent else ""))
    if a.check and (bad or errors):
        for s, why in bad:
            log(f"stability: {s.name} ({s.where()}): {why}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

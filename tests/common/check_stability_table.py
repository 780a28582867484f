#!/usr/bin/env python3
"""Checks scripts/stability_table.py on the fixture in tests/common/stability_fixture/ (ctest
stability_table_fixture).

    python3 tests/common/check_stability_table.py scripts/stability_table.py tests/common/stability_fixture WORKDIR

The fixture: sources/ (three PENUMBRA_STABILITY calls in two folders, one in a parameterised
test, one over three lines, and a #define that is not a call) and records/ (one per call, two
for the parameterised test's instances, one of a call no longer in the sources). Checked: the
table's rows, cells (measured values, '|' escaped, instances merged), JSON and --write between
markers; --check passing, then failing and naming the test for a missing record, a record older
than its source and a corrupt one; --run-missing leaving out (named) the calls of tests the
build does not have, and failing for a folder without tests; and a replay of 400 deterministic mutations of a record
(bit flips, truncations, insertions), each read as a record or rejected with RecordError naming
the file, nothing else (the record format's fuzz target).
"""
import importlib.util
import json
import os
import random
import shutil
import subprocess
import sys
import time

script, fixture, work = sys.argv[1:4]
failures = []


def check(ok, what):
    if not ok:
        failures.append(what)


def run(*args):
    p = subprocess.run([sys.executable, script, *args], capture_output=True, text=True)
    return p.returncode, p.stdout + p.stderr


shutil.rmtree(work, ignore_errors=True)
shutil.copytree(fixture, work)
src, records = os.path.join(work, "sources"), os.path.join(work, "records")
now = time.time()
for folder, _, files in os.walk(src):  # sources older than the records: every record fresh
    for f in files:
        os.utime(os.path.join(folder, f), (now - 100, now - 100))
for f in os.listdir(records):
    os.utime(os.path.join(records, f), (now, now))
base = ["--source", src, "--records", records]
md, js = os.path.join(work, "table.md"), os.path.join(work, "table.json")

rc, out = run(*base, "--check", "--markdown", md, "--json", js)
check(rc == 0, f"--check on the fixture: exit {rc}: {out}")
text = open(md).read() if os.path.exists(md) else ""
rows = [l for l in text.splitlines() if l.startswith("| ") and "---" not in l][1:]
check(len(rows) == 3, f"three rows, got {len(rows)}: {text}")
check("| alpha | a sphere of radius 0 | no shadow \\| finite | max \\|E\\| error = 0.0125 | "
      "radius clamped | `Alpha.ZeroRadiusIsFinite` |" in text, f"the first row: {text}")
check("bits = 1 (0); bits = 2 (1)" in text, "the parameterised test's instances in one row")
check("nan = non-finite" in text, "a non-finite measurement")
check("gone" not in text, "a record of a call no longer in the sources is ignored")
check(text.index("| alpha |") < text.index("| beta |"), "rows in system order")
table = json.load(open(js)) if os.path.exists(js) else {}
check(table.get("format") == "penumbra-stability-table" and len(table.get("rows", [])) == 3,
      "the JSON table")

doc = os.path.join(work, "doc.md")
with open(doc, "w") as f:
    f.write("# t\n\n<!-- stability table: scripts/stability_table.py --write docs/stability.md -->"
            "\nold\n<!-- end of the stability table -->\ntail\n")
rc, out = run(*base, "--write", doc)
d = open(doc).read()
check(rc == 0 and "old" not in d and "`Beta.EmptyCloudIsBlack`" in d and d.endswith("tail\n"),
      f"--write between the markers: {d}")

# A record older than its source.
os.utime(os.path.join(src, "tests", "beta", "beta_test.cpp"), (now + 50, now + 50))
rc, out = run(*base, "--check")
check(rc == 1 and "Beta.EmptyCloudIsBlack (tests/beta/beta_test.cpp:6): record older than its "
      "source" in out, f"a stale record fails --check naming the test: {out}")
os.utime(os.path.join(src, "tests", "beta", "beta_test.cpp"), (now - 100, now - 100))

# A missing record.
alpha = os.path.join(records, "Alpha.ZeroRadiusIsFinite@6.json")
kept = open(alpha, "rb").read()
os.remove(alpha)
rc, out = run(*base, "--check")
check(rc == 1 and "Alpha.ZeroRadiusIsFinite (tests/alpha/alpha_test.cpp:6): no record" in out,
      f"a missing record fails --check naming the test: {out}")
rc, out = run(*base, "--markdown", md)
check(rc == 0 and "(no record: run the test)" in open(md).read(), "without --check: shown missing")

# A corrupt record (one byte of its JSON changed: the CRC no longer matches).
with open(alpha, "wb") as f:
    f.write(kept.replace(b"radius 0", b"radius 1"))
rc, out = run(*base, "--check")
check(rc == 1 and "CRC-32 mismatch" in out and "Alpha.ZeroRadiusIsFinite@6.json" in out,
      f"a corrupt record is named: {out}")

# --run-missing with a build that has other tests only (a CTestTestfile.cmake of one test): the
# calls of tests it does not have are named and left out of --check; a folder without tests is
# no build and fails.
with open(alpha, "wb") as f:
    f.write(kept)
os.utime(alpha, (now, now))
os.remove(os.path.join(records, "Beta.EmptyCloudIsBlack@6.json"))
build = os.path.join(work, "build")
os.makedirs(build)
with open(os.path.join(build, "CTestTestfile.cmake"), "w") as f:
    f.write(f'add_test(Other.Test "{sys.executable}" -c "pass")\n')
rc, out = run(*base, "--build", build, "--run-missing", "--check")
check(rc == 0 and "Beta.EmptyCloudIsBlack (tests/beta/beta_test.cpp:6) is not a test of" in out
      and "1 of tests this build does not have" in out, f"a test the build does not have: {out}")
empty = os.path.join(work, "empty")
os.makedirs(empty)
rc, out = run(*base, "--build", empty, "--run-missing", "--check")
check(rc == 1 and "has no tests" in out, f"a folder without tests fails --check: {out}")

# Fuzz replay: mutations of a valid record are read or rejected with RecordError, nothing else.
spec = importlib.util.spec_from_file_location("stability_table", script)
st = importlib.util.module_from_spec(spec)
spec.loader.exec_module(st)
rng = random.Random(17)
target = os.path.join(work, "fuzz.json")
accepted = 0
for i in range(400):
    b = bytearray(kept)
    kind = i % 4
    if kind == 0:
        b[rng.randrange(len(b))] ^= 1 << rng.randrange(8)
    elif kind == 1:
        del b[rng.randrange(len(b)):]
    elif kind == 2:
        b.insert(rng.randrange(len(b)), rng.randrange(256))
    else:  # a valid CRC over mutated JSON: the reader's own checks
        j = bytearray(kept.split(b"\n")[0])
        j[rng.randrange(len(j))] = rng.choice(b'{}[]",:0aZ\\')
        b = bytearray(bytes(j) + b"\ncrc32 %08x\n" % st.zlib.crc32(bytes(j)))
    with open(target, "wb") as f:
        f.write(b)
    try:
        r = st.read_record(target)
        accepted += 1
        check(isinstance(r, dict) and isinstance(r["measured"], list), f"mutation {i}: a dict")
    except st.RecordError as e:
        check(str(e).startswith(target + ":"), f"mutation {i}: the error names the file: {e}")
    except Exception as e:  # noqa: BLE001
        failures.append(f"mutation {i}: {type(e).__name__}: {e}")
check(accepted < 400, "most mutations are rejected")

for f in failures:
    print("FAIL:", f)
print(f"check_stability_table: {len(failures)} failures")
sys.exit(1 if failures else 0)

#!/usr/bin/env python3
"""Checks scripts/terrain_ab.py with made-up programs in place of terrain_ab_time (ctest
terrain_ab_fixture).

    python3 tests/bench/check_terrain_ab.py scripts/terrain_ab.py WORKDIR [TERRAIN_AB_TIME]

Three fake programs print a terrain_ab_time line each call: a baseline (10 ms one thread, 5 ms
two), one 10% faster on one thread and 10% slower on two with the baseline's hash, and one with
another hash; each call also logs its name, so the order of the rounds can be checked. Checked:
the paired ratios (0.900 and 1.100, the spread of a ratio that varies by round), the hash verdicts,
the order (as given, then reversed), and that a program printing something else, a missing
program and a single variant each stop it with exit code 2 and a message naming the cause. With
TERRAIN_AB_TIME (the real program), one round of its `light` case against itself: a line the
script reads, and the same hash twice.
"""
import os
import stat
import subprocess
import sys


def fake(work, name, one, two, digest, vary=False):
    path = os.path.join(work, name)
    log = os.path.join(work, "calls.log")
    # `vary`: one thread reads one + 1 ms every other call (a ratio that changes by round).
    body = f"""#!/usr/bin/env python3
import sys
log = {log!r}
with open(log, "a") as f:
    f.write({name!r} + "\\n")
calls = sum(1 for l in open(log) if l.strip() == {name!r})
one = {one} + (1.0 if {vary} and calls % 2 == 0 else 0.0)
print('{{"case": "%s", "reps": %s, "one_thread_ms": %.4f, "two_threads_ms": %.4f, '
      '"one_thread_min_ms": 0, "two_threads_min_ms": 0, "hash": "{digest}"}}'
      % (sys.argv[1], sys.argv[2], one, {two}))
"""
    with open(path, "w") as f:
        f.write(body)
    os.chmod(path, os.stat(path).st_mode | stat.S_IXUSR)
    return path


def call(script, *args):
    return subprocess.run([sys.executable, script, *args], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True)


def main():
    script, work = sys.argv[1], sys.argv[2]
    os.makedirs(work, exist_ok=True)
    failures = []

    def check(cond, what):
        if not cond:
            failures.append(what)

    log = os.path.join(work, "calls.log")
    if os.path.exists(log):
        os.remove(log)
    base = fake(work, "base", 10.0, 5.0, "00000000000000aa")
    faster = fake(work, "faster", 9.0, 5.5, "00000000000000aa")
    other = fake(work, "other", 10.0, 5.0, "00000000000000bb", vary=True)
    r = call(script, "--rounds", "4", "--reps", "3", f"base={base}", f"faster={faster}",
             f"other={other}")
    check(r.returncode == 0, f"three fake variants: exit {r.returncode}, {r.stderr}")
    lines = {l.split("|")[1].strip(): l for l in r.stdout.splitlines() if l.startswith("| ")}
    check("baseline" in lines.get("base", ""), "the first variant is the baseline")
    check("0.900 (0.900-0.900)" in lines.get("faster", ""), "paired one thread 0.900")
    check("1.100 (1.100-1.100)" in lines.get("faster", ""), "paired two threads 1.100")
    check("(same)" in lines.get("faster", ""), "the baseline's hash: the same floats")
    check("1.050 (1.000-1.100)" in lines.get("other", ""),
          "a ratio that varies by round: median 1.050, range 1.000-1.100")
    check("DIFFERENT floats" in lines.get("other", ""), "another hash: different floats")
    check("case horizons, 4 rounds of 3 calls" in r.stdout, "the header names case and rounds")
    order = [l.strip() for l in open(log)]
    check(order == ["base", "faster", "other", "other", "faster", "base"] * 2,
          f"rounds in order, reversed every other one: {order}")

    garbage = os.path.join(work, "garbage")
    with open(garbage, "w") as f:
        f.write("#!/bin/sh\necho 'not json'\n")
    os.chmod(garbage, 0o755)
    r = call(script, "--rounds", "1", f"base={base}", f"garbage={garbage}")
    check(r.returncode == 2 and "not a terrain_ab_time line" in r.stderr and garbage in r.stderr,
          f"a program printing something else: exit {r.returncode}, {r.stderr!r}")
    missing = os.path.join(work, "missing")
    r = call(script, f"base={base}", f"missing={missing}")
    check(r.returncode == 2 and "not a program" in r.stderr and missing in r.stderr,
          f"a missing program: exit {r.returncode}, {r.stderr!r}")
    r = call(script, f"base={base}")
    check(r.returncode == 2 and "two variants at least" in r.stderr,
          f"one variant: exit {r.returncode}, {r.stderr!r}")
    r = call(script, "HEAD:" + os.path.join(work, "no.patch"), f"base={base}")
    check(r.returncode == 2 and "no such file" in r.stderr,
          f"a patch that does not exist: exit {r.returncode}, {r.stderr!r}")

    if len(sys.argv) > 3:
        real = sys.argv[3]
        r = call(script, "--case", "light", "--rounds", "1", "--reps", "1", f"a={real}",
                 f"b={real}")
        check(r.returncode == 0 and "(same)" in r.stdout,
              f"terrain_ab_time against itself: exit {r.returncode}, {r.stdout!r} {r.stderr!r}")

    for f in failures:
        print("FAILED:", f)
    print(f"check_terrain_ab: {'FAILED' if failures else 'passed'}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Compares builds of the terrain system's stages: interleaved rounds, paired medians.

    python3 scripts/terrain_ab.py [--case horizons|env|light|edit] [--rounds 20] [--reps 15]
                                  VARIANT VARIANT [VARIANT ...]

A VARIANT is one of
    REV             a git revision (HEAD, a commit, a branch): built from a worktree of it
    REV:PATCH       the same with a patch applied (`git apply`), e.g. an experiment kept as a
                    patch under tests/bench/ab/
    NAME=PROGRAM    a terrain_ab_time already built (no build)

Each revision is checked out under build/ab/<key>/src, configured as the release preset builds
(Release, Ninja) into build/ab/<key>/build and only `terrain_ab_time` is built there
(tests/bench/terrain_ab_time.cpp, so REV must contain it); the key holds the commit and the
patch's hash, so a second run reuses the build. Then ROUNDS rounds: each runs every variant's
program once (REPS calls on one thread, then REPS on two; their medians), in turn, the order
reversed every other round. The first variant is the baseline: for each other, the median over
rounds of its time divided by the baseline's in the same round, on one thread and on two, and
whether its output hash equals the baseline's (the same floats).

Machines differ and their moments change within minutes (docs/terrain_shadow.md, "What a slow
moment is"): read a ratio with its spread and the load averages printed beside it, not a
millisecond figure on its own.
"""
import argparse
import datetime
import hashlib
import json
import os
import statistics
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASES = ("horizons", "env", "light", "edit")


class AbError(Exception):
    pass


def run(cmd, cwd=None):
    r = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if r.returncode != 0:
        raise AbError(f"{' '.join(cmd)} failed ({r.returncode}):\n{r.stdout[-3000:]}")
    return r.stdout


def parse_variant(text):
    """'NAME=PROGRAM' -> ('program', NAME, PROGRAM, None); 'REV[:PATCH]' -> ('rev', text, REV,
    PATCH or None)."""
    if "=" in text:
        name, program = text.split("=", 1)
        if not name or not program:
            raise AbError(f"variant '{text}': NAME=PROGRAM needs both")
        return ("program", name, program, None)
    rev, _, patch = text.partition(":")
    if not rev:
        raise AbError(f"variant '{text}': no revision")
    return ("rev", text, rev, patch or None)


def build_variant(rev, patch, jobs):
    """Builds terrain_ab_time for REV (+ PATCH) under build/ab; returns the program's path."""
    patch_path = os.path.abspath(patch) if patch else None
    if patch_path and not os.path.isfile(patch_path):
        raise AbError(f"patch '{patch}': no such file")
    commit = run(["git", "rev-parse", "--verify", rev + "^{commit}"], cwd=ROOT).strip()
    key = commit[:12]
    if patch_path:
        with open(patch_path, "rb") as f:
            key += "-" + hashlib.sha1(f.read()).hexdigest()[:8]
    base = os.path.join(ROOT, "build", "ab", key)
    src, build = os.path.join(base, "src"), os.path.join(base, "build")
    program = os.path.join(build, "tests", "bench", "terrain_ab_time")
    if not os.path.isdir(src):
        run(["git", "worktree", "add", "--detach", "--force", src, commit], cwd=ROOT)
        if patch_path:
            try:
                run(["git", "apply", patch_path], cwd=src)
            except AbError:
                # Not left behind: the next run would find the tree and build it unpatched.
                run(["git", "worktree", "remove", "--force", src], cwd=ROOT)
                raise
    if not os.path.exists(os.path.join(build, "build.ninja")):
        run(["cmake", "-S", src, "-B", build, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release"])
    run(["cmake", "--build", build, "-j", str(jobs), "--target", "terrain_ab_time"])
    return program


def measure(program, case, reps):
    out = run([program, case, str(reps)])
    try:
        row = json.loads(out.strip().splitlines()[-1])
        return {k: row[k] for k in ("one_thread_ms", "two_threads_ms", "hash")}
    except (ValueError, KeyError, IndexError, TypeError) as e:
        raise AbError(f"{program}: not a terrain_ab_time line ({e}): {out[-300:]!r}")


def rounds_order(names, rounds):
    """The variants' order in each round: as given, reversed every other round."""
    return [list(names) if r % 2 == 0 else list(reversed(names)) for r in range(rounds)]


def summarize(names, results):
    """results[name] = list of per-round dicts -> rows: medians, paired ratios, hash checks."""
    base = names[0]
    rows = []
    for name in names:
        rs = results[name]
        hashes = sorted({r["hash"] for r in rs})
        row = {"variant": name,
               "one_thread_ms": statistics.median(r["one_thread_ms"] for r in rs),
               "two_threads_ms": statistics.median(r["two_threads_ms"] for r in rs),
               "hashes": hashes}
        if name != base:
            for key, label in (("one_thread_ms", "paired_one"), ("two_threads_ms", "paired_two")):
                ratios = sorted(r[key] / b[key] for r, b in zip(rs, results[base]))
                row[label] = statistics.median(ratios)
                row[label + "_range"] = [ratios[0], ratios[-1]]
            row["same_floats"] = hashes == sorted({r["hash"] for r in results[base]})
        rows.append(row)
    return rows


def report(rows, case, rounds, reps, loads):
    print(f"terrain_ab: case {case}, {rounds} rounds of {reps} calls a thread count; "
          f"load average {loads[0]:.2f} at the start, {loads[1]:.2f} at the end "
          f"({loads[2]}, {os.cpu_count()} CPUs)")
    print("| variant | one thread, ms | two threads, ms | paired one (range) | "
          "paired two (range) | hash |")
    print("| --- | ---: | ---: | --- | --- | --- |")
    for row in rows:
        def paired(label):
            if label not in row:
                return "baseline"
            lo, hi = row[label + "_range"]
            return f"{row[label]:.3f} ({lo:.3f}-{hi:.3f})"
        same = "" if "same_floats" not in row else (
            " (same)" if row["same_floats"] else " (DIFFERENT floats)")
        print(f"| {row['variant']} | {row['one_thread_ms']:.3f} | {row['two_threads_ms']:.3f} | "
              f"{paired('paired_one')} | {paired('paired_two')} | "
              f"{', '.join(row['hashes'])}{same} |")


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("variants", nargs="+", metavar="VARIANT")
    ap.add_argument("--case", choices=CASES, default="horizons")
    ap.add_argument("--rounds", type=int, default=20)
    ap.add_argument("--reps", type=int, default=15)
    ap.add_argument("--jobs", type=int, default=2, help="build jobs (default 2)")
    a = ap.parse_args(argv)
    if len(a.variants) < 2:
        raise AbError("two variants at least: the first is the baseline")
    if a.rounds < 1 or a.reps < 1:
        raise AbError("--rounds and --reps must be at least 1")
    programs = {}
    for text in a.variants:
        kind, name, what, patch = parse_variant(text)
        if name in programs:
            raise AbError(f"variant '{name}' given twice")
        programs[name] = what if kind == "program" else build_variant(what, patch, a.jobs)
        if not os.access(programs[name], os.X_OK):
            raise AbError(f"variant '{name}': {programs[name]} is not a program")
    names = [parse_variant(t)[1] for t in a.variants]
    loads = [os.getloadavg()[0]]
    results = {n: [] for n in names}
    for order in rounds_order(names, a.rounds):
        for name in order:
            results[name].append(measure(programs[name], a.case, a.reps))
    loads += [os.getloadavg()[0], datetime.datetime.now(datetime.timezone.utc).strftime(
        "%Y-%m-%d %H:%M UTC")]
    rows = summarize(names, results)
    report(rows, a.case, a.rounds, a.reps, loads)
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except AbError as e:
        print(f"terrain_ab: {e}", file=sys.stderr)
        sys.exit(2)

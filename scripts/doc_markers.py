"""Replace the text between two marker lines of a document, atomically (the tables of README.md
and docs/ are generated, never typed: scripts/bench_table.py, scripts/play_table.py)."""
import os
import sys


def write_between(target, begin, end, text):
    """Puts `text` between the `begin` and `end` markers of file `target`; exits naming the file
    when a marker is missing."""
    with open(target) as f:
        doc = f.read()
    if begin not in doc or end not in doc:
        sys.exit(f"{target}: no {begin} ... {end} markers")
    head, rest = doc.split(begin, 1)
    _, tail = rest.split(end, 1)
    with open(target + ".tmp", "w") as f:
        f.write(head + begin + "\n" + text + "\n" + end + tail)
    os.replace(target + ".tmp", target)

#!/usr/bin/env python3
"""Checks that the only AVX-512 code in the terrain shadow library is its dispatched kernels.

sweep_lanes_avx512.cpp compiles the line sweep's kernels for AVX-512 (src/sweep_lanes.h,
sweep_isa()); the library must still run on any x86-64-v3 CPU. Functions the linker may take
from that object for other callers (inline functions, std:: templates) must therefore hold no
AVX-512 instruction. This disassembles the library's objects named on the command line and
fails, naming the function, where an instruction uses an AVX-512 register (k0-k7, zmm, or
xmm/ymm 16-31) outside namespace penumbra::terrain_shadow::detail::avx512.

usage: check_isa_isolation.py OBJECT...
"""
import re
import subprocess
import sys

EVEX = re.compile(r"%k[0-7]\b|%zmm|%[xy]mm(1[6-9]|2[0-9]|3[01])\b")
FUNCTION = re.compile(r"^[0-9a-f]+ <(.*)>:$")
ALLOWED = "penumbra::terrain_shadow::detail::avx512::"


def main(objects):
    if not objects:
        print("usage: check_isa_isolation.py OBJECT...", file=sys.stderr)
        return 2
    bad, kernels = set(), 0
    for obj in objects:
        out = subprocess.run(["objdump", "-d", "--no-show-raw-insn", "-C", obj], check=True,
                             capture_output=True, text=True).stdout
        name = None
        for line in out.splitlines():
            m = FUNCTION.match(line)
            if m:
                name = m.group(1)
                continue
            if name and EVEX.search(line):
                if ALLOWED in name:
                    kernels += 1
                else:
                    bad.add(f"{obj}: {name}")
    for b in sorted(bad):
        print("AVX-512 code outside the dispatched kernels:", b)
    if kernels == 0:
        print("no AVX-512 instruction found in the dispatched kernels: wrong objects?")
        return 1
    print(f"{kernels} AVX-512 instructions, all in {ALLOWED}*")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

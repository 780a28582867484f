#!/usr/bin/env python3
"""Same-named file-local functions in one unity-built target (docs/ci.md, README "CI time").

A unity batch (CMake's UNITY_BUILD: one generated unity_N_cxx.cxx that includes several
sources) merges the anonymous namespaces of its files. Two file-local functions with one name and
the same parameters fail to compile there; with different parameters they compile as overloads,
and a call in one file may then resolve to the other file's function without a word. Which files
share a batch changes as files come and go, so this lists such names over all the files of each
unity-built target of a build tree (its batches together) and fails when there is one.

A file-local function is a definition at column 0 between `namespace {` and its
`}  // namespace` (the layout .clang-format gives); members and lambdas are indented or assigned
and are not counted.

usage: check_unity_names.py BUILD_DIR    every Unity/unity_*_cxx.cxx under BUILD_DIR
       check_unity_names.py --self-test  the check on two made-up files, with and without a clash
"""
import pathlib
import re
import sys
import tempfile

INCLUDE = re.compile(r'^#include "([^"]+)"', re.M)
NOT_A_FUNCTION = ('using ', 'namespace ', 'struct ', 'class ', 'enum ', 'union ', 'typedef ',
                  'template ', 'static_assert', '#', '//')
# [qualifiers] return type, then the name and its opening parenthesis.
DEFINITION = re.compile(r'(?:(?:inline|static|constexpr|\[\[[^\]]*\]\])\s+)*'
                        r'[A-Za-z_][\w:<>,*& ]*?[\s*&]([A-Za-z_]\w*)\(')


def file_local_functions(text):
    names = set()
    inside = False
    for line in text.splitlines():
        if line.startswith('namespace {'):
            inside = True
        elif inside and line.rstrip() == '}  // namespace':
            inside = False
        elif inside and line[:1].isalpha() and not line.startswith(NOT_A_FUNCTION):
            head = line.split('(')[0]
            m = DEFINITION.match(line)
            if m and '=' not in head and not line.rstrip().endswith(';'):
                names.add(m.group(1))
    return names


def target_clashes(unity_dir):
    """{name: [files]} for the names defined file-locally in two or more files of the target
    whose batches are in unity_dir."""
    where = {}
    for unity_file in sorted(unity_dir.glob('unity_*_cxx.cxx')):
        for source in INCLUDE.findall(unity_file.read_text()):
            path = pathlib.Path(source)
            for name in file_local_functions(path.read_text(errors='replace')):
                where.setdefault(name, []).append(path.name)
    return {name: files for name, files in where.items() if len(files) > 1}


def check(build_dir):
    targets = sorted({p.parent for p in pathlib.Path(build_dir).glob('**/Unity/unity_*_cxx.cxx')})
    failures = 0
    for unity_dir in targets:
        for name, files in sorted(target_clashes(unity_dir).items()):
            target = unity_dir.parent.name.removesuffix('.dir')
            print(f'{target}: file-local {name}() in {", ".join(files)}')
            failures += 1
    print(f'{len(targets)} unity-built targets read, {failures} shared file-local names')
    return 1 if failures else 0


def self_test():
    with tempfile.TemporaryDirectory() as tmp:
        tmp = pathlib.Path(tmp)
        (tmp / 'a.cpp').write_text('namespace p {\nnamespace {\n\nbool is_space(unsigned char c) {\n'
                                   '  return c == 32;\n}\n\n}  // namespace\n}  // namespace p\n')
        (tmp / 'b.cpp').write_text('namespace {\nconst int* find(int x) {\n  return nullptr;\n}\n'
                                   'bool is_space(char c) {\n  return c == 9;\n}\n'
                                   '}  // namespace\nbool is_space(int);\n')
        (tmp / 'c.cpp').write_text('namespace {\nstruct S {\n  bool is_space(char c);\n};\n'
                                   'auto find = [](int) { return 0; };\n}  // namespace\n')
        clash, clean = tmp / 'clash' / 'Unity', tmp / 'clean' / 'Unity'
        clash.mkdir(parents=True)
        clean.mkdir(parents=True)
        (clash / 'unity_0_cxx.cxx').write_text(f'#include "{tmp / "a.cpp"}"\n')
        (clash / 'unity_1_cxx.cxx').write_text(f'#include "{tmp / "b.cpp"}"\n')
        (clean / 'unity_0_cxx.cxx').write_text(f'#include "{tmp / "a.cpp"}"\n#include "{tmp / "c.cpp"}"\n')
        got0, got1 = target_clashes(clash), target_clashes(clean)
        ok = got0 == {'is_space': ['a.cpp', 'b.cpp']} and got1 == {}
        print('self-test', 'passed' if ok else f'FAILED: {got0} {got1}')
        return 0 if ok else 1


if __name__ == '__main__':
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(self_test() if sys.argv[1] == '--self-test' else check(sys.argv[1]))

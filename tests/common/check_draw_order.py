#!/usr/bin/env python3
"""Random draws whose order is the compiler's (docs/ci.md, "Compilers").

In glm::vec3(u(rng), u(rng), u(rng)) the three draws are arguments of one call, and C++ leaves
the order in which a call's arguments are evaluated to the compiler: GCC draws z first, clang x.
The same seed then gives other points under another compiler, and every bound and table set on
one compiler's points can fail on the other's. This fails when any call in the sources has draws
in two of its arguments (a draw: `name(rng)`, `name(gen)` or `name(engine)`, at any depth inside
the argument); write the draws out in order instead (tests/common/random_draws.h draws in GCC's
order, z then y then x, which set the numbers the tests and docs quote).

Sequenced forms pass: draws in one argument (a product, a conditional), a braced list
{u(rng), u(rng)}, a declaration `float a = u(rng), b = u(rng);`. Not seen: draws hidden in a
lambda or function called twice in one call's arguments (`f(pt(), pt())`).

usage: check_draw_order.py ROOT        the git-tracked C++ sources under ROOT
       check_draw_order.py --self-test the check on made-up lines, with and without draws in
                                       two arguments
"""
import pathlib
import re
import subprocess
import sys

DRAW = re.compile(r'\b[A-Za-z_]\w*\(\s*(?:rng|gen|engine)\s*\)')
NOT_CALLS = {'if', 'for', 'while', 'switch', 'return', 'sizeof', 'alignof', 'decltype', 'catch',
             'static_assert', 'noexcept', 'throw', 'co_return', 'co_yield'}
TOKEN = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)


def blank(m):  # comments and literals to spaces, newlines kept (line numbers stay)
    return re.sub(r'[^\n]', ' ', m.group(0))


def findings(text):
    """(line, call) for every call with draws in two or more of its arguments."""
    code = TOKEN.sub(blank, text)
    draws = {m.start(): m.end() for m in DRAW.finditer(code)}
    stack = []  # [opening char, is a call, argument index, args with draws, start]
    out = []
    i = 0
    while i < len(code):
        if i in draws:  # a draw: the argument it is in, in every call around it
            for group in stack:
                if group[1]:
                    group[3].add(group[2])
            i = draws[i]
            continue
        c = code[i]
        if c in '([{':
            is_call = False
            if c == '(':
                word = re.search(r'([A-Za-z_]\w*)\s*(?:<[^;{}()]*>)?\s*$', code[max(0, i - 200):i])
                before = code[:i].rstrip()[-1:]
                is_call = (word is not None and word.group(1) not in NOT_CALLS) or before in ')]'
            stack.append([c, is_call, 0, set(), i])
        elif c in ')]}':
            if stack:
                group = stack.pop()
                if group[1] and len(group[3]) > 1:
                    line = code.count('\n', 0, group[4]) + 1
                    name = re.search(r'([\w:]+)\s*(?:<[^;{}()]*>)?\s*$', code[:group[4]])
                    out.append((line, name.group(1) if name else '(call)'))
        elif c == ',' and stack:
            stack[-1][2] += 1
        i += 1
    return out


def self_test():
    bad = ['const glm::vec3 p(u(rng), u(rng), u(rng));',
           'p.emplace_back(x(rng), y(rng), z(rng));',
           'v = glm::normalize(glm::vec3(g(rng), g(rng), 1.0f));',
           'f(zh(s(rng), 1.0f), random_direction(rng));',
           'q = glm::vec3(2.0f * (u(rng) - 0.5f), /* y */ 2.0f * u(rng), 1);']
    good = ['const float z = u(rng), y = u(rng), x = u(rng);',
            'p.push_back({u(rng), u(rng), u(rng)});',
            'const double d = 2.5 + 150 * u(rng) * u(rng);',
            'f(i % 2 ? u(rng) : v(rng), 3);',
            'for (int i = 0; i < n; ++i) p.push_back(draw_zyx<glm::vec3>(rng, u));',
            'std::printf("%g %g", "u(rng), v(rng)", 1);  // u(rng), v(rng)',
            'if (u(rng) < 0.5f && v(rng) > 0) x = 1;']
    failures = [b for b in bad if not findings(b)] + [g for g in good if findings(g)]
    for f in failures:
        print('self-test: wrong verdict on:', f)
    return 1 if failures else 0


def main():
    if sys.argv[1:] == ['--self-test']:
        return self_test()
    root = pathlib.Path(sys.argv[1])
    files = subprocess.run(['git', '-C', str(root), 'ls-files', '*.cpp', '*.h'],
                           capture_output=True, text=True, check=True).stdout.split()
    count = 0
    for f in files:
        text = (root / f).read_text(errors='replace')
        if not DRAW.search(text):
            continue
        for line, name in findings(text):
            print(f'{f}:{line}: {name}(...) draws in two of its arguments: their order is the '
                  'compiler\'s (write the draws out in order; tests/common/random_draws.h)')
            count += 1
    print(f'draw order: {len(files)} files, {count} calls with draws in two arguments')
    return 1 if count else 0


if __name__ == '__main__':
    sys.exit(main())

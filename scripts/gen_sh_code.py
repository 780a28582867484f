#!/usr/bin/env python3
"""Generates straight-line C++ for real SH basis evaluation (2..6 bands) and SH products
(general and square, 2..6 bands):

  python3 scripts/gen_sh_code.py basis   > engine/sh/generated/basis_generated.h
  python3 scripts/gen_sh_code.py product > engine/sh/generated/product_generated.h


Conventions (pinned by tests/sh/basis_test.cpp): real SH, index i = l(l+1)+m, no Condon-Shortley
phase, band 1 ordered (y, z, x) -- [Ambrosj16] appendix A, [Giraud]
eq. 3-5. Basis polynomials follow the Legendre recurrences in Cartesian form (Sloan 2013,
"Efficient Spherical Harmonic Evaluation"); product coefficients are the SH triple-product
(Gaunt) tensor, [Giraud] eq. 6, integrated exactly with Gauss-Legendre x uniform-azimuth quadrature.
"""
import math
import sys

MAX_BANDS = 6
TOL = 1e-12


def k_lm(l, m):
    m = abs(m)
    return math.sqrt((2 * l + 1) / (4 * math.pi) * math.factorial(l - m) / math.factorial(l + m))


def eval_basis(n, x, y, z):
    """Reference evaluation in Python (used to build the product tensor)."""
    out = [0.0] * (n * n)
    c = [1.0]  # Re((x+iy)^m)
    s = [0.0]  # Im((x+iy)^m)
    for m in range(1, n):
        c.append(x * c[m - 1] - y * s[m - 1])
        s.append(x * s[m - 1] + y * c[m - 1])
    for m in range(0, n):
        # P_m^m without (-1)^m (no Condon-Shortley) and without the sin^m factor (in c, s).
        pmm = 1.0
        for k in range(1, m + 1):
            pmm *= (2 * k - 1)
        p = {m: pmm}
        if m + 1 < n:
            p[m + 1] = (2 * m + 1) * z * pmm
        for l in range(m + 2, n):
            p[l] = ((2 * l - 1) * z * p[l - 1] - (l + m - 1) * p[l - 2]) / (l - m)
        for l in range(m, n):
            if m == 0:
                out[l * (l + 1)] = k_lm(l, 0) * p[l]
            else:
                out[l * (l + 1) + m] = math.sqrt(2) * k_lm(l, m) * p[l] * c[m]
                out[l * (l + 1) - m] = math.sqrt(2) * k_lm(l, m) * p[l] * s[m]
    return out


def gauss_legendre(n):
    """Nodes and weights on [-1, 1] by Newton iteration."""
    nodes, weights = [], []
    for i in range(1, n + 1):
        x = math.cos(math.pi * (i - 0.25) / (n + 0.5))
        for _ in range(100):
            p0, p1 = 1.0, x
            for k in range(2, n + 1):
                p0, p1 = p1, ((2 * k - 1) * x * p1 - (k - 1) * p0) / k
            dp = n * (x * p1 - p0) / (x * x - 1)
            dx = p1 / dp
            x -= dx
            if abs(dx) < 1e-15:
                break
        nodes.append(x)
        weights.append(2 / ((1 - x * x) * dp * dp))
    return nodes, weights


def gaunt(n):
    """Gamma[i][j][k] = integral of y_i y_j y_k over the sphere, exact for degree <= 3(n-1)."""
    zs, ws = gauss_legendre(2 * n)
    nphi = 4 * n
    count = n * n
    g = [[[0.0] * count for _ in range(count)] for _ in range(count)]
    for z, w in zip(zs, ws):
        r = math.sqrt(max(0.0, 1 - z * z))
        for a in range(nphi):
            phi = 2 * math.pi * (a + 0.5) / nphi
            y = eval_basis(n, r * math.cos(phi), r * math.sin(phi), z)
            wt = w * 2 * math.pi / nphi
            for i in range(count):
                if y[i] == 0.0:
                    continue
                for j in range(count):
                    yij = y[i] * y[j] * wt
                    for k in range(j, count):
                        g[i][j][k] += yij * y[k]
    return g


def emit_basis(n):
    # Templated on the lane type T: float, or a GCC/Clang vector of floats for SoA batches.
    # Constants enter only as scalar operands of * and +, which both kinds of T accept.
    lines = [f"// {n} bands: out[0..{n*n - 1}] = y_i(x, y, z) for a unit vector (T: float or float vector).",
             "template <class T>",
             f"inline void eval_basis_{n}(T x, T y, T z, T* out) {{"]
    lines.append("  // Re/Im of (x + iy)^m: the sin^m(theta) cos/sin(m phi) factors.")
    lines.append("  const T c1 = x;")
    lines.append("  const T s1 = y;")
    for m in range(2, n):
        lines.append(f"  const T c{m} = x * c{m-1} - y * s{m-1};")
        lines.append(f"  const T s{m} = x * s{m-1} + y * c{m-1};")
    for m in range(0, n):
        pmm = 1.0
        for k in range(1, m + 1):
            pmm *= (2 * k - 1)
        # P_l^m(z) / P_m^m as named temporaries (Legendre recurrence, Cartesian form); the
        # constant P_m^m is folded into the normalisation.
        q = {m: None}
        if m + 1 < n:
            lines.append(f"  const T p{m+1}_{m} = {float(2*m+1)!r}f * z;")
            q[m + 1] = f"p{m+1}_{m}"
        for l in range(m + 2, n):
            a = (2 * l - 1) / (l - m)
            b = (l + m - 1) / (l - m)
            prev2 = f"p{l-2}_{m}" if q[l - 2] is not None else None
            term2 = f" - {b!r}f * {prev2}" if prev2 else f" - T{{}} - {b!r}f"
            if prev2 is None:
                lines.append(f"  const T p{l}_{m} = {a!r}f * z * p{l-1}_{m} - {b!r}f;")
            else:
                lines.append(f"  const T p{l}_{m} = {a!r}f * z * p{l-1}_{m}{term2};")
            q[l] = f"p{l}_{m}"
        for l in range(m, n):
            k = k_lm(l, m) * pmm * (1 if m == 0 else math.sqrt(2))
            factor = f" * {q[l]}" if q[l] is not None else ""
            if m == 0:
                if q[l] is None:
                    lines.append(f"  out[{l*(l+1)}] = T{{}} + {k!r}f;")
                else:
                    lines.append(f"  out[{l*(l+1)}] = {k!r}f{factor};")
            else:
                lines.append(f"  out[{l*(l+1)+m}] = {k!r}f{factor} * c{m};")
                lines.append(f"  out[{l*(l+1)-m}] = {k!r}f{factor} * s{m};")
    lines.append("}")
    return "\n".join(lines)


def emit_product(n, g, square):
    count = n * n
    name = f"square_{n}" if square else f"product_{n}"
    args = "const T* f, T* out" if square else "const T* f, const T* g, T* out"
    # Templated on the lane type T, as the basis: float, or a GCC/Clang vector of floats for
    # structure-of-arrays batches (sh/batch.h); constants enter only as scalar operands of *.
    lines = ["template <class T>", f"inline void {name}({args}) {{"]
    # Factoring: every pair product f_j g_k + f_k g_j is formed once and feeds every output i
    # whose Gaunt coefficient with (j, k) is non-zero.
    acc = [[] for _ in range(count)]
    pair_lines = []
    nonzero = 0
    for j in range(count):
        for k in range(j, count):
            used = [(i, g[i][j][k]) for i in range(count) if abs(g[i][j][k]) > TOL]
            if not used:
                continue
            nonzero += len(used)
            t = f"t{j}_{k}"
            if square:
                expr = f"f[{j}] * f[{j}]" if j == k else f"2.0f * f[{j}] * f[{k}]"
            else:
                expr = f"f[{j}] * g[{j}]" if j == k else f"f[{j}] * g[{k}] + f[{k}] * g[{j}]"
            pair_lines.append(f"  const T {t} = {expr};")
            for i, c in used:
                acc[i].append(f"{c!r}f * {t}")
    lines += pair_lines
    for i in range(count):
        lines.append(f"  out[{i}] = " + (" + ".join(acc[i]) if acc[i] else "T{}") + ";")
    lines.append("}")
    return "\n".join(lines), nonzero


def main():
    what = sys.argv[1] if len(sys.argv) > 1 else ""
    if what not in ("basis", "product"):
        sys.exit("usage: gen_sh_code.py basis|product")
    print("// GENERATED by scripts/gen_sh_code.py -- do not edit. See that script for the conventions.")
    print("// clang-format off")
    print("#pragma once\n")
    print("namespace penumbra::sh::generated {\n")
    if what == "basis":
        for n in range(2, MAX_BANDS + 1):
            print(emit_basis(n))
            print()
    else:
        print("struct GauntEntry {\n  unsigned char i, j, k;\n  float value;\n};\n")
        for n in range(2, MAX_BANDS + 1):
            g = gaunt(n)
            code, nonzero = emit_product(n, g, square=False)
            print(code)
            print()
            code, _ = emit_product(n, g, square=True)
            print(code)
            print()
            # Sparse tensor for the reference implementation (tests and benchmark baseline).
            entries = []
            for i in range(n * n):
                for j in range(n * n):
                    for k in range(n * n):
                        a, b = min(j, k), max(j, k)
                        if abs(g[i][a][b]) > TOL:
                            entries.append(f"{{{i}, {j}, {k}, {g[i][a][b]!r}f}}")
            print(f"// Non-zero triple-product entries (i, j, k, Gamma_ijk) for {n} bands: {len(entries)}.")
            print(f"inline constexpr GauntEntry kGaunt{n}[] = {{")
            for e in range(0, len(entries), 4):
                print("    " + ", ".join(entries[e:e + 4]) + ",")
            print("};\n")
    print("}  // namespace penumbra::sh::generated")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Fits the polynomial coefficients in src/models/beckmann_math.hpp (needs python3-mpmath).

  scripts/fit_beckmann_math.py > coefficients.inc   (the block between the clang-format marks)

erfcx(x) = exp(x^2) erfc(x) on [0, 8): 32 intervals of width 1/4, a degree-10 polynomial in
t = x - centre each; on [8, inf): erfcx(x) x sqrt(pi) as a degree-8 polynomial in y = 1/x^2.
erfinv(t) / t as a polynomial in w = -ln(1 - t^2) (degree 16 on [0, 3) and on [3, 6.25)), in
sqrt(w) (degree 18 for 6.25 <= w < 16, degree 20 for 16 <= w < 56.25). Every polynomial
interpolates at the Chebyshev nodes of its interval in 40-digit arithmetic; the script prints the largest relative error of each (evaluated in double
by Horner's rule on a dense grid) to stderr.
"""
import sys

try:
    import mpmath as mp
except ImportError:
    sys.exit("fit_beckmann_math.py needs mpmath: apt-get install python3-mpmath (a maintenance "
             "script; the build and the tests do not run it)")
mp.mp.dps = 40

def cheb_interp(f, a, b, n):
    """Monomial coefficients in (v - c), c = (a + b)/2, of the degree-n interpolant at the
    Chebyshev nodes of [a, b]."""
    a, b = mp.mpf(a), mp.mpf(b)
    c, h = (a + b) / 2, (b - a) / 2
    s = [mp.cos(mp.pi * (k + mp.mpf(1) / 2) / (n + 1)) for k in range(n + 1)]
    V = mp.matrix([[sk ** j for j in range(n + 1)] for sk in s])
    cs = mp.lu_solve(V, mp.matrix([f(c + h * sk) for sk in s]))
    return c, [cs[j] / h ** j for j in range(n + 1)]

def horner(coef, t):
    r = 0.0
    for q in reversed(coef):
        r = r * t + q
    return r

def worst(f, a, b, c, coef, m=200):
    w = 0.0
    cf = [float(q) for q in coef]
    for i in range(m + 1):
        v = float(a) + (float(b) - float(a)) * i / m
        ref = f(mp.mpf(v))
        w = max(w, float(abs(mp.mpf(horner(cf, v - float(c))) - ref) / abs(ref)))
    return w

def erfcx(x):
    return mp.exp(x * x) * mp.erfc(x)

def tail(y):  # erfcx(x) x sqrt(pi), y = 1/x^2
    if y == 0:
        return mp.mpf(1)
    x = 1 / mp.sqrt(y)
    return erfcx(x) * x * mp.sqrt(mp.pi)

def erfinv_ratio(w):  # erfinv(t)/t, w = -ln(1 - t^2)
    if w == 0:
        return mp.sqrt(mp.pi) / 2
    t = mp.sqrt(-mp.expm1(-w))
    return mp.erfinv(t) / t

def emit(name, rows):
    print(f"inline constexpr double {name}[{len(rows)}][{len(rows[0])}] = {{")
    for r in rows:
        print("    {" + ", ".join(f"{float(q):.17g}" for q in r) + "},")
    print("};")

rows = []
for k in range(32):
    a, b = k / 4, (k + 1) / 4
    c, coef = cheb_interp(erfcx, a, b, 10)
    assert abs(float(c) - (k + 0.5) / 4) < 1e-15
    rows.append(coef)
    print(f"erfcx [{a}, {b}): {worst(erfcx, a, b, c, coef):.3g}", file=sys.stderr)
emit("kErfcx", rows)

c, coef = cheb_interp(tail, 0, mp.mpf(1) / 64, 8)
# re-expand around y = 0
res = [mp.mpf(0)] * 9
for j, q in enumerate(coef):  # q (y - c)^j
    for i in range(j + 1):
        res[i] += q * mp.binomial(j, i) * (-c) ** (j - i)
print(f"erfcx tail: {worst(tail, 0, 1/64, 0, res):.3g}", file=sys.stderr)
emit("kErfcxTail", [res])

for name, var, a, b, n in [("kErfinvW1", "w", 0, 3, 16), ("kErfinvW2", "w", 3, 6.25, 16),
                           ("kErfinvS1", "s", 2.5, 4, 18), ("kErfinvS2", "s", 4, 7.5, 20)]:
    f = erfinv_ratio if var == "w" else (lambda v: erfinv_ratio(v * v))
    c, coef = cheb_interp(f, a, b, n)
    print(f"{name} centre {float(c)}: {worst(f, a, b, c, coef):.3g}", file=sys.stderr)
    emit(name, [coef])

#!/usr/bin/env python3
"""Writes the stiff-and-extreme suite: the scenes (*.expr) and cases.csv, one ray per line with
the answer mathematics gives.

Each root is computed in mpmath at 4,000 bits from the real function the scene defines (its
literals read as the nearest doubles, as certray reads them), then bracketed by the two doubles
around it: root_lo = the largest double <= root, root_hi = the smallest double >= root (equal
when the root is a double). `expect` is
  hit      the first root in [tmin, tmax] is simple: a certified method must prove it,
           with t_lo <= root_lo and root_hi <= t_hi;
  miss     no root in [tmin, tmax];
  tangent  the first root is a double root (touching, tangent, grazing): hit containing it or
           unknown with t_lo <= root_lo, never miss;
  hard     a simple root that double arithmetic cannot prove (no double point on its left has a
           decided sign): as tangent;
  nohit    within a rounding error of touching but no root: miss or unknown, never hit.
Run from anywhere: python3 scenes/stress/make_stress.py (needs python3-mpmath).
"""
import math
import os

import mpmath as mp

mp.mp.prec = 4000  # 1 + exp(-700) needs more than 1,000 bits
HERE = os.path.dirname(os.path.abspath(__file__))


def D(x):
    """The real value of the double nearest to the decimal literal x (as the parser reads it)."""
    return mp.mpf(float(x))


def bracket(root):
    d = float(root)
    lo = d if mp.mpf(d) <= root else math.nextafter(d, -math.inf)
    hi = d if mp.mpf(d) >= root else math.nextafter(d, math.inf)
    return lo, hi


scenes = {}
cases = []


def scene(name, text, comment):
    scenes[name] = f"# {comment}\n{text}\n"


def case(label, name, o, d, tmin, tmax, expect, root=None, note=""):
    lo = hi = "nan"
    if root is not None:
        a, b = bracket(root)
        lo, hi = a.hex(), b.hex()
    cases.append([label, name + ".expr", *[repr(float(v)) for v in (*o, *d, tmin, tmax)],
                  expect, lo, hi, note])


# Steep: the unit sphere's distance scaled by 1e8 (a huge gradient).
scene("steep", "1e8 * (sqrt(x^2 + y^2 + z^2) - 1)", "steep: |grad f| = 1e8 on the unit sphere")
case("steep-head-on", "steep", (0, 0, -3), (0, 0, 1), 0, 10, "hit", mp.mpf(2))
case("steep-oblique", "steep", (0.25, 0.5, -3), (0, 0, 1), 0, 10, "hit",
     3 - mp.sqrt(1 - D(0.25) ** 2 - D(0.5) ** 2))
# Tiny: scaled by 2^-600 (values near the bottom of the double range, no subnormal trouble yet).
scene("tiny", "(sqrt(x^2 + y^2 + z^2) - 1) * 0.5^600", "tiny: f scaled by 2^-600")
case("tiny-head-on", "tiny", (0, 0, -3), (0, 0, 1), 0, 10, "hit", mp.mpf(2))
case("tiny-miss", "tiny", (0, 2, -3), (0, 0, 1), 0, 10, "miss")
# Subnormal: scaled by 2^-1070: values are subnormal, the sign is still exact.
scene("subnormal", "(x - 0.5) * 0.5^1070", "subnormal values: (x - 1/2) * 2^-1070")
case("subnormal-root", "subnormal", (0, 0, 0), (1, 0, 0), 0, 1, "hit", mp.mpf(0.5))
# Far: a unit sphere centred at 1e6 on the z axis, seen from the origin and from near it.
scene("far", "sqrt(x^2 + y^2 + (z - 1000000)^2) - 1", "far: unit sphere at (0, 0, 1e6)")
case("far-from-origin", "far", (0, 0, 0), (0, 0, 1), 0, 2e6, "hit", mp.mpf(999999))
case("far-offset", "far", (0.5, 0, 0), (0, 0, 1), 0, 2e6, "hit",
     1000000 - mp.sqrt(1 - D(0.5) ** 2))
case("far-near", "far", (0, 0, 1e6 - 3), (0, 0, 1), 0, 10, "hit", mp.mpf(2))
# Thin shell: | |p| - 1 | - 2^-31, thickness 2^-30.
scene("thin", "abs(sqrt(x^2 + y^2 + z^2) - 1) - 0.0000000004656612873077392578125",
      "thin shell of thickness 2^-30 around the unit sphere")
case("thin-head-on", "thin", (0, 0, -3), (0, 0, 1), 0, 10, "hit", 2 - mp.mpf(2) ** -31)
case("thin-from-inside", "thin", (0, 0, 0), (1, 0, 0), 0, 10, "hit", 1 - mp.mpf(2) ** -31)
# Tangent and near-tangent rays on the algebraic sphere.
scene("quadric", "x^2 + y^2 + z^2 - 1", "algebraic unit sphere")
case("tangent", "quadric", (-3, 1, 0), (1, 0, 0), 0, 10, "tangent", mp.mpf(3))
case("near-miss-2^-40", "quadric", (-3, 1 + 2.0 ** -40, 0), (1, 0, 0), 0, 10, "nohit")
case("near-hit-2^-40", "quadric", (-3, 1 - 2.0 ** -40, 0), (1, 0, 0), 0, 10, "hit",
     3 - mp.sqrt(1 - (1 - mp.mpf(2) ** -40) ** 2))
# Touching zero without a sign change.
scene("touch", "(x - 0.5)^2 * (y^2 + 1)", "touches zero on the plane x = 1/2, no sign change")
case("touch", "touch", (0, 0.25, 0), (1, 0, 0), 0, 1, "tangent", D(0.5))
# Grazing rays on a torus (R = 1, r = 0.25).
scene("torus", "(sqrt(x^2 + y^2) - 1)^2 + z^2 - 0.0625", "torus R = 1, r = 1/4")
case("torus-graze-top", "torus", (-3, 0, 0.25), (1, 0, 0), 0, 6, "tangent", mp.mpf(2))
zg = 0.25 - 2.0 ** -20
case("torus-graze-2^-20", "torus", (-3, 0, zg), (1, 0, 0), 0, 6, "hit",
     2 - mp.sqrt(D(0.0625) - mp.mpf(zg) ** 2))
case("torus-hole", "torus", (0, 0, -3), (0, 0, 1), 0, 6, "miss")
# Domain edges.
scene("sqrt-edge", "sqrt(x) - 0.5", "sqrt of a negative region: undefined for x < 0")
case("sqrt-edge", "sqrt-edge", (-1, 0, 0), (1, 0, 0), 0, 4, "hit", mp.mpf(1.25))
scene("log-edge", "log(x) + 700", "log near 0: root at x = exp(-700)")
case("log-edge", "log-edge", (0, 0, 0), (1, 0, 0), 0, 4, "hit", mp.exp(-700))
# From x = -1 the root 1 + exp(-700) lies strictly between the doubles 1 (where x = 0 and log is
# undefined) and 1 + 2^-52 (where g > 0): no double point has g < 0, so no sign change can prove
# it in double arithmetic. Honest answers: a hit or unknown holding it, never a miss.
case("log-edge-unprovable", "log-edge", (-1, 0, 0), (1, 0, 0), 0, 4, "hard", 1 + mp.exp(-700))
scene("exp-overflow", "exp(x) - 1e300", "exp overflows for x > 709.78")
case("exp-overflow", "exp-overflow", (0, 0, 0), (1, 0, 0), 0, 1000, "hit", mp.log(D(1e300)))
# Clustered roots of a degree-10 polynomial: 0.5 + k 2^-30, k = 0..9.
terms = [f"(x - {mp.nstr(mp.mpf(0.5) + k * mp.mpf(2) ** -30, 40)})" for k in range(10)]
scene("cluster10", " * ".join(terms), "degree 10, roots 1/2 + k 2^-30 (k = 0..9)")
case("cluster10-first", "cluster10", (0, 0, 0), (1, 0, 0), 0, 1, "hit", mp.mpf(0.5))
case("cluster10-last", "cluster10", (1, 0, 0), (-1, 0, 0), 0, 1, "hit",
     1 - (mp.mpf(0.5) + 9 * mp.mpf(2) ** -30))
# A huge Lipschitz constant: sin(1e6 x) + 1/2, first root 7 pi / 6e6.
scene("oscillate", "sin(1000000 * x) + 0.5", "Lipschitz constant 1e6: sin(1e6 x) + 1/2")
case("oscillate", "oscillate", (0, 0, 0), (1, 0, 0), 0, 1, "hit", 7 * mp.pi / 6000000)
# NaN-producing expressions.
scene("undefined", "log(-(x^2) - 1)", "undefined everywhere: no zero anywhere")
case("undefined", "undefined", (-1, 0, 0), (1, 0, 0), 0, 2, "miss")
scene("removable", "x / x - 1", "zero wherever defined (x != 0); undefined at x = 0")
case("removable", "removable", (-1, 0, 0), (1, 0, 0), 0, 2, "hit", mp.mpf(0))
scene("pole", "1 / x - 1", "a pole at x = 0 (sign change without a zero); root at x = 1")
case("pole", "pole", (-2, 0, 0), (1, 0, 0), 0, 4, "hit", mp.mpf(3))
# Deep CSG: a union of 10^4 spheres of radius 0.004 on a 100 x 100 grid of spacing 0.01 in z = 0.
lines = ["# deep CSG: a union of 10^4 spheres (radius 0.004, grid spacing 0.01 in the plane z = 0)"]
k = 0
for i in range(100):
    for j in range(100):
        cx, cy = i / 100, j / 100
        s = f"sqrt((x - {cx!r})^2 + (y - {cy!r})^2 + z^2) - 0.004"
        lines.append(f"u{k} = {s}" if k == 0 else f"u{k} = min(u{k - 1}, {s})")
        k += 1
lines.append(f"u{k - 1}")
scenes["deep_csg"] = "\n".join(lines) + "\n"
case("deep-csg-centre", "deep_csg", (0.5, 0.5, 1), (0, 0, -1), 0, 2, "hit", 1 - D(0.004))
case("deep-csg-gap", "deep_csg", (0.505, 0.505, 1), (0, 0, -1), 0, 2, "miss")

# Poles: a root past a pole must be narrowed like any other, a ray crossing only poles is a miss
# (a sign change across a pole is no zero: g is undefined there).
scene("pole-shift", "1 / (x - 0.3) + 0.5", "a pole at x = 0.3, the root at x = 0.3 - 2")
xr = D(0.3) - 2
case("pole-then-root", "pole-shift", (1, 0, 0), (-0.7, 0.3, 0.1), 0, 6, "hit", (1 - xr) / D(0.7))
case("pole-only", "pole-shift", (1, 0, 0), (-0.7, 0.3, 0.1), 0, 3, "miss")
case("root-then-pole", "pole-shift", (-3, 0, 0), (1.1, 0, 0), 0, 5, "hit", (xr + 3) / D(1.1))
scene("tan", "sin(x) / cos(x)", "tan x as sin/cos: roots at k pi, poles at pi/2 + k pi")
case("tan-past-pole", "tan", (0.5, 0, 0), (0.9, 0.2, 0), 0, 10, "hit", (mp.pi - D(0.5)) / D(0.9))
case("tan-pole-only", "tan", (0.5, 0, 0), (0.9, 0.2, 0), 0, 2.75, "miss")
case("tan-2pi", "tan", (3.5, 0, 0), (1.3, 0, 0), 0, 5, "hit", (2 * mp.pi - D(3.5)) / D(1.3))
case("tan-negative", "tan", (-0.5, 0, 0), (-1, 0, 0), 0, 4, "hit", mp.pi - D(0.5))
# A box with faces at +-0.75: on octree cell faces of [-2, 2]^3 at depths >= 4.
scene("box-face", "max(max(abs(x), abs(y)), abs(z)) - 0.75", "a box with faces at +-0.75")
ox = -3.1059441656784625
case("box-face-head-on", "box-face", (ox, 0.20367648172826502, -0.23023625089302696),
     (1.149522427097173, 0, 0), 0, 20, "hit", (D(-0.75) - D(ox)) / D(1.149522427097173))
case("box-face-oblique", "box-face", (3, 0.1, -0.2), (-1.3, 0.05, 0.07), 0, 20, "hit",
     (D(3) - D(0.75)) / D(1.3))

for name, text in scenes.items():
    with open(os.path.join(HERE, name + ".expr"), "w") as f:
        f.write(text)
with open(os.path.join(HERE, "cases.csv"), "w") as f:
    f.write("case,scene,ox,oy,oz,dx,dy,dz,tmin,tmax,expect,root_lo,root_hi,note\n")
    for c in cases:
        f.write(",".join(c) + "\n")
print(f"wrote {len(scenes)} scenes and {len(cases)} cases to {HERE}")

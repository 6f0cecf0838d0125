#!/usr/bin/env python3
"""Writes the face and pole measurement scenes and rays (docs/benchmarks.md, "Roots on cell faces
and poles") into a directory: box, rounded box and CSG difference with faces at +-0.75 (on octree
cell faces of [-2, 2]^3 at depths >= 4) with 138 head-on and oblique rays into the faces;
1/(x - 0.3) + 0.5 and sin(x)/cos(x) with 80 rays each (40 with a root past a pole, 40 crossing
only a pole). Usage: python3 scripts/face_pole_rays.py OUTDIR
"""
import os
import random
import sys

out = sys.argv[1] if len(sys.argv) > 1 else "."
os.makedirs(out, exist_ok=True)
scenes = {
    "box": "max(max(abs(x), abs(y)), abs(z)) - 0.75",
    "rbox": "sqrt(max(abs(x) - 0.5, 0)^2 + max(abs(y) - 0.5, 0)^2 + max(abs(z) - 0.5, 0)^2) - 0.25",
    "csgbox": "b = max(max(abs(x), abs(y)), abs(z)) - 0.75\ns = sqrt(x^2 + y^2 + z^2) - 0.9\n"
              "min(max(b, -s), sqrt((x-1.5)^2 + y^2 + z^2) - 0.2)",
    "pole1": "1 / (x - 0.3) + 0.5",
    "tan": "sin(x) / cos(x)",
}
for name, text in scenes.items():
    with open(os.path.join(out, name + ".expr"), "w") as f:
        f.write(text + "\n")


def write(name, rows):
    with open(os.path.join(out, name), "w") as f:
        f.write("ox,oy,oz,dx,dy,dz,tmin,tmax\n")
        for r in rows:
            f.write(",".join(repr(float(v)) for v in r) + "\n")


random.seed(2)
rows = []
for axis in range(3):
    for sgn in (1, -1):
        for k in range(8):
            o = [random.uniform(-0.6, 0.6) for _ in range(3)]
            o[axis] = -random.uniform(2.5, 3.5) * sgn
            d = [0, 0, 0]
            d[axis] = sgn * random.uniform(0.3, 1.7)
            rows.append(o + d + [0, 20])
for k in range(90):
    axis = random.randrange(3)
    sgn = random.choice((1, -1))
    target = [random.uniform(-0.7, 0.7) for _ in range(3)]
    target[axis] = 0.75 * sgn
    o = [random.uniform(-3, 3) for _ in range(3)]
    o[axis] = 3 * sgn
    s = random.uniform(0.3, 1.9)
    rows.append(o + [(target[i] - o[i]) * s for i in range(3)] + [0, 20])
write("box_rays.csv", rows)

random.seed(5)
rows = []
for k in range(40):  # the pole (x = 0.3), then the root (x = -1.7)
    ox, dx = random.uniform(0.5, 3), -random.uniform(0.5, 2)
    length = (ox + 1.7) / -dx
    rows.append([ox, random.uniform(-1, 1), random.uniform(-1, 1), dx, random.uniform(-1, 1),
                 random.uniform(-1, 1), 0, length * random.uniform(1.05, 3)])
for k in range(40):  # the pole only
    ox, dx = random.uniform(0.5, 3), -random.uniform(0.5, 2)
    t_pole, t_root = (ox - 0.3) / -dx, (ox + 1.7) / -dx
    rows.append([ox, 0.1, 0.2, dx, 0.3, 0, 0, random.uniform(t_pole * 1.05, t_root * 0.95)])
write("pole1_rays.csv", rows)
rows = []
for k in range(40):  # the pole pi/2, then the root pi
    ox, dx = random.uniform(0.2, 1.4), random.uniform(0.5, 2)
    rows.append([ox, 0, 0, dx, random.uniform(-1, 1), 0, 0, (3.5 - ox) / dx])
for k in range(40):  # the pole only (stops at x = 3 < pi)
    ox, dx = random.uniform(0.2, 1.4), random.uniform(0.5, 2)
    rows.append([ox, 0, 0, dx, 0, random.uniform(-1, 1), 0, (3.0 - ox) / dx])
write("tan_rays.csv", rows)
print("wrote", out)

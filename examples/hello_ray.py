"""hello_ray.py — the first root of rays on a scene, certified, from Python.

    python3 examples/hello_ray.py [SCENE]
"""
import sys

import numpy as np

import certray

scene = certray.Scene.load(sys.argv[1]) if len(sys.argv) > 1 else certray.Scene.parse(
    certray.sqrt(certray.x**2 + certray.y**2 + certray.z**2) - 1)
# From (0, 0, -3) along +z (the unit sphere is first met at t = 2), and one ray beside it.
rays = np.array([[0, 0, -3, 0, 0, 1, 0, 10], [0, 1.5, -3, 0, 0, 1, 0, 10]])
hits, stats = scene.query(rays, method="certified")
for h in hits:
    print(f"{h['status']} [{h['t_lo']!r}, {h['t_hi']!r}]")
print("proven" if stats["certified"] else "approximate", stats["status"])
sys.exit(1 if (hits["status"] == "unknown").any() else 0)

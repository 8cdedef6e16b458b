#!/usr/bin/env python3
"""Regenerates the example map configs in this folder (python3 generate.py).

The same polygons are built in tests/mapping/test_polygons.hpp; the tests load
these files and check that the adaptive composite map is bijective on each."""
import json, math, re

def write(name, source, target, **opts):
    m = {"type": "composite_mean_value", "source": source, "target": target,
         "vertex_path": "linear", "partition": "adaptive", "sample_resolution": 64, "min_interval": 1e-4}
    m.update(opts)
    cfg = {"map": m, "output": {"directory": f"output/{name}"}}
    with open(f"{name}.json", "w") as f:
        text = json.dumps(cfg, indent=2)
        text = re.sub(r"\[\s*(-?[0-9.e-]+),\s*(-?[0-9.e-]+)\s*\]", r"[\1, \2]", text)  # one point per line
        f.write(text + "\n")

r = lambda p: [round(p[0], 12), round(p[1], 12)]

# 1. Square -> concave quadrilateral (thesis §2.1.2: one vertex pulled far inside).
write("square_to_dart", [[-1, 0], [0, -1], [1, 0], [0, 1]], [[-1, 0], [0, -1], [-0.6, 0], [0, 1]])

# 2. Five-pointed star -> bent (pinwheel) star, intrinsic vertex path.
star = [r(((1.0 if i % 2 == 0 else 0.4) * math.cos(math.pi / 2 + i * math.pi / 5),
           (1.0 if i % 2 == 0 else 0.4) * math.sin(math.pi / 2 + i * math.pi / 5))) for i in range(10)]
bent = [r(((1.0 if i % 2 == 0 else 0.4) * math.cos(math.pi / 2 + i * math.pi / 5 + (0.5 if i % 2 == 0 else 0.0)),
           (1.0 if i % 2 == 0 else 0.4) * math.sin(math.pi / 2 + i * math.pi / 5 + (0.5 if i % 2 == 0 else 0.0))))
        for i in range(10)]
write("star_to_bent_star", star, bent, vertex_path="intrinsic")

# 3. Square carrying 40 boundary vertices (10 per side) -> 10-tooth gear.
square = []
for i in range(40):
    s = 8.0 * i / 40  # arc length from (-1,-1), counter-clockwise
    side, u = int(s // 2), s % 2
    square.append(r([[-1 + u, -1], [1, -1 + u], [1 - u, 1], [-1, 1 - u]][side]))
radius = [0.55, 1.0, 1.0, 0.55]
gear = [r((radius[i % 4] * math.cos(-0.75 * math.pi + 2 * math.pi * i / 40),
           radius[i % 4] * math.sin(-0.75 * math.pi + 2 * math.pi * i / 40))) for i in range(40)]
write("square_to_gear", square, gear)

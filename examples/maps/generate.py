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

# 4. The 64-vertex gear of ../study_gear64.json with straight edges (Ω0) -> the same
#    gear with curved edges (Ω1): tip and root arcs on their circles and convex flanks.
#    Every straight edge carries two extra vertices (192 in all) that the map moves onto
#    the curves; the corners stay where they are, so the map keeps the corner angles
#    up to the curves' tangents (sigma1/sigma2 <= 1.4 on dense samples). This is how the
#    framework is meant to meet a curved boundary: a polygon with the same corners as
#    Ω0 and the exact boundary as Ω1. Written as ../poisson_gear_curved.json.
def curved_gear(k=3, teeth=16, r_tip=1.0, r_root=0.78):
    pitch = 2 * math.pi / teeth
    w_tip, w_flank, w_root = math.radians(6.8), math.radians(4.5), math.radians(6.7)
    polar = lambda rad, a: [rad * math.cos(a), rad * math.sin(a)]
    source, target = [], []
    for t in range(teeth):
        a = -0.75 * math.pi + t * pitch
        corners = [(r_tip, a), (r_tip, a + w_tip), (r_root, a + w_tip + w_flank),
                   (r_root, a + w_tip + w_flank + w_root), (r_tip, a + pitch)]
        for e in range(4):
            (r0, b0), (r1, b1) = corners[e], corners[e + 1]
            p0, p1 = polar(r0, b0), polar(r1, b1)
            for j in range(k):
                s = j / k
                source.append(r([p0[0] + s * (p1[0] - p0[0]), p0[1] + s * (p1[1] - p0[1])]))
                if e in (0, 2):  # tip arc, root arc
                    target.append(r(polar(r0, b0 + s * (b1 - b0))))
                else:  # flanks bulge away from their tooth (convex teeth)
                    u = 1 - (1 - s) ** 2 if e == 1 else s * s
                    target.append(r(polar(r0 + s * (r1 - r0), b0 + u * (b1 - b0))))
    return source, target

source, target = curved_gear()
config = {
    "verbosity": "info",
    "map": {"type": "composite_mean_value", "source": source, "target": target,
            "partition": "adaptive", "sample_resolution": 64},
    "mesh": {"type": "delaunay", "max_edge_length": 0.15, "refinements": 3},
    "problem": {"type": "poisson", "order": 2, "source": "1", "dirichlet": [{"edges": "all", "value": 0}]},
    "solver": {"rtol": 1e-10, "multigrid": {"smoother": "chebyshev_sor"}},
    "output": {"directory": "output/gear_curved", "name": "solution"},
}
with open("../poisson_gear_curved.json", "w") as f:
    text = json.dumps(config, indent=2)
    text = re.sub(r"\[\s*(-?[0-9.e-]+),\s*(-?[0-9.e-]+)\s*\]", r"[\1, \2]", text)
    f.write(text + "\n")

# 3D: a 3 x 3 x 3 subdivided cube cage (56 vertices, 108 triangles) to a twisted and bent
# version (three eighths of a turn about the vertical axis from bottom to top, top bent sideways).
# The cages are OFF files next to the config (the same cube as tests/mapping/test_polyhedra.hpp).
def subdivided_cube(k):
    verts, index, tris = [], {}, []
    def vertex(c):
        if c not in index:
            index[c] = len(verts)
            verts.append([c[0] / k, c[1] / k, c[2] / k])
        return index[c]
    for a in range(3):
        for side in range(2):
            for i in range(k):
                for j in range(k):
                    u, w = (a + 1) % 3, (a + 2) % 3
                    def corner(di, dj):
                        c = [0, 0, 0]
                        c[a], c[u], c[w] = side * k, i + di, j + dj
                        return vertex(tuple(c))
                    q0, q1, q2, q3 = corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)
                    tris += [[q0, q1, q2], [q0, q2, q3]] if side == 1 else [[q0, q2, q1], [q0, q3, q2]]
    return verts, tris

def twist_and_bend(p, turn=0.75 * math.pi, bend=0.3):
    a = turn * p[2]
    x, y = p[0] - 0.5, p[1] - 0.5
    return [round(0.5 + math.cos(a) * x - math.sin(a) * y + bend * p[2] ** 2, 12),
            round(0.5 + math.sin(a) * x + math.cos(a) * y, 12), round(p[2], 12)]

def write_off(name, verts, tris):
    with open(name, "w") as f:
        f.write(f"OFF\n{len(verts)} {len(tris)} 0\n")
        f.writelines(f"{v[0]:.12g} {v[1]:.12g} {v[2]:.12g}\n" for v in verts)
        f.writelines(f"3 {t[0]} {t[1]} {t[2]}\n" for t in tris)

cube, cube_tris = subdivided_cube(3)
write_off("cube_cage.off", cube, cube_tris)
write_off("cube_twisted.off", [twist_and_bend(p) for p in cube], cube_tris)
with open("cube_to_twisted.json", "w") as f:
    f.write(json.dumps({"map": {"type": "composite_mean_value", "source": {"file": "cube_cage.off"},
                                "target": {"file": "cube_twisted.off"}, "partition": "adaptive",
                                "max_halvings": 8},
                        "output": {"directory": "output/cube_to_twisted", "grid_max_volume": 2e-4,
                                   "slices": [0.1, 0.5, 0.9]}},
                       indent=2) + "\n")

# Half a turn (and the bend): the linear vertex path crushes the top face at t = 1/2 and is
# refused; the intrinsic path turns the triangles instead.
write_off("cube_half_turn.off", [twist_and_bend(p, math.pi) for p in cube], cube_tris)
with open("cube_to_half_turn.json", "w") as f:
    f.write(json.dumps({"map": {"type": "composite_mean_value", "source": {"file": "cube_cage.off"},
                                "target": {"file": "cube_half_turn.off"}, "vertex_path": "intrinsic",
                                "partition": "adaptive", "max_halvings": 8},
                        "output": {"directory": "output/cube_to_half_turn", "grid_max_volume": 1e-3}},
                       indent=2) + "\n")

# The composite harmonic map of the same cube to the twisted and bent one folds (P1 harmonic maps
# of volumes need not be bijective; warpfem refuses it). A milder twist (one eighth of a turn, a
# smaller bend) is mapped harmonically.
write_off("cube_twisted_mild.off", [twist_and_bend(p, 0.25 * math.pi, 0.15) for p in cube], cube_tris)
for name, target in [("cube_to_twisted_harmonic.json", "cube_twisted_mild.off")]:
    with open(name, "w") as f:
        f.write(json.dumps({"map": {"type": "composite_harmonic", "source": {"file": "cube_cage.off"},
                                    "target": {"file": target}, "fem_max_volume": 2e-4},
                            "output": {"directory": "output/cube_to_twisted_harmonic", "grid_max_volume": 2e-4,
                                       "slices": [0.1, 0.5, 0.9]}},
                           indent=2) + "\n")

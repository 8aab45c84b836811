"""What Mitsuba 3.9.1 does where its own behaviour defines the format, the values that
tests/mitsuba_conformance.rs pins (pip install mitsuba==3.9.1):

    python3 scripts/mitsuba_conformance_probe.py

- `rotate`: Transform4f.rotate's matrix for axes that are not unit vectors (Mitsuba uses the
  axis as written: no normalisation, so such a `rotate` also scales and shears).
- Smooth normals: the vertex normals Mitsuba computes for `obj` and `ply` meshes without
  normals (tests/data/mitsuba-conformance/fan*.{obj,ply}), after a non-uniform `to_world`
  scale, listed per vertex position.
"""
import os

import mitsuba as mi

mi.set_variant("scalar_rgb")
DATA = os.path.join(os.path.dirname(__file__), "..", "tests", "data", "mitsuba-conformance")

for axis, angle in [([0, 1, 1], 15), ([0, 0, 2], 90), ([1, 0, 0], 90)]:
    m = mi.ScalarTransform4f().rotate(axis, angle).matrix
    rows = [[round(float(m[r][c]), 6) for c in range(3)] for r in range(3)]
    print(f"rotate axis {axis} angle {angle}: rows {rows}")

SCALE = [1, 2, 0.5]
for name, kind in [("fan.obj", "obj"), ("fan_seam.obj", "obj"), ("fan.ply", "ply")]:
    shape = mi.load_dict({
        "type": kind,
        "filename": os.path.join(DATA, name),
        "to_world": mi.ScalarTransform4f().scale(SCALE),
    })
    params = mi.traverse(shape)
    p = params["vertex_positions"]
    n = params["vertex_normals"]
    print(f"{name} scaled by {SCALE}: {len(p) // 3} vertices")
    for i in range(len(p) // 3):
        pos = [round(float(p[3 * i + k]), 6) for k in range(3)]
        nor = [round(float(n[3 * i + k]), 6) for k in range(3)]
        print(f"  position {pos} normal {nor}")

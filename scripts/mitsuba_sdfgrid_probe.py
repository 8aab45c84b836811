"""Mitsuba 3's `sdfgrid` (src/scene/sdf_grid.rs reproduces it): where rays hit the torus of the
suite's various_shapes scene (placed by its shapegroup + instance) and the normals there, the
geometric (`analytic`) one and the shading (`smooth`) one, for tests/sdf_grid.rs to pin
(pip install mitsuba==3.9.1). Two variants that trace it independently (scalar_rgb: Embree;
llvm_ad_rgb: Mitsuba's own kernels, needs libLLVM) must agree with each other first.

    python3 scripts/mitsuba_sdfgrid_probe.py [scalar_rgb|llvm_ad_rgb]

Prints one Rust row per ray from the camera's origin (-24, 0, 0) towards a grid of points
around the torus: its direction, then, where the sdfgrid is the first hit, t, the point, n
and the shading normal; a ray that hits nothing is a row with t = -1 (zeros after it); rays
whose first hit is another shape are left out.
"""
import os
import sys

import drjit as dr
import mitsuba as mi

variant = sys.argv[1] if len(sys.argv) > 1 else "scalar_rgb"
mi.set_variant(variant)

here = os.path.dirname(os.path.abspath(__file__))
xml = os.path.join(here, "..", "tests", "data", "mitsuba-suite", "tests", "scenes",
                   "various_shapes", "test_various_shapes_path.xml")
scene = mi.load_file(xml)

origin = [-24.0, 0.0, 0.0]  # the scene's camera
rows = []
steps = [-2.1, -1.5, -0.9, -0.3, 0.3, 0.9, 1.5, 2.1]
for dy in steps:
    for dz in steps:
        target = mi.ScalarPoint3f(0.0, -3.5 + dy, -5.0 + dz)
        d = target - mi.ScalarPoint3f(origin)
        d = d / (d[0] ** 2 + d[1] ** 2 + d[2] ** 2) ** 0.5
        ray = mi.Ray3f(mi.Point3f(origin), mi.Vector3f(d))
        si = scene.ray_intersect(ray)
        valid = bool(mi.Bool(si.is_valid()).numpy()[0]) if variant.startswith("llvm") \
            else bool(si.is_valid())
        if not valid:
            rows.append((d, -1.0, [0.0] * 3, [0.0] * 3, [0.0] * 3))
            continue
        # The torus is the scene's only instanced shape.
        if variant.startswith("llvm"):
            instanced = bool(dr.all(si.instance != None)[0])
        else:
            instanced = si.instance is not None
        if not instanced:
            continue

        def v(x):
            return [float(x[i][0]) if variant.startswith("llvm") else float(x[i])
                    for i in range(3)]
        t = float(si.t[0]) if variant.startswith("llvm") else float(si.t)
        rows.append((d, t, v(si.p), v(si.n), v(si.sh_frame.n)))

fmt = lambda xs: "[" + ", ".join(f"{x:.7}" for x in xs) + "]"
for d, t, p, n, ns in rows:
    print(f"    ({fmt([float(x) for x in d])}, {t:.7}, {fmt(p)}, {fmt(n)}, {fmt(ns)}),")
print(f"# {sum(r[1] > 0 for r in rows)} rays hit the sdfgrid ({variant})", file=sys.stderr)

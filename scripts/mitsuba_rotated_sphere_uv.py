"""Mitsuba 3.9.1's uv on a sphere whose to_world rotates (and scales and moves) it: the
parameterisation is the sphere's object space's, so the checkerboard turns with it
(tests/texture_mitsuba.rs, `rotated_sphere_uv_equals_mitsuba`; pip install mitsuba==3.9.1).

    python3 scripts/mitsuba_rotated_sphere_uv.py

Prints one Rust row per ray hit: the hit point (world), then u, v.
"""
import math

import mitsuba as mi

mi.set_variant("scalar_rgb")
T = mi.ScalarTransform4f
# various_shapes' sphere: scale 1.5, rotate x -35, rotate y -25, translate (0, -5, -2).
to_world = (T().translate([0.0, -5.0, -2.0]) @ T().rotate([0, 1, 0], -25)
            @ T().rotate([1, 0, 0], -35) @ T().scale(1.5))
scene = mi.load_dict({"type": "scene", "s": {"type": "sphere", "to_world": to_world}})
for k in range(12):
    a = 2 * math.pi * k / 12
    b = 0.9 * math.sin(3 * a)
    d = mi.ScalarVector3f(math.cos(a) * math.cos(b), math.sin(a) * math.cos(b), math.sin(b))
    o = mi.ScalarPoint3f(0.0, -5.0, -2.0) + 4.0 * d
    si = scene.ray_intersect(mi.Ray3f(o, -d))
    p = si.p
    print(f"    ([{p[0]:.7}, {p[1]:.7}, {p[2]:.7}], {si.uv[0]:.7}, {si.uv[1]:.7}),")

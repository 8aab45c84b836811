"""Mitsuba 3's `disk` and `cylinder`, which src/importers/mitsuba/round.rs meshes: their areas,
normals and texture coordinates at known points (pip install mitsuba==3.9.1).

    python3 scripts/mitsuba_round_shapes.py
"""
import math
import mitsuba as mi

mi.set_variant("scalar_rgb")

d = mi.load_dict({"type": "disk"})
print("disk area", d.surface_area())
for x, y in [(0.5, 0.0), (0.0, 0.5), (-0.5, 0.0), (0.0, -0.5), (0.3, 0.4)]:
    si = d.ray_intersect(mi.Ray3f([x, y, 1], [0, 0, -1]))
    print(f"disk at ({x}, {y}): uv {si.uv}, n {si.n}")

c = mi.load_dict({"type": "cylinder"})
print("cylinder area", c.surface_area())
for a in [0, 90, 180, 270]:
    t = math.radians(a)
    ray = mi.Ray3f([2 * math.cos(t), 2 * math.sin(t), 0.25], [-math.cos(t), -math.sin(t), 0])
    si = c.ray_intersect(ray)
    print(f"cylinder at {a} deg, z 0.25: uv {si.uv}, n {si.n}")
c2 = mi.load_dict({"type": "cylinder", "p0": [0, 0, 0], "p1": [0, 0, 2], "radius": 0.5})
print("cylinder p1 (0, 0, 2), radius 0.5: area", c2.surface_area())

#!/usr/bin/env python3
"""The tangent of Mitsuba 3.9.1's shading frame (`si.sh_frame.s`, the BSDF frame's x axis, along
which an anisotropic BSDF's `alpha_u` runs) at ray hits on three shapes, for tests/mesh_uvs.rs:

- `uv`: the suite's `meshes/sphere.obj` (uvs and vertex normals) under the rotations of
  `bsdf_spheres/test_normalmap_identity_roughconductor_path.xml`: the per-triangle dp/du made
  orthogonal to the interpolated shading normal;
- `nouv`: a two-triangle OBJ with vertex normals and no `vt`: dp/du is the triangle's first
  edge (p1 - p0);
- `sphere`: an analytic `sphere` (translated, scaled): the parameterisation's azimuth direction.

    pip install mitsuba==3.9.1
    python3 scripts/mitsuba_shading_frame.py   # writes tests/data/mitsuba_shading_frame.csv

Each row: shape, ray origin, ray direction, Mitsuba's hit point and sh_frame.s.
"""
import math
import os
import random

import mitsuba as mi

mi.set_variant('scalar_rgb')

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
COMMON = os.path.join(ROOT, 'tests', 'data', 'mitsuba-suite', 'common')

NOUV_OBJ = """v -1 -1 0
v 1 -1 0.2
v 1 1 0
v -1 1 -0.3
vn 0.1 0 1
vn 0 0.2 1
vn -0.1 0.1 1
vn 0.2 -0.1 1
f 1//1 2//2 3//3
f 1//1 3//3 4//4
"""


def shapes(tmp):
    rot = (mi.ScalarTransform4f().rotate([1, 0, 0], 30) @ mi.ScalarTransform4f().rotate([0, 1, 0], 30)
           @ mi.ScalarTransform4f().rotate([0, 0, 1], 30))
    nouv = os.path.join(tmp, 'nouv.obj')
    with open(nouv, 'w') as f:
        f.write(NOUV_OBJ)
    return {
        'uv': {'type': 'obj', 'filename': os.path.join(COMMON, 'meshes', 'sphere.obj'), 'to_world': rot},
        'nouv': {'type': 'obj', 'filename': nouv},
        'sphere': {'type': 'sphere', 'center': [0.3, -0.2, 0.1], 'radius': 0.8},
    }


def random_hits(scene, rng, above):
    """Endless hits of `scene` (origin, direction, interaction): rays from a point at distance 4
    (above z = 1 where `above`) towards a point near the origin, the misses skipped."""
    while True:
        z = rng.uniform(-1, 1)
        phi = rng.uniform(0, 2 * math.pi)
        r = math.sqrt(1 - z * z)
        o = [4 * r * math.cos(phi), 4 * r * math.sin(phi), 4 * z]
        if above:
            o[2] = abs(o[2]) + 1.0
        t = [rng.uniform(-0.4, 0.4) for _ in range(3)]
        d = [t[i] - o[i] for i in range(3)]
        n = math.sqrt(sum(c * c for c in d))
        d = [c / n for c in d]
        si = scene.ray_intersect(mi.Ray3f(o, d))
        if si.is_valid():
            yield o, d, si


def main():
    import itertools
    import tempfile
    rng = random.Random(7)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, shape in shapes(tmp).items():
            scene = mi.load_dict({'type': 'scene', 'shape': shape})
            for o, d, si in itertools.islice(random_hits(scene, rng, name == 'nouv'), 12):
                s = si.sh_frame.s
                rows.append([name] + o + d + [si.p[0], si.p[1], si.p[2], s[0], s[1], s[2]])
    out = os.path.join(ROOT, 'tests', 'data', 'mitsuba_shading_frame.csv')
    with open(out, 'w') as f:
        f.write('# scripts/mitsuba_shading_frame.py (Mitsuba %s, scalar_rgb)\n' % mi.__version__)
        f.write('shape,ox,oy,oz,dx,dy,dz,px,py,pz,sx,sy,sz\n')
        for r in rows:
            f.write(','.join([r[0]] + ['%.9g' % v for v in r[1:]]) + '\n')
    print('wrote', out, len(rows), 'rows')


if __name__ == '__main__':
    main()

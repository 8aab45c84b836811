#!/usr/bin/env python3
"""Mitsuba 3.9.1's `bumpmap` at ray hits, for tests/bump_map.rs: the height texture's gradient
(`bitmap.eval_1_grad`) and the bumped shading normal, on three shapes:

- `uv`: the suite's `meshes/sphere.obj` (uvs, vertex normals) rotated, with the suite's
  `textures/floor_tiles_bumpmap.png` (raw) at `scale` 0.02, as `test_bumpmap_path.xml`;
- `mirror`: a two-triangle OBJ whose uvs are mirrored (a negative Jacobian: the cross product
  of the partials points against the face, which Mitsuba turns), the same texture (not raw:
  sRGB-decoded) at `scale` 0.001;
- `sphere`: an analytic `sphere` (translated, scaled), the texture through a `to_uv` with
  shear (the gradient's transpose and resolution order), `scale` 0.002.

The bumped normal is not exposed by Mitsuba's Python API (`sh_frame` is C++ only), so it is
measured: the bumpmap around a white `diffuse` (no shadowing function) evaluates to
`max(0, n . wo) / pi` (in the hit's local frame), which six directions around the
unperturbed normal give by least squares (each value positive, residual printed).

    pip install mitsuba==3.9.1
    python3 scripts/mitsuba_bumpmap.py   # writes tests/data/mitsuba_bumpmap.csv

Each row: shape, ray origin, direction, Mitsuba's hit point, uv, gradient (eval_1_grad, before
`scale`) and the bumped normal in world space.
"""
import math
import os
import random

import mitsuba as mi

from mitsuba_shading_frame import random_hits

mi.set_variant('scalar_rgb')

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
COMMON = os.path.join(ROOT, 'tests', 'data', 'mitsuba-suite', 'common')
PNG = os.path.join(COMMON, 'textures', 'floor_tiles_bumpmap.png')

MIRROR_OBJ = """v -1 -1 0
v 1 -1 0.2
v 1 1 0
v -1 1 -0.3
vt 0.7 0.1
vt 0.1 0.2
vt 0.2 0.9
vt 0.8 0.7
vn 0.1 0 1
vn 0 0.2 1
vn -0.1 0.1 1
vn 0.2 -0.1 1
f 1/1/1 2/2/2 3/3/3
f 1/1/1 3/3/3 4/4/4
"""

# Directions around the local normal at which the diffuse is evaluated.
PROBES = [(0.3, 0.0), (-0.3, 0.0), (0.0, 0.3), (0.0, -0.3), (0.2, 0.2), (0.0, 0.0)]


def shapes(tmp):
    rot = (mi.ScalarTransform4f().rotate([1, 0, 0], 30) @ mi.ScalarTransform4f().rotate([0, 1, 0], 30)
           @ mi.ScalarTransform4f().rotate([0, 0, 1], 30))
    mirror = os.path.join(tmp, 'mirror.obj')
    with open(mirror, 'w') as f:
        f.write(MIRROR_OBJ)
    to_uv = mi.ScalarTransform4f([[2.0, 0.5, 0, 0.1], [-0.25, 1.5, 0, 0.3], [0, 0, 1, 0], [0, 0, 0, 1]])
    return {
        'uv': ({'type': 'obj', 'filename': os.path.join(COMMON, 'meshes', 'sphere.obj'), 'to_world': rot},
               {'type': 'bitmap', 'filename': PNG, 'raw': True}, 0.02),
        'mirror': ({'type': 'obj', 'filename': mirror},
                 {'type': 'bitmap', 'filename': PNG}, 0.001),
        'sphere': ({'type': 'sphere', 'center': [0.3, -0.2, 0.1], 'radius': 0.8},
                   {'type': 'bitmap', 'filename': PNG, 'raw': True, 'to_uv': to_uv}, 0.002),
    }


def solve3(a, b):
    """Solves the 3x3 system a x = b (Cramer)."""
    def det(m):
        return (m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
                - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
                + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]))
    d = det(a)
    out = []
    for k in range(3):
        m = [[b[i] if j == k else a[i][j] for j in range(3)] for i in range(3)]
        out.append(det(m) / d)
    return out


def bumped_normal(bsdf, si):
    """The bumped normal (local frame of si) from the diffuse's values; None where a probe
    direction is below it."""
    ctx = mi.BSDFContext()
    rows, vals = [], []
    for x, y in PROBES:
        wo = mi.Vector3f(x, y, math.sqrt(1 - x * x - y * y))
        v = bsdf.eval(ctx, si, wo)[0] * math.pi
        if not v > 1e-4:
            return None, 0
        rows.append([wo[0], wo[1], wo[2]])
        vals.append(v)
    # Least squares: (A^T A) n = A^T v.
    ata = [[sum(r[i] * r[j] for r in rows) for j in range(3)] for i in range(3)]
    atv = [sum(r[i] * v for r, v in zip(rows, vals)) for i in range(3)]
    n = solve3(ata, atv)
    resid = max(abs(sum(r[i] * n[i] for i in range(3)) - v) for r, v in zip(rows, vals))
    return n, resid


def main():
    import tempfile
    rng = random.Random(11)
    rows = []
    worst = 0.0
    with tempfile.TemporaryDirectory() as tmp:
        for name, (shape, tex, scale) in shapes(tmp).items():
            scene = mi.load_dict({'type': 'scene', 'shape': shape})
            texture = mi.load_dict(tex)
            bsdf = mi.load_dict({'type': 'bumpmap', 'height': tex, 'scale': scale,
                                 'use_shadowing_function': False,
                                 'bsdf': {'type': 'diffuse', 'reflectance': 1.0}})
            hits = random_hits(scene, rng, name == 'mirror')
            got = 0
            while got < 12:
                o, d, si = next(hits)
                local, resid = bumped_normal(bsdf, si)
                if local is None:
                    continue
                got += 1
                worst = max(worst, resid)
                ln = math.sqrt(sum(c * c for c in local))
                nw = si.to_world(mi.Vector3f(local[0] / ln, local[1] / ln, local[2] / ln))
                g = texture.eval_1_grad(si)
                rows.append([name] + o + d + [si.p[0], si.p[1], si.p[2], si.uv[0], si.uv[1],
                                              g[0], g[1], nw[0], nw[1], nw[2]])
    out = os.path.join(ROOT, 'tests', 'data', 'mitsuba_bumpmap.csv')
    with open(out, 'w') as f:
        f.write('# scripts/mitsuba_bumpmap.py (Mitsuba %s, scalar_rgb)\n' % mi.__version__)
        f.write('shape,ox,oy,oz,dx,dy,dz,px,py,pz,u,v,gu,gv,nx,ny,nz\n')
        for r in rows:
            f.write(','.join([r[0]] + ['%.9g' % v for v in r[1:]]) + '\n')
    print('wrote', out, len(rows), 'rows; worst least-squares residual %.2e' % worst)


if __name__ == '__main__':
    main()

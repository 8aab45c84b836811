#!/usr/bin/env python3
"""Mitsuba 3.9.1's `bumpmap` at ray hits, for tests/bump_map.rs: the height texture's gradient
(`bitmap.eval_1_grad`) and the bumped shading frame, on three shapes:

- `uv`: the suite's `meshes/sphere.obj` (uvs, vertex normals) rotated, with the suite's
  `textures/floor_tiles_bumpmap.png` (raw) at `scale` 0.02, as `test_bumpmap_path.xml`;
- `mirror`: a two-triangle OBJ whose uvs are mirrored (a negative Jacobian: the cross product
  of the partials points against the face, which Mitsuba turns), the same texture (not raw:
  sRGB-decoded) at `scale` 0.001;
- `sphere`: an analytic `sphere` (translated, scaled), the texture through a `to_uv` with
  shear (the gradient's transpose and resolution order), `scale` 0.002.

The bumped frame is what the nested bsdf receives: a Python bsdf (`Probe`) nested in the
bumpmap records `si.sh_frame` at its `eval` (the bumped frame relative to the hit's, as
bumpmap.cpp hands it on), taken to world space by the hit's frame. Its normal is the bumped
normal; its tangent shows 3.9.1's Gram-Schmidt of the world dp/du against the local normal.

    pip install mitsuba==3.9.1
    python3 scripts/mitsuba_bumpmap.py   # writes tests/data/mitsuba_bumpmap.csv

Each row: shape, ray origin, direction, Mitsuba's hit point, uv, gradient (eval_1_grad, before
`scale`), the bumped normal and the bumped frame's tangent in world space.
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

class Probe(mi.BSDF):
    """A nested bsdf that records the frame it is evaluated in (and reflects nothing)."""

    frames = []

    def __init__(self, props):
        mi.BSDF.__init__(self, props)
        self.m_flags = mi.BSDFFlags.DiffuseReflection | mi.BSDFFlags.FrontSide
        self.m_components = [self.m_flags]

    def eval(self, ctx, si, wo, active=True):
        f = si.sh_frame
        Probe.frames.append((f.s, f.n))
        return mi.Color3f(0.0)

    def sample(self, ctx, si, sample1, sample2, active=True):
        return (mi.BSDFSample3f(), mi.Color3f(0.0))

    def pdf(self, ctx, si, wo, active=True):
        return 0.0

    def eval_pdf(self, ctx, si, wo, active=True):
        return (self.eval(ctx, si, wo, active), 0.0)

    def to_string(self):
        return 'Probe'


mi.register_bsdf('probe', lambda props: Probe(props))


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


def bumped_frame(bsdf, si):
    """The bumped frame's normal and tangent in world space."""
    Probe.frames.clear()
    bsdf.eval(mi.BSDFContext(), si, mi.Vector3f(0, 0, 1))
    s, n = Probe.frames[-1]
    return si.to_world(n), si.to_world(s)


def main():
    import itertools
    import tempfile
    rng = random.Random(11)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, (shape, tex, scale) in shapes(tmp).items():
            scene = mi.load_dict({'type': 'scene', 'shape': shape})
            texture = mi.load_dict(tex)
            bsdf = mi.load_dict({'type': 'bumpmap', 'height': tex, 'scale': scale,
                                 'bsdf': {'type': 'probe'}})
            for o, d, si in itertools.islice(random_hits(scene, rng, name == 'mirror'), 12):
                n, s = bumped_frame(bsdf, si)
                g = texture.eval_1_grad(si)
                rows.append([name] + o + d + [si.p[0], si.p[1], si.p[2], si.uv[0], si.uv[1],
                                              g[0], g[1], n[0], n[1], n[2], s[0], s[1], s[2]])
    out = os.path.join(ROOT, 'tests', 'data', 'mitsuba_bumpmap.csv')
    with open(out, 'w') as f:
        f.write('# scripts/mitsuba_bumpmap.py (Mitsuba %s, scalar_rgb)\n' % mi.__version__)
        f.write('shape,ox,oy,oz,dx,dy,dz,px,py,pz,u,v,gu,gv,nx,ny,nz,sx,sy,sz\n')
        for r in rows:
            f.write(','.join([r[0]] + ['%.9g' % v for v in r[1:]]) + '\n')
    print('wrote', out, len(rows), 'rows')


if __name__ == '__main__':
    main()

#!/usr/bin/env python3
"""Mitsuba 3.9.1's `checkerboard` read as a float (`eval_1`, what a float parameter such as
principled's `metallic` reads) gives the other colour than its RGB `eval`: its eval_1 picks
color0 where the cell masks differ, eval where they agree. Prints both at a few uv and fails
unless eval_1 is eval with the colours swapped everywhere (src/importers/mitsuba/principled.rs
swaps them for float parameters).

    pip install mitsuba==3.9.1 && python3 scripts/mitsuba_checkerboard_eval1.py
"""
import mitsuba as mi

mi.set_variant('scalar_rgb')
c0, c1 = 0.7, 0.1
tex = mi.load_dict({'type': 'checkerboard', 'color0': c0, 'color1': c1})
swapped = 0
points = [(0.1, 0.1), (0.6, 0.1), (0.1, 0.6), (0.6, 0.6), (1.3, 2.8), (2.7, 0.2)]
for u, v in points:
    si = mi.SurfaceInteraction3f()
    si.uv = mi.Point2f(u, v)
    rgb = tex.eval(si)[0]
    f = tex.eval_1(si)
    print('uv (%.1f, %.1f): eval %.2f eval_1 %.2f' % (u, v, rgb, f))
    close = lambda a, b: abs(a - b) < 1e-6
    swapped += (close(rgb, c0) and close(f, c1)) or (close(rgb, c1) and close(f, c0))
assert swapped == len(points), 'eval_1 is not eval with the colours swapped'
print('eval_1 swaps the colours at all %d points' % len(points))

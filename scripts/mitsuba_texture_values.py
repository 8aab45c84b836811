#!/usr/bin/env python3
"""Reference values from Mitsuba 3.9.1 for tests/texture_mitsuba.rs.

Writes small test images into tests/data/textures/, evaluates Mitsuba's `bitmap` texture on
them (every filter, wrap mode, raw/sRGB, a `to_uv` transform) and the uv of Mitsuba's analytic
shapes (rectangle, sphere, disk, cube) at ray hits, into
tests/data/textures/mitsuba_bitmap.csv and tests/data/textures/mitsuba_uv.csv.

    python3 -m venv /tmp/mi && /tmp/mi/bin/pip install mitsuba==3.9.1 numpy
    /tmp/mi/bin/python scripts/mitsuba_texture_values.py
"""
import os
import numpy as np
import mitsuba as mi

mi.set_variant("scalar_rgb")
OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "data", "textures")
os.makedirs(OUT, exist_ok=True)


def write_images():
    """4x3 RGB8, 3x2 grey+alpha 8-bit, 3x3 RGBA8, 4x3 float RGB EXR and Radiance HDR."""
    w, h = 4, 3
    rgb = np.zeros((h, w, 3), np.uint8)
    for y in range(h):
        for x in range(w):
            rgb[y, x] = [40 + 50 * x, 30 + 70 * y, 200 - 20 * x - 30 * y]
    mi.Bitmap(rgb).write(os.path.join(OUT, "rgb4x3.png"))
    ya = np.array([[[10, 255], [90, 128], [200, 0]], [[255, 64], [0, 200], [140, 30]]], np.uint8)
    mi.Bitmap(ya, mi.Bitmap.PixelFormat.YA).write(os.path.join(OUT, "ya3x2.png"))
    rgba = np.zeros((3, 3, 4), np.uint8)
    for y in range(3):
        for x in range(3):
            rgba[y, x] = [25 + 80 * x, 240 - 60 * y, 17 * (x + 3 * y), 40 + 25 * (x + 3 * y)]
    mi.Bitmap(rgba, mi.Bitmap.PixelFormat.RGBA).write(os.path.join(OUT, "rgba3x3.png"))
    f = np.zeros((h, w, 3), np.float32)
    for y in range(h):
        for x in range(w):
            f[y, x] = [0.25 + 1.5 * x, 3.0 - 0.75 * y, 0.125 * (x + 1) * (y + 1)]
    mi.Bitmap(f).write(os.path.join(OUT, "float4x3.exr"))
    mi.Bitmap(f).write(os.path.join(OUT, "float4x3.hdr"), mi.Bitmap.FileFormat.RGBE)


def uv_points():
    """A grid over [-1.3, 2.2]^2 (outside the unit square too) plus texel centres and edges."""
    g = np.linspace(-1.3, 2.2, 10)
    pts = [(u, v) for u in g for v in g]
    pts += [((i + 0.5) / 4, (j + 0.5) / 3) for i in range(4) for j in range(3)]
    pts += [(0.0, 0.0), (1.0, 1.0), (0.0, 1.0), (1.0, 0.0), (0.5, 0.5), (-0.25, 0.999), (3.01, -2.49)]
    return [(float(np.float32(u)), float(np.float32(v))) for u, v in pts]


def bitmap_rows():
    # (file, raw, filter, wrap, to_uv as [[a, b, c], [d, e, f]])
    ident = [[1, 0, 0], [0, 1, 0]]
    rot = mi.ScalarTransform3f().translate([0.3, -0.2]) @ mi.ScalarTransform3f().rotate(30.0) \
        @ mi.ScalarTransform3f().scale([2.0, 0.5])
    m = np.array(rot.matrix)
    tuv = [[float(m[0][0]), float(m[0][1]), float(m[0][2])], [float(m[1][0]), float(m[1][1]), float(m[1][2])]]
    cases = []
    for raw in (True, False):
        for filt in ("nearest", "bilinear"):
            for wrap in ("repeat", "mirror", "clamp"):
                cases.append(("rgb4x3.png", raw, filt, wrap, ident))
    for filt in ("nearest", "bilinear"):
        cases.append(("rgb4x3.png", False, filt, "repeat", tuv))
        cases.append(("rgb4x3.png", True, filt, "mirror", tuv))
        for f in ("ya3x2.png", "rgba3x3.png"):
            for raw in (True, False):
                cases.append((f, raw, filt, "repeat", ident))
        for f in ("float4x3.exr", "float4x3.hdr"):
            for wrap in ("repeat", "mirror", "clamp"):
                cases.append((f, True, filt, wrap, ident))
    rows = []
    for f, raw, filt, wrap, t in cases:
        d = {"type": "bitmap", "filename": os.path.join(OUT, f), "filter_type": filt,
             "wrap_mode": wrap, "raw": raw}
        if t is not ident:
            d["to_uv"] = mi.ScalarTransform3f(np.array(t + [[0, 0, 1]], dtype=np.float64))
        tex = mi.load_dict(d)
        si = mi.SurfaceInteraction3f()
        for u, v in uv_points():
            si.uv = mi.Point2f(u, v)
            c = tex.eval(si)
            tt = ",".join("%.9g" % x for x in t[0] + t[1])
            rows.append("%s,%s,%s,%s,%s,%.9g,%.9g,%.9g,%.9g,%.9g" % (
                f, "raw" if raw else "srgb", filt, wrap, tt, u, v, c[0], c[1], c[2]))
    # The checkerboard: file "checkerboard", encoding/filter/wrap unused, colours
    # (0.1, 0.2, 0.3) and (0.9, 0.8, 0.7).
    for t in (ident, tuv):
        d = {"type": "checkerboard", "color0": {"type": "rgb", "value": [0.1, 0.2, 0.3]},
             "color1": {"type": "rgb", "value": [0.9, 0.8, 0.7]}}
        if t is not ident:
            d["to_uv"] = mi.ScalarTransform3f(np.array(t + [[0, 0, 1]], dtype=np.float64))
        tex = mi.load_dict(d)
        si = mi.SurfaceInteraction3f()
        for u, v in uv_points():
            si.uv = mi.Point2f(u, v)
            c = tex.eval(si)
            tt = ",".join("%.9g" % x for x in t[0] + t[1])
            rows.append("checkerboard,-,-,-,%s,%.9g,%.9g,%.9g,%.9g,%.9g" % (tt, u, v, c[0], c[1], c[2]))
    with open(os.path.join(OUT, "mitsuba_bitmap.csv"), "w") as out:
        out.write("file,encoding,filter,wrap,a,b,c,d,e,f,u,v,r,g,b\n")
        out.write("\n".join(rows) + "\n")


def uv_rows():
    rng = np.random.default_rng(7)
    rows = []
    for shape in ("rectangle", "disk", "sphere", "cube"):
        scene = mi.load_dict({"type": "scene", "s": {"type": shape}})
        n = 0
        while n < 60:
            if shape in ("rectangle", "disk"):
                x, y = rng.uniform(-1, 1, 2)
                if shape == "disk" and x * x + y * y >= 0.999:
                    continue
                o, d = [x, y, 3.0], [0.0, 0.0, -1.0]
            else:
                d = rng.normal(size=3)
                d /= np.linalg.norm(d)
                off = rng.uniform(-0.4, 0.4, 3)
                o = list(-4.0 * d + off)
                d = list(d)
            si = scene.ray_intersect(mi.Ray3f(mi.Point3f(o), mi.Vector3f(d)))
            if not si.is_valid():
                continue
            p = si.p
            if shape == "sphere" and abs(p[2]) > 0.999:
                continue  # the poles' u is arbitrary
            rows.append("%s,%.9g,%.9g,%.9g,%.9g,%.9g" % (shape, p[0], p[1], p[2], si.uv[0], si.uv[1]))
            n += 1
    with open(os.path.join(OUT, "mitsuba_uv.csv"), "w") as out:
        out.write("shape,x,y,z,u,v\n")
        out.write("\n".join(rows) + "\n")


if __name__ == "__main__":
    write_images()
    bitmap_rows()
    uv_rows()

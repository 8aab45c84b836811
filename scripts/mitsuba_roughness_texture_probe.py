"""Mitsuba 3.9.1's float evaluation (`eval_1`, what a rough conductor's or dielectric's
textured `alpha_u`/`alpha_v`/`alpha` reads) of a colour checkerboard and of `rawconstant`
textures, for tests/mitsuba.rs (`rawconstant_and_textured_roughness`).

Run: python3 scripts/mitsuba_roughness_texture_probe.py (pip mitsuba==3.9.1).
"""
import mitsuba as mi

mi.set_variant("scalar_rgb")
checker = mi.load_dict({
    "type": "checkerboard",
    "color0": {"type": "rgb", "value": [0.1, 0.2, 0.9]},
    "color1": 0.3,
})
raw3 = mi.load_dict({"type": "rawconstant", "value": mi.ScalarVector3f(0.5, -2.0, 3.0)})
raw1 = mi.load_dict({"type": "rawconstant", "value": 2.5})
si = mi.SurfaceInteraction3f()
for uv in [(0.25, 0.25), (0.75, 0.25), (0.25, 0.75), (0.75, 0.75)]:
    si.uv = mi.Point2f(*uv)
    print(f"checkerboard eval_1 at {uv}: {checker.eval_1(si):.7f}")
si.uv = mi.Point2f(0.3, 0.9)
print("rawconstant vector eval_3:", raw3.eval_3(si))
print("rawconstant float eval_3:", raw1.eval_3(si), "eval_1:", raw1.eval_1(si))

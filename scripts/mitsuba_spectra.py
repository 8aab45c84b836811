"""Reference values for tests/mitsuba_xml.rs and the CIE table of
src/importers/mitsuba/cie.rs, from Mitsuba 3 itself (pip install mitsuba==3.9.1).

    python3 scripts/mitsuba_spectra.py table   # the CIE 1931 table, as Rust
    python3 scripts/mitsuba_spectra.py         # the reference colours
"""
import sys
import mitsuba as mi

mi.set_variant("scalar_rgb")

if sys.argv[1:] == ["table"]:
    # Mitsuba's table: CIE 1931 2-degree observer, 360..830 nm every 5 nm.
    n = int((mi.MI_CIE_MAX - mi.MI_CIE_MIN) / 5) + 1
    for i in range(n):
        x, y, z = mi.cie1931_xyz(mi.MI_CIE_MIN + 5.0 * i)
        print(f"    [{x:.9}, {y:.9}, {z:.9}],")
    for e in ([1, 0, 0], [0, 1, 0], [0, 0, 1]):
        print("xyz_to_srgb column", mi.xyz_to_srgb(mi.Color3f(e)))
    print("Y normalization", mi.MI_CIE_Y_NORMALIZATION)
    sys.exit()

CURVE = "400:0.343, 404:0.445, 450:0.3, 500:0.15, 560:0.6, 610:0.7, 700:0.8"
for name, tag, value in [
    ("reflectance", "bsdf", CURVE),
    ("reflectance", "bsdf", "0.5"),
    ("reflectance", "bsdf", "360:1, 830:1"),
    ("eta", "bsdf", "400:1.5, 700:1.8"),
    ("radiance", "emitter", "400:1.5, 500:3, 600:2, 700:0.5"),
    ("radiance", "emitter", "7"),
]:
    if tag == "bsdf":
        kind = "conductor" if name == "eta" else "diffuse"
        extra = '<spectrum name="k" value="0"/>' if name == "eta" else ""
        xml = f'<bsdf version="3.0.0" type="{kind}"><spectrum name="{name}" value="{value}"/>{extra}</bsdf>'
    else:
        xml = f'<emitter version="3.0.0" type="point"><spectrum name="intensity" value="{value}"/></emitter>'
    obj = mi.load_string(xml)
    params = mi.traverse(obj)
    key = [k for k in params.keys() if k.endswith(".value")][0]
    print(tag, name, value, "->", params[key])

# A blackbody: Mitsuba's RGB variants refuse it; its spectral variants integrate
# Planck's law against the CIE curves (the film's XYZ, times MI_CIE_Y_NORMALIZATION).
mi.set_variant("scalar_spectral")
for t in [2700.0, 6500.0]:
    bb = mi.load_dict({"type": "blackbody", "temperature": t})
    si = mi.SurfaceInteraction3f()
    steps = 1000
    acc = [0.0, 0.0, 0.0]
    for i in range(steps):
        x = mi.MI_CIE_MIN + (i / (steps - 1)) * (mi.MI_CIE_MAX - mi.MI_CIE_MIN)
        si.wavelengths = mi.Spectrum([x, x, x, x])
        p = bb.eval(si)[0]
        xyz = mi.cie1931_xyz(x)
        for c in range(3):
            acc[c] += xyz[c] * p
    scale = (mi.MI_CIE_MAX - mi.MI_CIE_MIN) / steps * mi.MI_CIE_Y_NORMALIZATION
    mi.set_variant("scalar_rgb")
    print("blackbody", t, "->", mi.xyz_to_srgb(mi.Color3f([a * scale for a in acc])))
    mi.set_variant("scalar_spectral")

"""What Mitsuba 3 does with a scene written for Mitsuba 0.x (`<scene version>` below 2.0.0),
the behaviour src/importers/mitsuba/upgrade.rs follows (pip install mitsuba==3.9.1):

    python3 scripts/mitsuba_upgrade_probe.py

Each case loads a small scene and prints what Mitsuba made of it: the names it did not use
(after its camelCase to snake_case conversion), the bsdf it built, or its error.
"""
import mitsuba as mi

mi.set_variant("scalar_rgb")

CAM = ('<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/>'
       '<integer name="height" value="4"/></film></sensor>')


def run(label, version, body):
    xml = f'<scene version="{version}">{body}</scene>'
    try:
        s = mi.load_string(xml)
        out = "; ".join(" ".join(str(sh.bsdf()).split()) for sh in s.shapes()) or "loaded"
    except Exception as e:
        out = "error: " + " ".join(str(e).split())
    print(f"{label}:\n  {out}\n")


def names(*names):
    floats = "".join(f'<float name="{n}" value="1"/>' for n in names)
    return CAM.replace("<film", floats + "<film")


# The conversion of names (reported back as unused parameters of the sensor).
run("names", "0.6.0", names("aBcD", "xYZwQ", "a2B", "ABc", "_aB", "aB_cD", "intIOR"))
# A diffuse bsdf's diffuseReflectance is its reflectance.
run("diffuse", "0.6.0", CAM + '<shape type="sphere"><bsdf type="diffuse">'
    '<rgb name="diffuseReflectance" value="0.2"/></bsdf></shape>')
# uoffset/voffset/uscale/vscale: a to_uv transform, the offset first.
run("uv floats", "0.6.0", CAM + '<shape type="sphere"><bsdf type="diffuse">'
    '<texture type="checkerboard" name="reflectance"><float name="vscale" value="3"/>'
    '<float name="uoffset" value="0.5"/><float name="uscale" value="4"/></texture>'
    '</bsdf></shape>')
# <lookAt> is not renamed: an error.
run("lookAt", "0.6.0", CAM.replace(
    "<film", '<transform name="toWorld"><lookAt origin="1,1,1" target="0,0,0"/></transform><film'))
# Which versions are upgraded, and what a version must look like.
for v in ["1.9.9", "2.0.0", "3.0.0"]:
    run(f"version {v}", v, names("farClip"))
run("version 0.6", "0.6", CAM)
# Mitsuba 0.6's hdrfilm `banner` is accepted by Mitsuba 3.
run("banner", "3.0.0", CAM.replace("<integer", '<boolean name="banner" value="false"/><integer', 1))

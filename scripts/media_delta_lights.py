#!/usr/bin/env python3
"""Point, spot and directional lights inside a bounded medium (issue 41): Mitsuba 3.9.1
`volpath` against gpu-photon on variants of scenes/mitsuba/fog-box-null.xml.

Each variant replaces the scene's area light (and makes the glass sphere diffuse: Mitsuba's
volpath cannot see a delta light through smooth glass, where ours renders the caustic): `point` (a point light inside the fog, the
camera outside), `spot` (a spot inside the fog aimed down and across it) and `directional`
(a sun from above, the camera inside the fog: its sensor names the fog). Mitsuba renders it
(llvm_ad_rgb, --mspp samples, seed 7), gpu-photon at its defaults (`render --backend cpu`,
the file's resolution, --res). Prints each channel's mean ratio (ours / Mitsuba) and the
16 x 16 blocks' ratios (their range, and those of the blocks off by more than --tol).
Before issue 41's fix these lights' photons started in the camera's medium: the point and
spot light's photons in vacuum inside the fog, the sun's in fog outside the box.

    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \\
    python3 scripts/media_delta_lights.py [--lights point,spot,directional] [--mspp 1024]
        [--res 64] [--extra '--spp 16']
"""
import argparse
import os
import re
import subprocess
import tempfile

import numpy as np

os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")
import mitsuba as mi  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SCENE = os.path.join(ROOT, "scenes", "mitsuba", "fog-box-null.xml")
BIN = os.path.join(ROOT, "target", "release", "gpu-photon")

LIGHTS = {
    "point": '<emitter type="point"><point name="position" x="-0.35" y="0.05" z="0.3"/>'
             '<rgb name="intensity" value="1.5, 1.0, 0.4"/></emitter>',
    "spot": '<emitter type="spot"><transform name="to_world"><lookat origin="-0.5, 0.3, 0.2" '
            'target="0.3, -0.9, -0.2" up="0, 1, 0"/></transform><float name="cutoff_angle" '
            'value="35"/><float name="beam_width" value="25"/>'
            '<rgb name="intensity" value="3, 2, 1"/></emitter>',
    "directional": '<emitter type="directional"><vector name="direction" x="0.3" y="-1" z="-0.2"/>'
                   '<rgb name="irradiance" value="2, 1.5, 1"/></emitter>',
}
# The camera inside the fog, looking across it at the sphere (the directional variant).
INSIDE = ('<lookat origin="-0.2, -0.1, 0.7" target="0.15, -0.5, 0" up="0, 1, 0"/></transform>'
          '<ref id="fog"/>')


def variant(light, res):
    xml = open(SCENE).read()
    xml = re.sub(r"<!-- the light:.*?</shape>\n", "", xml, flags=re.S)
    xml = xml.replace("</scene>", LIGHTS[light] + "\n</scene>")
    # Mitsuba's volpath finds no light from a delta light through smooth glass (caustics):
    # the sphere is diffuse here.
    xml = re.sub(r'<bsdf type="dielectric">.*?</bsdf>',
                 '<bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.5, 0.5"/></bsdf>', xml)
    xml = re.sub(r'name="(width|height)" value="\d+"', rf'name="\1" value="{res}"', xml)
    if light == "directional":
        xml = re.sub(r"<lookat [^>]*/></transform>", INSIDE, xml, count=1)
    return xml


def blocks(a, b=16):
    h, w, c = a.shape
    return a[: h // b * b, : w // b * b].reshape(h // b, b, w // b, b, c).mean((1, 3))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--lights", default=",".join(LIGHTS))
    ap.add_argument("--mspp", type=int, default=1024)
    ap.add_argument("--res", type=int, default=64)
    ap.add_argument("--tol", type=float, default=0.03)
    ap.add_argument("--extra", default="", help="more arguments for gpu-photon render")
    ap.add_argument("--keep", default=None, help="folder to keep the scenes and EXRs in")
    args = ap.parse_args()
    mi.set_variant("llvm_ad_rgb")
    for light in args.lights.split(","):
        xml = variant(light, args.res)
        with tempfile.TemporaryDirectory() as tmp:
            path = os.path.join(tmp, f"fog-box-{light}.xml")
            open(path, "w").write(xml)
            ref = np.array(mi.render(mi.load_file(path), spp=args.mspp, seed=7), dtype=np.float64)[..., :3]
            out = os.path.join(tmp, "ours.exr")
            subprocess.run([BIN, "render", path, "-o", out, "--backend", "cpu", "--quiet"]
                           + args.extra.split(), check=True)
            ours = np.array(mi.Bitmap(out), dtype=np.float64)[..., :3]
            if args.keep:
                os.makedirs(args.keep, exist_ok=True)
                open(os.path.join(args.keep, f"{light}.xml"), "w").write(xml)
                mi.Bitmap(ref.astype(np.float32)).write(os.path.join(args.keep, f"{light}-mitsuba.exr"))
                mi.Bitmap(ours.astype(np.float32)).write(os.path.join(args.keep, f"{light}-ours.exr"))
        ratio = ours.mean((0, 1)) / ref.mean((0, 1))
        r = blocks(ours).mean(2) / np.maximum(blocks(ref).mean(2), 1e-9)
        off = [(i, j, round(float(r[i, j]), 3)) for i in range(r.shape[0]) for j in range(r.shape[1])
               if abs(r[i, j] - 1) > args.tol]
        print(f"{light}: mean ratio {np.round(ratio, 4)}, blocks {r.min():.3f}..{r.max():.3f}, "
              f"off by > {args.tol}: {off}", flush=True)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""The spectral reflectances of tests/data/cornell-idiomatic/ and Mitsuba's check of that scene.

1. Solves, by Newton's method on Mitsuba 3.9.1's own conversion (scalar_rgb: a `diffuse`
   BSDF's reflectance evaluated), three-plateau spectra (360-489, 490-579, 580-830 nm) whose
   RGB is exactly tests/data/cornell-diffuse.xml's red and green, and prints them as the
   `<spectrum value="...">` strings fragments/materials.xml holds.
2. Renders tests/data/cornell-idiomatic/cornell.xml with Mitsuba's path tracer (llvm_ad_rgb,
   SPP samples per pixel) and prints its mean ratio per channel and 16 x 16-block RMSE
   against tests/data/cornell-diffuse.exr: Mitsuba reads the idiomatic file as the same scene.

    pip install mitsuba==3.9.1 numpy; apt-get install libllvm19
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \\
    python3 scripts/cornell_spectra.py [SPP]   (default 1024)
"""
import os
import sys
import numpy as np
import mitsuba as mi

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_refs import block_rmse  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
SCENE = os.path.join(ROOT, "tests", "data", "cornell-idiomatic", "cornell.xml")
REFERENCE = os.path.join(ROOT, "tests", "data", "cornell-diffuse.exr")
BANDS = [(360, 489), (490, 579), (580, 830)]
TARGETS = {"red": (0.63, 0.065, 0.05), "green": (0.14, 0.45, 0.091)}


def spectrum(levels):
    """The `<spectrum value>` string of three plateaus."""
    return ", ".join(f"{lo}:{v:.6f}, {hi}:{v:.6f}" for (lo, hi), v in zip(BANDS, levels))


def rgb(levels):
    """The RGB albedo Mitsuba gives a diffuse BSDF of that spectrum (as written, 6 decimals)."""
    xml = ('<bsdf version="3.0.0" type="diffuse">'
           f'<spectrum name="reflectance" value="{spectrum(levels)}"/></bsdf>')
    bsdf = mi.load_string(xml)
    si = mi.SurfaceInteraction3f()
    si.wi = [0, 0, 1]
    si.sh_frame = mi.Frame3f([0, 0, 1])
    return np.array(bsdf.eval(mi.BSDFContext(), si, [0, 0, 1])) * np.pi


def solve(target):
    target = np.array(target)
    x = target[::-1].copy()
    for _ in range(8):
        f = rgb(x)
        jac = np.zeros((3, 3))
        for i in range(3):
            e = np.zeros(3)
            e[i] = 1e-3
            jac[:, i] = (rgb(x + e) - f) / 1e-3
        x = x + np.linalg.solve(jac, target - f)
    return x


def main():
    spp = int(sys.argv[1]) if len(sys.argv) > 1 else 1024
    mi.set_variant("scalar_rgb")
    for name, target in TARGETS.items():
        x = solve(target)
        print(f"{name}: {spectrum(x)}  -> rgb {rgb(x)} (target {target})")
    mi.set_variant("llvm_ad_rgb")
    img = np.array(mi.render(mi.load_file(SCENE), spp=spp), dtype=np.float64)[:, :, :3]
    ref = np.array(mi.Bitmap(REFERENCE), dtype=np.float64)[:, :, :3]
    print("mean ratio vs cornell-diffuse.exr", img.reshape(-1, 3).mean(0) / ref.reshape(-1, 3).mean(0))
    print(f"block rmse (16x16) {block_rmse(img, ref):.5f}")


if __name__ == "__main__":
    main()

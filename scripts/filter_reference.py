#!/usr/bin/env python3
"""The pixel-filter scene's Mitsuba 3.9.1 reference.

Renders scenes/mitsuba/filter.xml (32 x 32, gaussian reconstruction filter) with Mitsuba's
path tracer in its llvm_ad_rgb variant (its JIT variants evaluate the filter exactly; the
scalar ones use a 31-step table of it, which moves edges by about 0.03 pixels, 1-4% of
their contrast here) as two independent halves (seeds 1 and 2), writes their mean to
tests/data/filter.exr and prints the halves' own noise: the RMSE of the mean over the pixels
two or more pixels from the border (half the halves' difference) and their mean ratio.

    pip install mitsuba==3.9.1 numpy; apt-get install libllvm19
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \
    python3 scripts/filter_reference.py [SPP_PER_HALF]   (default 16384)
"""
import os
import sys
import numpy as np
import mitsuba as mi

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_refs import render_halves  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
SCENE = os.path.join(ROOT, "scenes", "mitsuba", "filter.xml")
OUT = os.path.join(ROOT, "tests", "data", "filter.exr")


def main():
    spp = int(sys.argv[1]) if len(sys.argv) > 1 else 16384
    mi.set_variant("llvm_ad_rgb")
    a, b, ratio = render_halves(SCENE, spp)
    mean = 0.5 * (a + b)
    mi.Bitmap(mean.astype(np.float32)).write(OUT)
    inner = (slice(2, -2), slice(2, -2))
    noise = 0.5 * np.sqrt(((a - b)[inner] ** 2).mean())
    print(f"spp per half {spp}")
    print("mean per channel", mean.reshape(-1, 3).mean(axis=0))
    print("halves' mean ratio", ratio)
    print(f"reference's own rmse (inner pixels) {noise:.5f}")


if __name__ == "__main__":
    main()

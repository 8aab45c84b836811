#!/usr/bin/env python3
"""The environment-light reference scene and its Mitsuba 3.9.1 reference.

1. Writes the procedural sky of scenes/mitsuba/envlight.xml, scenes/mitsuba/envlight-sky.exr
   (64 x 32 lat-long, Mitsuba's convention: +y the top row): a blue-to-white gradient over a
   dim ground, and a sun (a Gaussian disc of about 3 degrees) at 40 degrees elevation.
2. Renders the scene with Mitsuba's path tracer as two independent halves (seeds 1 and 2),
   writes their mean to tests/data/envlight.exr and prints the halves' own noise: the
   16 x 16-block RMSE of the mean (half the difference's block RMSE) and the mean ratio of
   the halves per channel.

    pip install mitsuba==3.9.1 numpy     (or: python3 -m venv /tmp/mi && /tmp/mi/bin/pip ...)
    python3 scripts/envlight_reference.py [SPP_PER_HALF]   (default 2048)
"""
import os
import sys
import numpy as np
import mitsuba as mi

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_refs import block_rmse, render_halves  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
SCENE = os.path.join(ROOT, "scenes", "mitsuba", "envlight.xml")
SKY = os.path.join(ROOT, "scenes", "mitsuba", "envlight-sky.exr")
OUT = os.path.join(ROOT, "tests", "data", "envlight.exr")


def sky(w=64, h=32):
    """Linear RGB, float32, (h, w, 3); direction of texel (x, y) as Mitsuba's uv_to_direction."""
    img = np.zeros((h, w, 3), np.float32)
    sun_theta, sun_phi = np.radians(50.0), np.radians(120.0)
    sun = np.array([np.sin(sun_phi) * np.sin(sun_theta), np.cos(sun_theta),
                    -np.cos(sun_phi) * np.sin(sun_theta)])
    for y in range(h):
        theta = np.pi * y / (h - 1)
        for x in range(w):
            phi = 2 * np.pi * (x + 0.5) / w
            d = np.array([np.sin(phi) * np.sin(theta), np.cos(theta), -np.cos(phi) * np.sin(theta)])
            if d[1] > 0:
                t = d[1]
                c = (1 - t) * np.array([0.9, 0.95, 1.0]) + t * np.array([0.25, 0.45, 0.9])
            else:
                c = np.array([0.25, 0.22, 0.2]) * (1 + d[1] * 0.5)
            ang = np.arccos(np.clip(np.dot(d, sun), -1, 1))
            c = c + np.array([30.0, 27.0, 22.0]) * np.exp(-0.5 * (ang / np.radians(6.0)) ** 2)
            img[y, x] = c
    return img


def main():
    spp = int(sys.argv[1]) if len(sys.argv) > 1 else 2048
    mi.set_variant("scalar_rgb")
    mi.Bitmap(sky()).write(SKY)
    a, b, ratio = render_halves(SCENE, spp)
    mean = 0.5 * (a + b)
    mi.Bitmap(mean.astype(np.float16)).write(OUT)
    print(f"spp per half {spp}")
    print("mean per channel", mean.reshape(-1, 3).mean(axis=0))
    print("halves' mean ratio", ratio)
    print(f"reference block rmse (16x16) {0.5 * block_rmse(a, b):.5f}")


if __name__ == "__main__":
    main()

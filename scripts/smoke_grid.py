#!/usr/bin/env python3
"""Writes scenes/mitsuba/smoke.vol, the smoke grid of scenes/mitsuba/smoke-caustic.xml (issue 41's
heterogeneous volume caustic).

A 32 x 32 x 32 single-channel density in [0, 1] over the unit cube (Mitsuba's `.vol` format,
version 3, float32, x fastest; the bounding box written is the unit cube, which Mitsuba 3 and
gpu-photon ignore in favour of the volume's `to_world`): a ball of smoke that thins towards its
edge, broken up by a sum of random Gaussian puffs and a few holes, so that the medium varies by
two orders of magnitude within the majorant grid's cells and across them. Deterministic: numpy's
PCG64 with seed 41; numpy only.

    python3 scripts/smoke_grid.py [--out scenes/mitsuba/smoke.vol] [--res 32]
"""
import argparse
import os
import struct

import numpy as np

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def density(res, seed=41):
    rng = np.random.default_rng(seed)
    c = (np.arange(res) + 0.5) / res
    z, y, x = np.meshgrid(c, c, c, indexing="ij")
    # The ball: 1 at its centre, 0 at radius 0.5, smooth in between.
    r = np.sqrt((x - 0.5) ** 2 + (y - 0.5) ** 2 + (z - 0.5) ** 2) / 0.5
    ball = np.clip(1.0 - r * r, 0.0, 1.0) ** 1.5
    # Puffs and holes: Gaussians of random place, width and sign.
    puffs = np.zeros_like(ball)
    for _ in range(40):
        p = rng.uniform(0.1, 0.9, 3)
        w = rng.uniform(0.04, 0.12)
        a = rng.uniform(0.5, 1.5) if rng.uniform() < 0.75 else -rng.uniform(0.5, 1.0)
        d2 = (x - p[0]) ** 2 + (y - p[1]) ** 2 + (z - p[2]) ** 2
        puffs += a * np.exp(-d2 / (2 * w * w))
    d = ball * np.clip(0.35 + puffs, 0.0, None)
    # Scaled so that the densest 2% of the smoke's cells are 1 (clipped).
    d = np.clip(d / np.quantile(d[d > 0], 0.98), 0.0, 1.0)
    return d.astype(np.float32)


def write_vol(path, d):
    zres, yres, xres = d.shape
    head = b"VOL" + bytes([3]) + struct.pack("<i", 1) + struct.pack("<iiii", xres, yres, zres, 1)
    head += struct.pack("<6f", 0, 0, 0, 1, 1, 1)
    with open(path, "wb") as f:
        f.write(head)
        f.write(np.ascontiguousarray(d, dtype="<f4").tobytes())


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--out", default=os.path.join(ROOT, "scenes", "mitsuba", "smoke.vol"))
    ap.add_argument("--res", type=int, default=32)
    a = ap.parse_args()
    d = density(a.res)
    write_vol(a.out, d)
    print(f"{a.out}: {a.res}^3, mean density {d.mean():.4f}, "
          f"cells above 0.5: {(d > 0.5).mean():.3f}, empty: {(d == 0).mean():.3f}")


if __name__ == "__main__":
    main()

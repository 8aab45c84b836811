#!/usr/bin/env python3
"""Heavy tails of a suite scene's per-pass estimate (issue 41): renders pass 0 of the suite's
budget (16 spp, 100,000 photons, CPU; pass --first) at N seeds and prints, for each 4 x 4 block in the
rows asked, the mean over seeds / the reference, the median / the reference and the largest
single seed's share of the sum. A block whose median sits far below its mean carries its
light in rare passes: the suite's t-test over 8 passes then fails it by chance.

    python3 scripts/hetero_tail_probe.py test_hetero_spectral_sigmat_volpathmis \\
        --seeds 32 --rows 5,6,7 [--mode gather] [--extra '--max-depth 3']
"""
import argparse
import os
import shlex
import subprocess
import sys
import tempfile

import numpy as np

os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")
import mitsuba as mi  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SUITE = os.path.join(ROOT, "tests/data/mitsuba-suite/tests/scenes/participating_media")
BIN = os.path.join(ROOT, "target/release/gpu-photon")


def read(path):
    mi.set_variant("scalar_rgb")
    return np.array(mi.Bitmap(path))[..., :3].astype(np.float64)


def blocks(img, b=4):
    h, w, _ = img.shape
    return img.reshape(h // b, b, w // b, b, 3).mean((1, 3))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--seeds", type=int, default=32)
    ap.add_argument("--rows", default="5,6,7")
    ap.add_argument("--first", type=int, default=0, help="which progressive pass to render")
    ap.add_argument("--photons", type=int, default=100000)
    ap.add_argument("--extra", default="", help="more `render` arguments")
    a = ap.parse_args()
    stem = a.scene.rsplit("_", 1)[0]
    ref = blocks(read(os.path.join(SUITE, "refs", stem + "_ref_rgb.exr")))
    out = []
    with tempfile.TemporaryDirectory() as tmp:
        for s in range(1, a.seeds + 1):
            exr = os.path.join(tmp, f"{s}.exr")
            cmd = [BIN, "render", os.path.join(SUITE, a.scene + ".xml"), "-o", exr,
                   "--backend", "cpu", "--spp", "16", "--photons", str(a.photons),
                   "--caustic-photons", str(a.photons // 2),
                   "--pass-range", f"{a.first}..{a.first + 1}", "--seed", str(s)] + shlex.split(a.extra)
            subprocess.run(cmd, check=True, capture_output=True)
            out.append(blocks(read(exr)))
    out = np.array(out)  # seeds x by x bx x 3
    np.set_printoptions(linewidth=220, precision=2, suppress=True)
    print("image mean / reference:", out.mean((0, 1, 2)) / ref.mean((0, 1)))
    for r in [int(x) for x in a.rows.split(",")]:
        for c in range(3):
            v = out[:, r, :, c]
            print(f"row {r} ch {c} mean/ref  ", v.mean(0) / ref[r, :, c])
            print(f"row {r} ch {c} median/ref", np.median(v, 0) / ref[r, :, c])
            print(f"row {r} ch {c} max share ", v.max(0) / v.sum(0))


if __name__ == "__main__":
    sys.exit(main())

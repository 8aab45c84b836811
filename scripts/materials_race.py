#!/usr/bin/env python3
"""Time to error on the materials scene, Mitsuba 3 against gpu-photon, in one run.

Renders scenes/mitsuba/materials.xml with Mitsuba 3.9.1's path tracer (the file's own
integrator, llvm_ad_rgb) at SPP samples per pixel, then with gpu-photon for each time budget
given (`render --time T`, CPU backend by default), and prints each render's seconds and RMSE
against the reference tests/data/materials.exr (whose own noise is 0.0032: see
tests/data/materials.json). Mitsuba's time excludes its JIT warm-up (one 4-spp render first).

Needs `pip install mitsuba==3.9.1 numpy`, `apt-get install libllvm19` and
DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1, and a release build
(target/release/gpu-photon).

    python3 scripts/materials_race.py [--spp 420] [--times 6,12] [--backend cpu]
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENE = ROOT / "scenes/mitsuba/materials.xml"
REFERENCE = ROOT / "tests/data/materials.exr"
BINARY = ROOT / "target/release/gpu-photon"


def rmse(a, b):
    import numpy as np

    return float(np.sqrt(np.mean((np.asarray(a, dtype=np.float64) - b) ** 2)))


def mitsuba_render(spp):
    import mitsuba as mi
    import numpy as np

    scene = mi.load_file(str(SCENE))
    mi.render(scene, spp=4)  # JIT warm-up
    t = time.perf_counter()
    img = mi.render(scene, spp=spp)
    img = np.array(img)[:, :, :3]
    return time.perf_counter() - t, img


def ours(seconds, backend):
    with tempfile.TemporaryDirectory() as d:
        out = Path(d) / "ours.exr"
        t = time.perf_counter()
        subprocess.run(
            [str(BINARY), "render", str(SCENE), "-o", str(out), "--backend", backend,
             "--time", str(seconds), "-q"],
            check=True,
        )
        wall = time.perf_counter() - t
        diff = subprocess.run([str(BINARY), "diff", str(out), str(REFERENCE)], check=True,
                              capture_output=True, text=True).stdout
    stats = dict(line.split(None, 1) for line in diff.strip().splitlines())
    return wall, float(stats["rmse"])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp", type=int, default=420)
    ap.add_argument("--times", default="6,12")
    ap.add_argument("--backend", default="cpu")
    args = ap.parse_args()
    os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")
    import mitsuba as mi
    import numpy as np

    mi.set_variant("llvm_ad_rgb")
    reference = np.array(mi.TensorXf(mi.Bitmap(str(REFERENCE))))
    secs, img = mitsuba_render(args.spp)
    print(f"mitsuba {args.spp} spp: {secs:.1f} s, RMSE {rmse(img, reference[:, :, :3]):.4f}")
    for t in args.times.split(","):
        wall, e = ours(float(t), args.backend)
        print(f"gpu-photon --time {t} ({args.backend}): {wall:.1f} s wall, RMSE {e:.4f}")


if __name__ == "__main__":
    sys.exit(main())

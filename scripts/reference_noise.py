"""The noise of a Mitsuba reference, block by block, from independent renders.

The references' JSON gives `estimated_block16_rmse_of_reference` from the difference of
its two halves: one draw per block, so where a few blocks hold most of the noise (the
emitter seen through fog, whose pixels Mitsuba's volpath reaches with probability T: a
Bernoulli estimate) that figure can be far from the reference's actual block noise. This
renders the scene --renders times at --spp samples with distinct seeds, takes each 16 x 16
block mean's standard deviation over them, scales it to the reference's spp (the samples of
a render are independent, so the variance falls as 1/spp), and prints the RMS over blocks
and the noisiest blocks.

    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \\
    python3 scripts/reference_noise.py volume-caustic [--renders 8] [--spp 512]
"""
import argparse
import json
import os

import numpy as np
import mitsuba as mi

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))


def block_means(img, n=16):
    h, w, _ = img.shape
    d = img.mean(axis=2)[: h // n * n, : w // n * n]
    return d.reshape(h // n, n, w // n, n).mean(axis=(1, 3))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("name")
    ap.add_argument("--renders", type=int, default=8)
    ap.add_argument("--spp", type=int, default=512)
    args = ap.parse_args()
    mi.set_variant("llvm_ad_rgb")
    meta = json.load(open(os.path.join(ROOT, "tests/data", args.name + ".json")))
    scene = mi.load_file(os.path.join(ROOT, "scenes/mitsuba", args.name + ".xml"))
    blocks = np.array([block_means(np.array(mi.render(scene, spp=args.spp, seed=5000 + k)))
                       for k in range(args.renders)])
    scale = np.sqrt(args.spp / meta["spp"])
    std = blocks.std(axis=0, ddof=1) * scale
    rms = float(np.sqrt((std ** 2).mean()))
    print(f"{args.name}: {args.renders} renders of {args.spp} spp, scaled to the reference's "
          f"{meta['spp']} spp: block16 noise (RMS over blocks) {rms:.6f}; from the halves "
          f"{meta['estimated_block16_rmse_of_reference']:.6f}")
    order = np.argsort(std.ravel())[::-1][:4]
    for i in order:
        r, c = divmod(int(i), std.shape[1])
        print(f"  block ({r}, {c}): {std[r, c]:.6f} (mean {blocks[:, r, c].mean():.4f})")
    rest = np.sort(std.ravel())[:-2]
    print(f"  without the two noisiest blocks: {float(np.sqrt((rest ** 2).mean())):.6f}")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Where fog-cornell's deficit against its Mitsuba reference comes from (issue 24).

gpu-photon's default render of scenes/fog-cornell.toml was 0.4% darker in the mean than the
Mitsuba 3 volpath reference (tests/data/fog-cornell.exr, from scenes/mitsuba/fog-cornell.xml)
at every setting tried. This script decomposes that with small renders (64 x 64 unless
--size), two seeds each so that the noise of every figure is known:

- `near`: Mitsuba's perspective sensor starts its rays at the near clip plane (near_clip,
  default 0.01, so at 0.01 / cos(theta) from the eye), skipping that much fog. Renders the
  XML as it is and with --near (1e-5: a skipped optical depth of 3e-6) at the same seed,
  with the fog's albedo 0 (a pure absorber: the ratio must be exactly the skipped
  transmittance, exp(sigma_t near_clip / cos theta), pixel by pixel) and 0.8 (the scene's);
- `compare`: gpu-photon's default render (CPU backend, seeds 1 and 2) against Mitsuba with
  the XML's own near_clip and with --near, mean ratios per channel and their noise
  (half the seed-to-seed difference), over all pixels, those that see the light (emission
  above 1) and the rest; `--albedo 0` compares the pure absorber.

The XML now sets near_clip itself (1e-5); both commands also render it without (Mitsuba's
default 0.01, as the old reference was made), to show the deficit that made.

Needs `pip install mitsuba==3.9.1 numpy`, `apt-get install libllvm19`,
DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 and a release build.

    python3 scripts/fog_bias.py near [--size 64] [--spp 1024]
    python3 scripts/fog_bias.py compare [--size 64] [--spp 4096] [--albedo 0.8]
        [--binary target/release/gpu-photon]
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
XML = ROOT / "scenes/mitsuba/fog-cornell.xml"
TOML = ROOT / "scenes/fog-cornell.toml"
SIGMA_T = 0.3
FOV_Y = 40.0
OLD_NEAR = 0.01


def mitsuba():
    import mitsuba as mi

    if mi.variant() is None:
        mi.set_variant("llvm_ad_rgb")
    return mi


def xml_text(size, albedo, near):
    """The fog-cornell XML at size x size, with the fog's albedo and the sensor's near_clip
    (None: Mitsuba's default, 0.01)."""
    s = XML.read_text()
    s = re.sub(r'<float name="near_clip" value="[^"]*"/>', "", s)
    s = s.replace('<float name="albedo" value="0.8"/>', f'<float name="albedo" value="{albedo}"/>')
    s = s.replace('<integer name="width" value="128"/>', f'<integer name="width" value="{size}"/>')
    s = s.replace('<integer name="height" value="128"/>', f'<integer name="height" value="{size}"/>')
    if near is not None:
        s = s.replace('<float name="fov" value="40.0"/>',
                      f'<float name="fov" value="40.0"/><float name="near_clip" value="{near}"/>')
    return s


def mitsuba_render(size, albedo, near, spp, seed, chunk=1024):
    mi = mitsuba()
    scene = mi.load_string(xml_text(size, albedo, near))
    total = 0.0
    for k in range(max(1, spp // chunk)):
        img = mi.render(scene, spp=min(spp, chunk), seed=seed + 2 * k)
        total = total + np.array(img, dtype=np.float64)[:, :, :3]
    return total / max(1, spp // chunk)


def ours(binary, size, albedo, seed):
    with tempfile.TemporaryDirectory() as tmp:
        toml = Path(tmp) / "fog.toml"
        toml.write_text(TOML.read_text().replace("albedo = 0.8", f"albedo = {albedo}"))
        out = Path(tmp) / "out.exr"
        cmd = [str(binary), "render", str(toml), "--backend", "cpu", "--seed", str(seed),
               "--width", str(size), "--height", str(size), "-o", str(out)]
        subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        mi = mitsuba()
        return np.array(mi.TensorXf(mi.Bitmap(str(out))), dtype=np.float64)[:, :, :3]


def inv_cos(size):
    """1 / cos(theta) at each pixel's centre: the camera ray's length per unit of depth."""
    f = np.tan(np.radians(FOV_Y / 2))
    y, x = np.mgrid[0:size, 0:size]
    px = (2 * (x + 0.5) / size - 1) * f
    py = (1 - 2 * (y + 0.5) / size) * f
    return np.sqrt(1 + px ** 2 + py ** 2)


def means(img, mask=None):
    flat = img.reshape(-1, 3) if mask is None else img[mask]
    return flat.mean(axis=0)


def fmt(v):
    return " ".join(f"{x:.5f}" for x in v)


def cmd_near(args):
    """The near clip's share: Mitsuba with the old near_clip against --near, same seeds."""
    skipped = np.exp(SIGMA_T * OLD_NEAR * inv_cos(args.size))[:, :, None]
    for albedo in ("0", "0.8"):
        ratios, predicted = [], []
        for seed in (1, 2):
            t = time.perf_counter()
            old = mitsuba_render(args.size, albedo, None, args.spp, seed)
            new = mitsuba_render(args.size, albedo, args.near, args.spp, seed)
            ratios.append(means(old) / means(new))
            predicted.append(means(new * skipped) / means(new))
            print(f"albedo {albedo} seed {seed}: near_clip 0.01 / {args.near}: {fmt(ratios[-1])}"
                  f" (skipped transmittance alone: {fmt(predicted[-1])})"
                  f" {time.perf_counter() - t:.0f} s", flush=True)
        r = np.mean(ratios, axis=0)
        noise = 0.5 * np.abs(ratios[0] - ratios[1])
        print(f"albedo {albedo}: mean ratio {fmt(r)} +- {fmt(noise)}; "
              f"transmittance predicts {fmt(np.mean(predicted, axis=0))}", flush=True)


def cmd_compare(args):
    """gpu-photon against Mitsuba at the old and the new near clip."""
    ms = {}
    for near in (None, args.near):
        ms[near] = [mitsuba_render(args.size, args.albedo, near, args.spp, seed)
                    for seed in (11, 12)]
    us = [ours(args.binary, args.size, args.albedo, seed) for seed in (1, 2)]
    light = (ms[args.near][0] + ms[args.near][1]).mean(axis=2) > 2.0
    print(f"{args.size} x {args.size}, albedo {args.albedo}, Mitsuba {args.spp} spp x 2 seeds, "
          f"ours seeds 1 and 2; {light.sum()} pixels see the light", flush=True)
    for near, ref in ms.items():
        label = f"near_clip {near if near is not None else OLD_NEAR}"
        for name, mask in (("all", None), ("light", light), ("rest", ~light)):
            r = [means(u, mask) / means(m, mask) for u in us for m in ref]
            # Noise of the ratio: ours seed-to-seed and Mitsuba seed-to-seed, in quadrature.
            n_us = 0.5 * np.abs(means(us[0], mask) - means(us[1], mask)) / means(ref[0], mask)
            n_m = 0.5 * np.abs(means(ref[0], mask) - means(ref[1], mask)) / means(ref[0], mask)
            noise = np.sqrt(n_us ** 2 + n_m ** 2)
            print(f"  {label:18s} {name:5s}: ours / Mitsuba {fmt(np.mean(r, axis=0))}"
                  f" +- {fmt(noise)}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    sub = ap.add_subparsers(dest="cmd", required=True)
    near = sub.add_parser("near", help="the near clip's share of the deficit (Mitsuba only)")
    near.add_argument("--spp", type=int, default=1024)
    compare = sub.add_parser("compare", help="gpu-photon against Mitsuba")
    compare.add_argument("--spp", type=int, default=4096)
    compare.add_argument("--albedo", default="0.8")
    compare.add_argument("--binary", default=os.environ.get(
        "GPU_PHOTON", str(Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
                          / "release/gpu-photon")))
    for p in (near, compare):
        p.add_argument("--size", type=int, default=64)
        p.add_argument("--near", type=float, default=1e-5)
    args = ap.parse_args()
    {"near": cmd_near, "compare": cmd_compare}[args.cmd](args)


if __name__ == "__main__":
    sys.exit(main())

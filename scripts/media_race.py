#!/usr/bin/env python3
"""Time to error on the participating-media scenes, Mitsuba 3's volpath against gpu-photon,
in one run (issue 24).

For each scene (scenes/mitsuba/NAME.xml for Mitsuba; for gpu-photon scenes/NAME.toml, the
same scene (tests/media_scenes.rs), or where there is none the same XML file), renders

- Mitsuba 3.9.1 (llvm_ad_rgb, the file's own integrator: volpath) at each of --spp, after
  one 4-spp JIT warm-up render, seeds 1001, 1002, ...;
- gpu-photon's default render (`render scenes/NAME.toml`, CPU backend unless --backend)
  with seeds 1 and 2;

alternating the two renderers, and measures each image's RMSE against the reference
tests/data/NAME.exr with the reference's own noise (tests/data/NAME.json,
`estimated_rmse_of_reference`) subtracted in quadrature. Mitsuba's path tracer is unbiased,
so its RMSE^2 x seconds is a constant; its median over the --spp renders gives the time
Mitsuba needs for gpu-photon's RMSE, and the ratio of that to gpu-photon's time is the
speed-up at equal error. The seed-to-seed RMSE of gpu-photon's two renders over sqrt(2) is
its own noise (the rest of its RMSE is the estimator's bias). Prints a Markdown table and
writes it, with every render's figures, as JSON to --json.

Needs `pip install mitsuba==3.9.1 numpy`, `apt-get install libllvm19` and
DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1, and a release build
(target/release/gpu-photon, or --binary).

    python3 scripts/media_race.py [--scenes fog-cornell,volume-caustic,smoke-caustic] [--spp 256,1024]
        [--backend cpu] [--json race.json]
"""
import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))
from mitsuba_refs import block_rmse  # noqa: E402


def rmse(a, b):
    import numpy as np

    return float(np.sqrt(np.mean((np.asarray(a, dtype=np.float64) - b) ** 2)))


def load(path):
    import mitsuba as mi
    import numpy as np

    return np.array(mi.TensorXf(mi.Bitmap(str(path))))[:, :, :3]


def mitsuba_render(name, spp, seed):
    import mitsuba as mi
    import numpy as np

    scene = mi.load_file(str(ROOT / f"scenes/mitsuba/{name}.xml"))
    mi.render(scene, spp=4, seed=seed + 500)  # JIT warm-up
    t = time.perf_counter()
    img = mi.render(scene, spp=spp, seed=seed)
    img = np.array(img)[:, :, :3]
    return time.perf_counter() - t, img


def our_scene(name):
    """gpu-photon's file for NAME: its TOML twin where there is one, else the Mitsuba file."""
    toml = ROOT / f"scenes/{name}.toml"
    return toml if toml.exists() else ROOT / f"scenes/mitsuba/{name}.xml"


def ours(binary, name, seed, backend, out):
    t = time.perf_counter()
    subprocess.run(
        [str(binary), "render", str(our_scene(name)), "-o", str(out),
         "--backend", backend, "--seed", str(seed), "-q"],
        check=True,
    )
    return time.perf_counter() - t


def without(raw, noise):
    """An RMSE with the reference's own noise taken out in quadrature."""
    return math.sqrt(max(raw * raw - noise * noise, 0.0))


def race(name, spps, backend, binary, tmp):
    reference = load(ROOT / f"tests/data/{name}.exr")
    meta = json.loads((ROOT / f"tests/data/{name}.json").read_text())
    ref_noise = meta["estimated_rmse_of_reference"]
    peer, mine, images = [], [], []
    for i, spp in enumerate(spps + [None] * max(0, 2 - len(spps))):
        if spp is not None:
            secs, img = mitsuba_render(name, spp, 1001 + i)
            raw = rmse(img, reference)
            peer.append({"spp": spp, "seconds": secs, "rmse_raw": raw,
                         "rmse": without(raw, ref_noise)})
            print(f"  mitsuba {spp} spp: {secs:.1f} s, RMSE {peer[-1]['rmse']:.4f}", flush=True)
        if len(mine) < 2:
            seed = len(mine) + 1
            out = Path(tmp) / f"{name}-{seed}.exr"
            secs = ours(binary, name, seed, backend, out)
            img = load(out)
            images.append(img)
            raw = rmse(img, reference)
            mine.append({"seed": seed, "seconds": secs, "rmse_raw": raw,
                         "rmse": without(raw, ref_noise),
                         "block16_rmse": block_rmse(img, reference),
                         "mean_ratio": [float(img[:, :, c].mean() / reference[:, :, c].mean())
                                        for c in range(3)]})
            print(f"  gpu-photon seed {seed}: {secs:.1f} s, RMSE {mine[-1]['rmse']:.4f}, "
                  f"block16 {mine[-1]['block16_rmse']:.6f}", flush=True)
    constant = statistics.median(p["rmse"] ** 2 * p["seconds"] for p in peer)
    our_seconds = statistics.median(m["seconds"] for m in mine)
    our_rmse = statistics.mean(m["rmse"] for m in mine)
    peer_seconds = constant / our_rmse ** 2
    return {
        "scene": name,
        "reference_noise": ref_noise,
        "mitsuba": peer,
        "gpu_photon": mine,
        "gpu_photon_noise": rmse(images[0], images[1]) / math.sqrt(2.0),
        "gpu_photon_seconds": our_seconds,
        "gpu_photon_rmse": our_rmse,
        "mitsuba_seconds_at_equal_rmse": peer_seconds,
        "speedup": peer_seconds / our_seconds,
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scenes", default="fog-cornell,volume-caustic,smoke-caustic")
    ap.add_argument("--spp", default="256,1024")
    ap.add_argument("--backend", default="cpu")
    ap.add_argument("--binary", default=str(ROOT / "target/release/gpu-photon"))
    ap.add_argument("--json")
    args = ap.parse_args()
    os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")
    import mitsuba as mi

    mi.set_variant("llvm_ad_rgb")
    spps = [int(s) for s in args.spp.split(",")]
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for name in args.scenes.split(","):
            print(f"{name}:", flush=True)
            results.append(race(name, spps, args.backend, args.binary, tmp))
    print()
    print("| scene | gpu-photon default (median s, mean RMSE, own noise) | Mitsuba volpath "
          "| Mitsuba at equal RMSE | speed-up |")
    print("|---|---|---|---|---|")
    for r in results:
        peer = ", ".join(f"{p['spp']} spp {p['seconds']:.1f} s / {p['rmse']:.4f}"
                         for p in r["mitsuba"])
        print(f"| {r['scene']} | {r['gpu_photon_seconds']:.1f} s, {r['gpu_photon_rmse']:.4f}, "
              f"{r['gpu_photon_noise']:.4f} | {peer} | {r['mitsuba_seconds_at_equal_rmse']:.1f} s "
              f"| {r['speedup']:.2f}x |")
    if args.json:
        Path(args.json).write_text(json.dumps(results, indent=1) + "\n")


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Lower-noise references for the CPU race (scripts/cpu_race.py): more Mitsuba 3 samples of a
race scene, averaged with its existing reference, so that the race's errors are ours and
Mitsuba's, not mostly the reference's own noise.

The race measures each renderer's RMSE against a reference and extrapolates Mitsuba's time
to our error. A reference's own noise n adds to both errors in quadrature and pulls their
ratio towards 1: materials.exr (4,096 spp, n = 0.0032) is most of our 0.0046. This renders
the scene's Mitsuba XML with Mitsuba 3.9.1 (`llvm_ad_rgb`, the file's own integrator) in two
independent halves of SPP/2 samples each (seeds from 100,001 upwards: never those of the
original reference's halves, 1 and 2 upwards, nor the race's seed 0), takes their mean, and
averages it with the existing reference weighted by samples. The new noise is measured, not
assumed: half the RMSE between the halves is the noise of their mean; the existing
reference's own noise comes from its table (or JSON); the combination's is
sqrt(w_old^2 n_old^2 + w_new^2 n_new^2). Writes tests/data/race/NAME.exr and NAME.json.

    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \\
    python3 scripts/race_references.py --scenes cornell-box,materials --spp 32768 [--chunk 256]
"""
import argparse
import json
import os
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "scripts"))

# name: (Mitsuba XML, existing reference, its samples, its own RMSE)
SCENES = {
    "cornell-box": ("tests/data/cornell-diffuse.xml", "tests/data/cornell-diffuse.exr",
                    16384, 0.0014),
    "materials": ("scenes/mitsuba/materials.xml", "tests/data/materials.exr", 4096, 0.003211),
}
FIRST_SEED = 100_001


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--spp", type=int, default=32768, help="new samples, both halves together")
    ap.add_argument("--chunk", type=int, default=256, help="samples per Mitsuba render")
    ap.add_argument("--out", default=str(ROOT / "tests/data/race"))
    args = ap.parse_args()
    half = args.spp // 2
    if half % args.chunk:
        sys.exit(f"race_references.py: --chunk {args.chunk} does not divide --spp/2 = {half}")
    os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")
    import mitsuba as mi
    import numpy as np
    from mitsuba_refs import block_rmse

    mi.set_variant("llvm_ad_rgb")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for name in args.scenes.split(","):
        xml, old_path, old_spp, old_noise = SCENES[name]
        old = np.array(mi.TensorXf(mi.Bitmap(str(ROOT / old_path))), dtype=np.float64)[:, :, :3]
        scene = mi.load_file(str(ROOT / xml))
        halves, seconds = [], []
        for h in range(2):
            start = time.perf_counter()
            total = None
            for k in range(half // args.chunk):
                seed = FIRST_SEED + h + 2 * k
                img = np.array(mi.render(scene, spp=args.chunk, seed=seed), dtype=np.float64)
                total = img[:, :, :3] if total is None else total + img[:, :, :3]
                print(f"{name}: half {h + 1}, {(k + 1) * args.chunk} of {half} spp, "
                      f"{time.perf_counter() - start:.0f} s", flush=True)
            halves.append(total / (half // args.chunk))
            seconds.append(time.perf_counter() - start)
        a, b = halves
        new = (a + b) / 2
        new_noise = float(np.sqrt(np.mean((a - b) ** 2))) / 2
        new_block = block_rmse(a, b) / 2
        w_old = old_spp / (old_spp + args.spp)
        w_new = 1 - w_old
        combined = w_old * old + w_new * new
        noise = float(np.hypot(w_old * old_noise, w_new * new_noise))
        mi.Bitmap(combined.astype(np.float32)).write(str(out / f"{name}.exr"))
        meta = {
            "scene": xml,
            "renderer": "Mitsuba 3.9.1 llvm_ad_rgb, the scene's integrator",
            "made_by": "scripts/race_references.py",
            "existing_reference": old_path,
            "existing_spp": old_spp,
            "existing_rmse_of_reference": old_noise,
            "new_spp": args.spp,
            "new_seeds": f"{FIRST_SEED} + half + 2k, chunks of {args.chunk} spp",
            "new_seconds_per_half": seconds,
            "new_rmse_between_halves": 2 * new_noise,
            "new_block16_rmse_between_halves": 2 * new_block,
            "new_mean_ratio_of_halves": (a.reshape(-1, 3).mean(0) / b.reshape(-1, 3).mean(0)).tolist(),
            "new_against_existing_rmse": float(np.sqrt(np.mean((new - old) ** 2))),
            "spp": old_spp + args.spp,
            "mean_rgb": combined.reshape(-1, 3).mean(0).tolist(),
            "estimated_rmse_of_reference": noise,
        }
        (out / f"{name}.json").write_text(json.dumps(meta, indent=1) + "\n")
        print(f"{name}: new halves {seconds[0]:.0f} + {seconds[1]:.0f} s, noise of the new "
              f"mean {new_noise:.5f}, new against existing {meta['new_against_existing_rmse']:.5f} "
              f"(expected {float(np.hypot(new_noise, old_noise)):.5f}), combined noise "
              f"{noise:.5f}", flush=True)


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The participating-media scenes' Mitsuba 3.9.1 references (issue 24).

Renders scenes/mitsuba/fog-cornell.xml, scenes/mitsuba/volume-caustic.xml,
scenes/mitsuba/fog-box-null.xml (issue 41: the fog inside a null cube, camera and light outside) and
scenes/mitsuba/smoke-caustic.xml (issue 41: a volume caustic in a heterogeneous smoke grid) with the
files' own integrator (Mitsuba's `volpath`, max_depth 64, rr_depth 16) in the llvm_ad_rgb
variant as two independent halves (mitsuba_refs.render_halves: seeds 1 and 2, each half
rendered in chunks of CHUNK samples per pixel, half h's k-th chunk with seed h + 2k, since
a JIT variant traces a render's samples as one wavefront), and writes for each scene

- tests/data/NAME.exr: the mean of the halves;
- tests/data/NAME.json: spp per half, each half's seconds, the mean RGB, the noise of the
  reference estimated from its halves (the RMSE of the mean, half the RMS of the halves'
  difference, and the same for the 16 x 16-pixel block means, mitsuba_refs.block_rmse),
  the command, and `peer_curve`: Mitsuba's own time against RMSE, single renders of the
  same file at a few spp (seeds 1001, 1002, ...: independent of the halves) measured
  against the finished reference after one 4-spp JIT warm-up render, for comparing
  gpu-photon's speed later. Each curve point's `rmse` includes the reference's own noise
  (`estimated_rmse_of_reference`), negligible while it is well below it.

The default spp per half were chosen so that each scene's two halves take about 30 minutes
of the 2-core machine this was written on (chunks of 1024 spp measured at 42 s for
fog-cornell and 78 s for volume-caustic); smoke-caustic's heterogeneous volpath takes about
100 s per 1024 spp, so its halves are 4096 spp (about 15 minutes in all); pass --spp to
change them.

    pip install mitsuba==3.9.1 numpy; apt-get install libllvm19
    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \\
    python3 scripts/media_references.py [--scenes fog-cornell,volume-caustic]
        [--spp 20480,11264] [--chunk 1024] [--curve 16,64,256,1024]
"""
import argparse
import json
import os
import sys
import time

import numpy as np
import mitsuba as mi

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_refs import block_rmse, render_halves  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SCENES = {"fog-cornell": 20480, "volume-caustic": 11264, "fog-box-null": 1536,
          "smoke-caustic": 4096}
VARIANT = "llvm_ad_rgb"


def rmse(a, b):
    return float(np.sqrt(np.mean((a - b) ** 2)))


def peer_curve(scene_file, reference, spps):
    """Mitsuba's seconds and RMSE against reference for a render at each of spps."""
    scene = mi.load_file(scene_file)
    mi.render(scene, spp=4, seed=1000)  # JIT warm-up
    points = []
    for i, spp in enumerate(spps):
        start = time.perf_counter()
        img = np.array(mi.render(scene, spp=spp, seed=1001 + i), dtype=np.float64)[:, :, :3]
        seconds = time.perf_counter() - start
        point = {
            "spp": spp,
            "seed": 1001 + i,
            "seconds": seconds,
            "rmse": rmse(img, reference),
            "block16_rmse": block_rmse(img, reference),
        }
        print(f"  curve: {spp:6d} spp {seconds:8.2f} s rmse {point['rmse']:.5f} "
              f"block16 {point['block16_rmse']:.6f}", flush=True)
        points.append(point)
    return points


def reference(name, spp, chunk, curve, command, note):
    scene_file = os.path.join(ROOT, "scenes", "mitsuba", name + ".xml")
    exr = os.path.join(ROOT, "tests", "data", name + ".exr")
    report = os.path.join(ROOT, "tests", "data", name + ".json")
    print(f"{name}: {spp} spp per half in chunks of {chunk}", flush=True)
    times = []
    a, b, ratio = render_halves(scene_file, spp, chunk=chunk, times=times)
    mean = 0.5 * (a + b)
    mi.Bitmap(mean.astype(np.float32)).write(exr)
    out = {
        "scene": os.path.relpath(scene_file, ROOT),
        "renderer": f"Mitsuba {mi.__version__} {VARIANT}, the scene's integrator (volpath)",
        "spp": 2 * spp,
        "spp_per_half": spp,
        "chunk_spp": chunk,
        "seeds": "half 1: 1, 3, 5, ...; half 2: 2, 4, 6, ... (one per chunk)",
        "seconds_per_half": times,
        "seconds": sum(times),
        "mean_rgb": mean.reshape(-1, 3).mean(axis=0).tolist(),
        "halves_mean_ratio": ratio.tolist(),
        "estimated_rmse_of_reference": 0.5 * rmse(a, b),
        "estimated_block16_rmse_of_reference": 0.5 * block_rmse(a, b),
        "command": command,
    }
    if note:
        out["note"] = note
    print(f"  halves {times[0]:.1f} s + {times[1]:.1f} s, mean {out['mean_rgb']}, "
          f"ratio {ratio}, rmse of reference {out['estimated_rmse_of_reference']:.5f}, "
          f"block16 {out['estimated_block16_rmse_of_reference']:.6f}", flush=True)
    with open(report, "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")
    if curve:
        out["peer_curve"] = peer_curve(scene_file, mean, curve)
        with open(report, "w") as f:
            json.dump(out, f, indent=1)
            f.write("\n")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--spp", help="spp per half, one per scene (default: 20480,11264)")
    ap.add_argument("--chunk", type=int, default=1024, help="spp per render call")
    ap.add_argument("--curve", default="16,64,256,1024", help="peer_curve spps ('' for none)")
    ap.add_argument("--note", default="", help="a remark for the JSON (why the spp are lower)")
    args = ap.parse_args()
    names = args.scenes.split(",")
    spps = [int(s) for s in args.spp.split(",")] if args.spp else [SCENES[n] for n in names]
    curve = [int(s) for s in args.curve.split(",") if s]
    mi.set_variant(VARIANT)
    command = "python3 scripts/media_references.py " + " ".join(
        f"'{a}'" if " " in a else a for a in sys.argv[1:])
    for name, spp in zip(names, spps, strict=True):
        chunk = min(args.chunk, spp)
        reference(name, spp, chunk, curve, command.strip(), args.note)


if __name__ == "__main__":
    main()

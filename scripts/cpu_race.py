#!/usr/bin/env python3
"""The CPU backend against Mitsuba 3 at equal error, three scenes side by side in one run.

For each scene: gpu-photon's default render (`render SCENE -o OUT --backend cpu`, its own
passes and settings), its wall time and RMSE against the Mitsuba reference; then Mitsuba
3.9.1's path tracer (`llvm_ad_rgb`, the scene's Mitsuba XML) at SPP samples per pixel after a
4-spp JIT warm-up, its render time and RMSE. Mitsuba's time for our error follows from its
RMSE falling as time^-0.5: t_mitsuba(e) = t_spp * (e_spp / e)^2. The speed-up is that time
over ours. Both errors are also given with the reference's own noise taken out in
quadrature (sqrt(e^2 - n^2)), and the speed-up from those ("true").

| scene | ours | Mitsuba XML | reference (own noise) |
|---|---|---|---|
| cornell-box | scenes/cornell-box.toml | tests/data/cornell-diffuse.xml | cornell-diffuse.exr (0.0014) |
| cornell-caustics | scenes/cornell-caustics.toml | tests/data/caustics-small-light.xml | caustics-small-light.exr (0.0043) |
| materials | scenes/mitsuba/materials.xml | the same file | tests/data/materials.exr (0.0032) |

caustics-small-light.exr is looked up in shared/reference/ beside the repository (or
--references DIR). Where tests/data/race/ holds a lower-noise reference for a scene (made by
scripts/race_references.py: more Mitsuba samples averaged with the one above; its own noise in
its JSON), the race measures against it instead, so that both errors are the renderers' and
not mostly the reference's; --original-references measures against the table's. Needs `pip install mitsuba==3.9.1 numpy`, `apt-get install libllvm19`,
DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 (set here when unset), and a
release build (target/release/gpu-photon).

    python3 scripts/cpu_race.py [--spp 256] [--scenes cornell-box,cornell-caustics,materials]
        [--binary target/release/gpu-photon] [--json out.json] [--args '--adaptive 16']
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
DATA = ROOT / "tests/data"

# name: (our scene, Mitsuba XML, reference file name, reference's own RMSE)
SCENES = {
    "cornell-box": ("scenes/cornell-box.toml", DATA / "cornell-diffuse.xml",
                    "cornell-diffuse.exr", 0.0014),
    "cornell-caustics": ("scenes/cornell-caustics.toml", DATA / "caustics-small-light.xml",
                         "caustics-small-light.exr", 0.0043),
    "materials": ("scenes/mitsuba/materials.xml", ROOT / "scenes/mitsuba/materials.xml",
                  "materials.exr", 0.0032),
}


def race_reference(scene_name):
    """The lower-noise reference of tests/data/race/ for a race scene and its own noise, or
    None."""
    exr, meta = DATA / "race" / f"{scene_name}.exr", DATA / "race" / f"{scene_name}.json"
    if not (exr.exists() and meta.exists()):
        return None
    return exr, json.loads(meta.read_text())["estimated_rmse_of_reference"]


def find_reference(name, extra):
    for d in [extra, DATA, ROOT.parent / "shared/reference", Path("/work/shared/reference")]:
        if d is not None and (Path(d) / name).exists():
            return Path(d) / name
    sys.exit(f"cpu_race.py: reference {name} not found (give --references DIR)")


def rmse(a, b):
    import numpy as np

    return float(np.sqrt(np.mean((np.asarray(a, dtype=np.float64) - b) ** 2)))


def true_error(e, noise):
    return max(e * e - noise * noise, 1e-12) ** 0.5


def mitsuba(xml, spp, reference):
    import mitsuba as mi
    import numpy as np

    scene = mi.load_file(str(xml))
    mi.render(scene, spp=4)  # JIT warm-up
    t = time.perf_counter()
    img = np.array(mi.render(scene, spp=spp))[:, :, :3]
    return time.perf_counter() - t, rmse(img, reference)


def ours(binary, scene, reference_path, extra):
    with tempfile.TemporaryDirectory() as d:
        out = Path(d) / "ours.exr"
        t = time.perf_counter()
        subprocess.run([str(binary), "render", str(ROOT / scene), "-o", str(out),
                        "--backend", "cpu", "-q"] + extra, check=True)
        wall = time.perf_counter() - t
        diff = subprocess.run([str(binary), "diff", str(out), str(reference_path)], check=True,
                              capture_output=True, text=True).stdout
    stats = dict(line.split(None, 1) for line in diff.strip().splitlines())
    return wall, float(stats["rmse"])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--spp", type=int, default=256)
    ap.add_argument("--scenes", default=",".join(SCENES))
    ap.add_argument("--binary", default=str(ROOT / "target/release/gpu-photon"))
    ap.add_argument("--references", default=None)
    ap.add_argument("--json", default=None)
    ap.add_argument("--args", default="",
                    help="more flags for our render, e.g. '--adaptive 16' (default: none)")
    ap.add_argument("--original-references", action="store_true",
                    help="measure against the table's references, not tests/data/race/'s")
    args = ap.parse_args()
    os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")
    import mitsuba as mi
    import numpy as np

    mi.set_variant("llvm_ad_rgb")
    print(f"load: {os.getloadavg()[0]:.1f} ({os.cpu_count()} CPUs)")
    print(f"{'scene':<17} {'ours s':>7} {'RMSE':>7} {'mitsuba s':>9} {'RMSE':>7} "
          f"{'mi. at ours s':>13} {'speed-up':>8} {'true':>6}")
    rows = []
    for name in args.scenes.split(","):
        scene, xml, ref_name, noise = SCENES[name]
        ref_path = find_reference(ref_name, args.references)
        refined = None if args.original_references else race_reference(name)
        if refined:
            ref_path, noise = refined
        reference = np.array(mi.TensorXf(mi.Bitmap(str(ref_path))))[:, :, :3]
        t_ours, e_ours = ours(args.binary, scene, ref_path, args.args.split())
        t_mi, e_mi = mitsuba(xml, args.spp, reference)
        t_equal = t_mi * (e_mi / e_ours) ** 2
        t_true = t_mi * (true_error(e_mi, noise) / true_error(e_ours, noise)) ** 2
        row = {"scene": name, "ours_s": t_ours, "ours_rmse": e_ours, "mitsuba_spp": args.spp,
               "mitsuba_s": t_mi, "mitsuba_rmse": e_mi, "reference": str(ref_path),
               "reference_noise": noise,
               "speedup": t_equal / t_ours, "speedup_true": t_true / t_ours}
        rows.append(row)
        print(f"{name:<17} {t_ours:7.2f} {e_ours:7.4f} {t_mi:9.2f} {e_mi:7.4f} "
              f"{t_equal:13.1f} {row['speedup']:7.1f}x {row['speedup_true']:5.1f}x   "
              f"({Path(ref_path).relative_to(ROOT) if ROOT in Path(ref_path).parents else ref_path}, "
              f"noise {noise:.5f})", flush=True)
    if args.json:
        Path(args.json).write_text(json.dumps(rows, indent=1) + "\n")


if __name__ == "__main__":
    sys.exit(main())

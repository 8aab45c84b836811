#!/usr/bin/env python3
"""The render suite's principledthin scene with deep paths: Mitsuba 3.9.1 against ours.

The suite's test_texturedprincipledthin caps paths at 2 segments (direct light only), which
our `direct` mode renders. This script raises `max_depth` (default 8) so that light scattered
and transmitted by the sheet more than once, and the photon maps of our default `gather` mode,
count too: it writes the scene beside its fragment, renders Mitsuba's path tracer (scalar_rgb)
as two independent halves (seeds 1 and 2) and prints the halves' own noise; given our render
of the same file (`gpu-photon render OUT/deep.xml -o ours.exr ...`) it prints our channel-mean
ratio to Mitsuba's and the 16 x 16-block RMSE against the halves' own.

    python3 scripts/principledthin_deep.py OUT_DIR [SPP_PER_HALF] [--ours ours.exr]
"""
import os
import sys
import numpy as np
import mitsuba as mi

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_refs import block_rmse, render_halves  # noqa: E402

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
SUITE = os.path.join(ROOT, "tests", "data", "mitsuba-suite")
SCENE = os.path.join(SUITE, "tests", "scenes", "bsdf_spheres", "test_texturedprincipledthin_path.xml")
FRAGMENT = os.path.join(SUITE, "tests", "scenes", "bsdf_spheres", "fragments", "single_sphere.xml")
DEPTH = 8


def write_scene(out):
    """The suite's scene and fragment with max_depth DEPTH, under out: the scene's path."""
    common = os.path.abspath(os.path.join(SUITE, "common"))
    frag = open(FRAGMENT).read().replace('name="max_depth" value="2"', f'name="max_depth" value="{DEPTH}"')
    assert f'value="{DEPTH}"' in frag
    frag_path = os.path.join(out, "deep_fragment.xml")
    open(frag_path, "w").write(frag)
    scene = open(SCENE).read().replace('<path value="../../../common"/>', f'<path value="{common}"/>')
    scene = scene.replace("fragments/single_sphere.xml", frag_path)
    path = os.path.join(out, "deep.xml")
    open(path, "w").write(scene)
    return path


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    ours = sys.argv[sys.argv.index("--ours") + 1] if "--ours" in sys.argv else None
    if ours in args:
        args.remove(ours)
    out = os.path.abspath(args[0])
    spp = int(args[1]) if len(args) > 1 else 1024
    os.makedirs(out, exist_ok=True)
    path = write_scene(out)
    mi.set_variant("scalar_rgb")
    a, b, ratio = render_halves(path, spp)
    ref = (a + b) / 2
    mi.Bitmap(ref.astype(np.float32)).write(os.path.join(out, "mitsuba.exr"))
    noise = block_rmse(a, b) / 2
    print(f"Mitsuba {mi.__version__} scalar_rgb, max_depth {DEPTH}, 2 x {spp} spp: "
          f"halves' ratio {ratio.round(4)}, block RMSE of the mean {noise:.2e}, "
          f"channel means {ref.reshape(-1, 3).mean(axis=0).round(5)}")
    if ours:
        o = np.array(mi.Bitmap(ours), dtype=np.float64)[:, :, :3]
        r = o.reshape(-1, 3).mean(axis=0) / ref.reshape(-1, 3).mean(axis=0)
        print(f"ours {ours}: channel-mean ratio {r.round(4)}, block RMSE {block_rmse(o, ref):.2e}")


if __name__ == "__main__":
    main()

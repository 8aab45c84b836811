#!/usr/bin/env python3
"""Ablations of a scene of Mitsuba's media suite (issue 41): the same file rendered by
Mitsuba 3.9.1 `volpath` and by gpu-photon at a few `max_depth`s, or with parts of the file
replaced, to find which path segment of ours is off.

For each max_depth the scene (tests/data/mitsuba-suite/tests/scenes/participating_media/NAME.xml)
is copied beside itself with its includes inlined, every `max_depth` set to the value and the
`--sub OLD=>NEW` replacements made; Mitsuba renders it (llvm_ad_rgb, --mspp samples, seed 7)
and gpu-photon renders it (`render --backend cpu`, the suite's budget by default: 8 passes x
16 spp, 100,000 photons, seed 1, --mode as given). Prints each channel's image mean and our
ratio to Mitsuba's, and the mean over a box of pixels with --box x0,y0,x1,y1.

    DRJIT_LIBLLVM_PATH=/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1 \\
    python3 scripts/media_suite_probe.py test_homo_roughdielectric_spot_volpath \\
        --depths 2,3,16 [--sub 'value="1.3"=>value="1.0"'] [--mode gather] [--mspp 1024]
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

os.environ.setdefault("DRJIT_LIBLLVM_PATH", "/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1")
import mitsuba as mi  # noqa: E402

ROOT = os.path.normpath(os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
SUITE = os.path.join(ROOT, "tests/data/mitsuba-suite/tests/scenes/participating_media")
BIN = os.path.join(ROOT, "target/release/gpu-photon")


def inline(text, folder):
    """The file's text with each `<include filename=...>` replaced by the included scene's body."""
    def body(m):
        inc = open(os.path.join(folder, m.group(1))).read()
        inc = re.sub(r"<\?xml[^>]*\?>", "", inc)
        inc = re.sub(r"<scene[^>]*>", "", inc, count=1)
        inc = inc.replace("</scene>", "")
        return inline(inc, folder)
    return re.sub(r'<include\s+filename="([^"]+)"\s*/>', body, text)


def means(img, box):
    a = np.asarray(img, dtype=np.float64)[..., :3]
    if box:
        x0, y0, x1, y1 = box
        a = a[y0:y1, x0:x1]
    return a.mean(axis=(0, 1))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("scene")
    ap.add_argument("--depths", default="16")
    ap.add_argument("--sub", action="append", default=[])
    ap.add_argument("--mode", default=None)
    ap.add_argument("--mspp", type=int, default=1024)
    ap.add_argument("--passes", type=int, default=8)
    ap.add_argument("--spp", type=int, default=16)
    ap.add_argument("--photons", type=int, default=100000)
    ap.add_argument("--box", default=None)
    ap.add_argument("--keep", default=None, help="folder to keep the EXRs in")
    ap.add_argument("--extra", default="", help="more arguments for gpu-photon render")
    ap.add_argument("--our-depth-add", type=int, default=0,
                    help="render ours at max_depth + this (what a bounce-counted pass-through costs)")
    args = ap.parse_args()
    box = [int(v) for v in args.box.split(",")] if args.box else None
    mi.set_variant("llvm_ad_rgb")
    src = os.path.join(SUITE, args.scene + ".xml")
    text = inline(open(src).read(), SUITE)
    for s in args.sub:
        old, new = s.split("=>")
        if old not in text:
            sys.exit(f"--sub: {old!r} not in the scene")
        text = text.replace(old, new)
    for depth in [int(d) for d in args.depths.split(",")]:
        t = re.sub(r'(name="max_depth"\s+value=")\d+', rf"\g<1>{depth}", text)
        fd, path = tempfile.mkstemp(suffix=".xml", prefix="_probe_", dir=SUITE)
        with os.fdopen(fd, "w") as f:
            f.write(t)
        ours_path = path
        if args.our_depth_add:
            fd2, ours_path = tempfile.mkstemp(suffix=".xml", prefix="_probe_", dir=SUITE)
            with os.fdopen(fd2, "w") as f:
                f.write(re.sub(r'(name="max_depth"\s+value=")\d+',
                               rf"\g<1>{depth + args.our_depth_add}", text))
        try:
            scene = mi.load_file(path)
            ref = mi.render(scene, spp=args.mspp, seed=7)
            m_ref = means(ref, box)
            out = tempfile.mktemp(suffix=".exr", prefix="gp_probe_")
            cmd = [BIN, "render", ours_path, "-o", out, "--backend", "cpu", "-q",
                   "--passes", str(args.passes), "--spp", str(args.spp),
                   "--photons", str(args.photons), "--seed", "1"]
            if args.mode:
                cmd += ["--mode", args.mode]
            cmd += args.extra.split()
            subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
            ours = mi.Bitmap(out)
            m_ours = means(ours, box)
            if args.keep:
                os.makedirs(args.keep, exist_ok=True)
                mi.util.write_bitmap(os.path.join(args.keep, f"mitsuba_d{depth}.exr"), ref)
                os.replace(out, os.path.join(args.keep, f"ours_d{depth}.exr"))
            else:
                os.remove(out)
        finally:
            os.remove(path)
            if ours_path != path:
                os.remove(ours_path)
        ratio = m_ours / np.maximum(m_ref, 1e-12)
        fmt = lambda v: " ".join(f"{x:.5g}" for x in v)  # noqa: E731
        print(f"max_depth {depth:3}: mitsuba {fmt(m_ref)}  ours {fmt(m_ours)}  ratio {fmt(ratio)}",
              flush=True)


if __name__ == "__main__":
    main()

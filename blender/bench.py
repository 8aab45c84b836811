"""How fast the engine is inside Blender, against the command line on the same scene and
settings: the Cornell box of the tests (its glTF-exportable variant under a point light, so that the
command line renders the same scene from Blender's own export), rendered by F12's operator
(``bpy.ops.render.render``) and by ``gpu-photon render`` on the exported .glb, in alternating
rounds. Prints the seconds from the operator's call to the first pass in the render result
(what F12 shows first), each whole render, and the medians' ratio.

    blender -b --factory-startup --python blender/bench.py -- [--size W H] [--passes N]
        [--spp N] [--photons N] [--caustic-photons N] [--rounds N] [--backend cpu|gpu|auto]

Needs the add-on installed (blender/install.sh) and target/release/gpu-photon (or
GPU_PHOTON_BIN)."""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time

import bpy

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "tests"))
import common  # noqa: E402
import scenes  # noqa: E402


def main():
    argv = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
    p = argparse.ArgumentParser()
    p.add_argument("--size", type=int, nargs=2, default=(480, 270))
    p.add_argument("--passes", type=int, default=8)
    p.add_argument("--spp", type=int, default=4)
    p.add_argument("--photons", type=int, default=100_000)
    p.add_argument("--caustic-photons", type=int, default=50_000)
    p.add_argument("--rounds", type=int, default=3)
    p.add_argument("--backend", default="cpu")
    p.add_argument("--mode", default="gather")
    p.add_argument("--light", choices=["point", "area"], default="point",
                   help="area: the tests' Cornell box (no glTF export: no CLI rounds)")
    a = p.parse_args(argv)
    out = tempfile.mkdtemp(prefix="gpu-photon-bench-")
    if a.light == "point":
        scene = scenes.cornell_box(a.size[0], a.size[1], principled=True, light="point")
    else:
        scene = scenes.cornell_box(a.size[0], a.size[1])
    common.use_engine(scene, passes=a.passes, spp=a.spp, photons=a.photons,
                      caustic_photons=a.caustic_photons)
    scene.gpu_photon.backend = a.backend
    scene.gpu_photon.mode = a.mode
    glb = os.path.join(out, "cornell.glb")
    bpy.ops.export_scene.gltf(filepath=glb, export_format="GLB", export_cameras=True,
                              export_lights=True)
    exe = os.environ.get("GPU_PHOTON_BIN") or os.path.join(HERE, "..", "target", "release",
                                                           "gpu-photon")
    cli = [exe, "render", glb, "-o", os.path.join(out, "cli.exr"), "--backend", a.backend,
           "--width", str(a.size[0]), "--height", str(a.size[1]), "--passes", str(a.passes),
           "--spp", str(a.spp), "--photons", str(a.photons), "--caustic-photons",
           str(a.caustic_photons), "--seed", "1", "--mode", a.mode, "-q"]
    engine = common.enable().engine
    first = []
    original = engine.cancelled

    def note_first_pass(e):
        if len(first) < len(starts):
            first.append(time.monotonic())
        return original(e)

    engine.cancelled = note_first_pass
    starts, ours, theirs = [], [], []
    scene.render.filepath = os.path.join(out, "engine.exr")
    scene.render.image_settings.file_format = "OPEN_EXR"
    for r in range(a.rounds):
        starts.append(time.monotonic())
        bpy.ops.render.render(write_still=False)
        ours.append(time.monotonic() - starts[-1])
        t = time.monotonic()
        if a.light == "point":
            subprocess.run(cli, check=True)
        theirs.append(time.monotonic() - t)
        print(f"round {r}: engine {ours[-1]:.2f} s (first pass after "
              f"{first[-1] - starts[-1]:.2f} s), CLI {theirs[-1]:.2f} s", flush=True)
    firsts = [f - s for f, s in zip(first, starts)]
    print(f"{a.size[0]}x{a.size[1]}, {a.passes} passes of {a.spp} spp, {a.photons} + "
          f"{a.caustic_photons} photons, mode {a.mode}, backend {a.backend}, {a.light} light, "
          f"{a.rounds} rounds:")
    print(f"first pass in Blender: median {statistics.median(firsts):.2f} s "
          f"(all {', '.join(f'{x:.2f}' for x in firsts)})")
    if a.light == "point":
        ratio = statistics.median(ours) / statistics.median(theirs)
        print(f"whole render: engine median {statistics.median(ours):.2f} s, CLI median "
              f"{statistics.median(theirs):.2f} s, ratio {ratio:.3f}")
    engine.cancelled = original


main()

"""The Cornell box with a glass and a mirror sphere, built by bpy, rendered by the engine:
- against Cycles' render of the same scene (CPU, seeded, 1024 samples: its image means carry
  well under 0.5% of noise): each channel's image mean within 3%;
- against our command line's render of Blender's own glTF export of it (Principled BSDFs
  and a lamp box, what glTF carries): each channel's mean within 1%;
- saved as cornell.blend (with the engine's settings and the engine's own render, for
  run.sh's `blender -b cornell.blend -E GPU_PHOTON -f 1`).
Run by run.sh: blender -b --factory-startup --python-exit-code 1 --python test_cornell.py"""

import os
import subprocess
import sys

import bpy

sys.path.insert(0, os.path.dirname(__file__))
import common  # noqa: E402
import scenes  # noqa: E402

SIZE = 64
CYCLES_SAMPLES = 1024


def test_against_cycles():
    scene = scenes.cornell_box(SIZE, SIZE)
    common.use_cycles(scene, CYCLES_SAMPLES)
    cycles, t_cycles = common.render(scene, "cornell-cycles")
    common.use_engine(scene, passes=8, spp=16)
    ours, t_ours = common.render(scene, "cornell-engine")
    print(f"Cycles {CYCLES_SAMPLES} spp: {t_cycles:.1f} s; gpu-photon 8 passes: {t_ours:.1f} s")
    common.means_agree(ours, cycles, 0.03, "Cornell box, gpu-photon vs Cycles")
    # The engine's settings and render, for the command-line frame render in run.sh.
    scene.gpu_photon.passes = 2
    scene.gpu_photon.spp = 4
    ours2, _ = common.render(scene, "cornell-engine-2")
    bpy.ops.wm.save_as_mainfile(filepath=os.path.join(common.OUT, "cornell.blend"))


def test_against_gltf_export():
    import gpu_photon

    scene = scenes.cornell_box(SIZE, SIZE, principled=True, light="lamp")
    common.use_engine(scene, passes=8, spp=16)
    ours, _ = common.render(scene, "cornell-gltf-engine")
    glb = os.path.join(common.OUT, "cornell.glb")
    kw = dict(filepath=glb, export_format="GLB", export_cameras=True, export_yup=True)
    bpy.ops.export_scene.gltf(**kw)
    exe = os.environ.get("GPU_PHOTON_BIN") or os.path.join(
        os.path.dirname(__file__), "..", "..", "target", "release", "gpu-photon")
    out = os.path.join(common.OUT, "cornell-gltf-cli.exr")
    cmd = [exe, "render", glb, "-o", out, "--backend", "cpu", "--width", str(SIZE),
           "--height", str(SIZE), "--passes", "8", "--spp", "16", "--photons", "100000",
           "--caustic-photons", "100000", "--seed", "1", "-q"]
    print(" ".join(cmd), flush=True)
    subprocess.run(cmd, check=True)
    cli = gpu_photon.read_image(out)
    # Both are this renderer: only the translations differ (seeds move the means by ~0.2%).
    common.means_agree(ours, cli, 0.01, "Cornell box, engine vs CLI on the glTF export")


if __name__ == "__main__":
    common.run([test_against_cycles, test_against_gltf_export])

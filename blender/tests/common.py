"""Helpers of the Blender tests: enabling the installed add-on, rendering a scene with an
engine to a float array, and checks that print what they compared."""

import os
import sys
import tempfile
import time

import addon_utils
import bpy
import numpy as np

OUT = os.environ.get("GPU_PHOTON_TEST_OUT") or tempfile.mkdtemp(prefix="gpu-photon-blender-")


def enable():
    """Enables the installed add-on (tests run with --factory-startup, which does not)."""
    mod = addon_utils.enable("gpu_photon_blender", default_set=True)
    assert mod is not None, "the gpu_photon_blender add-on is not installed"
    return mod


def render(scene, name):
    """Renders ``scene`` with its engine to ``OUT/name.exr``; returns the image (H, W, 3),
    top row first, and the seconds the render took."""
    import gpu_photon

    scene.render.image_settings.file_format = "OPEN_EXR"
    scene.render.image_settings.color_depth = "32"
    scene.render.filepath = os.path.join(OUT, name + ".exr")
    started = time.monotonic()
    bpy.ops.render.render(write_still=True)
    seconds = time.monotonic() - started
    return gpu_photon.read_image(scene.render.filepath), seconds


def use_engine(scene, passes=8, spp=16, photons=100_000, caustic_photons=100_000, seed=1):
    """Our engine on the CPU backend (deterministic, in every CI)."""
    enable()
    scene.render.engine = "GPU_PHOTON"
    p = scene.gpu_photon
    p.backend, p.mode = "cpu", "gather"
    p.passes, p.spp, p.photons, p.caustic_photons, p.seed = passes, spp, photons, \
        caustic_photons, seed
    p.time_limit = p.noise_target = 0.0


def use_cycles(scene, samples, seed=1):
    """Cycles on the CPU as a reference: no denoising, adaptive sampling, clamping or glossy
    filter, bounces enough for the Cornell box to converge."""
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    c.samples = samples
    c.seed = seed
    c.use_denoising = False
    c.use_adaptive_sampling = False
    c.sample_clamp_direct = c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.max_bounces = c.diffuse_bounces = c.glossy_bounces = c.transmission_bounces = 64
    c.transparent_max_bounces = 64
    c.caustics_reflective = c.caustics_refractive = True


def check(ok, message):
    print(("PASS " if ok else "FAIL ") + message, flush=True)
    if not ok:
        raise AssertionError(message)


def means_agree(a, b, tolerance, what):
    """Checks each channel's image mean of ``a`` within ``tolerance`` (relative) of ``b``'s."""
    ma, mb = a.reshape(-1, 3).mean(axis=0), b.reshape(-1, 3).mean(axis=0)
    rel = np.abs(ma / mb - 1.0)
    check(bool(np.all(rel <= tolerance)),
          f"{what}: means {np.round(ma, 4).tolist()} vs {np.round(mb, 4).tolist()}, "
          f"relative differences {np.round(rel, 4).tolist()} <= {tolerance}")


def run(tests):
    """Runs the test functions ``tests`` in order; exits non-zero when one fails."""
    failed = 0
    for t in tests:
        print(f"== {t.__name__}", flush=True)
        try:
            t()
        except Exception as e:  # noqa: BLE001 (report every failure, then fail)
            import traceback

            traceback.print_exc()
            print(f"FAIL {t.__name__}: {e}", flush=True)
            failed += 1
    sys.stdout.flush()
    if failed:
        sys.exit(1)

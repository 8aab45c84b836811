"""The render engine: translates the evaluated depsgraph (:mod:`translate`), opens a
``gpu_photon.Renderer`` on it and renders progressive passes into Blender's render result,
updating the image after every pass (``update_result``) and stopping after the pass in
progress when Esc is pressed (``test_break``), at the planned passes, or at the time or noise
target. The Combined pass is linear scene-referred radiance (Blender's colour management
applies the view transform); with Denoising Data on, the Denoising Albedo and Denoising Normal
passes (Cycles' definitions, ``gpu_photon.Scene.aovs``) feed the compositor's Denoise node.
"""

import time

import bpy
import numpy as np

from . import translate

# The most progressive passes a render with no pass limit may take (the library's MAX_PASSES).
UNLIMITED_PASSES = (1 << 32) // 256 - 1

DENOISING_PASSES = (("Denoising Albedo", "albedo", "RGB", "COLOR"),
                    ("Denoising Normal", "normal", "XYZ", "VECTOR"))


def renderer_settings(props, width, height):
    """The ``gpu_photon.Renderer`` keywords of the scene's gpu-photon settings."""
    passes = props.passes
    if passes == 0:
        passes = UNLIMITED_PASSES if (props.time_limit > 0 or props.noise_target > 0) else 16
    return dict(backend=props.backend, mode=props.mode, passes=passes, spp=props.spp,
                photons=props.photons, caustic_photons=props.caustic_photons, seed=props.seed,
                width=width, height=height)


def cancelled(engine):
    """Whether the user asked the render to stop (Esc): Blender's ``test_break``. A function
    of its own so that the tests can stand in for the key press."""
    return engine.test_break()


def _rect(image):
    """A (H, W, 3) top-row-first image as Blender's bottom-row-first RGBA rows."""
    h, w, _ = image.shape
    rgba = np.ones((h, w, 4), dtype=np.float32)
    rgba[:, :, :3] = image
    return rgba[::-1].reshape(-1, 4)


def _set_pass(render_pass, image):
    """Writes a (H, W, k) image into ``render_pass`` (its channels from the image's first)."""
    rows = _rect(image) if image.shape[2] == 3 else image
    render_pass.rect = np.ascontiguousarray(rows[:, :render_pass.channels])


class GpuPhotonEngine(bpy.types.RenderEngine):
    """gpu-photon: photon-mapped caustics."""

    bl_idname = "GPU_PHOTON"
    bl_label = "gpu-photon"
    bl_use_preview = False
    bl_use_shading_nodes_custom = False
    bl_use_eevee_viewport = True

    def update_render_passes(self, scene=None, renderlayer=None):
        self.register_pass(scene, renderlayer, "Combined", 4, "RGBA", "COLOR")
        if scene is not None and scene.gpu_photon.denoising_data:
            for name, _, chan, kind in DENOISING_PASSES:
                self.register_pass(scene, renderlayer, name, 3, chan, kind)

    def render(self, depsgraph):
        scene = depsgraph.scene
        props = scene.gpu_photon
        report = translate.Report(self)
        try:
            import gpu_photon
        except ImportError as e:
            self.report({"ERROR"}, "gpu-photon: the gpu_photon Python package is not "
                        f"installed for this Blender ({e}); run blender/install.sh")
            return
        self.update_stats("", "gpu-photon: translating the scene")
        started = time.monotonic()
        try:
            gp_scene, triangles = translate.build(depsgraph, report, props.max_triangles)
        except gpu_photon.Error as e:
            if "no light" in str(e):
                report.warn("the scene has no light: rendered black")
                self._black(scene)
                return
            self.report({"ERROR"}, f"gpu-photon: {e}")
            return
        except RuntimeError as e:
            self.report({"ERROR"}, f"gpu-photon: {e}")
            return
        width, height = _size(scene)
        settings = renderer_settings(props, width, height)
        try:
            renderer = gpu_photon.Renderer(gp_scene, **settings)
        except gpu_photon.Error as e:
            self.report({"ERROR"}, f"gpu-photon: {e}")
            return
        if props.denoising_data:
            for name, _, chan, _ in DENOISING_PASSES:
                self.add_pass(name, 3, chan)
        result = self.begin_result(0, 0, width, height)
        try:
            done = self._passes(renderer, gp_scene, props, result, settings,
                                f"{triangles} triangles", started)
        except gpu_photon.Error as e:
            self.report({"ERROR"}, f"gpu-photon: {e}")
            done = None
        finally:
            # The result is Blender's until ended, whatever happened to the passes.
            self.end_result(result)
        if done is not None:
            seconds = time.monotonic() - started
            self.update_stats("", f"gpu-photon: {done} passes in {seconds:.1f} s")

    def _passes(self, renderer, gp_scene, props, result, settings, size, started):
        """Renders passes into ``result`` until a stop, then the denoising passes; ``size``
        ends the status line. Returns the passes rendered."""
        combined = result.layers[0].passes["Combined"]
        planned = settings["passes"]
        limited = planned < UNLIMITED_PASSES
        done, stopped = 0, False
        while True:
            if not renderer.render_pass():
                break
            done += 1
            _set_pass(combined, renderer.image())
            self.update_result(result)
            elapsed = time.monotonic() - started
            noise = renderer.noise
            noise_text = f", noise {100.0 * noise:.1f}%" if noise is not None else ""
            of = f"/{planned}" if limited else ""
            self.update_stats("", f"gpu-photon: pass {done}{of}{noise_text}, {elapsed:.1f} s, "
                              f"{size}")
            if limited:
                self.update_progress(done / planned)
            if cancelled(self):
                stopped = True
                break
            if props.time_limit > 0 and elapsed >= props.time_limit:
                break
            if props.noise_target > 0 and noise is not None and noise <= props.noise_target:
                break
        if props.denoising_data and not stopped:
            self.update_stats("", "gpu-photon: denoising passes")
            aovs = gp_scene.aovs(["albedo", "normal"], props.aov_samples, seed=props.seed,
                                 width=settings["width"], height=settings["height"])
            passes = result.layers[0].passes
            for name, key, _, _ in DENOISING_PASSES:
                _set_pass(passes[name], aovs[key])
        return done

    def _black(self, scene):
        width, height = _size(scene)
        result = self.begin_result(0, 0, width, height)
        self.end_result(result)


def _size(scene):
    from .camera import resolution
    return resolution(scene)

"""The engine's behaviour inside Blender: Esc (test_break) stops a render within one pass;
an unsupported node is reported as a warning and rendered by its documented fallback; the
Denoising Albedo and Denoising Normal passes hold Cycles' definitions and feed the
compositor's Denoise node; a scene without a light renders black with a warning."""

import os
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import common  # noqa: E402
import scenes  # noqa: E402


class CountingRenderer:
    """gpu_photon.Renderer, with the time each pass ended."""

    ends = []

    def __init__(self, *args, **kwargs):
        import gpu_photon

        self.inner = gpu_photon._gpu_photon.Renderer(*args, **kwargs)
        CountingRenderer.ends = []

    def render_pass(self):
        more = self.inner.render_pass()
        if more:
            CountingRenderer.ends.append(time.monotonic())
        return more

    def __getattr__(self, name):
        return getattr(self.inner, name)


def patched(obj, name, value):
    """Sets ``obj.name`` to ``value``; returns a function that restores it."""
    old = obj.__dict__.get(name)

    def restore():
        if old is None:
            delattr(obj, name)
        else:
            setattr(obj, name, old)

    setattr(obj, name, value)
    return restore


def test_cancel_within_one_pass():
    import gpu_photon

    scene = scenes.cornell_box(48, 48)
    common.use_engine(scene, passes=200, spp=4, photons=20_000, caustic_photons=20_000)
    # Esc is "pressed" 0.3 s after the first pass ends: test_break answers True from then on.
    state = {}

    def test_break(engine):
        if not CountingRenderer.ends:
            return False
        state.setdefault("esc", CountingRenderer.ends[0] + 0.3)
        return time.monotonic() >= state["esc"]

    undo = [patched(gpu_photon, "Renderer", CountingRenderer),
            patched(common.enable().engine, "cancelled", test_break)]
    try:
        _, seconds = common.render(scene, "cancel")
        returned = time.monotonic()
    finally:
        for u in undo:
            u()
    ends = CountingRenderer.ends
    passes = np.diff(ends) if len(ends) > 1 else np.array([ends[0] - ends[0]])
    longest = max(float(passes.max()) if len(passes) else 0.0, 0.05)
    after = returned - state["esc"]
    print(f"{len(ends)} passes of at most {longest:.3f} s; returned {after:.3f} s after Esc")
    common.check(len(ends) < 200, "the render stopped short of its 200 planned passes")
    common.check(after <= longest + 0.5,
                 f"returned {after:.3f} s after Esc, within one pass ({longest:.3f} s) "
                 "and 0.5 s of writing the result")


def test_unsupported_node_is_reported():
    scene = scenes.cornell_box(32, 32)
    mat = bpy.data.materials["White"]
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    toon = nodes.new("ShaderNodeBsdfToon")
    toon.inputs["Color"].default_value = (0.2, 0.4, 0.6, 1.0)
    links.new(toon.outputs[0], nodes["Material Output"].inputs["Surface"])
    red = bpy.data.materials["Red"].node_tree
    wave = red.nodes.new("ShaderNodeTexWave")
    red.links.new(wave.outputs["Color"], red.nodes["Diffuse BSDF"].inputs["Color"])
    reports = []
    cls = common.enable().translate.Report
    original = cls.warn

    def warn(self, message):
        reports.append(({"WARNING"}, message))
        return original(self, message)

    common.use_engine(scene, passes=1, spp=1, photons=10_000, caustic_photons=0)
    undo = patched(cls, "warn", warn)
    try:
        image, _ = common.render(scene, "unsupported")
    finally:
        undo()
    for r in reports:
        print("report:", r)
    warned = [m for k, m in reports if "WARNING" in k]
    common.check(any("Toon BSDF is not translated" in m and "material White" in m
                     for m in warned), "the Toon BSDF is reported as a warning")
    common.check(any("Wave Texture" in m and "material Red" in m for m in warned),
                 "the Wave Texture is reported as a warning")
    common.check(bool(np.isfinite(image).all()) and image.mean() > 0.0,
                 "the scene still renders (the documented fallbacks)")


def compositor(scene):
    """The scene's compositor, emptied, and its output node (its input "Image" is the image):
    the Composite node of `scene.node_tree` up to 4.x, a Group Output of the node group
    `scene.compositing_node_group` from 5.0 (which removed both)."""
    if bpy.app.version >= (5, 0, 0):
        tree = bpy.data.node_groups.new("Compositing", "CompositorNodeTree")
        tree.interface.new_socket("Image", in_out="OUTPUT", socket_type="NodeSocketColor")
        scene.compositing_node_group = tree
        return tree, tree.nodes.new("NodeGroupOutput")
    scene.use_nodes = True
    tree = scene.node_tree
    for n in list(tree.nodes):
        tree.nodes.remove(n)
    return tree, tree.nodes.new("CompositorNodeComposite")


def render_pass(scene, name, pass_name):
    """Renders with the compositor routing ``pass_name`` to the Composite output."""
    tree, out = compositor(scene)
    layers = tree.nodes.new("CompositorNodeRLayers")
    if pass_name == "Denoise":
        denoise = tree.nodes.new("CompositorNodeDenoise")
        tree.links.new(layers.outputs["Image"], denoise.inputs["Image"])
        tree.links.new(layers.outputs["Denoising Normal"], denoise.inputs["Normal"])
        tree.links.new(layers.outputs["Denoising Albedo"], denoise.inputs["Albedo"])
        tree.links.new(denoise.outputs["Image"], out.inputs["Image"])
    else:
        tree.links.new(layers.outputs[pass_name], out.inputs["Image"])
    image, _ = common.render(scene, name)
    return image


def test_denoising_passes():
    scene = scenes.cornell_box(32, 32)
    common.use_engine(scene, passes=2, spp=4, photons=20_000, caustic_photons=20_000)
    scene.gpu_photon.denoising_data = True
    scene.view_settings.view_transform = "Standard"
    albedo = render_pass(scene, "albedo", "Denoising Albedo")
    normal = render_pass(scene, "normal", "Denoising Normal")
    # The back wall at the image's centre-top and the red wall at its left.
    back = albedo[10:14, 14:18].reshape(-1, 3).mean(axis=0)
    red = albedo[14:20, 6:8].reshape(-1, 3).mean(axis=0)
    common.check(bool(np.allclose(back, 0.8, atol=0.02)), f"back wall albedo {back} is 0.8")
    common.check(bool(np.allclose(red, [0.8, 0.1, 0.1], atol=0.02)),
                 f"red wall albedo {red} is (0.8, 0.1, 0.1)")
    n_back = normal[10:14, 14:18].reshape(-1, 3).mean(axis=0)
    n_floor = normal[24:27, 15:17].reshape(-1, 3).mean(axis=0)
    common.check(bool(np.allclose(n_back, [0.0, 0.0, -1.0], atol=0.02)),
                 f"back wall normal {n_back} faces the camera (camera space, -z)")
    common.check(bool(np.allclose(n_floor, [0.0, 1.0, 0.0], atol=0.05)),
                 f"floor normal {n_floor} points up (camera space, +y)")
    denoised = render_pass(scene, "denoised", "Denoise")
    noisy = render_pass(scene, "noisy", "Image")
    common.check(bool(np.isfinite(denoised).all()), "the Denoise node ran on our passes")
    ratio = denoised.mean() / noisy.mean()
    common.check(abs(ratio - 1.0) < 0.1, f"denoised mean / noisy mean {ratio:.3f} is about 1")
    scene.use_nodes = False


def test_a_failing_pass_is_reported_and_ends_the_result():
    import gpu_photon

    class FailingRenderer(CountingRenderer):
        def render_pass(self):
            if len(CountingRenderer.ends) == 1:
                raise gpu_photon.Error("the device was lost (a test's stand-in)")
            return super().render_pass()

    scene = scenes.cornell_box(16, 16)
    common.use_engine(scene, passes=4, spp=1, photons=5_000, caustic_photons=0)
    undo = patched(gpu_photon, "Renderer", FailingRenderer)
    try:
        image, _ = common.render(scene, "failing")
        raised = None
    except RuntimeError as e:  # the operator reports the engine's error
        raised, image = e, None
    finally:
        undo()
    print("operator:", raised)
    common.check(raised is not None and "the device was lost" in str(raised),
                 "the pass's error reaches Blender's report as an error")
    common.check(len(CountingRenderer.ends) == 1, "after the one pass that was rendered")


def test_no_light_renders_black():
    scene = scenes.cornell_box(16, 16)
    bpy.data.objects.remove(bpy.data.objects["Light"])
    common.use_engine(scene, passes=1, spp=1)
    image, _ = common.render(scene, "nolight")
    common.check(float(np.abs(image).max()) == 0.0, "a scene without light renders black")



if __name__ == "__main__":
    common.run([test_cancel_within_one_pass, test_unsupported_node_is_reported,
                test_denoising_passes, test_a_failing_pass_is_reported_and_ends_the_result,
                test_no_light_renders_black])

"""The render settings the engine keeps on each scene (``scene.gpu_photon``): the stop
targets, the photon counts, the mode and backend, and the feature passes for denoising.
Their names and ranges are the command line's (``gpu-photon render --help``)."""

import bpy
from bpy.props import BoolProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty


class GpuPhotonRenderSettings(bpy.types.PropertyGroup):
    """gpu-photon's settings of a scene."""

    backend: EnumProperty(
        name="Backend",
        items=[
            ("auto", "Auto", "The faster backend on this machine (measured once)"),
            ("cpu", "CPU", "The rayon CPU backend"),
            ("gpu", "GPU", "The wgpu compute kernels on a Vulkan device"),
        ],
        default="auto",
    )
    mode: EnumProperty(
        name="Mode",
        items=[
            ("gather", "Final gather", "Final gathering from a radiance cache (the default)"),
            ("direct", "Direct", "Shadow rays plus the photon maps"),
            ("photon", "Photon", "The photon maps alone"),
        ],
        default="gather",
    )
    passes: IntProperty(
        name="Passes",
        description="Progressive passes to render; 0: until the time or noise target",
        default=16,
        min=0,
        soft_max=4096,
    )
    time_limit: FloatProperty(
        name="Time Limit",
        description="Stop after the pass that ends past this many seconds (0: none)",
        default=0.0,
        min=0.0,
        subtype="TIME_ABSOLUTE",
    )
    noise_target: FloatProperty(
        name="Noise Target",
        description="Stop at the first even pass count whose estimated relative noise is at "
        "most this (0: none)",
        default=0.0,
        min=0.0,
        max=1.0,
        precision=3,
    )
    spp: IntProperty(
        name="Samples per Pass",
        description="Camera samples per pixel in each pass (fewer: quicker updates and "
        "cancellation)",
        default=4,
        min=1,
        soft_max=256,
    )
    photons: IntProperty(
        name="Photons",
        description="Photon paths for the global map, per pass",
        default=50_000,
        min=1,
        soft_max=10_000_000,
    )
    caustic_photons: IntProperty(
        name="Caustic Photons",
        description="Photons aimed at specular surfaces for the caustic map, per pass "
        "(0: none)",
        default=25_000,
        min=0,
        soft_max=10_000_000,
    )
    seed: IntProperty(name="Seed", default=1, min=0)
    denoising_data: BoolProperty(
        name="Denoising Data",
        description="Write the Denoising Albedo and Denoising Normal passes (for the "
        "compositor's Denoise node)",
        default=False,
    )
    aov_samples: IntProperty(
        name="Denoising Samples",
        description="First-hit samples per pixel of the denoising passes",
        default=4,
        min=1,
        max=256,
    )
    max_triangles: IntProperty(
        name="Triangle Budget",
        description="Most triangles the scene may have once instances are flattened",
        default=20_000_000,
        min=1,
        max=1 << 26,
    )


def register():
    bpy.utils.register_class(GpuPhotonRenderSettings)
    bpy.types.Scene.gpu_photon = PointerProperty(type=GpuPhotonRenderSettings)


def unregister():
    del bpy.types.Scene.gpu_photon
    bpy.utils.unregister_class(GpuPhotonRenderSettings)

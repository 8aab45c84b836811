"""Render Properties for the engine: its own panel (stop targets, photon counts, mode and
backend, denoising data), and Blender's own panels that apply to it (output, dimensions,
colour management, materials, lights, world, camera) opened to it."""

import bpy

# Blender's panels that also serve this engine: those of the built-in engines whose settings
# it reads (by name, where present in this Blender).
SHARED_PANELS = [
    "RENDER_PT_color_management", "RENDER_PT_color_management_curves",
    "RENDER_PT_format", "RENDER_PT_frame_range", "RENDER_PT_output", "RENDER_PT_post_processing",
    "DATA_PT_lens", "DATA_PT_camera", "DATA_PT_camera_dof", "DATA_PT_camera_dof_aperture",
    "DATA_PT_context_light", "DATA_PT_light", "DATA_PT_EEVEE_light", "DATA_PT_EEVEE_light_distance",
    "DATA_PT_area", "DATA_PT_spot", "DATA_PT_preview",
    "EEVEE_MATERIAL_PT_context_material", "EEVEE_MATERIAL_PT_surface", "EEVEE_MATERIAL_PT_volume",
    "MATERIAL_PT_preview", "EEVEE_WORLD_PT_surface", "WORLD_PT_context_world",
    "VIEWLAYER_PT_layer", "VIEWLAYER_PT_layer_passes",
]


class RENDER_PT_gpu_photon(bpy.types.Panel):
    bl_label = "gpu-photon"
    bl_space_type = "PROPERTIES"
    bl_region_type = "WINDOW"
    bl_context = "render"
    COMPAT_ENGINES = {"GPU_PHOTON"}

    @classmethod
    def poll(cls, context):
        return context.engine in cls.COMPAT_ENGINES

    def draw(self, context):
        props = context.scene.gpu_photon
        layout = self.layout
        layout.use_property_split = True
        layout.use_property_decorate = False
        col = layout.column()
        col.prop(props, "backend")
        col.prop(props, "mode")
        col = layout.column(heading="Stop")
        col.prop(props, "passes")
        col.prop(props, "time_limit")
        col.prop(props, "noise_target")
        col = layout.column()
        col.prop(props, "spp")
        col.prop(props, "photons")
        col.prop(props, "caustic_photons")
        col.prop(props, "seed")
        col = layout.column()
        col.prop(props, "denoising_data")
        sub = col.column()
        sub.active = props.denoising_data
        sub.prop(props, "aov_samples")
        layout.prop(props, "max_triangles")


def _shared():
    for name in SHARED_PANELS:
        panel = getattr(bpy.types, name, None)
        if panel is not None and hasattr(panel, "COMPAT_ENGINES"):
            yield panel


def register():
    bpy.utils.register_class(RENDER_PT_gpu_photon)
    for panel in _shared():
        panel.COMPAT_ENGINES.add("GPU_PHOTON")


def unregister():
    for panel in _shared():
        panel.COMPAT_ENGINES.discard("GPU_PHOTON")
    bpy.utils.unregister_class(RENDER_PT_gpu_photon)

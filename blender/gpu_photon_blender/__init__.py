"""gpu-photon as a Blender render engine (Render Properties > Render Engine > gpu-photon):
photon-mapped caustics from the evaluated scene, rendered progressively in Blender's render
window. ``blender/install.sh`` installs this add-on and the ``gpu_photon`` package for the
``blender`` on PATH and enables it; the README's Blender section says what is translated."""

bl_info = {
    "name": "gpu-photon",
    "author": "gpu-photon developers",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "Render Properties > Render Engine > gpu-photon",
    "description": "Photon-mapped caustics: the gpu-photon renderer as a render engine",
    "category": "Render",
}

if "engine" in locals():
    import importlib

    for _m in (properties, engine, ui):  # noqa: F821 (reloaded modules)
        importlib.reload(_m)

from . import engine, properties, ui  # noqa: E402


def register():
    import bpy

    properties.register()
    bpy.utils.register_class(engine.GpuPhotonEngine)
    ui.register()


def unregister():
    import bpy

    ui.unregister()
    bpy.utils.unregister_class(engine.GpuPhotonEngine)
    properties.unregister()

"""Run after install.sh, in the user profile it installed into (not --factory-startup): the
add-on is enabled in the saved preferences, the engine is registered, and the gpu_photon
package imports on Blender's own Python."""

import os
import sys

import bpy

sys.path.insert(0, os.path.dirname(__file__))
import common  # noqa: E402


def test_installed_and_enabled():
    import gpu_photon

    common.check("gpu_photon_blender" in bpy.context.preferences.addons,
                 "the add-on is enabled in the user preferences")
    engines = [e.bl_idname for e in bpy.types.RenderEngine.__subclasses__()]
    common.check("GPU_PHOTON" in engines, f"GPU_PHOTON is a render engine ({engines})")
    common.check(hasattr(gpu_photon, "SceneBuilder"),
                 f"gpu_photon imports from {os.path.dirname(gpu_photon.__file__)} on Python "
                 f"{sys.version.split()[0]} (Blender {bpy.app.version_string})")


if __name__ == "__main__":
    common.run([test_installed_and_enabled])

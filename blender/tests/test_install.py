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

    if bpy.app.binary_path:
        common.check("gpu_photon_blender" in bpy.context.preferences.addons,
                     "the add-on is enabled in the user preferences")
    else:
        # Blender as a Python module (tests/bpy_as_blender.py) reads no user preferences (its
        # wm.read_userpref crashes in 4.2): the add-on installed into the user scripts is
        # enabled here instead, which checks that it loads from where install.sh put it.
        print("SKIP the saved preferences: Blender as a Python module does not read them")
        mod = common.enable()
        common.check(os.path.dirname(mod.__file__).startswith(bpy.utils.user_resource("SCRIPTS")),
                     f"the add-on loads from the user scripts ({mod.__file__})")
    # Blender 4.x lists its HydraRenderEngine base class, which has no bl_idname, too.
    engines = [getattr(e, "bl_idname", None) for e in bpy.types.RenderEngine.__subclasses__()]
    common.check("GPU_PHOTON" in engines, f"GPU_PHOTON is a render engine ({engines})")
    common.check(hasattr(gpu_photon, "SceneBuilder"),
                 f"gpu_photon imports from {os.path.dirname(gpu_photon.__file__)} on Python "
                 f"{sys.version.split()[0]} (Blender {bpy.app.version_string})")


if __name__ == "__main__":
    common.run([test_installed_and_enabled])

"""gpu-photon: a photon-mapping renderer (wgpu compute kernels, with a rayon CPU reference).

    import gpu_photon
    scene = gpu_photon.load("scenes/cornell-box.toml")
    image = scene.render(spp=16, passes=4, backend="auto", seed=1)  # float32 (H, W, 3)
    gpu_photon.write_exr("cornell.exr", image)

A scene can also be built in memory from NumPy arrays and dicts, without a file (the Blender
add-on does so); every value goes through the same scene builder as the file importers::

    b = gpu_photon.SceneBuilder("room")
    white = b.add_material("white", {"kind": "diffuse", "colour": (0.8, 0.8, 0.8)})
    lamp = b.add_material("lamp", {"kind": "black", "emission": (20, 20, 20)})
    b.add_mesh("floor", positions, triangles, np.array([white], np.uint32))  # (N,3), (T,3)
    b.add_mesh("lamp", quad, two_triangles, np.array([lamp], np.uint32), transform=matrix)
    tile = b.add_mesh_group("tile", positions, triangles, np.array([white], np.uint32))
    for i, m in enumerate(matrices):  # stored once, placed many times (two-level BVH)
        b.add_instance(f"tile{i}", tile, m)
    b.set_camera(eye, forward, up, fov_y, width, height)
    scene = b.finish()
    features = scene.aovs(["albedo", "normal"])  # for denoisers, as Cycles defines them

Material kinds: black, diffuse, mirror, dielectric, conductor, phong, metallic_roughness,
transparent; each with emission, textures (``add_texture``: linear RGBA (H, W, 4)) and alpha.

Settings are keywords with the command line's names (``caustic_photons`` for
``--caustic-photons``) and ranges; ``gpu_photon.setting_names`` lists them. Errors are
``gpu_photon.Error`` (``SceneError`` with ``file``, ``line``, ``field``; ``SettingError``) or
``OSError``; warnings go through :mod:`warnings` as ``GpuPhotonWarning``.
"""

import numpy as _np

from . import _gpu_photon
from ._gpu_photon import (
    Error,
    GpuPhotonWarning,
    Renderer,
    Scene,
    SceneBuilder,
    SceneError,
    SettingError,
    load,
    read_image,
    setting_names,
)

__all__ = [
    "Error",
    "GpuPhotonWarning",
    "Renderer",
    "Scene",
    "SceneBuilder",
    "SceneError",
    "SettingError",
    "diff",
    "load",
    "read_image",
    "setting_names",
    "write_exr",
    "write_png",
]


def _rgb(image):
    """The image as a C-contiguous float32 (H, W, 3) array (no copy when it already is)."""
    return _np.ascontiguousarray(image, dtype=_np.float32)


def diff(a, b, block=16):
    """``gpu-photon diff A B``'s statistics of ``a`` against the reference ``b``: a dict of
    rmse, block_rmse (means of block x block pixels), rel_mse, mean_ratio (per channel),
    max_error, and the lines the command prints."""
    return _gpu_photon.diff(_rgb(a), _rgb(b), block)


def write_exr(path, image):
    """Writes ``image`` (H, W, 3) as a linear float EXR, atomically."""
    _gpu_photon.write_exr(str(path), _rgb(image))


def write_png(path, image, exposure=0.0):
    """Writes ``image`` (H, W, 3) as an 8-bit sRGB PNG scaled by 2**exposure, atomically."""
    _gpu_photon.write_png(str(path), _rgb(image), exposure)

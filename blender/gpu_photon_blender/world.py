"""The world as the renderer's environment light: a Background node's colour times its
strength (a world without nodes: its colour, as Cycles), or an Environment Texture
(equirectangular) driving the colour, optionally turned by a Mapping node's Z rotation.

Cycles looks a direction ``d`` up at ``u = 0.5 - atan2(d.y, d.x) / 2 pi``, ``v = 0.5 +
asin(d.z) / pi`` (``kernel/geom/`` ``direction_to_equirectangular``: +X at the image's centre,
+Z at its top row). The renderer's lat-long (Mitsuba's) reads ``u = atan2(x, -z) / 2 pi``,
``v = acos(y) / pi`` in the map's frame, row 0 at the zenith; the two agree when the map's
x, y, z axes are the world's +Y, +Z, +X and the rows run from the top.
"""

import math

import numpy as np

from .images import texels
from .nodes import source

# The map's frame in world space (rows of the matrix: the world axes in map coordinates;
# columns: the map's x, y, z axes in the world), row-major.
MAP_TO_WORLD = np.array([[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])


def add_world(builder, world, report):
    """Adds the environment of Blender ``world`` (None: none)."""
    if world is None:
        return
    where = f"world {world.name}"
    if not world.use_nodes or world.node_tree is None:
        c = [max(x, 0.0) for x in world.color]
        if max(c) > 0.0:
            builder.set_environment(c)
        return
    out = world.node_tree.get_output_node("CYCLES")
    surface = source(out.inputs["Surface"]) if out is not None else None
    if surface is None:
        return
    node = surface.node
    if node.type != "BACKGROUND":
        report.warn(f"{where}: a {node.bl_label} node is not translated; the world is black")
        return
    strength = node.inputs["Strength"].default_value
    if node.inputs["Strength"].is_linked:
        report.warn(f"{where}: a linked Strength is not translated; its value is used")
    colour_src = source(node.inputs["Color"])
    if colour_src is None:
        c = [max(x * strength, 0.0) for x in node.inputs["Color"].default_value[:3]]
        if max(c) > 0.0:
            builder.set_environment(c)
        return
    tex = colour_src.node
    if tex.type != "TEX_ENVIRONMENT" or tex.image is None:
        report.warn(f"{where}: a {tex.bl_label} node drives the background colour; it is not "
                    "translated (the unlinked colour is used)")
        c = [max(x * strength, 0.0) for x in node.inputs["Color"].default_value[:3]]
        if max(c) > 0.0:
            builder.set_environment(c)
        return
    if tex.projection != "EQUIRECTANGULAR":
        report.warn(f"{where}: a {tex.projection} environment is read as equirectangular")
    rgba = texels(tex.image)
    if rgba is None:
        report.warn(f"{where}: image {tex.image.name} has no pixels; the world is black")
        return
    rotation = _mapping_rotation(tex, report, where)
    image = np.ascontiguousarray(rgba[::-1, :, :3], dtype=np.float32)
    to_world = rotation @ MAP_TO_WORLD
    builder.set_environment([max(strength, 0.0)] * 3, image, to_world.tolist())


def _mapping_rotation(tex, report, where):
    """The rotation a Mapping node before the texture applies to directions (its Z rotation;
    a texture-space mapping turns the lookup the other way)."""
    vec = source(tex.inputs["Vector"])
    if vec is None:
        return np.eye(3)
    node = vec.node
    if node.type != "MAPPING":
        report.warn(f"{where}: the environment's Vector input is not translated")
        return np.eye(3)
    rot = node.inputs["Rotation"].default_value
    if abs(rot[0]) > 1e-6 or abs(rot[1]) > 1e-6:
        report.warn(f"{where}: only the Mapping node's Z rotation is rendered")
    angle = rot[2] if node.vector_type in ("POINT", "VECTOR") else -rot[2]
    # The texture is looked up at R d: the world sees it turned by R^-1.
    c, s = math.cos(-angle), math.sin(-angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])

"""Blender's lights in the renderer's units, converted as Cycles interprets them.

Cycles (``intern/cycles/blender/light.cpp``, ``BlenderSync::sync_light``) sets a light's
strength to ``color * energy`` (watts for point, spot and area lights, W/m^2 for the sun) and
its direction to the object's -Z axis; the kernel turns the strength into radiance with a
factor ``eval_fac`` (``intern/cycles/scene/light.cpp``, ``kernel/light/``):

- point, radius 0: ``eval_fac = 1 / (4 pi)``, a radiant intensity ``I = P / (4 pi)`` W/sr
  (Cycles 3.4 ``light.h``: ``M_1_PI_F * 0.25f * invarea`` with ``invarea = 1``; 4.x
  ``scene/light.cpp``: ``invarea = 1/4``, ``eval_fac = invarea * M_1_PI_F``);
- point, radius r > 0: a disc facing the shading point (3.x) or a sphere (4.x) of radiance
  ``P / (4 pi * pi r^2)``; both have the point's far-field intensity ``P / (4 pi)``. Rendered
  as an emissive sphere of that radiance;
- spot: the point light's intensity on the axis times ``smoothstep((cos - cos_half) /
  ((1 - cos_half) blend))`` inside the cone of half-angle ``spot_size / 2`` (Cycles 3.5 and
  later, ``kernel/light/spot.h``); Cycles 3.4 (``kernel/light/common.h``,
  ``spot_light_attenuation``) also multiplies by ``cos``. Rendered with the renderer's spot
  (glTF's ramp, quadratic in the cosine, over the same cosine interval): exact inside the
  inner cone, an approximation on the ramp (and of 3.4's cosine);
- area: a one-sided emitter facing -Z of area ``A`` (``size`` x ``size_y``, times pi/4 for a
  disc or ellipse, object scale included) of radiance ``P / (4 A)`` in Cycles 3.x
  (``kernel/light/area.h``: ``eval_fac = 0.25f * invarea``) and ``P / (pi A)`` since 4.0
  (commit a21af93e6, "Fix wrong conversion from power to radiance of area lights");
- sun: ``eval_fac = invarea / cos^3`` over a disc of directions of area ``1/invarea``: the
  irradiance on a surface facing it is the strength, ``E = color * strength`` W/m^2. Rendered
  as a directional light (its angular size is not).

A light's node tree, a spot's radius, an area light's spread below 180 degrees and a sun's
angle are not rendered (a warning says so where it changes the image).
"""

import math

import bpy
import numpy as np

# Segments of the polygon that stands for a disc or ellipse area light.
ROUND_SEGMENTS = 64


def _strength(light):
    return [c * light.energy for c in light.color]


def _area_eval_fac():
    """Cycles' factor from an area light's power over its area to its radiance."""
    return 1.0 / math.pi if bpy.app.version >= (4, 0, 0) else 0.25


def point_intensity(light):
    """W/sr of a point (or a spot on its axis) of Blender ``light``."""
    return [s / (4.0 * math.pi) for s in _strength(light)]


def spot_cone(light):
    """(inner, outer) half-angles in degrees of the renderer's spot for Blender ``light``: the
    outer one is ``spot_size / 2``; the inner one where Cycles' smoothstep reaches 1."""
    half = 0.5 * light.spot_size
    cos_outer = math.cos(half)
    cos_inner = cos_outer + (1.0 - cos_outer) * min(max(light.spot_blend, 0.0), 1.0)
    return math.degrees(math.acos(min(cos_inner, 1.0))), math.degrees(half)


def area_shape(light, matrix):
    """World-space triangles (T, 3, 3) of an area light and their radiance (rgb): a square,
    rectangle, disc or ellipse in the object's XY plane, front face towards -Z."""
    sx = light.size
    sy = light.size if light.shape in ("SQUARE", "DISK") else light.size_y
    round_shape = light.shape in ("DISK", "ELLIPSE")
    if round_shape:
        n = ROUND_SEGMENTS
        # The polygon's area is the ellipse's: its vertices a little outside it.
        grow = math.sqrt(math.pi / (0.5 * n * math.sin(2.0 * math.pi / n)))
        angles = [2.0 * math.pi * i / n for i in range(n)]
        ring = [(0.5 * sx * grow * math.cos(a), 0.5 * sy * grow * math.sin(a)) for a in angles]
    else:
        ring = [(-0.5 * sx, -0.5 * sy), (0.5 * sx, -0.5 * sy), (0.5 * sx, 0.5 * sy),
                (-0.5 * sx, 0.5 * sy)]
    m = np.array(matrix, dtype=np.float64)
    local = np.array([(x, y, 0.0, 1.0) for x, y in ring])
    world = (local @ m.T)[:, :3]
    centre = (np.array([0.0, 0.0, 0.0, 1.0]) @ m.T)[:3]
    # Clockwise seen from +Z: the front face (counter-clockwise) looks down -Z.
    tris = [(centre, world[(i + 1) % len(ring)], world[i]) for i in range(len(ring))]
    axis_u, axis_v = m[:3, 0] * sx, m[:3, 1] * sy
    area = np.linalg.norm(axis_u) * np.linalg.norm(axis_v)
    if round_shape:
        area *= math.pi / 4.0
    if area <= 0.0:
        return None, None
    radiance = [s * _area_eval_fac() / area for s in _strength(light)]
    return np.array(tris, dtype=np.float32), radiance


def sphere_radiance(light, radius):
    """Radiance of the sphere that stands for a point light of ``radius``."""
    return [s / (4.0 * math.pi * math.pi * radius * radius) for s in _strength(light)]


def add_light(builder, materials, name, obj, report):
    """Adds Blender light object ``obj`` (evaluated, at its world matrix) to ``builder``."""
    light = obj.data
    m = obj.matrix_world
    position = list(m.translation)
    # Cycles: light->set_dir(-transform_get_column(&tfm, 2)).
    direction = list(-m.col[2].xyz)
    if light.use_nodes:
        report.warn(f"light {light.name}: its node tree is not rendered (colour x power is)")
    if light.type == "POINT":
        radius = light.shadow_soft_size
        if radius > 0.0:
            emitter = materials.emitter(sphere_radiance(light, radius))
            builder.add_sphere(name, position, radius, emitter)
        else:
            builder.add_point_light(name, position, point_intensity(light))
    elif light.type == "SPOT":
        inner, outer = spot_cone(light)
        if light.shadow_soft_size > 0.0:
            report.warn(f"light {light.name}: a spot light's radius is rendered as 0")
        builder.add_spot_light(name, position, direction, point_intensity(light), inner, outer)
    elif light.type == "SUN":
        irradiance = _strength(light)
        builder.add_directional_light(name, direction, irradiance)
    elif light.type == "AREA":
        if light.spread < math.pi - 1e-6:
            report.warn(f"light {light.name}: an area light's spread is rendered as 180 degrees")
        tris, radiance = area_shape(light, m)
        if tris is None:
            report.warn(f"light {light.name}: an area light of zero size is skipped")
            return
        positions = tris.reshape(-1, 3)
        triangles = np.arange(len(positions), dtype=np.uint32).reshape(-1, 3)
        emitter = materials.emitter(radiance)
        builder.add_mesh(name, positions, triangles, np.array([emitter], dtype=np.uint32))
    else:
        report.warn(f"light {light.name}: type {light.type} is not rendered")

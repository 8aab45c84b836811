"""Each Blender light type against its analytic irradiance on a diffuse plane: the engine's
render of a plane of albedo 0.5 seen from straight above (no other surface) against the
radiance ``albedo E / pi`` at each pixel's point of the plane, with ``E`` the irradiance of the
light as Cycles defines its power (see gpu_photon_blender/lights.py): image means within 1%
and 8x8-pixel block means within 4% (the area lights' shadow-ray noise). Cycles renders the
point light and the square area light too, as a check of the formulas themselves (means
within 1%). The spot light is checked against the renderer's model of it (Cycles' cone and
on-axis intensity, glTF's ramp between the blend's cosines)."""

import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import common  # noqa: E402
import scenes  # noqa: E402

SIZE = 32
CAMERA_HEIGHT = 1.0
LENS = 35.0
ALBEDO = 0.5
COLOUR = (1.0, 0.6, 0.3)


def plane_points():
    """World (x, y) of each pixel centre's point on the plane z = 0 (row 0 at the top)."""
    t = 18.0 / LENS  # tan(fov / 2): a 36 mm sensor fits the square image
    px = (np.arange(SIZE) + 0.5) / SIZE
    x = CAMERA_HEIGHT * (2.0 * px - 1.0) * t
    y = CAMERA_HEIGHT * (1.0 - 2.0 * px) * t
    return np.meshgrid(x, y)


def new_light(kind, location, power, rotation=(0.0, 0.0, 0.0), **props):
    light = bpy.data.lights.new("Light", kind)
    light.energy = power
    light.color = COLOUR
    for k, v in props.items():
        setattr(light, k, v)
    obj = bpy.data.objects.new("Light", light)
    bpy.context.scene.collection.objects.link(obj)
    obj.location = location
    obj.rotation_euler = rotation
    return obj


def setup():
    scene = scenes.empty_scene(SIZE, SIZE)
    scenes.plane_under(None, size=6.0, albedo=ALBEDO)
    scenes.camera((0.0, 0.0, CAMERA_HEIGHT), (0.0, 0.0, 0.0), lens=LENS)
    return scene


def area_eval_fac():
    return 1.0 / math.pi if bpy.app.version >= (4, 0, 0) else 0.25


def rect_corner(x, y, h):
    """Irradiance over radiance from the rectangle [0, x] x [0, y] parallel to the plane at
    height h, at the point below its corner (signed in x and y)."""
    X, Y = x / h, y / h
    a, b = np.sqrt(1 + X * X), np.sqrt(1 + Y * Y)
    return 0.5 * (X / a * np.arctan(Y / a) + Y / b * np.arctan(X / b))


def irradiance_area(obj, x, y, shape, sx, sy):
    """The irradiance of a downward-facing area light (rotated about Z) at plane points."""
    light = obj.data
    cx, cy, h = obj.location
    angle = obj.rotation_euler[2]
    # The points in the light's frame.
    dx, dy = x - cx, y - cy
    u = math.cos(angle) * dx + math.sin(angle) * dy
    v = -math.sin(angle) * dx + math.cos(angle) * dy
    area = sx * sy * (math.pi / 4.0 if shape in ("DISK", "ELLIPSE") else 1.0)
    power = light.energy * np.array(light.color)
    radiance = power * area_eval_fac() / area
    if shape in ("SQUARE", "RECTANGLE"):
        f = (rect_corner(0.5 * sx - u, 0.5 * sy - v, h) - rect_corner(-0.5 * sx - u, 0.5 * sy - v, h)
             - rect_corner(0.5 * sx - u, -0.5 * sy - v, h)
             + rect_corner(-0.5 * sx - u, -0.5 * sy - v, h))
    else:
        # Midpoint quadrature over the ellipse in polar coordinates.
        n_r, n_t = 64, 128
        r = (np.arange(n_r) + 0.5) / n_r
        t = 2.0 * math.pi * (np.arange(n_t) + 0.5) / n_t
        R, T = np.meshgrid(r, t)
        lx, ly = 0.5 * sx * R * np.cos(T), 0.5 * sy * R * np.sin(T)
        dA = (0.5 * sx) * (0.5 * sy) * R * (1.0 / n_r) * (2.0 * math.pi / n_t)
        du = lx.ravel()[None, :] - u.ravel()[:, None]
        dv = ly.ravel()[None, :] - v.ravel()[:, None]
        d2 = du * du + dv * dv + h * h
        f = (h * h / (d2 * d2) * dA.ravel()[None, :]).sum(axis=1).reshape(u.shape)
    return f[:, :, None] * radiance[None, None, :]


def irradiance_point(obj, x, y, intensity_of_cos=lambda c: 1.0):
    cx, cy, h = obj.location
    d2 = (x - cx) ** 2 + (y - cy) ** 2 + h * h
    cos = h / np.sqrt(d2)
    i0 = obj.data.energy * np.array(obj.data.color) / (4.0 * math.pi)
    return (intensity_of_cos(cos) * cos / d2)[:, :, None] * i0[None, None, :]


def compare(name, image, expected, block_tolerance=0.04):
    radiance = ALBEDO * expected / math.pi
    common.means_agree(image, radiance, 0.01, f"{name}: image mean vs analytic")
    b = 8
    blocks = lambda a: a.reshape(SIZE // b, b, SIZE // b, b, 3).mean(axis=(1, 3))  # noqa: E731
    ours, want = blocks(image), blocks(radiance)
    lit = want > 0.05 * want.max()
    worst = float(np.max(np.abs(ours[lit] / want[lit] - 1.0)))
    common.check(worst <= block_tolerance,
                 f"{name}: worst 8x8 block of the lit area {worst:.4f} from analytic "
                 f"(<= {block_tolerance})")


def render(scene, name, passes=4):
    common.use_engine(scene, passes=passes, spp=4, photons=20_000, caustic_photons=0)
    image, _ = common.render(scene, f"light-{name}")
    return image


def test_point():
    scene = setup()
    obj = new_light("POINT", (0.2, -0.1, 1.5), 100.0, shadow_soft_size=0.0)
    x, y = plane_points()
    expected = irradiance_point(obj, x, y)
    compare("point", render(scene, "point"), expected)
    common.use_cycles(scene, 16)
    cycles, _ = common.render(scene, "light-point-cycles")
    common.means_agree(cycles, ALBEDO * expected / math.pi, 0.01, "point: Cycles vs analytic")


def test_point_radius():
    scene = setup()
    obj = new_light("POINT", (0.2, -0.1, 1.5), 100.0, shadow_soft_size=0.1)
    x, y = plane_points()
    # A sphere of uniform radiance above the plane: the point's irradiance exactly.
    compare("point, radius 0.1 (a sphere)", render(scene, "point-radius", passes=8),
            irradiance_point(obj, x, y))


def test_spot():
    scene = setup()
    obj = new_light("SPOT", (0.1, 0.0, 1.5), 100.0, shadow_soft_size=0.0,
                    spot_size=math.radians(60.0), spot_blend=0.4)
    cos_outer = math.cos(math.radians(30.0))
    cos_inner = cos_outer + (1.0 - cos_outer) * 0.4

    def ramp(c):
        return np.clip((c - cos_outer) / (cos_inner - cos_outer), 0.0, 1.0) ** 2

    x, y = plane_points()
    compare("spot", render(scene, "spot"), irradiance_point(obj, x, y, ramp))


def test_sun():
    scene = setup()
    new_light("SUN", (0.0, 0.0, 3.0), 3.0, rotation=(math.radians(30.0), 0.0, 0.0),
              angle=0.0)
    x, _ = plane_points()
    e = 3.0 * math.cos(math.radians(30.0)) * np.array(COLOUR)
    compare("sun", render(scene, "sun"), np.broadcast_to(e, x.shape + (3,)).copy())


def area_case(shape, sx, sy, rotation, cycles=False):
    scene = setup()
    props = dict(shape=shape, size=sx)
    if shape in ("RECTANGLE", "ELLIPSE"):
        props["size_y"] = sy
    obj = new_light("AREA", (0.1, -0.05, 1.5), 60.0, rotation=(0.0, 0.0, rotation), **props)
    x, y = plane_points()
    expected = irradiance_area(obj, x, y, shape, sx, sy)
    compare(f"area {shape.lower()}", render(scene, f"area-{shape.lower()}", passes=8), expected)
    if cycles:
        common.use_cycles(scene, 64)
        image, _ = common.render(scene, f"light-area-{shape.lower()}-cycles")
        common.means_agree(image, ALBEDO * expected / math.pi, 0.01,
                           f"area {shape.lower()}: Cycles vs analytic")


def test_area_square():
    area_case("SQUARE", 0.5, 0.5, 0.0, cycles=True)


def test_area_rectangle():
    area_case("RECTANGLE", 0.6, 0.3, math.radians(30.0))


def test_area_disk():
    area_case("DISK", 0.5, 0.5, 0.0)


def test_area_ellipse():
    area_case("ELLIPSE", 0.6, 0.3, math.radians(30.0))


if __name__ == "__main__":
    common.run([test_point, test_point_radius, test_spot, test_sun, test_area_square,
                test_area_rectangle, test_area_disk, test_area_ellipse])

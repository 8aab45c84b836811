"""gpu_photon.SceneBuilder (a scene from arrays and dicts, what the Blender add-on uses) and
Scene.aovs: the same pixels as the TOML scene it mirrors, textures, transforms as NumPy and
Blender write them, errors naming the key, and the feature images."""

from pathlib import Path

import numpy as np
import pytest

import gpu_photon as g

ROOT = Path(__file__).resolve().parents[2]
QUAD = np.array([[0, 1, 2], [0, 2, 3]], np.uint32)


def room(builder, world_lamp=False, floor_texture=None):
    """A floor, back wall and lamp quad, the room of tests/scene_build.rs."""
    floor_spec = {"kind": "diffuse", "colour": (0.7, 0.7, 0.7)}
    if floor_texture is not None:
        floor_spec["colour_texture"] = floor_texture
    white = builder.add_material("white", floor_spec)
    red = builder.add_material("red", {"kind": "diffuse", "colour": (0.6, 0.1, 0.05)})
    lamp = builder.add_material("lamp", {"kind": "black", "emission": (20, 20, 20)})
    floor = np.array([[-1, -1, 1], [1, -1, 1], [1, -1, -1], [-1, -1, -1]], np.float32)
    uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 0], [1, 1], [0, 1]], np.float32)
    builder.add_mesh("floor", floor, QUAD, np.array([white], np.uint32), uvs=uvs)
    back = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1]], np.float32)
    builder.add_mesh("back", back, QUAD, np.array([red], np.uint32))
    # The lamp as a unit quad in its own space, placed by a transform (row-major 4x4).
    unit = np.array([[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]], np.float32)
    place = np.array([[0.3, 0, 0, 0], [0, 1, 0, 0.99], [0, 0, 0.3, 0], [0, 0, 0, 1]],
                     np.float32)
    if world_lamp:
        world = (np.c_[unit, np.ones(4)] @ place.T)[:, :3].astype(np.float32)
        builder.add_mesh("lamp", world, QUAD, np.array([lamp], np.uint32))
    else:
        builder.add_mesh("lamp", unit, QUAD, np.array([lamp], np.uint32), transform=place)
    builder.set_camera((0, 0, 3), (0, 0, -1), (0, 1, 0), 45.0, 24, 20)
    return builder.finish()


def render(scene):
    return scene.render(backend="cpu", spp=2, photons=3000, passes=2)


def test_a_transform_is_row_major_as_numpy_and_blender_write_it():
    image = render(room(g.SceneBuilder("room")))
    assert image.shape == (20, 24, 3) and image.mean() > 0.05
    # The lamp placed by its transform, or written out in world space: the same pixels.
    world = render(room(g.SceneBuilder("room"), world_lamp=True))
    assert np.array_equal(image, world)


def test_a_texture_multiplies_the_colour():
    b = g.SceneBuilder("tex")
    half = np.full((4, 4, 4), 0.5, np.float32)
    t = b.add_texture("half", half)
    textured = room(b, floor_texture=t)
    plain = room(g.SceneBuilder("plain"))
    a = textured.aovs(["albedo"], width=24, height=20)["albedo"]
    p = plain.aovs(["albedo"], width=24, height=20)["albedo"]
    # The floor (bottom row): albedo 0.5 (the texture replaces the colour) against 0.7.
    assert np.allclose(a[-1, 12], 0.5) and np.allclose(p[-1, 12], 0.7)


def test_material_dicts_are_checked_by_key():
    b = g.SceneBuilder("x")
    with pytest.raises(g.SceneError, match=r"materials\[m\]: color: unknown key"):
        b.add_material("m", {"kind": "diffuse", "color": (1, 0, 0)})
    with pytest.raises(g.SceneError, match=r"kind: unknown kind `plastic`"):
        b.add_material("m", {"kind": "plastic"})
    with pytest.raises(g.SceneError, match=r"x:0: materials\[m\]: roughness: must be in"):
        b.add_material("m", {"kind": "conductor", "roughness": 2.0})
    with pytest.raises(ValueError, match=r"positions: expected an array of shape \(N, 3\)"):
        b.add_mesh("m", np.zeros((3, 2), np.float32), QUAD, np.zeros(1, np.uint32))


def test_finish_takes_the_builder():
    b = g.SceneBuilder("y")
    room(b)
    with pytest.raises(g.Error, match="the builder has finished"):
        b.finish()


def test_aovs_are_arrays_by_name():
    scene = g.load(str(ROOT / "scenes" / "cornell-box.toml"))
    a = scene.aovs(width=32, height=24)
    assert sorted(a) == ["albedo", "normal"]
    assert a["albedo"].shape == (24, 32, 3) and a["albedo"].dtype == np.float32
    # The back wall (white, 0.73) faces the camera: camera-space normal (0, 0, -1).
    assert np.allclose(a["albedo"][10, 16], 0.73, atol=1e-6)
    assert np.allclose(a["normal"][10, 16], [0, 0, -1], atol=1e-5)
    with pytest.raises(g.SettingError, match="unknown AOV `depth`"):
        scene.aovs(["depth"])


def test_a_mesh_group_placed_thrice_renders_as_three_copies():
    # Three boxes' worth of the back wall: stored once as a group, or added three times.
    def scene(grouped):
        b = g.SceneBuilder("group")
        red = b.add_material("red", {"kind": "diffuse", "colour": (0.6, 0.1, 0.05)})
        lamp = b.add_material("lamp", {"kind": "black", "emission": (20, 20, 20)})
        assert b.material_instanceable(red) and not b.material_instanceable(lamp)
        unit = np.array([[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]], np.float32)
        place = np.array([[0.3, 0, 0, 0], [0, 1, 0, 0.99], [0, 0, 0.3, 0], [0, 0, 0, 1]],
                         np.float32)
        b.add_mesh("lamp", unit, QUAD, np.array([lamp], np.uint32), transform=place)
        tile = np.array([[-0.3, -0.3, 0], [0.3, -0.3, 0], [0.3, 0.3, 0], [-0.3, 0.3, 0]],
                        np.float32)
        places = [np.array([[1, 0, 0, x], [0, 1, 0, -0.2], [0, 0, 1, -1], [0, 0, 0, 1]],
                           np.float32) for x in (-0.7, 0.0, 0.7)]
        if grouped:
            group = b.add_mesh_group("tile", tile, QUAD, np.array([red], np.uint32))
            for i, p in enumerate(places):
                b.add_instance(f"tile{i}", group, p)
        else:
            for i, p in enumerate(places):
                b.add_mesh(f"tile{i}", tile, QUAD, np.array([red], np.uint32), transform=p)
        b.set_camera((0, 0, 3), (0, 0, -1), (0, 1, 0), 45.0, 24, 20)
        return b.finish()

    grouped, copies = render(scene(True)), render(scene(False))
    assert grouped.mean() > 0.01
    # The same hits on the same rays, so the same image but for float rounding.
    assert np.abs(grouped - copies).max() <= 1e-3 * max(copies.max(), 1.0)


def test_a_mesh_group_refuses_an_emitter_and_an_unknown_group():
    b = g.SceneBuilder("group")
    lamp = b.add_material("lamp", {"kind": "black", "emission": (1, 1, 1)})
    tile = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], np.float32)
    with pytest.raises(g.Error, match=r"group:0: meshes\[tile\]: material 0 emits or is alpha-tested"):
        b.add_mesh_group("tile", tile, QUAD, np.array([lamp], np.uint32))
    with pytest.raises(g.Error, match=r"group:0: instances\[a\]: no mesh group 3 \(the build has 0\)"):
        b.add_instance("a", 3, np.eye(4, dtype=np.float32))

"""The translation of a depsgraph, checked on what it produces: modifiers applied, instances
placed (and the triangle budget), an image texture read the right way up through the UVs, a
normal map through Blender's tangents, the world's colour, a Principled BSDF's parameters (the
albedo and normal passes show what the renderer got)."""

import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import common  # noqa: E402
import scenes  # noqa: E402


def build(max_triangles=10**6):
    mod = common.enable()
    report = mod.translate.Report()
    depsgraph = bpy.context.evaluated_depsgraph_get()
    scene, triangles = mod.translate.build(depsgraph, report, max_triangles)
    return scene, triangles, report


def lit_scene(size=32):
    scene = scenes.empty_scene(size, size)
    light = bpy.data.lights.new("Sun", "SUN")
    light.energy = 1.0
    obj = bpy.data.objects.new("Sun", light)
    scene.collection.objects.link(obj)
    return scene


def uv_plane(mat):
    """The plane [-1, 1]^2 at z = 0, uv (0, 0) at (-1, -1) and (1, 1) at (1, 1), of ``mat``.
    Its uvs are set before the object enters the scene (and the depsgraph)."""
    mesh = bpy.data.meshes.new("Plane")
    mesh.from_pydata([(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], [], [(0, 1, 2, 3)])
    uv = mesh.uv_layers.new(name="UVMap")
    for loop, (u, v) in zip(uv.data, [(0, 0), (1, 0), (1, 1), (0, 1)]):
        loop.uv = (u, v)
    mesh.materials.append(mat)
    bpy.context.scene.collection.objects.link(bpy.data.objects.new("Plane", mesh))


def test_modifiers_are_applied_and_instances_placed():
    lit_scene()
    white = scenes.material("White", "diffuse", colour=(0.8, 0.8, 0.8))
    plane = scenes.quad("Plane", [(-1, -1, 0), (1, -1, 0), (1, 1, 0), (-1, 1, 0)], white)
    sub = plane.modifiers.new("Subdivision", "SUBSURF")
    sub.levels = sub.render_levels = 2
    sub.subdivision_type = "SIMPLE"
    scenes.camera((0, 0, 3), (0, 0, 0))
    _, triangles, _ = build()
    common.check(triangles == 32, f"a quad subdivided twice is 32 triangles ({triangles})")
    # The plane in a collection, instanced twice more by empties.
    coll = bpy.data.collections.new("Tile")
    bpy.context.scene.collection.children.link(coll)
    bpy.context.scene.collection.objects.unlink(plane)
    coll.objects.link(plane)
    for i in range(2):
        empty = bpy.data.objects.new(f"Instance{i}", None)
        empty.instance_type = "COLLECTION"
        empty.instance_collection = coll
        empty.location = (0, 0, -1 - i)
        bpy.context.scene.collection.objects.link(empty)
    _, triangles, _ = build()
    # Placed three times, stored once: a mesh group and three instances.
    common.check(triangles == 32, f"the plane and two instances store 32 triangles ({triangles})")
    try:
        build(max_triangles=16)
        common.check(False, "a budget of 16 triangles is refused")
    except RuntimeError as e:
        common.check("more than the budget of 16" in str(e), f"the budget is named: {e}")
    # An emissive mesh cannot be a group (Mitsuba's rule): its three placements are copies.
    lamp = scenes.material("Lamp", "emission", strength=2.0)
    plane.data.materials[0] = lamp
    _, triangles, _ = build()
    common.check(triangles == 3 * 32,
                 f"an emissive plane and two instances: three copies, 96 triangles ({triangles})")


def test_image_texture_reads_through_the_uvs_the_right_way_up():
    lit_scene(32)
    # A 2x2 image: bottom-left red, bottom-right green, top-left blue, top-right white
    # (Blender's rows go from the bottom up).
    image = bpy.data.images.new("Quads", 2, 2, alpha=True, float_buffer=True)
    image.pixels = [1, 0, 0, 1, 0, 1, 0, 1, 0, 0, 1, 1, 1, 1, 1, 1]
    mat = scenes.material("Textured", "diffuse", colour=(1, 1, 1))
    tex = mat.node_tree.nodes.new("ShaderNodeTexImage")
    tex.image, tex.interpolation = image, "Closest"
    mat.node_tree.links.new(tex.outputs["Color"], mat.node_tree.nodes["Diffuse BSDF"].inputs["Color"])
    uv_plane(mat)
    scenes.camera((0, 0, 2.2), (0, 0, 0), lens=35.0)  # looking down, +Y up in the image
    scene, _, _ = build()
    albedo = scene.aovs(["albedo"], width=32, height=32)["albedo"]
    want = {"bottom-left": ((24, 8), [1, 0, 0]), "bottom-right": ((24, 24), [0, 1, 0]),
            "top-left": ((8, 8), [0, 0, 1]), "top-right": ((8, 24), [1, 1, 1])}
    for name, ((y, x), c) in want.items():
        common.check(bool(np.allclose(albedo[y, x], c, atol=1e-4)),
                     f"{name} of the image at the plane's {name}: {albedo[y, x]} is {c}")


def test_normal_map_tilts_the_shading_normal():
    lit_scene(16)
    # A constant tangent-space normal (0.6, 0, 0.8): tilted towards the tangent, +u.
    image = bpy.data.images.new("Normal", 4, 4, alpha=True, float_buffer=True)
    image.colorspace_settings.name = "Non-Color"
    image.pixels = [0.8, 0.5, 0.9, 1.0] * 16
    mat = scenes.material("Bumpy", "principled", **{"Base Color": (0.5, 0.5, 0.5, 1.0)})
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    tex = nodes.new("ShaderNodeTexImage")
    tex.image = image
    nmap = nodes.new("ShaderNodeNormalMap")
    links.new(tex.outputs["Color"], nmap.inputs["Color"])
    links.new(nmap.outputs["Normal"], nodes["Principled BSDF"].inputs["Normal"])
    uv_plane(mat)
    scenes.camera((0, 0, 2), (0, 0, 0))
    built, _, report = build()
    normal = built.aovs(["normal"], width=16, height=16)["normal"][8, 8]
    # World (0.6, 0, 0.8); in camera space (right +X, up +Y, looking down -Z): (0.6, 0, -0.8).
    common.check(bool(np.allclose(normal, [0.6, 0.0, -0.8], atol=0.01)),
                 f"the shading normal {normal} is the normal map's, through Blender's tangents")
    common.check(report.seen == [], f"nothing to warn about ({report.seen})")


def test_orthographic_camera_sees_ortho_scale_across():
    scene = lit_scene(32)
    white = scenes.material("White", "diffuse", colour=(0.5, 0.5, 0.5))
    scenes.quad("Plane", [(-0.5, -0.5, 0), (0.5, -0.5, 0), (0.5, 0.5, 0), (-0.5, 0.5, 0)], white)
    cam = scenes.camera((0, 0, 7), (0, 0, 0))
    cam.data.type, cam.data.ortho_scale = "ORTHO", 2.0
    scene.render.resolution_x = 64  # 64 x 32: the sensor fits the width, 2 units across
    built, _, report = build()
    albedo = built.aovs(["albedo"], width=64, height=32)["albedo"][:, :, 0]
    covered = float((albedo > 0.25).mean())
    # The unit plane: 32 of 64 columns, all 32 rows: half the image.
    common.check(abs(covered - 0.5) < 1.0 / 32, f"the plane covers {covered} of the image")
    common.check(report.seen == [], f"nothing to warn about ({report.seen})")


def test_environment_texture_is_oriented_as_cycles_reads_it():
    scene = scenes.empty_scene(24, 24)
    # A 64x32 equirectangular image of 8x4 blocks of distinct colours: the renderers filter
    # texels differently (gpu-photon's lat-long is always bilinear), so pixels near a block's
    # edge may differ; elsewhere both see the block's colour.
    rng = np.random.default_rng(3)
    blocks = rng.uniform(0.1, 1.0, (4, 8, 3))
    rgb = np.repeat(np.repeat(blocks, 8, axis=0), 8, axis=1)
    texels = np.concatenate([rgb, np.ones((32, 64, 1))], axis=2)
    image = bpy.data.images.new("Sky", 64, 32, float_buffer=True)
    image.pixels = texels.astype(np.float32).ravel()
    nodes, links = scene.world.node_tree.nodes, scene.world.node_tree.links
    env = nodes.new("ShaderNodeTexEnvironment")
    env.image = image
    links.new(env.outputs["Color"], nodes["Background"].inputs["Color"])
    nodes["Background"].inputs["Strength"].default_value = 1.0
    cam = scenes.camera((0, 0, 0), (1, 0.3, 0.2), lens=18.0)
    mod = common.enable()
    for look in [(1, 0.3, 0.2), (-0.4, 1, -0.3), (0.2, -1, 0.6), (-1, -0.2, 0.1)]:
        cam.rotation_euler = __import__("mathutils").Vector(look).to_track_quat("-Z", "Y").to_euler()
        bpy.context.view_layer.update()
        built, _, _ = build()
        ours = built.aovs(["albedo"], samples=1, width=24, height=24)["albedo"]
        common.use_cycles(scene, 1)
        scene.cycles.pixel_filter_type = "BOX"
        cycles, _ = common.render(scene, "environment")
        # Texel colours seen: the same texel at most pixels (edges may round either way).
        same = np.all(np.abs(ours - cycles) < 1e-3, axis=2).mean()
        common.check(same > 0.6, f"looking along {look}: {same:.3f} of the pixels see the "
                     "colour Cycles sees")
    _ = mod


def test_world_colour_and_principled_parameters():
    scene = lit_scene(16)
    bg = scene.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value = (0.2, 0.3, 0.4, 1.0)
    bg.inputs["Strength"].default_value = 2.0
    gold = scenes.material("Gold", "principled", **{"Base Color": (0.9, 0.6, 0.2, 1.0),
                                                    "Metallic": 1.0, "Roughness": 0.3})
    scenes.quad("Plane", [(-0.3, -0.3, 0), (0.3, -0.3, 0), (0.3, 0.3, 0), (-0.3, 0.3, 0)], gold)
    scenes.camera((0, 0, 2), (0, 0, 0))
    built, _, report = build()
    albedo = built.aovs(["albedo"], samples=64, width=16, height=16)["albedo"]
    common.check(bool(np.allclose(albedo[0, 0], [0.4, 0.6, 0.8], atol=1e-5)),
                 f"the world is its colour x strength: {albedo[0, 0]}")
    # A rough gold metal: its albedo (the lobe's directional albedo) is about its base colour.
    centre = albedo[7:9, 7:9].reshape(-1, 3).mean(axis=0)
    ratio = centre / np.array([0.9, 0.6, 0.2])
    common.check(bool(np.all(np.abs(ratio - 1.0) < 0.15)),
                 f"the gold plane's albedo {centre} is about its base colour")
    common.check(report.seen == [], f"nothing to warn about ({report.seen})")


if __name__ == "__main__":
    common.run([test_modifiers_are_applied_and_instances_placed,
                test_image_texture_reads_through_the_uvs_the_right_way_up,
                test_normal_map_tilts_the_shading_normal,
                test_orthographic_camera_sees_ortho_scale_across,
                test_environment_texture_is_oriented_as_cycles_reads_it,
                test_world_colour_and_principled_parameters])

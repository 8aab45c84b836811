//! Scenes built in memory (`SceneBuild`, Python's `gpu_photon.SceneBuilder`): the same pixels
//! as the same scene read from a TOML file, transforms (mirrors keep front faces), errors that
//! name the build and the item, and the first-hit AOVs (albedo, camera-space normal) from the
//! facade and from `gpu-photon render --aov`.

mod common;

use gpu_photon::{Aov, Backend, CameraSpec, Image, MaterialSpec, MeshSpec, Scattering, Scene};

/// A box room (floor, back wall, ceiling) of white and red with a square light, as TOML.
const TOML: &str = r#"
[camera]
eye = [0.0, 0.0, 3.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 1.0, 0.0]
fov = 45.0
width = 24
height = 20

[materials.white]
type = "diffuse"
albedo = [0.7, 0.7, 0.7]

[materials.red]
type = "diffuse"
albedo = [0.6, 0.1, 0.05]

[[shapes]]
type = "quad"
corners = [[-1.0, -1.0, 1.0], [1.0, -1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, -1.0, -1.0]]
material = "white"

[[shapes]]
type = "quad"
corners = [[-1.0, -1.0, -1.0], [1.0, -1.0, -1.0], [1.0, 1.0, -1.0], [-1.0, 1.0, -1.0]]
material = "red"

[[shapes]]
type = "quad"
corners = [[-1.0, 1.0, -1.0], [1.0, 1.0, -1.0], [1.0, 1.0, 1.0], [-1.0, 1.0, 1.0]]
material = "white"

[[shapes]]
type = "quad"
corners = [[-0.3, 0.99, -0.3], [0.3, 0.99, -0.3], [0.3, 0.99, 0.3], [-0.3, 0.99, 0.3]]
emission = [20.0, 20.0, 20.0]
"#;

const QUADS: [([[f32; 3]; 4], u32); 4] = [
    (
        [
            [-1., -1., 1.],
            [1., -1., 1.],
            [1., -1., -1.],
            [-1., -1., -1.],
        ],
        0,
    ),
    (
        [
            [-1., -1., -1.],
            [1., -1., -1.],
            [1., 1., -1.],
            [-1., 1., -1.],
        ],
        1,
    ),
    (
        [[-1., 1., -1.], [1., 1., -1.], [1., 1., 1.], [-1., 1., 1.]],
        0,
    ),
    (
        [
            [-0.3, 0.99, -0.3],
            [0.3, 0.99, -0.3],
            [0.3, 0.99, 0.3],
            [-0.3, 0.99, 0.3],
        ],
        2,
    ),
];

fn camera() -> CameraSpec {
    CameraSpec {
        eye: [0.0, 0.0, 3.0],
        forward: [0.0, 0.0, -3.0],
        up: [0.0, 1.0, 0.0],
        fov_y: 45.0,
        aperture_radius: 0.0,
        focus_distance: 3.0,
        orthographic_height: None,
    }
}

/// The TOML's room, built; `transform` applied to every quad.
fn built(transform: Option<[[f32; 4]; 4]>) -> Scene {
    let mut b = gpu_photon::SceneBuild::new("room");
    let diffuse = |c| MaterialSpec::new(Scattering::Diffuse { colour: c });
    let white = b.add_material("white", &diffuse([0.7; 3])).unwrap();
    let red = b.add_material("red", &diffuse([0.6, 0.1, 0.05])).unwrap();
    let mut lamp = MaterialSpec::new(Scattering::Black);
    lamp.emission = [20.0; 3];
    let lamp = b.add_material("lamp", &lamp).unwrap();
    let ids = [white, red, lamp];
    for (i, (corners, m)) in QUADS.iter().enumerate() {
        let mesh = MeshSpec {
            positions: corners,
            triangles: &[[0, 1, 2], [0, 2, 3]],
            materials: &[ids[*m as usize]],
            normals: None,
            uvs: None,
            tangents: None,
            transform,
        };
        b.add_mesh(&format!("quad{i}"), &mesh).unwrap();
    }
    b.set_camera(&camera(), 24, 20).unwrap();
    b.finish().unwrap()
}

fn bits(i: &Image) -> Vec<u32> {
    i.rgb().iter().map(|v| v.to_bits()).collect()
}

fn settings(scene: &Scene) -> gpu_photon::RenderSettings {
    let mut s = scene.settings();
    for (name, v) in [("spp", 2u32), ("photons", 3000), ("passes", 2)] {
        s.set(name, v).unwrap();
    }
    s
}

#[test]
fn a_built_scene_renders_the_pixels_of_the_same_scene_from_a_file() {
    let path = common::scratch("room").join("room.toml");
    std::fs::write(&path, TOML).unwrap();
    let file = Scene::load(&path).unwrap();
    let ours = built(None);
    assert_eq!(ours.path(), std::path::Path::new("room"));
    let (a, _) = ours.render(&settings(&ours), Backend::Cpu).unwrap();
    let (b, _) = file.render(&settings(&file), Backend::Cpu).unwrap();
    assert_eq!((a.width, a.height), (24, 20));
    assert_eq!(bits(&a), bits(&b));
}

#[test]
fn a_mirroring_transform_keeps_the_front_faces() {
    // Mirrored in x: the same room, seen mirrored; the lamp still shines down (its power and
    // the floor's light are the same), and the image is the original flipped left to right.
    let flip = [
        [-1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
        [0.0, 0.0, 0.0, 1.0],
    ];
    let (plain, mirrored) = (built(None), built(Some(flip)));
    let lamp = |s: &Scene| {
        s.triangles
            .iter()
            .find(|t| t.light != u32::MAX)
            .unwrap()
            .normal()
    };
    assert!(lamp(&mirrored).y < -0.99, "{:?}", lamp(&mirrored));
    let mut s = settings(&plain);
    s.set("mode", "direct-only").unwrap();
    let (a, _) = plain.render(&s, Backend::Cpu).unwrap();
    let (b, _) = mirrored.render(&s, Backend::Cpu).unwrap();
    let (ma, mb) = (a.mean(), b.mean());
    for c in 0..3 {
        assert!((ma[c] / mb[c] - 1.0).abs() < 0.01, "{ma:?} vs {mb:?}");
    }
}

#[test]
fn errors_name_the_build_and_the_item() {
    let mut b = gpu_photon::SceneBuild::new("blender:Scene");
    let too_bright = MaterialSpec::new(Scattering::Diffuse {
        colour: [1.5, 0.0, 0.0],
    });
    let e = b.add_material("Red", &too_bright).unwrap_err().to_string();
    assert_eq!(e, "blender:Scene:0: materials[Red]: colour: components must be in [0, 1] (got [1.5, 0.0, 0.0])");
    let mut textured = MaterialSpec::new(Scattering::Mirror { colour: [1.0; 3] });
    textured.colour_texture = Some(0);
    let e = b.add_material("M", &textured).unwrap_err().to_string();
    assert_eq!(
        e,
        "blender:Scene:0: materials[M]: colour_texture: no texture 0 (the build has 0)"
    );
    let m = b
        .add_material(
            "White",
            &MaterialSpec::new(Scattering::Diffuse { colour: [0.5; 3] }),
        )
        .unwrap();
    let own = [m];
    let mut mesh = MeshSpec {
        positions: &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        triangles: &[[0, 1, 2]],
        materials: &own,
        normals: Some(&[[0.0, 0.0, 1.0]]),
        uvs: None,
        tangents: None,
        transform: None,
    };
    let e = b.add_mesh("Cube", &mesh).unwrap_err().to_string();
    assert_eq!(
        e,
        "blender:Scene:0: meshes[Cube]: 1 normals for 1 triangles (one per corner: 3)"
    );
    mesh.normals = None;
    mesh.triangles = &[[0, 1, 7]];
    let e = b.add_mesh("Cube", &mesh).unwrap_err().to_string();
    assert_eq!(
        e,
        "blender:Scene:0: meshes[Cube]: triangle 0: vertex 7 is out of range (3 vertices)"
    );
    mesh.triangles = &[[0, 1, 2]];
    mesh.materials = &[5];
    let e = b.add_mesh("Cube", &mesh).unwrap_err().to_string();
    assert_eq!(
        e,
        "blender:Scene:0: meshes[Cube]: no material 5 (the build has 1)"
    );
    mesh.materials = &own;
    mesh.positions = &[[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]];
    let e = b.add_mesh("Cube", &mesh).unwrap_err().to_string();
    assert_eq!(e, "blender:Scene:0: meshes[Cube]: vertices must be finite");
    let e = gpu_photon::SceneBuild::new("x")
        .finish()
        .unwrap_err()
        .to_string();
    assert_eq!(e, "x:0: camera: the scene has no camera");
    let mut dark = gpu_photon::SceneBuild::new("dark");
    dark.set_camera(&camera(), 8, 8).unwrap();
    let e = dark.finish().unwrap_err().to_string();
    assert_eq!(e, "dark: the scene has no light (add one, or give --env)");
}

#[test]
fn aovs_are_the_first_hit_albedo_and_camera_space_normal() {
    let scene = built(None);
    let s = settings(&scene);
    let images = scene.aovs(&s, &[Aov::Albedo, Aov::Normal], 4).unwrap();
    let (albedo, normal) = (&images[0], &images[1]);
    let at = |i: &Image, x: u32, y: u32| i.pixels[(y * i.width + x) as usize];
    // The red back wall at the centre faces the camera: normal (0, 0, -1) in camera space.
    assert_eq!(at(albedo, 12, 10), [0.6, 0.1, 0.05]);
    let n = at(normal, 12, 10);
    assert!(
        (n[2] + 1.0).abs() < 1e-5 && n[0].abs() < 1e-5 && n[1].abs() < 1e-5,
        "{n:?}"
    );
    // The floor (bottom row) points up: +y; the lamp (top centre) is its radiance, normal 0.
    let f = at(normal, 12, 19);
    assert!((f[1] - 1.0).abs() < 1e-5, "{f:?}");
    let lamp = (0..20)
        .flat_map(|y| (0..24).map(move |x| (x, y)))
        .find(|&(x, y)| at(albedo, x, y)[0] == 20.0);
    let (x, y) = lamp.expect("the lamp is seen with its radiance as albedo");
    assert_eq!(at(normal, x, y), [0.0; 3]);
    // Deterministic: the same images twice.
    let again = scene.aovs(&s, &[Aov::Albedo], 4).unwrap();
    assert_eq!(bits(&again[0]), bits(albedo));
}

#[test]
fn the_command_line_writes_aovs_as_exr_channels_beside_the_same_image() {
    let dir = common::scratch("room-aov");
    let path = dir.join("room.toml");
    std::fs::write(&path, TOML).unwrap();
    let (plain, with) = (dir.join("plain.exr"), dir.join("aov.exr"));
    for (out, aov) in [(&plain, None), (&with, Some("albedo,normal"))] {
        let mut cmd = common::bin();
        cmd.args([
            "render",
            path.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
        ]);
        cmd.args([
            "--backend",
            "cpu",
            "--spp",
            "2",
            "--photons",
            "3000",
            "--passes",
            "2",
            "-q",
        ]);
        if let Some(a) = aov {
            cmd.args(["--aov", a]);
        }
        let status = cmd.status().unwrap();
        assert!(status.success());
    }
    let (a, b) = (Image::read(&plain).unwrap(), Image::read(&with).unwrap());
    assert_eq!(bits(&a), bits(&b), "the RGB channels are the render's");
    let exr = exr::prelude::read_all_flat_layers_from_file(&with).unwrap();
    let names: Vec<String> = exr.layer_data[0]
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    assert_eq!(
        names,
        ["B", "G", "R", "albedo.B", "albedo.G", "albedo.R", "normal.B", "normal.G", "normal.R"]
    );
    let tags = |p: &std::path::Path| gpu_photon::render::film::read_tags(p).unwrap();
    assert_eq!(tags(&with), tags(&plain), "the render's tags are kept");
    let out = common::bin()
        .args([
            "render",
            path.to_str().unwrap(),
            "-o",
            "x.png",
            "--aov",
            "albedo",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    assert_eq!(
        String::from_utf8_lossy(&out.stderr).trim(),
        "error: --aov writes layers of an .exr image: x.png is not one"
    );
}

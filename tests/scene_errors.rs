//! Scene loading: the reference scenes, every scene in `scenes/`, and the errors (file, line,
//! field) that malformed scene files produce.

use glam::Vec3;
use gpu_photon::bsdfs::KINDS;
use gpu_photon::camera::Camera;
use gpu_photon::importers::{load, load_str};
use gpu_photon::scene::NO_LIGHT;
use gpu_photon::scene::{LightShape, Material, Scene, Triangle};
use gpu_photon::scene::{Origin, Part, SceneBuilder, Surface};
use gpu_photon::settings::{validate, FresnelMode, Mode, Range, RenderSettings, Slot, SETTINGS};
use gpu_photon::Error;
use std::f32::consts::PI;
use std::path::{Path, PathBuf};

fn scenes_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes")
}

fn scene(name: &str) -> Scene {
    load(&scenes_dir().join(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// Four lines: a valid camera.
const CAMERA: &str = "[camera]\neye = [0, 0, 3]\ntarget = [0, 0, 0]\nfov = 40\n";

/// Loads `CAMERA` + `body` as `test.toml` in `dir`.
fn parse_in(body: &str, dir: &Path) -> Result<Scene, Error> {
    load_str(&format!("{CAMERA}{body}"), "test.toml", dir)
}

fn parse(body: &str) -> Result<Scene, Error> {
    parse_in(body, &scenes_dir())
}

/// The (line, field, message) of a scene error, after checking its `file:line:` Display form.
fn scene_error(result: Result<Scene, Error>) -> Result<(usize, String, String), String> {
    match result {
        Err(e @ Error::Scene { .. }) => {
            let shown = e.to_string();
            let Error::Scene {
                file,
                line,
                field,
                message,
            } = e
            else {
                unreachable!()
            };
            if file != "test.toml" || !shown.starts_with(&format!("test.toml:{line}: {field}: ")) {
                return Err(format!("badly shown: {shown}"));
            }
            Ok((line, field, message))
        }
        Err(e) => Err(format!("not a scene error: {e}")),
        Ok(_) => Err("the scene loaded".into()),
    }
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol * b.abs().max_element().max(1.0)
}

/// Bad scenes, separated by `---` lines. Each is loaded after `CAMERA` (so its first line is
/// line 5) unless it contains `[camera]` or `# bare`. The line marked `#! FIELD | TEXT` is where
/// the error must be: on FIELD, with TEXT in the message.
const BAD: &str = r#"
[materials.w]
type = "diffuse"
albedo = [1, 1, 1]
[[shapes]]  #! shapes[0].radius | missing field `radius`
type = "sphere"
center = [0, 0, 0]
material = "w"
---
[camera]  #! camera.target | missing field `target`
eye = [0, 0, 3]
fov = 40
---
[materials.w]  #! materials.w.exponent | missing field `exponent`
type = "glossy"
kd = [0.5, 0.5, 0.5]
ks = [0.1, 0.1, 0.1]
---
[[shapes]]  #! shapes[0].type | missing field `type`
center = [0, 0, 0]
---
[[shapes]]  #! shapes[0].material | missing field `material`
type = "sphere"
center = [0, 0, 0]
radius = 1
---
# bare  #! camera | missing table [camera]
[render]
k = 5
---
[materials.plastic]
type = "plastic"  #! materials.plastic.type | unknown type "plastic" (valid: "diffuse", "glossy", "mirror", "glass", "null", "emissive")
---
[materials.white]
type = "diffuse"
albedo = [1, 1, 1]
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "whyte"  #! shapes[0].material | unknown material `whyte` (defined: `white`)
---
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = nan  #! shapes[0].radius | must be finite
emission = [1, 1, 1]
---
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = inf  #! shapes[0].radius | must be finite
emission = [1, 1, 1]
---
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1e300  #! shapes[0].radius | must be finite
emission = [1, 1, 1]
---
[[lights]]
type = "point"
position = [0, -inf, 0]  #! lights[0].position | must be finite
intensity = [1, 1, 1]
---
[render]
exposure = nan  #! render.exposure | must be finite
---
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = -nan  #! camera.fov | must be finite
---
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = -0.5  #! shapes[0].radius | must be positive
emission = [1, 1, 1]
---
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 0  #! shapes[0].radius | must be positive
emission = [1, 1, 1]
---
[render]
caustic_radius = -1  #! render.caustic_radius | must be positive
---
[[shapes]]
type = "quad"
corners = [[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]]  #! shapes[0].corners | zero-area light
emission = [1, 1, 1]
---
[materials.lamp]
type = "emissive"
radiance = [1, 1, 1]
[[shapes]]
type = "triangle"
vertices = [[0, 0, 0], [0, 0, 0], [0, 0, 0]]  #! shapes[0].vertices | zero-area light
material = "lamp"
---
[materials.w]
type = "diffuse"
albedo = [1, 1, 1]
[[shapes]]
type = "mesh"
material = "w"
file = "meshes/nothing-here.obj"  #! shapes[0].file | cannot read mesh
---
[materials.g]
type = "glossy"
kd = [0.5, 0.5, 0.5]
ks = [0.2, 0.6, 0.2]  #! materials.g.ks | kd + ks must be at most 1
exponent = 10
---
[materials.g]
type = "glossy"
kd = [0.5, 0.5, 0.5]
ks = [0.2, 0.2, 0.2]
exponent = -1  #! materials.g.exponent | must be >= 0
---
[materials.d]
type = "diffuse"
albedo = [0.5, 1.5, 0.5]  #! materials.d.albedo | must be in [0, 1]
---
[materials.d]
type = "diffuse"
albedo = [0.5, 0.5]  #! materials.d.albedo | must be three numbers
---
[materials.e]
type = "emissive"
radiance = [1, -1, 1]  #! materials.e.radiance | must be >= 0
---
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 40
width = 100000  #! camera.width | must be an integer in 1..=16384
---
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 40
height = 0  #! camera.height | 1..=16384
---
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 40
filter = "mitchell"  #! camera.filter | must be one of "box", "tent", "gaussian"
---
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 40
filter = "gaussian"
filter_radius = 2  #! camera.filter_radius | only with filter = "tent"
---
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 40
filter = "gaussian"
filter_stddev = 0  #! camera.filter_stddev | must be positive
---
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 40
aperture_radius = -0.1  #! camera.aperture_radius | must be 0 (a pinhole) or positive
---
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 40
aperture_radius = 0.1
focus_distance = -2  #! camera.focus_distance | must be positive
---
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 40
height = 256.0  #! camera.height | must be an integer
---
[render]
k = 0  #! render.k | must be an integer in 1..=1024
---
[render]
k = 5000  #! render.k | 1..=1024
---
[render]
photons = 0  #! render.photons | 1..=268435456
---
[render]
spp = 5000000000  #! render.spp | must be an integer in 1..=65536
---
[render]
shadow_samples = 1025  #! render.shadow_samples | must be an integer in 1..=1024
---
[render]
radius = 0  #! render.radius | must be positive and finite
---
[render]
max_depth = 65  #! render.max_depth | 1..=64
---
[render]
max_photon_bounces = 0  #! render.max_photon_bounces | 1..=64
---
[render]
mode = "fast"  #! render.mode | must be one of "photon", "direct", "gather", "direct-only", "global-only", "caustic-only"
---
[render]
filter = "gauss"  #! render.filter | "epanechnikov"
---
[render]
fresnel = "none"  #! render.fresnel | must be one of "exact", "schlick"
---
[camera]
eye = [0, 0, 3]  #! camera.eye | degenerate camera frame
target = [0, 0, 3]
fov = 40
---
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
up = [0, 0, 1]  #! camera.up | degenerate camera frame
fov = 40
---
[camera]  #! camera.up | degenerate camera frame
eye = [0, 3, 0]
target = [0, 0, 0]
fov = 40
---
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 180  #! camera.fov | must be in (0, 180)
---
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = "wide"  #! camera.fov | must be a number
---
[render]
k = 5
radius = [1  #! toml | unclosed array
---
[render  #! toml |
---
fov = 50  #! camera.fov | duplicate key
---
[[shapes]]
type = "sphere"
center = [0, 0, 0]
raduis = 1  #! shapes[0].raduis | unknown field `raduis`, expected one of `type`, `center`, `radius`, `material`, `emission`, `two_sided`
material = "w"
---
[render]
samples = 4  #! render.samples | unknown field `samples`
---
[rendr]  #! rendr | unknown field `rendr`
k = 4
---
[materials.w]
type = "diffuse"
albedo = [1, 1, 1]
ior = 1.5  #! materials.w.ior | `ior` does not apply to type "diffuse" (its keys: `type`, `albedo`)
---
[[shapes]]
type = "sphere"
corners = [[0, 0, 0]]  #! shapes[0].corners | does not apply to type "sphere"
---
[[shapes]]
type = "quad"
emission = [1, 1, 1]
corners = [  #! shapes[0].corners | every point must be three numbers
  [0, 0, 0],
  [1, "x", 0],
  [1, 1, 0],
  [0, 1, 0],
]
---
[[shapes]]
type = "quad"
corners = [[0, 0, 0], [1, 0, 0]]  #! shapes[0].corners | must be an array of 4 points
emission = [1, 1, 1]
---
[[lights]]
type = "area"  #! lights[0].type | valid: "point", "spot", "directional"
---
[[lights]]
type = "spot"
position = [0, 1, 0]
direction = [nan, -1, 0]  #! lights[0].direction | must be finite
outer_angle = 30
intensity = [1, 1, 1]
---
[[lights]]
type = "spot"
position = [0, 1, 0]
direction = [0, 0, 0]  #! lights[0].direction | must not be zero
outer_angle = 30
intensity = [1, 1, 1]
---
[[lights]]
type = "spot"
position = [0, 1, 0]
target = [0, 1, 0]  #! lights[0].target | must not be zero (`target` equals `position`)
outer_angle = 30
intensity = [1, 1, 1]
---
[[lights]]
type = "spot"
position = [0, 1, 0]
direction = [0, -1, 0]
target = [0, 0, 0]  #! lights[0].target | give `direction` or `target`, not both
outer_angle = 30
intensity = [1, 1, 1]
---
[[lights]]  #! lights[0].direction | missing field `direction` (or `target`)
type = "spot"
position = [0, 1, 0]
outer_angle = 30
intensity = [1, 1, 1]
---
[[lights]]
type = "spot"
position = [0, 1, 0]
direction = [0, -1, 0]
outer_angle = 0  #! lights[0].outer_angle | must be in (0, 90] degrees (got 0)
intensity = [1, 1, 1]
---
[[lights]]
type = "spot"
position = [0, 1, 0]
direction = [0, -1, 0]
outer_angle = 90.5  #! lights[0].outer_angle | must be in (0, 90] degrees (got 90.5)
intensity = [1, 1, 1]
---
[[lights]]  #! lights[0].outer_angle | missing field `outer_angle`
type = "spot"
position = [0, 1, 0]
direction = [0, -1, 0]
intensity = [1, 1, 1]
---
[[lights]]
type = "spot"
position = [0, 1, 0]
direction = [0, -1, 0]
inner_angle = 31  #! lights[0].inner_angle | must be in [0, outer angle 30] degrees (got 31)
outer_angle = 30
intensity = [1, 1, 1]
---
[[lights]]
type = "spot"
position = [0, 1, 0]
direction = [0, -1, 0]
outer_angle = 30
intensity = [1, -1, 1]  #! lights[0].intensity | components must be >= 0
---
[[lights]]
type = "directional"
direction = [0, -1, 0]
irradiance = [1, 1, -2]  #! lights[0].irradiance | components must be >= 0
---
[[lights]]
type = "directional"
direction = [0, 0, 0]  #! lights[0].direction | must not be zero
irradiance = [1, 1, 1]
---
[[lights]]
type = "directional"
direction = [0, -1, 0]
position = [0, 1, 0]  #! lights[0].position | does not apply to type "directional"
irradiance = [1, 1, 1]
---
[[lights]]  #! lights[0].irradiance | missing field `irradiance`
type = "directional"
direction = [0, -1, 0]
---
[materials.w]
type = "diffuse"
albedo = [1, 1, 1]
[[shapes]]
type = "sphere"
center = [0, 0, 0]
radius = 1
material = "w"
two_sided = true  #! shapes[0].two_sided | only applies to emissive shapes
---
[[shapes]]
type = "box"
min = [0, 0, 0]
max = [1, 0, 1]  #! shapes[0].max | must be greater than `min`
emission = [1, 1, 1]
---
[[shapes]]
type = "mesh"
file = "meshes/light.obj"
scale = "big"  #! shapes[0].scale | must be a number or [x, y, z]
emission = [1, 1, 1]
---
[[shapes]]
type = "mesh"
file = "meshes/light.obj"
scale = 1e39  #! shapes[0].scale | must be finite
emission = [1, 1, 1]
---
[[shapes]]
type = "mesh"
file = "meshes/light.obj"  #! shapes[0].file | light power is not finite
scale = 1e30
emission = [1, 1, 1]
---
shapes = [
  { type = "sphere", center = [0, 0, 0], radius = 1, emission = [1, 1, 1] },
  { type = "sphere", center = [0, 0, 0], radius = -1, emission = [1, 1, 1] },  #! shapes[1].radius | must be positive
]
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 40
---
[environment]
radiance = [1, 1, 1]
rotate_y = 10
scale = 2  #! environment.scale | only with `filename`
---
[environment]
filename = "no-such-sky.exr"  #! environment.filename | no-such-sky.exr
---
[environment]  #! environment.radiance | missing field `radiance` (or `filename`)
rotate_y = 10
---
[environment]
radiance = [1, 1, 1]
sun = 2  #! environment.sun | unknown field `sun`
---
shapes = 3  #! shapes | invalid type
[camera]
eye = [0, 0, 3]
target = [0, 0, 0]
fov = 40
"#;

#[test]
fn bad_scenes_name_line_and_field() {
    let mut failures = Vec::new();
    for case in BAD.split("\n---\n") {
        let own = case.contains("[camera]") || case.contains("# bare");
        let text = if own {
            case.trim_start().to_string()
        } else {
            format!("{CAMERA}{}", case.trim_start())
        };
        let (line, marker) = text
            .lines()
            .enumerate()
            .find_map(|(i, l)| Some((i + 1, l.split_once("#!")?.1)))
            .unwrap();
        let (field, needle) = marker.split_once('|').unwrap();
        let (field, needle) = (field.trim(), needle.trim());
        match scene_error(load_str(&text, "test.toml", &scenes_dir())) {
            Ok((l, f, m)) if (l, f.as_str()) == (line, field) && m.contains(needle) => {}
            Ok((l, f, m)) => failures.push(format!(
                "got {l}: {f}: {m}\n  want {line}: {field}: ..{needle}.."
            )),
            Err(e) => failures.push(format!("{e}\n  want {line}: {field}: ..{needle}..")),
        }
    }
    assert!(failures.is_empty(), "\n{}", failures.join("\n"));
}

#[test]
fn cornell_reference_scene() {
    let s = scene("cornell-box.toml");
    // 15 quads (5 walls, 2 boxes of 5 faces) and the light quad.
    assert_eq!(
        (s.triangles.len(), s.spheres.len(), s.lights.len()),
        (32, 0, 1)
    );
    assert_eq!(
        s.lights[0].shape,
        LightShape::Triangles(gpu_photon::lights::triangles::Triangles {
            first: 30,
            count: 2
        })
    );
    let l = Vec3::new(17.0, 12.0, 4.0);
    assert!(
        close(s.lights[0].power, PI * 0.25 * l, 1e-5),
        "{}",
        s.lights[0].power
    );
    for (i, t) in s.triangles.iter().enumerate() {
        assert_eq!(t.light, if i >= 30 { 0 } else { NO_LIGHT });
    }
    for i in 30..32 {
        assert_eq!(*s.material_of_triangle(i), Material::emitter(l));
        assert!(
            close(s.triangles[i].normal(), -Vec3::Y, 1e-6),
            "the light faces down"
        );
    }
    assert!(
        close(s.triangles[0].normal(), Vec3::Y, 1e-6),
        "the floor faces up"
    );
    let (red, green) = (Vec3::new(0.63, 0.065, 0.05), Vec3::new(0.14, 0.45, 0.091));
    let expected = [Vec3::splat(0.73), red, green].map(Material::diffuse);
    assert_eq!(s.materials[..3], expected);
    assert_eq!(
        (s.triangles[6].material, s.triangles[8].material),
        (1, 2),
        "red left, green right"
    );
    let cam = Camera::look_at(Vec3::new(0.0, 0.0, 3.5), Vec3::ZERO, Vec3::Y, 40.0);
    assert_eq!(Some(s.camera), cam);
    assert_eq!(
        s.settings,
        RenderSettings {
            mode: Mode::Gather,
            spp: 32,
            passes: 4,
            ..RenderSettings::default()
        }
    );
    let area: f32 = s.triangles.iter().map(|t| t.area()).sum();
    assert!(
        (area - (20.0 + 0.36 * 6.0 + 0.72 * 4.0 + 0.25)).abs() < 1e-3,
        "{area}"
    );
}

#[test]
fn point_light_reference_scene() {
    let s = scene("point-light-plane.toml");
    assert_eq!(s.triangles.len(), 2);
    assert!(s.triangles.iter().all(|t| t.light == NO_LIGHT));
    assert_eq!(s.lights.len(), 1);
    let (position, intensity) = (Vec3::new(0.25, 1.0, -0.25), Vec3::new(12.0, 10.0, 8.0));
    assert_eq!(
        s.lights[0].shape,
        LightShape::Point(gpu_photon::lights::point::Point {
            position,
            intensity
        })
    );
    assert!(close(s.lights[0].power, 4.0 * PI * intensity, 1e-6));
    assert_eq!(s.materials, vec![Material::diffuse(Vec3::splat(0.8))]);
    assert!(close(s.triangles[0].normal(), Vec3::Y, 1e-6));
    assert_eq!(s.settings.mode, Mode::Photon);
    let cam = Camera::look_at(Vec3::new(0.0, 3.0, 3.0), Vec3::ZERO, Vec3::Y, 45.0);
    assert_eq!(Some(s.camera), cam);
}

#[test]
fn every_scene_file_loads() {
    let mut names = Vec::new();
    for entry in std::fs::read_dir(scenes_dir()).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "toml") {
            let s = load(&path).unwrap_or_else(|e| panic!("{e}"));
            assert!(
                s.total_power().min_element() > 0.0,
                "{} is dark",
                path.display()
            );
            names.push(path.file_stem().unwrap().to_string_lossy().into_owned());
        }
    }
    names.sort();
    let expected = [
        "coloured-lights",
        "cornell-box",
        "cornell-caustics",
        "fog-cornell",
        "glossy-sphere",
        "inside-glass",
        "mesh-light",
        "point-light-plane",
        "spot-light",
        "volume-caustic",
    ];
    assert_eq!(names, expected);
}

#[test]
fn example_scenes_are_what_they_say() {
    let s = scene("cornell-caustics.toml");
    let kinds: Vec<&str> = s
        .spheres
        .iter()
        .map(|sp| kind_of(&s, sp.material))
        .collect();
    assert_eq!(kinds, ["Mirror", "Glass"]);
    assert!(
        s.spheres
            .iter()
            .all(|sp| (sp.center.y - sp.radius + 1.0).abs() < 1e-6),
        "on the floor"
    );

    let s = scene("glossy-sphere.toml");
    assert_eq!(kind_of(&s, s.spheres[0].material), "Phong");

    let s = scene("coloured-lights.toml");
    assert_eq!(s.lights.len(), 4);
    assert!(matches!(s.lights[3].shape, LightShape::Point(_)));
    let colours: Vec<usize> = s.lights[..3]
        .iter()
        .map(|l| l.power.max_position())
        .collect();
    assert_eq!(colours, [0, 1, 2], "red, green and blue lights");

    let s = scene("mesh-light.toml");
    assert_eq!(s.lights.len(), 1);
    let LightShape::Triangles(gpu_photon::lights::triangles::Triangles { first, count }) =
        s.lights[0].shape
    else {
        panic!("not a mesh light")
    };
    assert_eq!(count, 6);
    let tris = &s.triangles[first as usize..(first + count) as usize];
    let area: f32 = tris.iter().map(|t| t.area()).sum();
    assert!((area - 1.5 * 3f32.sqrt() * 0.09).abs() < 1e-4, "{area}");
    for t in tris {
        assert!(close(t.normal(), -Vec3::Y, 1e-5), "faces down");
        assert!((t.v0.y - 0.98).abs() < 1e-6 && t.light == 0);
    }
    assert!(close(
        s.lights[0].power,
        PI * area * Vec3::new(17.0, 12.0, 4.0),
        1e-5
    ));

    let s = scene("inside-glass.toml");
    let glass = s
        .spheres
        .iter()
        .find(|sp| kind_of(&s, sp.material) == "Glass")
        .unwrap();
    assert!(
        glass.center.distance(s.camera.eye) < glass.radius,
        "the eye is inside the glass"
    );
}

/// The name of a material's BSDF kind (`Glass`).
fn kind_of(s: &Scene, material: u32) -> &'static str {
    KINDS[s.materials[material as usize].bsdf.code() as usize].name
}

fn corners(tris: &[Triangle]) -> Vec<Vec3> {
    tris.iter().flat_map(|t| [t.v0, t.v1, t.v2]).collect()
}

#[test]
fn boxes_match_the_reference_box_quads() {
    // mesh-light.toml builds the two boxes of cornell-box.toml with `box` shapes.
    let reference = corners(&scene("cornell-box.toml").triangles[10..30]);
    let boxes = scene("mesh-light.toml");
    let built = &boxes.triangles[10..34];
    for v in corners(built) {
        let covered = v.y < -0.999 || reference.iter().any(|r| r.distance(v) < 1e-4);
        assert!(
            covered,
            "box corner {v} is not a corner of the reference boxes"
        );
    }
    for (i, one_box) in built.chunks(12).enumerate() {
        let centre: Vec3 = corners(one_box).iter().sum::<Vec3>() / 36.0;
        for t in one_box {
            let c = t.v0 + (t.e1() + t.e2()) / 3.0;
            assert!(
                t.normal().dot(c - centre) > 0.0,
                "box {i}: a face points inwards"
            );
        }
        let area: f32 = one_box.iter().map(|t| t.area()).sum();
        let expected = if i == 0 {
            6.0 * 0.36
        } else {
            2.0 * 0.36 + 4.0 * 0.72
        };
        assert!((area - expected).abs() < 1e-4, "box {i}: area {area}");
    }
}

#[test]
fn integers_defaults_and_empty_scenes() {
    let body = "[[shapes]]\ntype = \"triangle\"\nvertices = [[0, 0, 0], [1, 0, 0], [0, 1, 0]]\n\
                material = \"m\"\n[materials.m]\ntype = \"diffuse\"\nalbedo = [1, 0, 0]\n";
    let s = parse(body).unwrap();
    assert_eq!((s.triangles.len(), s.triangles[0].e1()), (1, Vec3::X));
    assert_eq!(s.materials[0], Material::diffuse(Vec3::X));
    assert!(s.lights.is_empty());
    assert_eq!(s.settings, RenderSettings::default());
    // A zero-area triangle that does not emit is kept; an empty scene is allowed (it is black).
    let s = parse(&body.replace("[1, 0, 0], [0, 1, 0]", "[1, 0, 0], [2, 0, 0]")).unwrap();
    assert_eq!(s.triangles[0].area(), 0.0);
    let s = parse("").unwrap();
    assert!(s.triangles.is_empty() && s.spheres.is_empty() && s.lights.is_empty());
}

#[test]
fn render_table_overrides_defaults() {
    let s = parse(
        "width = 320\nheight = 200\n[render]\nphotons = 1000\ncaustic_photons = 0\nk = 50\n\
         radius = 1\ncaustic_radius = 0.5\nspp = 4\nshadow_samples = 2\nmode = \"global-only\"\n\
         filter = \"cone\"\nfresnel = \"schlick\"\nmax_photon_bounces = 8\nmax_depth = 5\n\
         seed = 7\nexposure = -1.5\n",
    )
    .unwrap();
    let r = &s.settings;
    assert_eq!(
        (r.width, r.height, r.photons, r.caustic_photons, r.k),
        (320, 200, 1000, 0, 50)
    );
    assert_eq!(
        (r.radius, r.caustic_radius, r.spp, r.shadow_samples),
        (1.0, 0.5, 4, 2)
    );
    assert_eq!(
        (r.mode, r.filter.name(), r.fresnel),
        (Mode::GlobalOnly, "cone", FresnelMode::Schlick)
    );
    assert_eq!(
        (r.max_photon_bounces, r.max_depth, r.seed, r.exposure),
        (8, 5, 7, -1.5)
    );
}

#[test]
fn emissive_shapes_and_materials() {
    let quad =
        "[[shapes]]\ntype = \"quad\"\ncorners = [[0, 0, 0], [2, 0, 0], [2, 0, 2], [0, 0, 2]]\n";
    let s = parse(&format!(
        "[materials.lamp]\ntype = \"emissive\"\nradiance = [2, 2, 2]\n[materials.w]\n\
         type = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n[[shapes]]\ntype = \"sphere\"\n\
         center = [0, 0, 0]\nradius = 0.5\nmaterial = \"lamp\"\n{quad}material = \"w\"\n\
         emission = [1, 0, 0]\ntwo_sided = true\n{quad}material = \"w\"\n"
    ))
    .unwrap();
    assert_eq!(s.lights.len(), 2);
    assert_eq!(
        (s.lights[0].shape.clone(), s.spheres[0].light),
        (
            LightShape::Sphere(gpu_photon::lights::sphere::SphereLight { index: 0 }),
            0
        )
    );
    assert!(close(
        s.lights[0].power,
        Vec3::splat(PI * 4.0 * PI * 0.25 * 2.0),
        1e-5
    ));
    assert_eq!(
        s.lights[1].shape,
        LightShape::Triangles(gpu_photon::lights::triangles::Triangles { first: 0, count: 2 })
    );
    let two_sided = Vec3::new(2.0 * PI * 4.0, 0.0, 0.0);
    assert!(
        close(s.lights[1].power, two_sided, 1e-5),
        "two-sided doubles the power"
    );
    // The emissive quad has its own copy of `w`; the plain quad uses `w` itself.
    let own = s.material_of_triangle(0);
    assert_eq!(own.bsdf, gpu_photon::bsdfs::Bsdf::diffuse(Vec3::splat(0.5)));
    assert_eq!((own.emission, own.two_sided_emission), (Vec3::X, true));
    assert_eq!(
        *s.material_of_triangle(2),
        Material::diffuse(Vec3::splat(0.5))
    );
    let lights: Vec<u32> = s.triangles.iter().map(|t| t.light).collect();
    assert_eq!(lights, [1, 1, NO_LIGHT, NO_LIGHT]);
}

#[test]
fn meshes_are_scaled_and_translated() {
    let mesh = "[[shapes]]\ntype = \"mesh\"\nfile = \"meshes/light.obj\"\nmaterial = \"w\"\n";
    let s = parse(&format!(
        "[materials.w]\ntype = \"diffuse\"\nalbedo = [0.5, 0.5, 0.5]\n\
         {mesh}scale = [2, 1, 1]\ntranslate = [0, 5, 0]\n{mesh}scale = -1\n"
    ))
    .unwrap();
    assert_eq!((s.triangles.len(), s.lights.len()), (12, 0));
    let t = s.triangles[0];
    assert_eq!(
        (t.v0, t.e1()),
        (Vec3::new(0.0, 5.0, 0.0), Vec3::new(2.0, 0.0, 0.0))
    );
    assert!(close(t.normal(), -Vec3::Y, 1e-6));
    // A mirroring scale keeps the faces' orientation relative to the surface (here: up).
    assert!(close(s.triangles[6].normal(), Vec3::Y, 1e-6));
}

#[test]
fn broken_obj_files() {
    let dir = std::env::temp_dir().join(format!("gpu-photon-scene-errors-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mesh = |name: &str| {
        format!("[materials.w]\ntype = \"diffuse\"\nalbedo = [1, 1, 1]\n[[shapes]]\ntype = \"mesh\"\nmaterial = \"w\"\nfile = \"{name}\"\n")
    };
    let missing = scene_error(parse_in(&mesh("none.obj"), &dir)).unwrap();
    assert!(
        missing
            .2
            .contains(&dir.join("none.obj").display().to_string()),
        "{}",
        missing.2
    );
    let bad = [
        (
            "empty.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\n",
            "empty.obj:3: the mesh has no triangles",
        ),
        (
            "lines.obj",
            "v 0 0 0\nv 1 0 0\nl 1 2\np 1\n",
            "lines.obj:4: the mesh has no triangles",
        ),
        (
            "out-of-range.obj",
            "v 0 0 0\nv 1 0 0\nf 1 2 3\n",
            "out-of-range.obj:3: OBJ face corner `3`: vertex index out of range or malformed (2 v \
             records before it, 2 in all)",
        ),
        (
            "zero-index.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n",
            "zero-index.obj:4: OBJ face corner `0`: vertex index out of range",
        ),
        (
            "garbage.obj",
            "v 0 zero 0\n",
            "garbage.obj:1: OBJ record `v 0 zero 0`: `zero` is not a number",
        ),
        (
            "nan.obj",
            "v nan 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n",
            "nan.obj:1: OBJ vertex [NaN, 0, 0] is not finite",
        ),
        (
            "empty-face.obj",
            "v 0 0 0\nf\n",
            "empty-face.obj:2: OBJ face has 0 corners; a face needs 3 or more",
        ),
        (
            "vt-out-of-range.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/-99999999999 3/1\n",
            "vt-out-of-range.obj:5: OBJ face corner `2/-99999999999`: texture coordinate index",
        ),
        // i64::MIN, whose negation overflows (issue 44), in each slot of a corner: a panic
        // (vt), an error without a line (v, from tobj) and a mesh rendered (vn) before.
        (
            "min-vt.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nf 1/1 2/1 3/-9223372036854775808\n",
            "min-vt.obj:5: OBJ face corner `3/-9223372036854775808`: texture coordinate index \
             out of range (1 vt records before it)",
        ),
        (
            "min-v.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -9223372036854775808\n",
            "min-v.obj:4: OBJ face corner `-9223372036854775808`: vertex index out of range or \
             malformed (3 v records before it, 3 in all)",
        ),
        (
            "min-vn.obj",
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//-9223372036854775808\n",
            "min-vn.obj:5: OBJ face corner `3//-9223372036854775808`: normal index out of range \
             (1 vn records before it)",
        ),
    ];
    for (name, obj, needle) in bad {
        std::fs::write(dir.join(name), obj).unwrap();
        let (line, field, message) = scene_error(parse_in(&mesh(name), &dir)).unwrap();
        assert_eq!(
            (line, field.as_str()),
            (11, "shapes[0].file"),
            "{name}: {message}"
        );
        assert!(
            message.contains(needle) && message.contains(name),
            "{name}: {message}"
        );
    }
    // Normal indices are ignored, however wild, when a corner names none, and so are
    // materials; polygons are fans. (Texture indices are read: `tests/mesh_uvs.rs`.)
    let odd = "mtllib none.mtl\ng part\nusemtl nothing\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n\
               vt 0 0\nvn 0 0 1\ns off\nf 1/1/1 2//1 3//99999999999999 4\n";
    std::fs::write(dir.join("odd.obj"), odd).unwrap();
    let s = parse_in(&mesh("odd.obj"), &dir).unwrap();
    assert_eq!(s.triangles.len(), 2);
    assert!(close(s.triangles[1].normal(), Vec3::Z, 1e-6));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn unreadable_file_is_io_error() {
    let missing = scenes_dir().join("no-such-scene.toml");
    assert!(matches!(load(&missing), Err(Error::Io { path, .. }) if path == missing));
}

#[test]
fn truncated_scenes_never_panic() {
    let text = std::fs::read_to_string(scenes_dir().join("mesh-light.toml")).unwrap();
    for end in (0..=text.len()).filter(|&i| text.is_char_boundary(i)) {
        let result = load_str(&text[..end], "test.toml", &scenes_dir());
        if let Err(e) = result {
            assert!(matches!(e, Error::Scene { .. }), "{e}");
        }
    }
}

#[test]
fn readme_example_loads() {
    let readme = std::fs::read_to_string(scenes_dir().join("README.md")).unwrap();
    let example = readme
        .split("```toml\n")
        .nth(1)
        .unwrap()
        .split("```")
        .next()
        .unwrap();
    let s = load_str(example, "README.md", &scenes_dir()).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!((s.settings.width, s.settings.height), (320, 240));
    assert_eq!((s.materials.len(), s.spheres.len()), (6, 1));
    assert_eq!(
        (s.triangles.len(), s.lights.len()),
        (2 + 2 + 1 + 12 + 6 + 2, 3)
    );
    let sides: Vec<bool> = s.materials.iter().map(|m| m.two_sided_emission).collect();
    assert_eq!(sides, [false, false, false, false, false, true]);
}

/// The refusal of `value` for setting `name`, through a scene file (line, field, message) and
/// through `validate` (field, message).
fn refusals(name: &str, value: &str) -> ((usize, String, String), (String, String)) {
    let row = SETTINGS.iter().find(|r| r.name == name).unwrap();
    let table = row.table.expect("a scene-file setting");
    // `[camera]` settings go on line 5, inside CAMERA's table; `[render]` ones on line 6.
    let body = if table == "camera" {
        format!("{name} = {value}\n")
    } else {
        format!("[{table}]\n{name} = {value}\n")
    };
    let scene = scene_error(parse(&body)).unwrap_or_else(|e| panic!("{name} = {value}: {e}"));
    let mut s = RenderSettings::default();
    match row.slot {
        Slot::U32 { set, .. } => set(&mut s, value.parse().unwrap()),
        Slot::F32 { set, .. } => set(&mut s, value.parse().unwrap()),
    }
    match validate(&s) {
        Err(Error::Setting { field, message }) => (scene, (field.to_string(), message)),
        other => panic!("validate accepted {name} = {value}: {other:?}"),
    }
}

#[test]
fn scene_file_and_validate_refuse_spp_70000_with_one_range() {
    let ((line, field, message), (flag, refusal)) = refusals("spp", "70000");
    assert_eq!((line, field.as_str()), (6, "render.spp"));
    assert_eq!(message, "must be an integer in 1..=65536");
    assert_eq!(
        (flag.as_str(), refusal.as_str()),
        ("spp", "70000 is outside 1..=65536")
    );
    // 65,536 itself is accepted by both.
    let s = parse("[render]\nspp = 65536\n").unwrap();
    assert_eq!(s.settings.spp, 65536);
    assert!(validate(&s.settings).is_ok());
}

#[test]
fn every_scene_file_setting_has_the_range_of_validate() {
    // Just past each bound of every setting a scene file may set: both refuse it, naming the
    // same range; at the bound both accept it.
    let mut checked = 0;
    for row in SETTINGS.iter().filter(|r| r.table.is_some()) {
        let (bad, good): (Vec<String>, Vec<String>) = match row.range {
            Range::Int { lo, hi } => {
                let bad = [lo.checked_sub(1), hi.checked_add(1)].into_iter().flatten();
                (
                    bad.map(|v| v.to_string()).collect(),
                    vec![lo.to_string(), hi.to_string()],
                )
            }
            Range::Positive => (vec!["0.0".into(), "-1.5".into()], vec!["1e-6".into()]),
            Range::Finite => (vec![], vec!["-3.5".into()]),
            Range::Open { .. } => unreachable!("{}: no scene-file setting is open", row.name),
        };
        let range = row.range.to_string();
        for value in &bad {
            let ((_, field, message), (flag, refusal)) = refusals(row.name, value);
            let table = row.table.unwrap();
            assert_eq!(field, format!("{table}.{}", row.name));
            assert_eq!(flag, row.flag);
            assert!(
                message.contains(&range),
                "{}: {message} lacks {range}",
                row.name
            );
            assert!(
                refusal.contains(&range),
                "{}: {refusal} lacks {range}",
                row.name
            );
            assert!(refusal.contains(value.trim_end_matches(".0")), "{refusal}");
            checked += 1;
        }
        for value in &good {
            let body = match row.table {
                Some("camera") => format!("{} = {value}\n", row.name),
                _ => format!("[render]\n{} = {value}\n", row.name),
            };
            let s = parse(&body).unwrap_or_else(|e| panic!("{} = {value}: {e}", row.name));
            assert!(validate(&s.settings).is_ok(), "{} = {value}", row.name);
        }
    }
    // Two bad values for every setting but passes, caustic_photons and adaptive (one: their
    // bottom is 0) and seed and exposure (none: every u32, every finite number).
    assert_eq!(checked, 27);
}

#[test]
fn readme_tables_show_the_ranges_of_the_settings_table() {
    let readme = std::fs::read_to_string(scenes_dir().join("README.md")).unwrap();
    for row in SETTINGS.iter().filter(|r| r.table.is_some()) {
        let key = format!("| `{}` |", row.name);
        let line = readme.lines().find(|l| l.starts_with(&key));
        let line = line.unwrap_or_else(|| panic!("README has no row for `{}`", row.name));
        let range = row.range.to_string().replace("4294967295", "2^32-1");
        assert!(
            line.contains(&range),
            "README's `{}` row lacks {range}",
            row.name
        );
    }
}

#[test]
fn the_builder_without_a_file_format() {
    // What an importer of another format does: its own locations, the same rules.
    let at = |line: usize| Origin {
        file: "model.gltf".into(),
        line,
        field: format!("meshes[{line}]"),
    };
    let mut b = SceneBuilder::new();
    let white = Material::diffuse(Vec3::splat(0.5));
    let white = b.add_material(Some("white"), white, &at(0)).unwrap();
    let bright = Material::glossy(Vec3::splat(0.5), Vec3::splat(0.6), 10.0);
    let e = b
        .add_material(Some("bright"), bright, &at(0))
        .unwrap_err()
        .to_string();
    assert!(e.contains("kd + ks must be at most 1"), "{e}");
    let quad = [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 0.0, -1.0), -Vec3::Z];
    b.add_quad(quad, Surface::of(white), &at(1)).unwrap();
    let lamp = Surface {
        two_sided: Some(true),
        ..Surface::emitting(Vec3::splat(2.0))
    };
    b.add_sphere(Vec3::Y, 0.5, lamp, &at(2)).unwrap();
    b.add_point_light(Vec3::Y, Vec3::ONE, &at(3)).unwrap();
    let degenerate = [Vec3::ZERO, Vec3::X, 2.0 * Vec3::X];
    let e = b.add_triangle(degenerate, Surface::emitting(Vec3::ONE), &at(4));
    assert_eq!(
        e.unwrap_err().to_string(),
        "model.gltf:4: meshes[4]: zero-area light"
    );
    let e = b.material_named("grey", &at(5)).unwrap_err().to_string();
    assert!(
        e.contains("unknown material `grey` (defined: `white`)"),
        "{e}"
    );
    let e = b.add_triangle(
        degenerate,
        Surface {
            two_sided: Some(true),
            ..Surface::of(white)
        },
        &at(6),
    );
    assert!(e
        .unwrap_err()
        .to_string()
        .contains("only applies to emissive"));
    // A camera is required; the locator says where (here a closure).
    let no_camera = |part: Part, message: String| Error::Scene {
        file: "model.gltf".into(),
        line: 0,
        field: format!("{part:?}"),
        message,
    };
    let up_along_view = b.camera(Vec3::Z, Vec3::ZERO, Vec3::Z, 40.0, &no_camera);
    assert!(up_along_view
        .unwrap_err()
        .to_string()
        .contains(": Up: degenerate camera frame"));
    b.camera(3.0 * Vec3::Z, Vec3::ZERO, Vec3::Y, 40.0, &no_camera)
        .unwrap();
    let s = b.finish(&no_camera).unwrap();
    // The sphere got its own two-sided emitting copy of black; the quad kept `white`. The
    // calls that failed left no trace (no triangle, no light, no material copy).
    assert_eq!((s.triangles.len(), s.materials.len()), (2, 2));
    assert_eq!(s.triangles[0].material, white.index());
    let lamp = s.materials[s.spheres[0].material as usize];
    assert_eq!(
        (lamp.emission, lamp.two_sided_emission),
        (Vec3::splat(2.0), true)
    );
    assert_eq!(s.lights.len(), 2);
    assert_eq!(
        s.lights[0].shape,
        LightShape::Sphere(gpu_photon::lights::sphere::SphereLight { index: 0 })
    );
    let sphere_power = PI * 4.0 * PI * 0.25 * 2.0 * 2.0;
    assert!(close(s.lights[0].power, Vec3::splat(sphere_power), 1e-6));
    assert!(close(s.lights[1].power, Vec3::splat(4.0 * PI), 1e-6));
    assert!(SceneBuilder::new().finish(&no_camera).is_err());
}

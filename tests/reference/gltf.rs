//! The glTF 2.0 importer: a Cornell box written the way Blender exports it (Y up, one node
//! per object with TRS, an instanced box mesh under a scaled parent, one primitive per
//! material, non-metal roughness 1 with KHR_materials_specular 0, the area light as an
//! emissive mesh with KHR_materials_emissive_strength, a camera node) built and rendered
//! against its TOML twin `scenes/cornell-box.toml` and the reference image; a variant with
//! a KHR_lights_punctual point light in candela; and malformed files with their messages.

use crate::common;

use glam::{Quat, Vec3};
use gpu_photon::importers::{load, load_gltf, load_str, load_with_camera};
use gpu_photon::render::film::Image;
use gpu_photon::render::image_diff::diff;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::{LightShape, Scene};
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Accumulates one buffer, its views and accessors.
#[derive(Default)]
struct Bin {
    data: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Bin {
    /// Adds float VEC3 positions; returns the accessor index.
    fn positions(&mut self, p: &[Vec3]) -> usize {
        let offset = self.data.len();
        for v in p {
            for x in v.to_array() {
                self.data.extend(x.to_le_bytes());
            }
        }
        let (lo, hi) = p
            .iter()
            .fold((Vec3::MAX, Vec3::MIN), |(a, b), &v| (a.min(v), b.max(v)));
        self.views.push(format!(
            r#"{{"buffer": 0, "byteOffset": {offset}, "byteLength": {}, "target": 34962}}"#,
            12 * p.len()
        ));
        self.accessors.push(format!(
            r#"{{"bufferView": {}, "componentType": 5126, "count": {}, "type": "VEC3", "min": {:?}, "max": {:?}}}"#,
            self.views.len() - 1,
            p.len(),
            lo.to_array(),
            hi.to_array()
        ));
        self.accessors.len() - 1
    }
    /// Adds u16 indices; returns the accessor index.
    fn indices(&mut self, i: &[u16]) -> usize {
        let offset = self.data.len();
        for x in i {
            self.data.extend(x.to_le_bytes());
        }
        while !self.data.len().is_multiple_of(4) {
            self.data.push(0);
        }
        self.views.push(format!(
            r#"{{"buffer": 0, "byteOffset": {offset}, "byteLength": {}, "target": 34963}}"#,
            2 * i.len()
        ));
        self.accessors.push(format!(
            r#"{{"bufferView": {}, "componentType": 5123, "count": {}, "type": "SCALAR"}}"#,
            self.views.len() - 1,
            i.len()
        ));
        self.accessors.len() - 1
    }
}

/// Triangles of quads, fan-wise, as the TOML quads are split.
fn quads(q: &[[[f32; 3]; 4]]) -> Vec<Vec3> {
    q.iter()
        .flat_map(|c| [c[0], c[1], c[2], c[0], c[2], c[3]].map(Vec3::from))
        .collect()
}

/// The Cornell box of `scenes/cornell-box.toml` as a Blender-style glTF; with `point`, the
/// area light is replaced by a KHR_lights_punctual point light of `point` W/sr per channel.
fn cornell_gltf(point: Option<(Vec3, Vec3)>) -> String {
    cornell_parts(point, true).0
}

/// The JSON of [`cornell_gltf`] and its buffer; with `embed` false, the buffer has no URI
/// (a GLB's BIN chunk).
fn cornell_parts(point: Option<(Vec3, Vec3)>, embed: bool) -> (String, Vec<u8>) {
    let mut bin = Bin::default();
    let white = quads(&[
        [
            [-1.0, -1.0, 1.0],
            [1.0, -1.0, 1.0],
            [1.0, -1.0, -1.0],
            [-1.0, -1.0, -1.0],
        ],
        [
            [-1.0, 1.0, -1.0],
            [1.0, 1.0, -1.0],
            [1.0, 1.0, 1.0],
            [-1.0, 1.0, 1.0],
        ],
        [
            [-1.0, -1.0, -1.0],
            [1.0, -1.0, -1.0],
            [1.0, 1.0, -1.0],
            [-1.0, 1.0, -1.0],
        ],
    ]);
    let red = quads(&[[
        [-1.0, -1.0, -1.0],
        [-1.0, 1.0, -1.0],
        [-1.0, 1.0, 1.0],
        [-1.0, -1.0, 1.0],
    ]]);
    let green = quads(&[[
        [1.0, -1.0, 1.0],
        [1.0, 1.0, 1.0],
        [1.0, 1.0, -1.0],
        [1.0, -1.0, -1.0],
    ]]);
    let (w, r, g) = (
        bin.positions(&white),
        bin.positions(&red),
        bin.positions(&green),
    );
    // A cube [-1, 1]^3 without its bottom face, outward winding, indexed (shared by both boxes).
    let cube: Vec<Vec3> = [
        [-1, -1, -1],
        [1, -1, -1],
        [1, 1, -1],
        [-1, 1, -1],
        [-1, -1, 1],
        [1, -1, 1],
        [1, 1, 1],
        [-1, 1, 1],
    ]
    .iter()
    .map(|c| Vec3::new(c[0] as f32, c[1] as f32, c[2] as f32))
    .collect();
    let faces: [[u16; 4]; 5] = [
        [3, 7, 6, 2],
        [4, 5, 6, 7],
        [1, 0, 3, 2],
        [0, 4, 7, 3],
        [5, 1, 2, 6],
    ];
    let idx: Vec<u16> = faces
        .iter()
        .flat_map(|f| [f[0], f[1], f[2], f[0], f[2], f[3]])
        .collect();
    let (cube_p, cube_i) = (bin.positions(&cube), bin.indices(&idx));
    // The light: a 0.5 x 0.5 quad facing down, placed by its node.
    let lamp = quads(&[[
        [-0.25, 0.0, -0.25],
        [0.25, 0.0, -0.25],
        [0.25, 0.0, 0.25],
        [-0.25, 0.0, 0.25],
    ]]);
    let lamp_p = bin.positions(&lamp);

    let angle = 17f32.to_radians();
    let short = Quat::from_rotation_y(-angle).to_array();
    let tall = Quat::from_rotation_y(angle).to_array();
    let light_node = match point {
        None => r#"{"name": "Light", "mesh": 2, "translation": [0, 0.98, 0]}"#.to_string(),
        Some((position, _)) => format!(
            r#"{{"name": "Point", "translation": {:?}, "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}}"#,
            position.to_array()
        ),
    };
    let lights = match point {
        None => String::new(),
        Some((_, intensity)) => {
            let m = intensity.max_element();
            format!(
                r#", "extensions": {{"KHR_lights_punctual": {{"lights": [{{"name": "Point", "type": "point", "color": {:?}, "intensity": {}}}]}}}}"#,
                (intensity / m).to_array(),
                683.0 * m
            )
        }
    };
    let diffuse = |name: &str, c: [f32; 3]| {
        format!(
            r#"{{"name": "{name}", "doubleSided": true, "pbrMetallicRoughness": {{"baseColorFactor": [{}, {}, {}, 1], "metallicFactor": 0, "roughnessFactor": 1}}, "extensions": {{"KHR_materials_specular": {{"specularFactor": 0}}}}}}"#,
            c[0], c[1], c[2]
        )
    };
    let uri = match embed {
        true => format!(
            r#", "uri": "data:application/octet-stream;base64,{}""#,
            common::b64(&bin.data)
        ),
        false => String::new(),
    };
    let json = format!(
        r#"{{
  "asset": {{"generator": "Khronos glTF Blender I/O v4.1.63", "version": "2.0"}},
  "extensionsUsed": ["KHR_materials_specular", "KHR_materials_emissive_strength", "KHR_lights_punctual"],
  "scene": 0,
  "scenes": [{{"name": "Scene", "nodes": [0, 1, 2, 5]}}],
  "nodes": [
    {{"name": "Camera", "camera": 0, "translation": [0, 0, 3.5]}},
    {{"name": "Walls", "mesh": 0}},
    {{"name": "Boxes", "matrix": [2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1], "children": [3, 4]}},
    {{"name": "ShortBox", "mesh": 1, "translation": [0.2, -0.35, 0.175], "rotation": {short:?}, "scale": [0.15, 0.15, 0.15]}},
    {{"name": "TallBox", "mesh": 1, "translation": [-0.2, -0.2, -0.175], "rotation": {tall:?}, "scale": [0.15, 0.3, 0.15]}},
    {light_node}
  ],
  "cameras": [{{"name": "Camera", "type": "perspective", "perspective": {{"aspectRatio": 1.0, "yfov": {yfov}, "znear": 0.1, "zfar": 100}}}}],
  "materials": [
    {white}, {red}, {green},
    {{"name": "Lamp", "emissiveFactor": [1, {e1}, {e2}], "extensions": {{"KHR_materials_emissive_strength": {{"emissiveStrength": 17}}, "KHR_materials_specular": {{"specularFactor": 0}}}},
      "pbrMetallicRoughness": {{"baseColorFactor": [0, 0, 0, 1], "metallicFactor": 0, "roughnessFactor": 1}}}}
  ],
  "meshes": [
    {{"name": "Walls", "primitives": [{{"attributes": {{"POSITION": {w}}}, "material": 0}}, {{"attributes": {{"POSITION": {r}}}, "material": 1}}, {{"attributes": {{"POSITION": {g}}}, "material": 2}}]}},
    {{"name": "Box", "primitives": [{{"attributes": {{"POSITION": {cube_p}}}, "indices": {cube_i}, "material": 0}}]}},
    {{"name": "Lamp", "primitives": [{{"attributes": {{"POSITION": {lamp_p}}}, "material": 3}}]}}
  ],
  "accessors": [{accessors}],
  "bufferViews": [{views}],
  "buffers": [{{"byteLength": {len}{uri}}}]{lights}
}}
"#,
        yfov = 40f32.to_radians(),
        white = diffuse("White", [0.73, 0.73, 0.73]),
        red = diffuse("Red", [0.63, 0.065, 0.05]),
        green = diffuse("Green", [0.14, 0.45, 0.091]),
        e1 = 12.0 / 17.0,
        e2 = 4.0 / 17.0,
        accessors = bin.accessors.join(",\n    "),
        views = bin.views.join(",\n    "),
        len = bin.data.len(),
    );
    (json, bin.data)
}

/// Writes `text` as `target/test-output/gltf/NAME` and returns the path (each test writes
/// names of its own: tests run in parallel).
fn write(name: &str, text: &[u8]) -> PathBuf {
    let dir = root().join("target/test-output/gltf");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path
}

fn toml_box() -> Scene {
    load(&root().join("scenes/cornell-box.toml")).unwrap()
}

/// The scene's triangles in world space: its own, then each instance's mesh placed (glTF
/// meshes named at two or more nodes are instances).
fn world_triangles(s: &Scene) -> Vec<gpu_photon::scene::Triangle> {
    let mut out = s.triangles.clone();
    for inst in &s.instancing.instances {
        let mesh = &s.instancing.meshes[inst.mesh as usize];
        out.extend(mesh.triangles.iter().map(|t| {
            let p = |v: Vec3| inst.to_world.transform_point3(v);
            gpu_photon::scene::Triangle::new(
                p(t.v0),
                p(t.v0 + t.e1()),
                p(t.v0 + t.e2()),
                t.material,
            )
        }));
    }
    out
}

fn area(s: &Scene) -> f64 {
    world_triangles(s).iter().map(|t| t.area() as f64).sum()
}

fn rel(a: Vec3, b: Vec3) -> f32 {
    (a - b).abs().max_element() / b.abs().max_element()
}

/// The built scenes agree: triangles, area, emitted power, camera, materials.
fn compare(g: &Scene, t: &Scene, what: &str) {
    assert_eq!(
        world_triangles(g).len(),
        t.triangles.len(),
        "{what}: triangle count"
    );
    let (ag, at) = (area(g), area(t));
    eprintln!(
        "{what}: area glTF {ag:.6} TOML {at:.6}; power {} vs {}",
        g.total_power(),
        t.total_power()
    );
    assert!((ag / at - 1.0).abs() < 1e-5, "{what}: area {ag} vs {at}");
    assert!(
        rel(g.total_power(), t.total_power()) < 1e-6,
        "{what}: power"
    );
    for (a, b) in [
        (g.camera.eye, t.camera.eye),
        (g.camera.forward, t.camera.forward),
        (g.camera.right, t.camera.right),
        (g.camera.up, t.camera.up),
    ] {
        assert!((a - b).length() < 1e-6, "{what}: camera {a} vs {b}");
    }
    assert_eq!((g.settings.width, g.settings.height), (256, 256));
    // Every albedo of the TOML box is an albedo of the glTF one.
    for m in &t.materials {
        let same = |n: &gpu_photon::scene::Material| {
            n.bsdf.code() == m.bsdf.code()
                && match (n.bsdf.base_colour(), m.bsdf.base_colour()) {
                    (Some(a), Some(b)) => (a.get() - b.get()).length() < 1e-6,
                    (a, b) => a.is_none() && b.is_none(),
                }
                && (n.emission - m.emission).length() <= 1e-6 * m.emission.length()
        };
        assert!(
            g.materials.iter().any(same),
            "{what}: no material like {m:?}"
        );
    }
}

#[test]
fn cornell_box_gltf_builds_and_renders_as_its_toml_twin() {
    let path = write("cornell-box.gltf", cornell_gltf(None).as_bytes());
    let g = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let t = toml_box();
    compare(&g, &t, "cornell-box.gltf");
    // The light is the same one-sided quad, facing down.
    let LightShape::Triangles(gpu_photon::lights::triangles::Triangles { first, count }) =
        g.lights[0].shape
    else {
        panic!("area light")
    };
    assert_eq!((g.lights.len(), count), (1, 2));
    assert!(g.triangles[first as usize].normal().dot(-Vec3::Y) > 0.999);

    // What `gpu-photon render` renders with no flags (4 progressive passes of 32 spp). The
    // TOML box's image is the one the reference test renders (`main.rs`, same file and
    // settings), rendered once for both.
    let settings = t.settings.as_default_render();
    let reference = Image::read(&root().join("tests/data/cornell-diffuse.exr")).unwrap();
    let mut images = vec![];
    for (name, scene) in [("glTF", Some(&g)), ("TOML", None)] {
        let img = match scene {
            Some(scene) => {
                render(scene, &settings, Backend::Cpu, Progress::default())
                    .unwrap()
                    .0
            }
            None => crate::cornell_box_default_render().clone(),
        };
        let d = diff(&img, &reference, 16).unwrap();
        eprintln!("{name} vs reference: {d:?}");
        assert_eq!(img.non_finite(), 0);
        // The bounds of the reference test (`main.rs`) for the TOML box.
        assert!(
            d.mean_ratio.iter().all(|r| (0.98..=1.02).contains(r)),
            "{name}: {d:?}"
        );
        assert!(d.rmse < 0.0058 && d.block_rmse < 0.002, "{name}: {d:?}");
        images.push(img);
    }
    let d = diff(&images[0], &images[1], 16).unwrap();
    eprintln!("glTF vs TOML: {d:?}");
    assert!(
        d.mean_ratio.iter().all(|r| (0.99..=1.01).contains(r)),
        "{d:?}"
    );
}

#[test]
fn point_light_gltf_matches_its_toml_twin() {
    let (position, intensity) = (Vec3::new(0.1, 0.9, -0.2), Vec3::new(2.0, 1.5, 0.5));
    let path = write(
        "cornell-point.gltf",
        cornell_gltf(Some((position, intensity))).as_bytes(),
    );
    let g = load_gltf(&path, Some("Camera")).unwrap_or_else(|e| panic!("{e}"));
    let text = std::fs::read_to_string(root().join("scenes/cornell-box.toml")).unwrap();
    let cut = text.find("# The area light").unwrap();
    let twin = format!(
        "{}[[lights]]\ntype = \"point\"\nposition = [0.1, 0.9, -0.2]\nintensity = [2.0, 1.5, 0.5]\n",
        &text[..cut]
    );
    let t = load_str(&twin, "twin.toml", &root().join("scenes")).unwrap();
    assert_eq!(world_triangles(&g).len(), t.triangles.len());
    let LightShape::Point(gpu_photon::lights::point::Point {
        position: p,
        intensity: i,
    }) = g.lights[0].shape
    else {
        panic!("point")
    };
    assert!(
        (p - position).length() < 1e-6 && rel(i, intensity) < 1e-6,
        "{p} {i}"
    );
    compare(&g, &t, "cornell-point.gltf");
    eprintln!(
        "point light power: glTF {} TOML {}",
        g.total_power(),
        t.total_power()
    );
}

/// The message after `FILE:` of loading `bytes` as `NAME`, which must fail.
fn error_of(name: &str, bytes: &[u8]) -> String {
    let path = write(name, bytes);
    match load(&path) {
        Ok(_) => panic!("{name} loaded"),
        Err(e) => {
            let shown = e.to_string();
            let prefix = format!("{}:", path.display());
            assert!(shown.starts_with(&prefix), "{shown}");
            shown[prefix.len()..].to_string()
        }
    }
}

#[test]
fn glb_form_loads_as_the_gltf_form() {
    let (json, bin) = cornell_parts(None, false);
    let path = write("cornell-box.glb", &common::glb(&json, &bin));
    let g = load(&path).unwrap_or_else(|e| panic!("{e}"));
    let t = load(&write(
        "cornell-box-twin.gltf",
        cornell_gltf(None).as_bytes(),
    ))
    .unwrap();
    assert_eq!(g.triangles, t.triangles);
    assert_eq!(g.lights, t.lights);
}

/// A one-triangle scene with a camera whose first vertex is `x`.
fn tiny(x: f32) -> String {
    let mut bin = Bin::default();
    bin.positions(&[Vec3::new(x, 0.0, 0.0), Vec3::X, Vec3::Y]);
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scenes": [{{"nodes": [0, 1]}}],
"nodes": [{{"camera": 0, "translation": [0, 0, 3]}}, {{"mesh": 0}}],
"cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.7, "znear": 0.1}}}}],
"meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
"accessors": [{}], "bufferViews": [{}],
"buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}]}}"#,
        bin.accessors[0],
        bin.views[0],
        bin.data.len(),
        common::b64(&bin.data)
    )
}

#[test]
fn malformed_gltf_files_give_file_line_field_messages() {
    let good = cornell_gltf(Some((Vec3::Y * 0.5, Vec3::ONE)));
    let uri = good.find("data:application").unwrap();
    let end = uri + good[uri..].find('"').unwrap();
    let missing = format!("{}nowhere.bin{}", &good[..uri], &good[end..]);
    let (json, bin) = cornell_parts(None, false);
    let full = common::glb(&json, &bin);
    assert!(load(&write("tiny.gltf", tiny(0.0).as_bytes())).is_ok());
    let cases: Vec<(&str, Vec<u8>, String)> =
        vec![
        (
            "truncated.gltf",
            good.as_bytes()[..good.len() / 2].to_vec(),
            "22: json: EOF while parsing a string at line 22 column 75".into(),
        ),
        (
            "truncated.glb",
            full[..full.len() - 100].to_vec(),
            "0: glb: malformed GLB: could not completely read the object".into(),
        ),
        (
            "missing-buffer.gltf",
            missing.into_bytes(),
            "37: buffers[0]: cannot read buffer `nowhere.bin`: No such file or directory (os error 2)"
                .into(),
        ),
        (
            "short-buffer.gltf",
            good.replacen("\"buffers\": [{\"byteLength\": ", "\"buffers\": [{\"byteLength\": 9", 1)
                .into_bytes(),
            "37: buffers[0]: truncated: 588 bytes of 9588".into(),
        ),
        (
            "vec2.gltf",
            good.replacen("\"type\": \"VEC3\"", "\"type\": \"VEC2\"", 1).into_bytes(),
            "21: meshes[0].primitives[0]: POSITION must be VEC3 of FLOAT, not Vec2 of F32".into(),
        ),
        (
            "nan-vertex.gltf",
            tiny(f32::NAN).into_bytes(),
            "4: meshes[0].primitives[0]: POSITION 0 is not finite".into(),
        ),
        (
            "spot-wide.gltf",
            good.replacen(
                "\"type\": \"point\"",
                "\"type\": \"spot\", \"spot\": {\"outerConeAngle\": 2.0}",
                1,
            )
            .into_bytes(),
            "37: extensions.KHR_lights_punctual.lights[0]: light Point: spot.outerConeAngle (in \
             degrees): must be in (0, 90] degrees (got 114.59156)"
                .into(),
        ),
        (
            "spot-inner.gltf",
            good.replacen(
                "\"type\": \"point\"",
                "\"type\": \"spot\", \"spot\": {\"innerConeAngle\": 0.5, \"outerConeAngle\": 0.25}",
                1,
            )
            .into_bytes(),
            "37: extensions.KHR_lights_punctual.lights[0]: light Point: spot.innerConeAngle (in \
             degrees): must be in [0, outer angle 14.323945] degrees (got 28.64789)"
                .into(),
        ),
        (
            "directional-flat.gltf",
            good.replacen("\"type\": \"point\"", "\"type\": \"directional\"", 1)
                .replacen("\"name\": \"Point\", ", "\"name\": \"Point\", \"scale\": [1, 1, 0], ", 1)
                .into_bytes(),
            "37: extensions.KHR_lights_punctual.lights[0]: light Point: direction (the node's -Z \
             axis): must not be zero"
                .into(),
        ),
        (
            "bad-index.gltf",
            good.replacen("\"indices\": ", "\"indices\": 9", 1).into_bytes(),
            "22: meshes[1].primitives[0].indices: accessor 94 does not exist (6 accessors)".into(),
        ),
        (
            "huge-number.gltf",
            good.replacen("[0, 0, 3.5]", "[0, 0, 1e999]", 1).into_bytes(),
            "7: json: number out of range at line 7 column 63".into(),
        ),
    ];
    for (name, bytes, want) in cases {
        let got = error_of(name, &bytes);
        eprintln!("{name}: {got}");
        if want.ends_with(": ") {
            assert!(
                got.starts_with(&want),
                "{name}: `{got}` does not start with `{want}`"
            );
        } else {
            assert_eq!(got, want, "{name}");
        }
    }
}

#[test]
fn materials_map_by_the_documented_rules() {
    let base = tiny(0.0);
    let with = |m: &str| {
        let text = base.replacen(
            r#""attributes": {"POSITION": 0}"#,
            r#""attributes": {"POSITION": 0}, "material": 0"#,
            1,
        );
        let text = text.replacen(
            r#""meshes""#,
            &format!(r#""materials": [{m}], "meshes""#),
            1,
        );
        let s = load(&write("material.gltf", text.as_bytes())).unwrap_or_else(|e| panic!("{e}"));
        s.materials[s.triangles[0].material as usize]
    };
    let pbr = |c: &str, m: f32, r: f32| {
        format!(
            r#""pbrMetallicRoughness": {{"baseColorFactor": [{c}, 1], "metallicFactor": {m}, "roughnessFactor": {r}}}"#
        )
    };
    use gpu_photon::bsdfs::{Bsdf, MetallicRoughness};
    let gltf_of = |m: &gpu_photon::scene::Material| match m.bsdf {
        Bsdf::MetallicRoughness(g) => g,
        _ => panic!("not a metallic-roughness material: {m:?}"),
    };
    // A smooth metal: Appendix B's metal lobe (F0 = base colour), no longer a plain mirror.
    let metal = gltf_of(&with(&format!("{{{}}}", pbr("0.9, 0.8, 0.7", 1.0, 0.0))));
    assert_eq!(
        (
            metal.base.get(),
            metal.metallic.float(),
            metal.roughness.float()
        ),
        (Vec3::new(0.9, 0.8, 0.7), 1.0, 0.0)
    );
    // Transmission with a volume of some thickness: a refracting dielectric of the ior.
    let glass = with(&format!(
        r#"{{{}, "extensions": {{"KHR_materials_transmission": {{"transmissionFactor": 1}}, "KHR_materials_ior": {{"ior": 1.33}}, "KHR_materials_volume": {{"thicknessFactor": 0.1}}}}}}"#,
        pbr("1, 1, 1", 0.0, 0.0)
    ));
    assert!(
        matches!(glass.bsdf, Bsdf::Glass(g) if g.eta == 1.33),
        "{glass:?}"
    );
    // Without a volume the transmission is thin-walled, as the extension defines it.
    let thin = gltf_of(&with(&format!(
        r#"{{{}, "extensions": {{"KHR_materials_transmission": {{"transmissionFactor": 1}}}}}}"#,
        pbr("1, 1, 1", 0.0, 0.0)
    )));
    assert_eq!(thin.transmission.float(), 1.0);
    // A dielectric: f0 from ior 1.5 (0.04), f90 1.
    let plastic = gltf_of(&with(&format!("{{{}}}", pbr("0.5, 0.5, 0.5", 0.0, 0.5))));
    let want = MetallicRoughness::new(Vec3::splat(0.5), 0.0, 0.5, Vec3::splat(0.04), 1.0, 0.0);
    assert!(
        (plastic.f0.get() - want.f0.get()).length() < 1e-6 && plastic.f90 == 1.0,
        "{plastic:?}"
    );
    // KHR_materials_specular: f0 = min(F0(ior) colour, 1) specular, f90 = specular.
    let tinted = gltf_of(&with(&format!(
        r#"{{{}, "extensions": {{"KHR_materials_specular": {{"specularFactor": 0.8, "specularColorFactor": [0.5, 1, 30]}}}}}}"#,
        pbr("0.5, 0.5, 0.5", 0.0, 0.5)
    )));
    assert!(
        (tinted.f0.get() - Vec3::new(0.016, 0.032, 0.8)).length() < 1e-6,
        "{tinted:?}"
    );
    assert_eq!(tinted.f90, 0.8);
    // No dielectric reflection and no metal: exactly Lambertian.
    let matte = with(&format!(
        r#"{{{}, "extensions": {{"KHR_materials_specular": {{"specularFactor": 0}}}}}}"#,
        pbr("0.5, 0.4, 0.3", 0.0, 0.7)
    ));
    assert!(
        matches!(matte.bsdf, Bsdf::Diffuse(d) if d.reflectance.get() == Vec3::new(0.5, 0.4, 0.3)),
        "{matte:?}"
    );
    // The default material (none given) is glTF's: white metal, roughness 1.
    let s = load(&write("default.gltf", base.as_bytes())).unwrap();
    let d = gltf_of(&s.materials[s.triangles[0].material as usize]);
    assert_eq!(
        (d.base.get(), d.metallic.float(), d.roughness.float()),
        (Vec3::ONE, 1.0, 1.0)
    );
}

#[test]
fn a_mirroring_transform_keeps_the_front_face() {
    // The triangle (0,0,0), (1,0,0), (0,1,0) faces +z; mirrored in x it still does.
    for (scale, x) in [("[1, 1, 1]", 1.0), ("[-1, 1, 1]", -1.0)] {
        let text = tiny(0.0).replacen(
            r#"{"mesh": 0}"#,
            &format!(r#"{{"mesh": 0, "scale": {scale}}}"#),
            1,
        );
        let s = load(&write("mirrored.gltf", text.as_bytes())).unwrap();
        let t = s.triangles[0];
        assert!(t.normal().dot(Vec3::Z) > 0.999, "scale {scale}: {t:?}");
        assert!([t.v0, t.v1, t.v2].iter().any(|v| (v.x - x).abs() < 1e-6));
    }
}

#[test]
fn point_light_gltf_renders_as_its_toml_twin() {
    let (position, intensity) = (Vec3::new(0.1, 0.9, -0.2), Vec3::new(2.0, 1.5, 0.5));
    let path = write(
        "cornell-point.gltf",
        cornell_gltf(Some((position, intensity))).as_bytes(),
    );
    let g = load(&path).unwrap();
    let text = std::fs::read_to_string(root().join("scenes/cornell-box.toml")).unwrap();
    let cut = text.find("# The area light").unwrap();
    let twin = format!(
        "{}[[lights]]\ntype = \"point\"\nposition = [0.1, 0.9, -0.2]\nintensity = [2.0, 1.5, 0.5]\n",
        &text[..cut]
    );
    let t = load_str(&twin, "twin.toml", &root().join("scenes")).unwrap();
    let settings = gpu_photon::settings::RenderSettings {
        width: 64,
        height: 64,
        spp: 4,
        photons: 50_000,
        ..t.settings.clone()
    };
    let (a, _) = render(&g, &settings, Backend::Cpu, Progress::default()).unwrap();
    let (b, _) = render(&t, &settings, Backend::Cpu, Progress::default()).unwrap();
    let d = diff(&a, &b, 16).unwrap();
    eprintln!("point-light glTF vs TOML (64x64, 4 spp): {d:?}");
    assert!(a.mean().iter().all(|&m| m > 0.0));
    assert!(
        d.mean_ratio.iter().all(|r| (0.99..=1.01).contains(r)),
        "{d:?}"
    );
    assert!(d.rmse < 0.01, "{d:?}");
}

#[test]
fn camera_flag_picks_a_gltf_camera_by_name() {
    // Two cameras: "Front" at z = 3 and "Side" at x = 5 (the first in the traversal is Front).
    let two = tiny(0.0)
        .replacen(
            r#""nodes": [{"camera": 0, "translation": [0, 0, 3]}, {"mesh": 0}]"#,
            r#""nodes": [{"camera": 0, "translation": [0, 0, 3]}, {"mesh": 0}, {"camera": 1, "translation": [5, 0, 0]}]"#,
            1,
        )
        .replacen(r#""nodes": [0, 1]"#, r#""nodes": [0, 1, 2]"#, 1)
        .replacen(
            r#""cameras": [{"type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}}]"#,
            r#""cameras": [{"name": "Front", "type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}}, {"name": "Side", "type": "perspective", "perspective": {"yfov": 0.7, "znear": 0.1}}]"#,
            1,
        );
    let path = write("two-cameras.gltf", two.as_bytes());
    let eye = |name: Option<&str>| load_with_camera(&path, name).unwrap().camera.eye;
    assert_eq!(eye(None), Vec3::new(0.0, 0.0, 3.0));
    assert_eq!(eye(Some("Front")), Vec3::new(0.0, 0.0, 3.0));
    assert_eq!(eye(Some("Side")), Vec3::new(5.0, 0.0, 0.0));
    let err = load_with_camera(&path, Some("Top"))
        .unwrap_err()
        .to_string();
    assert!(
        err.ends_with("cameras: no camera named `Top` in the scene"),
        "{err}"
    );
    // Another format has one camera: naming one is a setting error, on the command line too.
    let toml = root().join("scenes/cornell-box.toml");
    let err = load_with_camera(&toml, Some("Side"))
        .unwrap_err()
        .to_string();
    assert_eq!(
        err,
        format!(
            "invalid setting camera: {} has one camera; --camera picks among a glTF scene's cameras",
            toml.display()
        )
    );
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_gpu-photon"))
        .args([
            "render",
            "scenes/cornell-box.toml",
            "--camera",
            "Side",
            "-o",
        ])
        .arg(root().join("target/test-output/gltf/never.png"))
        .current_dir(root())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        stderr.contains("--camera picks among a glTF scene's cameras"),
        "{stderr}"
    );
}

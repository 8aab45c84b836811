//! glTF normal maps in the frame the specification defines: `n = normalize(T m.x + B m.y +
//! N m.z)` with `B = w (N x T)` from the `TANGENT` attribute, MikkTSpace's tangents where a
//! primitive has none (the bitangent then points to the image's top, as glTF's +Y), and the
//! supplied tangents ignored without `NORMAL`. Checked at the hit (`Bvh::intersect`) against
//! that formula, through a mirroring node, and on both backends; malformed tangents give
//! exact messages.

mod common;

use glam::{Quat, Vec2, Vec3, Vec4};
use gpu_photon::bvh::Bvh;
use gpu_photon::importers::load;
use gpu_photon::math::geometry::Ray;
use gpu_photon::scene::Scene;
use std::path::{Path, PathBuf};

fn dir() -> PathBuf {
    let d = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/test-output/gltf-tangents");
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The normal texture's one texel (linear bytes): a normal tilted towards +X and +Y of its
/// tangent space.
const TEXEL: [u8; 3] = [180, 160, 230];

/// The tangent-space normal the texel encodes, `2 c - 1`.
fn texel_normal() -> Vec3 {
    Vec3::from_array(TEXEL.map(|b| b as f32 / 255.0)) * 2.0 - Vec3::ONE
}

fn png() -> Vec<u8> {
    let img = image::RgbaImage::from_raw(1, 1, vec![TEXEL[0], TEXEL[1], TEXEL[2], 255]).unwrap();
    let mut out = std::io::Cursor::new(Vec::new());
    image::DynamicImage::ImageRgba8(img)
        .write_to(&mut out, image::ImageFormat::Png)
        .unwrap();
    out.into_inner()
}

/// A normal-mapped quad in z = 0 (side 4, uvs glTF's way: v down the image, so the top edge
/// y = 2 has v = 0), seen by a camera at z = 3, lit by a directional light tilted 40 degrees
/// towards +x.
struct File {
    /// Per-vertex TANGENT, if any.
    tangent: Option<Vec4>,
    /// The accessor type TANGENT is declared with.
    tangent_type: &'static str,
    /// TANGENT elements (4 for a valid file).
    tangent_count: usize,
    /// The quad has a NORMAL attribute (+z).
    normals: bool,
    /// The mesh node's scale (a negative x mirrors it).
    scale: Vec3,
}

impl File {
    fn new(tangent: Option<Vec4>) -> Self {
        File {
            tangent,
            tangent_type: "VEC4",
            tangent_count: 4,
            normals: true,
            scale: Vec3::ONE,
        }
    }

    fn json(&self) -> String {
        let h = 2.0f32;
        let p = [
            Vec3::new(-h, -h, 0.0),
            Vec3::new(h, -h, 0.0),
            Vec3::new(h, h, 0.0),
            Vec3::new(-h, h, 0.0),
        ];
        let mut data: Vec<u8> = p
            .iter()
            .flat_map(|p| p.to_array())
            .flat_map(f32::to_le_bytes)
            .collect();
        let uv = p.map(|p| Vec2::new((p.x + h) / (2.0 * h), (h - p.y) / (2.0 * h)));
        data.extend(
            uv.iter()
                .flat_map(|uv| uv.to_array())
                .flat_map(f32::to_le_bytes),
        );
        data.extend(
            [0.0f32, 0.0, 1.0]
                .repeat(4)
                .iter()
                .flat_map(|x| x.to_le_bytes()),
        );
        let tangent_offset = data.len();
        let t = self.tangent.unwrap_or(Vec4::X);
        data.extend((0..4).flat_map(|_| t.to_array()).flat_map(f32::to_le_bytes));
        let index_offset = data.len();
        data.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
        let mut attributes = r#""POSITION": 0, "TEXCOORD_0": 1"#.to_string();
        if self.normals {
            attributes += r#", "NORMAL": 2"#;
        }
        if self.tangent.is_some() {
            attributes += r#", "TANGENT": 3"#;
        }
        let light = Quat::from_rotation_y(40f32.to_radians());
        format!(
            r#"{{"asset": {{"version": "2.0"}},
"extensionsUsed": ["KHR_lights_punctual"],
"scenes": [{{"nodes": [0, 1, 2]}}],
"nodes": [{{"camera": 0, "translation": [0, 0, 3]}}, {{"mesh": 0, "scale": {scale:?}}}, {{"rotation": {light:?}, "extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}}],
"cameras": [{{"type": "perspective", "perspective": {{"yfov": 0.9, "aspectRatio": 1, "znear": 0.1}}}}],
"extensions": {{"KHR_lights_punctual": {{"lights": [{{"type": "directional", "intensity": 1366}}]}}}},
"meshes": [{{"primitives": [{{"attributes": {{{attributes}}}, "indices": 4, "material": 0}}]}}],
"materials": [{{"pbrMetallicRoughness": {{"baseColorFactor": [0.8, 0.8, 0.8, 1], "metallicFactor": 0, "roughnessFactor": 1}}, "normalTexture": {{"index": 0}}}}],
"textures": [{{"source": 0}}],
"images": [{{"uri": "normal.png"}}],
"accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-2, -2, 0], "max": [2, 2, 0]}}, {{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}}, {{"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC3"}},
{{"bufferView": 3, "componentType": 5126, "count": {tangent_count}, "type": "{tangent_type}"}}, {{"bufferView": 4, "componentType": 5123, "count": 6, "type": "SCALAR"}}],
"bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": 48, "byteLength": 32}}, {{"buffer": 0, "byteOffset": 80, "byteLength": 48}}, {{"buffer": 0, "byteOffset": {tangent_offset}, "byteLength": 64}}, {{"buffer": 0, "byteOffset": {index_offset}, "byteLength": 12}}],
"buffers": [{{"byteLength": {len}, "uri": "data:application/octet-stream;base64,{b64}"}}]}}"#,
            scale = self.scale.to_array(),
            light = light.to_array(),
            tangent_count = self.tangent_count,
            tangent_type = self.tangent_type,
            len = data.len(),
            b64 = common::b64(&data),
        )
    }

    fn write(&self, name: &str) -> PathBuf {
        // Tests run in parallel: each writes the image whole, then renames it in place.
        let tmp = dir().join(format!("{name}.png"));
        std::fs::write(&tmp, png()).unwrap();
        std::fs::rename(&tmp, dir().join("normal.png")).unwrap();
        let path = dir().join(name);
        std::fs::write(&path, self.json()).unwrap();
        path
    }
}

fn loaded(path: &Path) -> Scene {
    load(path).unwrap_or_else(|e| panic!("{e}"))
}

/// The shading normal where a ray from the camera's side meets the quad at (0.3, 0.2).
fn shading_at(s: &Scene) -> Vec3 {
    let ray = Ray {
        origin: Vec3::new(0.3, 0.2, 3.0),
        dir: -Vec3::Z,
    };
    Bvh::build(s)
        .intersect(s, &ray, f32::INFINITY)
        .expect("the quad")
        .shading
}

/// glTF's normal for tangent `t`, bitangent sign `w` and normal `n` (world space).
fn spec_normal(t: Vec3, w: f32, n: Vec3) -> Vec3 {
    let m = texel_normal();
    let b = w * n.cross(t);
    (t * m.x + b * m.y + n * m.z).normalize()
}

fn assert_close(got: Vec3, want: Vec3, what: &str) {
    assert!((got - want).length() < 1e-5, "{what}: {got} vs {want}");
}

#[test]
fn supplied_tangents_set_the_frame() {
    for (t, name) in [
        (Vec4::new(1.0, 0.0, 0.0, 1.0), "x"),
        (Vec4::new(0.0, 1.0, 0.0, 1.0), "y"),
        (Vec4::new(1.0, 0.0, 0.0, -1.0), "x-flipped"),
        (Vec4::new(-0.6, 0.8, 0.0, -1.0), "diagonal"),
    ] {
        let s = loaded(&File::new(Some(t)).write(&format!("{name}.gltf")));
        assert_eq!(s.tangents.len(), s.triangles.len(), "{name}");
        let want = spec_normal(t.truncate(), t.w, Vec3::Z);
        assert_close(shading_at(&s), want, name);
    }
}

#[test]
fn generated_tangents_point_the_bitangent_to_the_image_top() {
    // MikkTSpace's: T along +u (+x), B to the image's top (+y, where v falls).
    let s = loaded(&File::new(None).write("mikk.gltf"));
    assert_eq!(s.tangents.len(), s.triangles.len());
    assert_close(
        shading_at(&s),
        spec_normal(Vec3::X, 1.0, Vec3::Z),
        "mikktspace",
    );
    // Without NORMAL the supplied tangents are ignored (the specification's MUST): the
    // triangle's own uv frame, flipped as MikkTSpace's where the mapping mirrors, is the
    // same frame.
    let mut f = File::new(Some(Vec4::new(0.0, 1.0, 0.0, 1.0)));
    f.normals = false;
    let s = loaded(&f.write("no-normals.gltf"));
    assert!(s
        .tangents
        .iter()
        .flatten()
        .all(|t| t.truncate().normalize() == Vec3::X));
    assert_close(
        shading_at(&s),
        spec_normal(Vec3::X, 1.0, Vec3::Z),
        "no normals",
    );
}

#[test]
fn a_mirroring_node_mirrors_the_frame() {
    // Scale -1 in x: T (object +x) goes to -x, B (object +y) stays, N stays +z.
    for tangent in [Some(Vec4::new(1.0, 0.0, 0.0, 1.0)), None] {
        let mut f = File::new(tangent);
        f.scale = Vec3::new(-1.0, 1.0, 1.0);
        let s = loaded(&f.write("mirror.gltf"));
        // B = w (N x T) = -(z x -x) = +y.
        let want = spec_normal(-Vec3::X, -1.0, Vec3::Z);
        assert_close(
            shading_at(&s),
            want,
            &format!("mirrored, tangent {tangent:?}"),
        );
    }
}

fn mean(img: &gpu_photon::render::film::Image) -> f32 {
    img.pixels.iter().map(|p| p[0] + p[1] + p[2]).sum::<f32>() / img.pixels.len() as f32
}

/// The GPU reads the same tangents: supplied ones (turned a quarter, which changes the
/// image) and generated ones render as on the CPU, up to f32 rounding.
#[test]
fn tangents_render_alike_on_both_backends() {
    let direct = |f: File, name: &str| common::direct_renders(&loaded(&f.write(name)), 24);
    let along_x = direct(File::new(Some(Vec4::new(1.0, 0.0, 0.0, 1.0))), "gx.gltf");
    let along_y = direct(File::new(Some(Vec4::new(0.0, 1.0, 0.0, 1.0))), "gy.gltf");
    let mikk = direct(File::new(None), "gm.gltf");
    // Lit from +x, a normal tilted to +x is brighter than one tilted to -x.
    let (a, b) = (mean(&along_x.0), mean(&along_y.0));
    assert!(a > 1.1 * b, "the tangent turns the normal: {a} vs {b}");
    assert!(
        (mean(&mikk.0) - a).abs() < 1e-3 * a,
        "mikktspace = +x tangent"
    );
    for (name, (cpu, gpu)) in [("x", along_x), ("y", along_y), ("mikk", mikk)] {
        if let Some(gpu) = gpu {
            let d = gpu_photon::render::image_diff::diff(&gpu, &cpu, 8).unwrap();
            assert!(d.max_error < 2e-3, "{name}: gpu vs cpu: {d:?}");
        }
    }
}

fn error_of(path: &Path) -> String {
    match load(path) {
        Ok(_) => panic!("{} loaded", path.display()),
        Err(e) => e.to_string(),
    }
}

#[test]
fn malformed_tangents_give_exact_messages() {
    let json_line = |f: &File| {
        f.json()
            .lines()
            .position(|l| l.contains("\"meshes\""))
            .unwrap()
            + 1
    };
    let mut f = File::new(Some(Vec4::X.with_w(1.0)));
    f.tangent_type = "VEC3";
    let path = f.write("vec3.gltf");
    assert_eq!(
        error_of(&path),
        format!(
            "{}:{}: meshes[0].primitives[0]: TANGENT must be VEC4 of FLOAT, not Vec3 of F32",
            path.display(),
            json_line(&f)
        )
    );
    let mut f = File::new(Some(Vec4::X.with_w(1.0)));
    f.tangent_count = 3;
    let path = f.write("count.gltf");
    assert_eq!(
        error_of(&path),
        format!(
            "{}:{}: meshes[0].primitives[0]: 3 TANGENTs for 4 POSITIONs",
            path.display(),
            json_line(&f)
        )
    );
}

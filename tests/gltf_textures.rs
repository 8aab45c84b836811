//! glTF texture coordinates and base colour textures: `TEXCOORD_n` (float and normalized
//! integer accessors) landing on `Scene.uvs`, `baseColorTexture` read from a file, a data URI
//! or a GLB bufferView with its sampler, `KHR_texture_transform` and `baseColorFactor`; a
//! textured quad under a directional light renders each texel's `albedo / pi * E` in its
//! image quadrant (the texture's orientation); malformed accessors and images give exact
//! `FILE:LINE: FIELD: what` messages.

mod common;

use glam::{Vec2, Vec3};
use gpu_photon::importers::load;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::Scene;
use gpu_photon::settings::{Mode, RenderSettings};
use gpu_photon::textures::{
    srgb_to_linear, Encoding, Filter, SceneTexture, Texels, UvTransform, Wrap,
};
use std::path::{Path, PathBuf};

fn dir() -> PathBuf {
    let d = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/test-output/gltf-textures");
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write(name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir().join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// sRGB bytes of the 2 x 2 test texture, row by row from the top: red, green / blue, yellow.
const TEXELS: [[u8; 3]; 4] = [[200, 30, 30], [30, 200, 30], [30, 30, 200], [200, 200, 30]];

fn png() -> Vec<u8> {
    let bytes: Vec<u8> = TEXELS
        .iter()
        .flat_map(|t| [t[0], t[1], t[2], 255])
        .collect();
    let img = image::RgbaImage::from_raw(2, 2, bytes).unwrap();
    let mut out = std::io::Cursor::new(Vec::new());
    image::DynamicImage::ImageRgba8(img)
        .write_to(&mut out, image::ImageFormat::Png)
        .unwrap();
    out.into_inner()
}

/// Half the side of the quad in z = 0; the camera at z = 3 sees [-1.5, 1.5]^2 of it.
const HALF: f32 = 2.0;
/// Irradiance of the directional light, W/m^2 (683 lux per W/m^2).
const E: f32 = 2.0;

/// One buffer: the quad's positions, then `uv_bytes` (the TEXCOORD accessor's data), then
/// indices, then `extra` (an embedded image).
struct Quad {
    positions: Vec<Vec3>,
    /// uv of each position, glTF's (v down: the top edge, y = HALF, has v = 0).
    uvs: Vec<Vec2>,
}

fn quad() -> Quad {
    let positions = vec![
        Vec3::new(-HALF, -HALF, 0.0),
        Vec3::new(HALF, -HALF, 0.0),
        Vec3::new(HALF, HALF, 0.0),
        Vec3::new(-HALF, HALF, 0.0),
    ];
    let uvs = positions
        .iter()
        .map(|p| Vec2::new((p.x + HALF) / (2.0 * HALF), (HALF - p.y) / (2.0 * HALF)))
        .collect();
    Quad { positions, uvs }
}

/// A glTF file of the textured quad: `image` is the image object's JSON; `uv_accessor`
/// overrides the TEXCOORD accessor (`{view}` is its bufferView), `uv_data` its bytes.
struct File {
    image: String,
    material_extra: String,
    /// The whole `materials` array, replacing the default textured Lambertian one.
    materials: Option<String>,
    uv_accessor: String,
    uv_data: Vec<u8>,
    uv_set: u32,
    /// Appended to the buffer (a GLB image), at a 4-byte boundary.
    extra: Vec<u8>,
    /// The buffer has no URI (a GLB's BIN chunk).
    glb: bool,
}

fn float_uvs(uvs: &[Vec2]) -> Vec<u8> {
    uvs.iter()
        .flat_map(|uv| [uv.x, uv.y])
        .flat_map(f32::to_le_bytes)
        .collect()
}

impl File {
    fn new(image: &str) -> Self {
        File {
            image: image.to_string(),
            material_extra: String::new(),
            materials: None,
            uv_accessor: r#"{"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC2"}"#
                .into(),
            uv_data: float_uvs(&quad().uvs),
            uv_set: 0,
            extra: Vec::new(),
            glb: false,
        }
    }

    /// The JSON, each top-level item on its own line, and the buffer.
    fn parts(&self) -> (String, Vec<u8>) {
        let q = quad();
        let mut data: Vec<u8> = q
            .positions
            .iter()
            .flat_map(|p| p.to_array())
            .flat_map(f32::to_le_bytes)
            .collect();
        let uv_offset = data.len();
        data.extend(&self.uv_data);
        while !data.len().is_multiple_of(4) {
            data.push(0);
        }
        let index_offset = data.len();
        data.extend([0u16, 1, 2, 0, 2, 3].iter().flat_map(|i| i.to_le_bytes()));
        while !data.len().is_multiple_of(4) {
            data.push(0);
        }
        let extra_offset = data.len();
        // An empty extra is 4 bytes of padding: bufferView 3 always lies in the buffer.
        let extra = match self.extra.is_empty() {
            true => vec![0; 4],
            false => self.extra.clone(),
        };
        data.extend(&extra);
        let uri = match self.glb {
            true => String::new(),
            false => format!(
                r#", "uri": "data:application/octet-stream;base64,{}""#,
                common::b64(&data)
            ),
        };
        let t = 0.5f32; // tan(yfov / 2): the camera sees [-1.5, 1.5]^2 at z = 0
        let json = format!(
            r#"{{"asset": {{"version": "2.0"}},
"extensionsUsed": ["KHR_lights_punctual", "KHR_materials_specular", "KHR_texture_transform"],
"scenes": [{{"nodes": [0, 1, 2]}}],
"nodes": [{{"camera": 0, "translation": [0, 0, 3]}}, {{"mesh": 0}}, {{"extensions": {{"KHR_lights_punctual": {{"light": 0}}}}}}],
"cameras": [{{"type": "perspective", "perspective": {{"yfov": {yfov}, "aspectRatio": 1, "znear": 0.1}}}}],
"extensions": {{"KHR_lights_punctual": {{"lights": [{{"type": "directional", "intensity": {lux}}}]}}}},
"meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "TEXCOORD_{set}": 1}}, "indices": 2, "material": 0}}]}}],
"materials": {materials},
"textures": [{{"source": 0, "sampler": 0}}],
"samplers": [{{"magFilter": 9728, "wrapS": 33071, "wrapT": 33648}}],
"images": [{image}],
"accessors": [{{"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-2, -2, 0], "max": [2, 2, 0]}}, {uv}, {{"bufferView": 2, "componentType": 5123, "count": 6, "type": "SCALAR"}}],
"bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": 48}}, {{"buffer": 0, "byteOffset": {uv_offset}, "byteLength": {uv_len}}}, {{"buffer": 0, "byteOffset": {index_offset}, "byteLength": 12}}, {{"buffer": 0, "byteOffset": {extra_offset}, "byteLength": {extra_len}}}],
"buffers": [{{"byteLength": {len}{uri}}}]}}"#,
            yfov = 2.0 * t.atan(),
            lux = 683.0 * E,
            set = self.uv_set,
            materials = self.materials.clone().unwrap_or(format!(
                r#"[{{"name": "textured", "pbrMetallicRoughness": {{"baseColorFactor": [1, 0.5, 0.25, 1], "baseColorTexture": {{"index": 0{extra}}}, "metallicFactor": 0, "roughnessFactor": 1}}, "extensions": {{"KHR_materials_specular": {{"specularFactor": 0}}}}}}]"#,
                extra = self.material_extra
            )),
            image = self.image,
            uv = self.uv_accessor,
            uv_len = self.uv_data.len().max(1),
            extra_len = extra.len(),
            len = data.len(),
        );
        (json, data)
    }

    /// Writes the file as `name` (GLB when `self.glb`).
    fn write(&self, name: &str) -> PathBuf {
        let (json, data) = self.parts();
        match self.glb {
            false => write(name, json.as_bytes()),
            true => write(name, &common::glb(&json, &data)),
        }
    }
}

fn loaded(path: &Path) -> Scene {
    load(path).unwrap_or_else(|e| panic!("{e}"))
}

/// The 4 corners' uvs of the quad's two triangles (indices 0 1 2, 0 2 3).
fn quad_corner_uvs(uvs: &[Vec2]) -> Vec<[Vec2; 3]> {
    vec![[uvs[0], uvs[1], uvs[2]], [uvs[0], uvs[2], uvs[3]]]
}

#[test]
fn base_colour_texture_loads_from_a_file_a_data_uri_and_a_glb_view() {
    write("quad1.png", &png());
    let file = loaded(&File::new(r#"{"uri": "quad1.png"}"#).write("file.gltf"));
    assert_eq!(file.uvs, quad_corner_uvs(&quad().uvs));
    assert_eq!(file.textures.len(), 1);
    assert_eq!(
        file.materials[file.triangles[0].material as usize]
            .bsdf
            .base_colour()
            .expect("a base colour")
            .texture,
        0
    );
    let SceneTexture::Bitmap(t) = &file.textures[0] else {
        panic!("not a bitmap")
    };
    assert_eq!((t.width, t.height), (2, 2));
    assert_eq!(t.sampler.filter, Filter::Nearest);
    assert_eq!(
        (t.sampler.wrap_u, t.sampler.wrap_v),
        (Wrap::Clamp, Wrap::Mirror)
    );
    assert_eq!(t.sampler.to_uv, UvTransform::IDENTITY);
    // The factor (1, 0.5, 0.25) is baked into float texels.
    assert!(matches!(t.texels, Texels::Float { channels: 4, .. }));
    for (i, bytes) in TEXELS.iter().enumerate() {
        let got = t.texel(i as u32 % 2, i as u32 / 2).truncate();
        let lin = Vec3::from_array(bytes.map(|b| srgb_to_linear(b as f64 / 255.0) as f32));
        let want = lin * Vec3::new(1.0, 0.5, 0.25);
        assert!(
            (got - want).abs().max_element() < 1e-6,
            "texel {i}: {got} vs {want}"
        );
    }

    let uri = format!(
        r#"{{"uri": "data:image/png;base64,{}"}}"#,
        common::b64(&png())
    );
    let data_uri = loaded(&File::new(&uri).write("data-uri.gltf"));
    assert_eq!(
        data_uri.textures,
        file.textures
            .iter()
            .map(|t| rename(t, &data_uri))
            .collect::<Vec<_>>()
    );
    let mut glb = File::new(r#"{"bufferView": 3, "mimeType": "image/png"}"#);
    glb.extra = png();
    glb.glb = true;
    let view = loaded(&glb.write("view.glb"));
    assert_eq!(
        view.textures,
        file.textures
            .iter()
            .map(|t| rename(t, &view))
            .collect::<Vec<_>>()
    );
    assert_eq!(view.uvs, file.uvs);
}

/// `t` named as `like`'s first texture (only the name differs between image sources).
fn rename(t: &SceneTexture, like: &Scene) -> SceneTexture {
    let (SceneTexture::Bitmap(t), SceneTexture::Bitmap(l)) = (t, &like.textures[0]) else {
        panic!("not bitmaps")
    };
    let mut t = t.clone();
    t.name = l.name.clone();
    SceneTexture::Bitmap(t)
}

#[test]
fn texture_transform_tex_coord_and_normalized_accessors() {
    write("quad2.png", &png());
    // KHR_texture_transform's texCoord override reads TEXCOORD_1; its offset, rotation and
    // scale become the sampler's to_uv; a white factor keeps the 8-bit texels.
    let mut f = File::new(r#"{"uri": "quad2.png"}"#);
    f.uv_set = 1;
    f.material_extra = r#", "texCoord": 0, "extensions": {"KHR_texture_transform": {"offset": [0.25, -0.5], "rotation": 0.3, "scale": [2, 3], "texCoord": 1}}"#.into();
    let (json, _) = f.parts();
    let json = json.replace("[1, 0.5, 0.25, 1]", "[1, 1, 1, 1]");
    let s = loaded(&write("transform.gltf", json.as_bytes()));
    assert_eq!(s.uvs, quad_corner_uvs(&quad().uvs));
    let SceneTexture::Bitmap(t) = &s.textures[0] else {
        panic!("not a bitmap")
    };
    assert_eq!(
        t.sampler.to_uv,
        UvTransform::from_gltf([0.25, -0.5], 0.3, [2.0, 3.0])
    );
    assert!(matches!(
        t.texels,
        Texels::Rgba8 {
            encoding: Encoding::Srgb,
            ..
        }
    ));

    // Normalized UNSIGNED_SHORT and UNSIGNED_BYTE uvs: x / 65535, x / 255.
    let short = [0u16, 65535, 32768, 1, 65535, 0, 0, 0];
    let mut f = File::new(r#"{"uri": "quad2.png"}"#);
    f.uv_data = short.iter().flat_map(|x| x.to_le_bytes()).collect();
    f.uv_accessor = r#"{"bufferView": 1, "componentType": 5123, "normalized": true, "count": 4, "type": "VEC2"}"#.into();
    let s = loaded(&f.write("short.gltf"));
    let want: Vec<Vec2> = short
        .chunks(2)
        .map(|c| Vec2::new(c[0] as f32 / 65535.0, c[1] as f32 / 65535.0))
        .collect();
    assert_eq!(s.uvs, quad_corner_uvs(&want));
    let bytes = [0u8, 255, 128, 1, 255, 0, 0, 0];
    f.uv_data = bytes.to_vec();
    f.uv_accessor = r#"{"bufferView": 1, "componentType": 5121, "normalized": true, "count": 4, "type": "VEC2"}"#.into();
    let s = loaded(&f.write("byte.gltf"));
    let want: Vec<Vec2> = bytes
        .chunks(2)
        .map(|c| Vec2::new(c[0] as f32 / 255.0, c[1] as f32 / 255.0))
        .collect();
    assert_eq!(s.uvs, quad_corner_uvs(&want));
}

#[test]
fn textured_quad_renders_each_texel_in_its_quadrant() {
    write("quad3.png", &png());
    let s = loaded(&File::new(r#"{"uri": "quad3.png"}"#).write("render.gltf"));
    let side = 32;
    let (img, gpu) = common::direct_renders(&s, side);
    let factor = Vec3::new(1.0, 0.5, 0.25);
    // Image quadrants (top-left, top-right, bottom-left, bottom-right) against texels in
    // file order: the image's top row is the texture's first, its left column the first.
    for (q, bytes) in TEXELS.iter().enumerate() {
        let (qx, qy) = (q as u32 % 2, q as u32 / 2);
        let mut sum = Vec3::ZERO;
        let mut n = 0;
        for py in 0..side / 2 - 1 {
            for px in 0..side / 2 - 1 {
                let (x, y) = (qx * (side / 2 + 1) + px, qy * (side / 2 + 1) + py);
                let p = img.pixels[(y * side + x) as usize];
                sum += Vec3::new(p[0], p[1], p[2]);
                n += 1;
            }
        }
        let mean = sum / n as f32;
        let lin = Vec3::from_array(bytes.map(|b| srgb_to_linear(b as f64 / 255.0) as f32));
        let want = lin * factor / std::f32::consts::PI * E;
        let err = ((mean - want) / want).abs().max_element();
        assert!(err < 1e-3, "quadrant {q}: {mean} vs {want}");
    }
    // The GPU renders the textured glTF scene as the CPU does: same random numbers, the
    // same texels bit for bit (tests/texture_gpu.rs), so only f32 rounding apart.
    if let Some(gpu) = gpu {
        let d = gpu_photon::render::image_diff::diff(&gpu, &img, 8).unwrap();
        assert!(d.max_error < 1e-4, "gpu vs cpu: {d:?}");
    }
}

/// A metallic-roughness material with every texture it reads (the 2x2 image as base colour,
/// metalness in blue and roughness in green, normal map, transmission, specular and specular
/// colour) loads them, and the GPU renders it as the CPU does: the same texels and the same
/// random numbers, so the images differ by f32 rounding in the BSDF and the perturbed
/// normals only.
#[test]
fn metallic_roughness_textures_render_alike_on_both_backends() {
    write("quad5.png", &png());
    let mut f = File::new(r#"{"uri": "quad5.png"}"#);
    f.materials = Some(
        r#"[{"name": "mr", "pbrMetallicRoughness": {"baseColorFactor": [1, 0.8, 0.6, 1], "baseColorTexture": {"index": 0}, "metallicFactor": 1, "roughnessFactor": 0.9, "metallicRoughnessTexture": {"index": 0}}, "normalTexture": {"index": 0, "scale": 0.5},
"extensions": {"KHR_materials_transmission": {"transmissionFactor": 0.5, "transmissionTexture": {"index": 0}}, "KHR_materials_specular": {"specularFactor": 0.7, "specularTexture": {"index": 0}, "specularColorTexture": {"index": 0}}}}]"#
            .into(),
    );
    let s = loaded(&f.write("mr.gltf"));
    let m = s.materials[s.triangles[0].material as usize];
    let gpu_photon::bsdfs::Bsdf::MetallicRoughness(mr) = m.bsdf else {
        panic!("not metallic-roughness: {:?}", m.bsdf)
    };
    let none = gpu_photon::textures::NO_TEXTURE;
    assert!(m.normal_texture != none);
    let slots = [
        mr.base,
        mr.metallic,
        mr.roughness,
        mr.f0,
        mr.transmission,
        mr.specular,
    ];
    assert!(slots.iter().all(|p| p.texture != none), "{slots:?}");
    let (cpu, gpu) = common::direct_renders(&s, 24);
    let mean: f32 = cpu.pixels.iter().map(|p| p[0] + p[1] + p[2]).sum::<f32>();
    assert!(mean > 0.0 && mean.is_finite(), "the quad renders: {mean}");
    if let Some(gpu) = gpu {
        let d = gpu_photon::render::image_diff::diff(&gpu, &cpu, 8).unwrap();
        assert!(d.max_error < 2e-3, "gpu vs cpu: {d:?}");
    }
}

/// glTF's `alphaMode`: MASK below the cutoff hides the quad, at or above it keeps it opaque
/// (no alpha test at all), BLEND shows it with probability alpha (CPU; tests/alpha.rs
/// compares the GPU).
#[test]
fn alpha_modes_cut_out_and_blend() {
    write("quad6.png", &png());
    let render_mean = |mode: &str, alpha: f32| {
        let mut f = File::new(r#"{"uri": "quad6.png"}"#);
        f.materials = Some(format!(
            r#"[{{"pbrMetallicRoughness": {{"baseColorFactor": [1, 1, 1, {alpha}], "baseColorTexture": {{"index": 0}}, "metallicFactor": 0}}, "alphaMode": "{mode}", "extensions": {{"KHR_materials_specular": {{"specularFactor": 0}}}}}}]"#
        ));
        let s = loaded(&f.write(&format!("alpha-{mode}-{alpha}.gltf")));
        let a = s.materials[s.triangles[0].material as usize].alpha;
        let settings = RenderSettings {
            width: 16,
            height: 16,
            spp: 32,
            mode: Mode::DirectOnly,
            ..s.settings.clone()
        };
        let (img, _) = render(&s, &settings, Backend::Cpu, Progress::default()).unwrap();
        let sum: f32 = img.pixels.iter().map(|p| p[0] + p[1] + p[2]).sum();
        (a, sum / img.pixels.len() as f32)
    };
    let (none, opaque) = render_mean("OPAQUE", 0.2);
    assert!(none.is_none() && opaque > 0.0);
    let (a, hidden) = render_mean("MASK", 0.3);
    assert_eq!(
        a.map(|a| a.mode),
        Some(gpu_photon::scene::AlphaMode::Mask(0.5))
    );
    assert_eq!(hidden, 0.0, "alpha 0.3 is below the default cutoff 0.5");
    let (a, kept) = render_mean("MASK", 0.7);
    assert!(
        a.is_none() && kept == opaque,
        "alpha 0.7 keeps the quad opaque"
    );
    let (a, half) = render_mean("BLEND", 0.5);
    assert_eq!(
        a.map(|a| (a.mode, a.factor)),
        Some((gpu_photon::scene::AlphaMode::Blend, 0.5))
    );
    // 16 x 16 x 32 camera rays, each stopped with probability 1/2: 0.6% relative error.
    assert!(
        (half / opaque - 0.5).abs() < 0.03,
        "blend: {half} vs {opaque}"
    );
}

/// The `FILE:LINE: ` prefix and the rest of the message of a file that must fail to load.
fn error_of(path: &Path) -> String {
    match load(path) {
        Ok(_) => panic!("{} loaded", path.display()),
        Err(e) => e.to_string(),
    }
}

/// The 1-based line of the first line of `json` containing `needle`.
fn line_of(json: &str, needle: &str) -> usize {
    json.lines().position(|l| l.contains(needle)).unwrap() + 1
}

#[test]
fn malformed_uvs_and_images_give_exact_messages() {
    write("quad4.png", &png());
    let primitive = |f: &File, name: &str, what: &str| {
        let path = f.write(name);
        let (json, _) = f.parts();
        let line = line_of(&json, "\"meshes\"");
        assert_eq!(
            error_of(&path),
            format!("{}:{line}: meshes[0].primitives[0]: {what}", path.display())
        );
    };
    // (uv accessor's component type, count and type; file; message)
    let cases = [
        (
            (5126, 2, "VEC3"),
            "vec3.gltf",
            "TEXCOORD_0 must be VEC2 of FLOAT, or of normalized U8 or U16, not Vec3 of F32",
        ),
        (
            (5121, 4, "VEC2"),
            "u8.gltf",
            "TEXCOORD_0 must be VEC2 of FLOAT, or of normalized U8 or U16, not Vec2 of U8",
        ),
        (
            (5126, 3, "VEC2"),
            "count.gltf",
            "3 TEXCOORD_0s for 4 POSITIONs",
        ),
        (
            (5126, 5, "VEC2"),
            "long.gltf",
            "5 elements run past the end of bufferView 1",
        ),
    ];
    for ((component, count, ty), name, what) in cases {
        let mut f = File::new(r#"{"uri": "quad4.png"}"#);
        f.uv_accessor = format!(
            r#"{{"bufferView": 1, "componentType": {component}, "count": {count}, "type": "{ty}"}}"#
        );
        primitive(&f, name, what);
    }
    let mut f = File::new(r#"{"uri": "quad4.png"}"#);
    f.uv_set = 1;
    primitive(
        &f,
        "set.gltf",
        "has no TEXCOORD_0 attribute, which its material's baseColorTexture reads",
    );

    let image = |f: &File, name: &str, what: String| {
        let path = f.write(name);
        let (json, _) = f.parts();
        let line = line_of(&json, "\"images\"");
        assert_eq!(
            error_of(&path),
            format!(
                "{}:{line}: images[0]: material textured: {what}",
                path.display()
            )
        );
    };
    let missing = dir().join("missing.png");
    image(
        &File::new(r#"{"uri": "missing.png"}"#),
        "missing.gltf",
        format!(
            "cannot read image {}: No such file or directory (os error 2)",
            missing.display()
        ),
    );
    let garbage = write("garbage.png", b"not an image");
    image(
        &File::new(r#"{"uri": "garbage.png"}"#),
        "garbage.gltf",
        format!(
            "image {}: unknown image format (expected PNG, JPEG, BMP, OpenEXR or Radiance HDR)",
            garbage.display()
        ),
    );
}

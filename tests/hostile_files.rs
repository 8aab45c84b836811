//! The importer crash and hang classes of issue 26, each found by a fuzzer: every file here
//! once panicked, aborted, allocated without bound or ran (nearly) forever. Each must now be
//! a located error, `FILE:LINE: field: message`, checked here in full.

use gpu_photon::importers::load;
use gpu_photon::importers::ply::read_ply;
use std::path::{Path, PathBuf};

/// A fresh directory for one test's files.
fn dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gpu-photon-hostile-{test}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `bytes` as `name` in a fresh directory for `test` and loads it; the error as
/// shown, with the directory left out (`name:LINE: field: message`).
fn load_error(test: &str, name: &str, bytes: &[u8]) -> String {
    let d = dir(test);
    let path = d.join(name);
    std::fs::write(&path, bytes).unwrap();
    let shown = match load(&path) {
        Ok(_) => panic!("{name} loaded"),
        Err(e) => e.to_string(),
    };
    let prefix = format!("{}/", d.display());
    shown.strip_prefix(&prefix).unwrap_or(&shown).to_string()
}

/// Checks that `bytes`, loaded as `name` (see [`load_error`]), fail with `want` as shown.
fn expect_error(test: &str, name: &str, bytes: &[u8], want: &str) {
    assert_eq!(load_error(test, name, bytes), want, "{test}");
}

/// A glTF file with one triangle mesh (POSITION `position`, `indices` if given) under node
/// 0, and three accessors (the first the triangle's positions). Line 7 holds the primitive.
fn gltf_mesh(position: &str, indices: &str) -> String {
    let floats: Vec<u8> = [0f32, 0., 0., 1., 0., 0., 0., 1., 0.]
        .iter()
        .flat_map(|x| x.to_le_bytes())
        .collect();
    let data = base64(&floats);
    let accessor = r#"{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}"#;
    format!(
        r#"{{
"asset": {{"version": "2.0"}},
"scene": 0,
"scenes": [{{"nodes": [0]}}],
"nodes": [{{"mesh": 0}}],
"meshes": [{{"primitives": [
{{"attributes": {{"POSITION": {position}}}{indices}}}
]}}],
"buffers": [{{"byteLength": 36, "uri": "data:application/octet-stream;base64,{data}"}}],
"bufferViews": [{{"buffer": 0, "byteLength": 36}}],
"accessors": [{accessor}, {accessor}, {accessor}]
}}"#
    )
}

/// Standard base64 with padding.
fn base64(bytes: &[u8]) -> String {
    const ABC: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let n = chunk.iter().fold(0u32, |n, &b| n << 8 | b as u32) << (8 * (3 - chunk.len()));
        for k in 0..4 {
            let c = ABC[(n >> (18 - 6 * k) & 63) as usize] as char;
            out.push(if k <= chunk.len() { c } else { '=' });
        }
    }
    out
}

#[test]
fn gltf_indices_name_items_that_exist() {
    // A POSITION accessor past the end panicked inside the gltf crate's validation.
    expect_error(
        "accessor",
        "t.gltf",
        gltf_mesh("7", "").as_bytes(),
        "t.gltf:7: meshes[0].primitives[0].attributes.POSITION: accessor 7 does not exist \
         (3 accessors)",
    );
    // 2^32 + 1 was read modulo 2^32: silently accessor 1.
    let indices = r#", "indices": 4294967297"#;
    expect_error(
        "wrap",
        "t.gltf",
        gltf_mesh("0", indices).as_bytes(),
        "t.gltf:7: meshes[0].primitives[0].indices: accessor 4294967297 does not exist \
         (3 accessors)",
    );
    let negative = gltf_mesh("0", "").replace(r#""nodes": [0]"#, r#""nodes": [-1]"#);
    expect_error(
        "negative",
        "t.gltf",
        negative.as_bytes(),
        "t.gltf:4: scenes[0].nodes[0]: must be an index (an integer >= 0), not -1",
    );
    let child = gltf_mesh("0", "").replace(r#"{"mesh": 0}"#, r#"{"mesh": 0, "children": [1]}"#);
    expect_error(
        "child",
        "t.gltf",
        child.as_bytes(),
        "t.gltf:5: nodes[0].children[0]: node 1 does not exist (1 node)",
    );
    let view = gltf_mesh("0", "").replace(r#"{"buffer": 0,"#, r#"{"buffer": 2,"#);
    expect_error(
        "view",
        "t.gltf",
        view.as_bytes(),
        "t.gltf:10: bufferViews[0].buffer: buffer 2 does not exist (1 buffer)",
    );
}

#[test]
fn gltf_camera_type_needs_its_parameters() {
    // `Option::unwrap()` on None in the gltf crate's `Camera::projection`.
    let text = gltf_mesh("0", "").replace(
        r#""nodes": [{"mesh": 0}],"#,
        "\"nodes\": [{\"mesh\": 0, \"camera\": 0}],\n\"cameras\": [{\"type\": \"orthographic\",\
         \n\"perspective\": {\"yfov\": 0.8, \"znear\": 0.1}}],",
    );
    expect_error(
        "camera",
        "t.gltf",
        text.as_bytes(),
        "t.gltf:6: cameras[0].type: type `orthographic` has no `orthographic` object",
    );
}

#[test]
fn gltf_accessor_count_is_checked_before_allocating() {
    // 2^31 VEC3 floats (24 GiB) were reserved before the count met its 36-byte view.
    let text = gltf_mesh("1", "").replacen(r#""count": 3"#, r#""count": 2147483648"#, 2);
    expect_error(
        "count",
        "t.gltf",
        text.as_bytes(),
        "t.gltf:7: meshes[0].primitives[0]: 2147483648 elements run past the end of \
         bufferView 0",
    );
}

#[test]
fn gltf_node_dag_unfolds_to_a_bounded_number_of_instances() {
    // 22 levels of `"children": [next, next]`: 4 million instances, once exponential time.
    let mut nodes: Vec<String> = (1..22)
        .map(|i| format!("{{\"children\": [{i}, {i}]}}"))
        .collect();
    nodes.push("{}".into());
    let text = format!(
        "{{\"asset\": {{\"version\": \"2.0\"}},\n\"scenes\": [{{\"nodes\": [0]}}],\n\
         \"nodes\": [\n{}\n]}}",
        nodes.join(",\n")
    );
    let start = std::time::Instant::now();
    // The one-million-and-first instance, in depth-first order, is of the deepest node.
    expect_error(
        "dag",
        "t.gltf",
        text.as_bytes(),
        "t.gltf:25: nodes[21]: the scene unfolds to more than 1000000 node instances (nodes \
         shared by several parents are instanced once per path)",
    );
    assert!(start.elapsed().as_secs() < 20, "took {:?}", start.elapsed());
}

#[test]
fn mitsuba_nesting_is_bounded() {
    // 10,000 nested `twosided` bsdfs overflowed the stack of the recursive bsdf reader.
    let depth = 10_000;
    let mut xml = String::from("<scene version=\"3.0.0\">\n");
    xml += &"<bsdf type=\"twosided\">\n".repeat(depth);
    xml += &"</bsdf>\n".repeat(depth);
    xml += "</scene>\n";
    // Element 65 below <scene> is on line 66.
    expect_error(
        "nesting",
        "t.xml",
        xml.as_bytes(),
        "t.xml:66: bsdf: elements nested deeper than 64 are not supported",
    );
}

#[test]
fn mitsuba_defaults_expand_to_a_bounded_size() {
    // `d{k} = $d{k-1}$d{k-1}`: 16 * 2^k bytes, d40 = 16 TiB.
    let mut xml = String::from("<scene version=\"3.0.0\">\n");
    xml += "<default name=\"d0\" value=\"0123456789abcdef\"/>\n";
    for k in 1..=40 {
        xml += &format!(
            "<default name=\"d{k}\" value=\"$d{}$d{}\"/>\n",
            k - 1,
            k - 1
        );
    }
    xml += "</scene>\n";
    // d17 would be 2 MiB: the first over 1 MiB, on line 19.
    expect_error(
        "defaults",
        "t.xml",
        xml.as_bytes(),
        "t.xml:19: default.d17: the value expands to more than 1048576 bytes (through `$d16`)",
    );
}

#[test]
fn mitsuba_includes_fan_out_to_a_bounded_count() {
    // f{k} includes f{k+1} twice: 2^13 - 1 inclusions without a cycle, each chain well
    // under the depth limit; the 1025th included file is refused at its include.
    let d = dir("include-fan");
    for k in 0..12 {
        let inc = format!("<include filename=\"f{}.xml\"/>\n", k + 1);
        let text = format!("<scene version=\"3.0.0\">\n{inc}{inc}</scene>\n");
        std::fs::write(d.join(format!("f{k}.xml")), text).unwrap();
    }
    std::fs::write(d.join("f12.xml"), "<scene version=\"3.0.0\"/>\n").unwrap();
    let xml = b"<scene version=\"3.0.0\">\n<include filename=\"f0.xml\"/>\n</scene>\n";
    let shown = load_error("include-fan", "t.xml", xml);
    assert!(
        shown.ends_with(": include: more than 1024 included files"),
        "{shown}"
    );
}

#[test]
fn invalid_utf8_is_located() {
    let toml = b"[camera]\neye = [0, 0, 3]\ntarget = [0, 0, \xff]\nfov = 40\n";
    expect_error(
        "utf8-toml",
        "t.toml",
        toml,
        "t.toml:3: text: invalid UTF-8 at byte 41",
    );
    let xml = b"<scene version=\"3.0.0\">\n<!-- \xc3( -->\n</scene>\n";
    expect_error(
        "utf8-xml",
        "t.xml",
        xml,
        "t.xml:2: text: invalid UTF-8 at byte 29",
    );
}

/// A TOML scene with a camera, a material and one mesh shape of file `mesh` (line 10).
fn toml_mesh(mesh: &str) -> String {
    format!(
        "[camera]\neye = [0, 0, 3]\ntarget = [0, 0, 0]\nfov = 40\n[materials.w]\n\
         type = \"diffuse\"\nalbedo = [1, 1, 1]\n[[shapes]]\ntype = \"mesh\"\nfile = \"{mesh}\"\n\
         material = \"w\"\n"
    )
}

#[test]
fn referenced_files_must_be_regular_files() {
    // `/dev/zero` never ends: OBJ text grew and the PLY header reader allocated without
    // bound. A directory is refused the same way.
    expect_error(
        "zero-toml",
        "t.toml",
        toml_mesh("/dev/zero").as_bytes(),
        "t.toml:10: shapes[0].file: cannot read mesh /dev/zero: not a regular file",
    );
    expect_error(
        "dir-toml",
        "t.toml",
        toml_mesh("/tmp").as_bytes(),
        "t.toml:10: shapes[0].file: cannot read mesh /tmp: not a regular file",
    );
    let xml = "<scene version=\"3.0.0\">\n<shape type=\"ply\">\n\
               <string name=\"filename\" value=\"/dev/zero\"/>\n</shape>\n</scene>\n";
    expect_error(
        "zero-ply",
        "t.xml",
        xml.as_bytes(),
        "t.xml:3: shape[0].filename: /dev/zero: cannot read: not a regular file",
    );
    let texture = "<scene version=\"3.0.0\">\n<bsdf type=\"diffuse\">\n\
                   <texture type=\"bitmap\" name=\"reflectance\">\n\
                   <string name=\"filename\" value=\"/dev/zero\"/>\n</texture>\n</bsdf>\n\
                   </scene>\n";
    expect_error(
        "zero-texture",
        "t.xml",
        texture.as_bytes(),
        "t.xml:4: bsdf[0].reflectance.filename: /dev/zero: not a regular file",
    );
    let buffer = gltf_mesh("0", "").replace(
        "data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAA",
        "/dev/zero",
    );
    expect_error(
        "zero-gltf",
        "t.gltf",
        buffer.as_bytes(),
        "t.gltf:9: buffers[0]: cannot read buffer `/dev/zero`: not a regular file",
    );
}

/// Writes a binary little-endian PLY file: one triangle, then `extra` header lines.
fn ply(d: &Path, extra: &str) -> PathBuf {
    let mut bytes = format!(
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n\
         property float y\nproperty float z\nelement face 1\n\
         property list uchar int vertex_indices\n{extra}end_header\n"
    )
    .into_bytes();
    for x in [0f32, 0., 0., 1., 0., 0., 0., 1., 0.] {
        bytes.extend(x.to_le_bytes());
    }
    bytes.push(3);
    for i in [0i32, 1, 2] {
        bytes.extend(i.to_le_bytes());
    }
    let path = d.join("t.ply");
    std::fs::write(&path, bytes).unwrap();
    path
}

#[test]
fn ply_element_counts_fit_the_bytes_that_follow() {
    let d = dir("ply-count");
    // The file itself reads.
    assert_eq!(read_ply(&ply(&d, "")).unwrap().triangles.len(), 1);
    // 2^32 - 1 rows of nothing: 4 billion empty rows read one by one.
    let e = read_ply(&ply(&d, "element material 4294967295\n")).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}:9: element `material` has 4294967295 rows: with the elements before it they \
             need at least 4294967332 bytes, but only 49 bytes follow the header",
            d.join("t.ply").display()
        )
    );
    // A vertex count far past the payload is refused before any row is read.
    let path = ply(&d, "");
    let bytes = std::fs::read(&path).unwrap();
    let at = bytes.windows(8).position(|w| w == b"vertex 3").unwrap();
    let huge = [&bytes[..at], b"vertex 4000000000", &bytes[at + 8..]].concat();
    std::fs::write(&path, huge).unwrap();
    let e = read_ply(&path).unwrap_err();
    assert!(
        e.to_string().ends_with(
            ":3: element `vertex` has 4000000000 rows: with the elements before it they need \
             at least 48000000000 bytes, but only 49 bytes follow the header"
        ),
        "{e}"
    );
    // In ASCII a row is a line, so the parser stops where the file ends.
    let text = "ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
                property float z\nelement face 0\nproperty list uchar int vertex_indices\n\
                element material 4294967295\nend_header\n\n\n";
    std::fs::write(d.join("a.ply"), text).unwrap();
    let e = read_ply(&d.join("a.ply")).unwrap_err();
    assert_eq!(
        e.to_string(),
        format!(
            "{}:13: not a valid PLY file: Unexpected end of file while reading element \
             'material' (expected 4294967295, got 2)",
            d.join("a.ply").display()
        )
    );
}

#[test]
fn gltf_image_needs_a_source() {
    // `Option::unwrap()` on None in the gltf crate's `Image::source`.
    let no_mime = gltf_mesh("0", "").replace(
        "\"accessors\"",
        "\"images\": [{\"bufferView\": 0}],\n\"accessors\"",
    );
    expect_error(
        "image-mime",
        "t.gltf",
        no_mime.as_bytes(),
        "t.gltf:11: images[0].bufferView: an image in a bufferView needs a `mimeType`",
    );
    let nothing = gltf_mesh("0", "").replace(
        "\"accessors\"",
        "\"images\": [{\"name\": \"x\"}],\n\"accessors\"",
    );
    expect_error(
        "image-none",
        "t.gltf",
        nothing.as_bytes(),
        "t.gltf:11: images[0]: an image needs a `uri` or a `bufferView`",
    );
}

#[test]
fn mitsuba_defaults_expand_to_a_bounded_total() {
    // Each value under 1 MiB, but a thousand of them: 1 GiB kept from a 40 kB file.
    let mut xml = String::from("<scene version=\"3.0.0\">\n");
    xml += &format!("<default name=\"d0\" value=\"{}\"/>\n", "x".repeat(1 << 10));
    xml += "<default name=\"d1\" value=\"$d0$d0$d0$d0$d0$d0$d0$d0$d0$d0$d0$d0$d0$d0$d0$d0\"/>\n";
    let big = "$d1".repeat(63);
    for k in 2..1000 {
        xml += &format!("<default name=\"d{k}\" value=\"{big}\"/>\n");
    }
    xml += "</scene>\n";
    // d{k} (k >= 2) is 1008 KiB; d1 16 KiB and d0 1 KiB: d18 passes 16 MiB, on line 20.
    expect_error(
        "defaults-total",
        "t.xml",
        xml.as_bytes(),
        "t.xml:20: default.d18: the defaults expand to more than 16777216 bytes",
    );
}

#[test]
fn scene_budgets_stop_triangles_and_texels_at_the_shape_that_crosses_them() {
    use glam::Vec3;
    use gpu_photon::scene::{
        Material, Origin, SceneBudgets, SceneBuilder, Surface, MAX_TEXTURE_BYTES, MAX_TRIANGLES,
    };
    use gpu_photon::textures::{Encoding, SceneTexture, Texture};
    let defaults = SceneBudgets::default();
    assert_eq!(
        (defaults.max_triangles, defaults.max_texture_bytes),
        (MAX_TRIANGLES, MAX_TEXTURE_BYTES)
    );
    let at = |line: usize, field: &str| Origin {
        file: "t.toml".into(),
        line,
        field: field.into(),
    };
    let mut b = SceneBuilder::new();
    b.set_budgets(SceneBudgets {
        max_triangles: 13,
        max_texture_bytes: 100,
        max_bytes: u64::MAX,
        memory: None,
    });
    let white = b
        .add_material(None, Material::diffuse(Vec3::ONE), &at(1, "materials.w"))
        .unwrap();
    let (lo, hi) = (Vec3::ZERO, Vec3::ONE);
    b.add_box(lo, hi, 0.0, Surface::of(white), &at(5, "shapes[0]"))
        .unwrap();
    let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
    b.add_triangle(tri, Surface::of(white), &at(7, "shapes[1]"))
        .unwrap();
    // 13 triangles: the next box (12 more) is refused, with its own place.
    let e = b
        .add_box(lo, hi, 0.0, Surface::of(white), &at(9, "shapes[2]"))
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.toml:9: shapes[2]: the scene would have 25 triangles (12 from this shape), more \
         than the 13 a scene may have"
    );
    // A 4 x 4 RGBA8 texture is 64 bytes: the second passes the 100-byte budget.
    let texture = || {
        let t = Texture::from_rgba8("t.png", 4, 4, vec![0; 16], Encoding::Raw).unwrap();
        SceneTexture::Bitmap(t)
    };
    assert_eq!(b.add_texture(texture(), &at(11, "materials.a")).unwrap(), 0);
    let e = b
        .add_texture(texture(), &at(14, "materials.b"))
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "t.toml:14: materials.b: the scene's textures would take 128 bytes (64 for this one), \
         more than the 100 a scene may have"
    );
}

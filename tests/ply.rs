//! PLY meshes: ASCII, binary little- and big-endian and OBJ give the same triangles; a TOML
//! scene whose light is a PLY mesh builds and renders (CPU) exactly as its OBJ twin; every
//! malformed file gives its `FILE: what` message.

mod common;

use glam::Vec3;
use gpu_photon::importers::load_str;
use gpu_photon::importers::ply::{read_ply, PlyMesh};
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use gpu_photon::scene::Scene;
use gpu_photon::Error;
use std::path::{Path, PathBuf};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// A fresh scratch directory for one test.
#[derive(Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    Le,
    Be,
}

/// How a generated PLY file encodes its mesh.
#[derive(Clone, Copy)]
struct Encoding {
    format: Format,
    /// `float` or `double` (or anything else, to test the errors).
    coord: &'static str,
    /// The face list's count and index types.
    count: &'static str,
    index: &'static str,
    /// `vertex_indices` or `vertex_index`.
    list: &'static str,
}

const ASCII: Encoding = Encoding {
    format: Format::Ascii,
    coord: "float",
    count: "uchar",
    index: "int",
    list: "vertex_indices",
};

/// Appends `v` encoded as PLY type `ty`.
fn put(out: &mut Vec<u8>, ty: &str, v: f64, format: Format) {
    macro_rules! bytes {
        ($t:ty) => {{
            let x = v as $t;
            if format == Format::Be {
                x.to_be_bytes().to_vec()
            } else {
                x.to_le_bytes().to_vec()
            }
        }};
    }
    if format == Format::Ascii {
        let text = match ty {
            "float" => format!("{}", v as f32),
            "double" => format!("{v}"),
            _ => format!("{}", v as i64),
        };
        out.extend_from_slice(text.as_bytes());
        out.push(b' ');
        return;
    }
    out.extend(match ty {
        "char" => bytes!(i8),
        "uchar" => bytes!(u8),
        "short" => bytes!(i16),
        "ushort" => bytes!(u16),
        "int" => bytes!(i32),
        "uint" => bytes!(u32),
        "float" => bytes!(f32),
        "double" => bytes!(f64),
        _ => panic!("no type {ty}"),
    });
}

/// A PLY file of `positions` and polygon `faces`.
fn ply_bytes(positions: &[Vec3], faces: &[Vec<i64>], e: Encoding) -> Vec<u8> {
    let format = match e.format {
        Format::Ascii => "ascii",
        Format::Le => "binary_little_endian",
        Format::Be => "binary_big_endian",
    };
    let c = e.coord;
    let mut out = format!(
        "ply\nformat {format} 1.0\nelement vertex {}\nproperty {c} x\nproperty {c} y\n\
         property {c} z\nelement face {}\nproperty list {} {} {}\nend_header\n",
        positions.len(),
        faces.len(),
        e.count,
        e.index,
        e.list
    )
    .into_bytes();
    let end_line = |out: &mut Vec<u8>| {
        if e.format == Format::Ascii {
            out.pop();
            out.push(b'\n');
        }
    };
    for p in positions {
        for x in p.to_array() {
            put(&mut out, c, x as f64, e.format);
        }
        end_line(&mut out);
    }
    for f in faces {
        put(&mut out, e.count, f.len() as f64, e.format);
        for &i in f {
            put(&mut out, e.index, i as f64, e.format);
        }
        end_line(&mut out);
    }
    out
}

fn write(dir: &Path, name: &str, bytes: &[u8]) -> PathBuf {
    let path = dir.join(name);
    std::fs::write(&path, bytes).unwrap();
    path
}

/// A unit cube as six quads (polygons to fan-triangulate), outward winding, and its OBJ.
fn cube() -> (Vec<Vec3>, Vec<Vec<i64>>, String) {
    let positions: Vec<Vec3> = (0..8)
        .map(|i| Vec3::new((i & 1) as f32, (i >> 1 & 1) as f32, (i >> 2 & 1) as f32) - 0.5)
        .collect();
    let faces: Vec<Vec<i64>> = [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ]
    .iter()
    .map(|f| f.to_vec())
    .collect();
    let mut obj = String::new();
    for p in &positions {
        obj += &format!("v {} {} {}\n", p.x, p.y, p.z);
    }
    for f in &faces {
        let corners: Vec<String> = f.iter().map(|i| (i + 1).to_string()).collect();
        obj += &format!("f {}\n", corners.join(" "));
    }
    (positions, faces, obj)
}

/// Four lines: a valid camera.
const CAMERA: &str = "[camera]\neye = [0, 0, 3]\ntarget = [0, 0, 0]\nfov = 40\n";

/// A scene of one emissive mesh shape `file` (relative to `dir`), with `extra` keys.
fn mesh_scene(dir: &Path, file: &str, extra: &str) -> Result<Scene, Error> {
    let text = format!(
        "{CAMERA}[[shapes]]\ntype = \"mesh\"\nfile = \"{file}\"\nemission = [1, 2, 3]\n{extra}"
    );
    load_str(&text, "test.toml", dir)
}

#[test]
fn ascii_binary_and_obj_give_identical_triangles() {
    let dir = common::scratch("formats");
    let (positions, faces, obj) = cube();
    write(&dir, "cube.obj", obj.as_bytes());
    let encodings = [
        ASCII,
        Encoding {
            format: Format::Le,
            coord: "double",
            count: "int",
            index: "ushort",
            list: "vertex_index",
        },
        Encoding {
            format: Format::Be,
            coord: "float",
            count: "uchar",
            index: "uint",
            list: "vertex_indices",
        },
        Encoding {
            format: Format::Le,
            coord: "float",
            count: "ushort",
            index: "char",
            list: "vertex_indices",
        },
        Encoding {
            format: Format::Be,
            coord: "double",
            count: "char",
            index: "short",
            list: "vertex_index",
        },
    ];
    let mut meshes = Vec::new();
    for (n, e) in encodings.iter().enumerate() {
        let name = format!("cube{n}.ply");
        let path = write(&dir, &name, &ply_bytes(&positions, &faces, *e));
        let mesh = read_ply(&path).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(mesh.positions, positions, "{name}");
        assert_eq!(mesh.triangles.len(), 12, "{name}: two triangles per quad");
        assert_eq!(mesh.triangles[..2], [[0, 2, 3], [0, 3, 1]], "{name}: fans");
        assert_eq!(mesh.normals, None, "{name}");
        meshes.push(mesh);
        // Scaled (mirroring in x), translated, through the TOML scene: as the OBJ.
        for extra in ["", "scale = [-2, 1, 0.5]\ntranslate = [1, 2, 3]\n"] {
            let ply = mesh_scene(&dir, &name, extra).unwrap_or_else(|e| panic!("{e}"));
            let obj = mesh_scene(&dir, "cube.obj", extra).unwrap_or_else(|e| panic!("{e}"));
            assert_eq!(ply.triangles, obj.triangles, "{name} {extra}");
            assert_eq!(ply.lights, obj.lights, "{name} {extra}");
            assert_eq!(ply.materials, obj.materials, "{name} {extra}");
        }
    }
    assert!(meshes.windows(2).all(|w| w[0] == w[1]));
    // Outward winding kept: every face normal points away from the centre, also mirrored.
    let mirrored = mesh_scene(&dir, "cube1.ply", "scale = [-2, 1, 0.5]\n").unwrap();
    for t in &mirrored.triangles {
        let n = (t.v1 - t.v0).cross(t.v2 - t.v0);
        assert!(n.dot(t.v0 + t.v1 + t.v2) > 0.0, "{t:?} faces inwards");
    }
}

/// The checked-in twin of scenes/meshes/light.obj, and its binary encodings.
#[test]
fn light_twin_matches_the_obj_and_keeps_normals() {
    let ascii = read_ply(&root().join("tests/data/light.ply")).unwrap();
    assert_eq!(ascii.positions.len(), 7);
    assert_eq!(ascii.triangles.len(), 6);
    assert_eq!(ascii.normals, Some(vec![Vec3::NEG_Y; 7]));
    let dir = common::scratch("light");
    let faces: Vec<Vec<i64>> = ascii
        .triangles
        .iter()
        .map(|t| t.map(i64::from).to_vec())
        .collect();
    for format in [Format::Ascii, Format::Le, Format::Be] {
        let e = Encoding { format, ..ASCII };
        let path = write(&dir, "light.ply", &ply_bytes(&ascii.positions, &faces, e));
        let mesh = read_ply(&path).unwrap();
        let expect = PlyMesh {
            normals: None,
            uvs: None,
            ..ascii.clone()
        };
        assert_eq!(mesh, expect);
    }
    let obj = mesh_scene(&root().join("scenes"), "meshes/light.obj", "").unwrap();
    let ply = mesh_scene(&root().join("tests/data"), "light.ply", "").unwrap();
    assert_eq!(ply.triangles, obj.triangles);
}

#[test]
fn mesh_light_scene_with_a_ply_light_builds_and_renders_as_the_obj() {
    let scenes = root().join("scenes");
    let text = std::fs::read_to_string(scenes.join("mesh-light.toml")).unwrap();
    let twin = root().join("tests/data/light.ply");
    let ply_text = text.replace("meshes/light.obj", twin.to_str().unwrap());
    assert_ne!(ply_text, text);
    let obj = load_str(&text, "mesh-light.toml", &scenes).unwrap();
    let ply = load_str(&ply_text, "mesh-light-ply.toml", &scenes).unwrap();
    assert_eq!(ply.triangles, obj.triangles);
    assert_eq!(ply.materials, obj.materials);
    assert_eq!(ply.lights, obj.lights);
    assert_eq!(ply.lights.len(), 1);
    // One light of 6 triangles, area 3 sqrt(3)/2 x 0.09 = 0.2338: power pi A L.
    let area = 3.0 * 3f32.sqrt() / 2.0 * 0.09;
    let power = ply.lights[0].power;
    let expect = std::f32::consts::PI * area * Vec3::new(17.0, 12.0, 4.0);
    assert!(
        (power - expect).abs().max_element() < 1e-4 * expect.max_element(),
        "{power}"
    );

    let mut settings = obj.settings.clone();
    settings.width = 32;
    settings.height = 32;
    settings.spp = 2;
    settings.photons = 2000;
    settings.caustic_photons = 0;
    let (a, _) = render(&obj, &settings, Backend::Cpu, Progress::default()).unwrap();
    let (b, _) = render(&ply, &settings, Backend::Cpu, Progress::default()).unwrap();
    assert!(
        a.pixels.iter().any(|p| p[0] > 0.0),
        "the light lights the box"
    );
    assert_eq!(a, b, "byte-identical CPU images");
}

/// The message of `read_ply` on a file of `bytes`, with the path replaced by `FILE`.
fn message(dir: &Path, name: &str, bytes: &[u8]) -> String {
    let path = write(dir, name, bytes);
    let e = read_ply(&path).expect_err(name);
    let shown = e.to_string();
    assert_eq!(e.path, path);
    shown.replace(&path.display().to_string(), "FILE")
}

#[test]
fn malformed_files_give_clear_messages() {
    let dir = common::scratch("bad");
    let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
    let face = vec![vec![0, 1, 2]];
    let le = Encoding {
        format: Format::Le,
        ..ASCII
    };
    let good = ply_bytes(&tri, &face, le);
    let ascii = ply_bytes(&tri, &face, ASCII);
    assert!(ascii.ends_with(b"\n3 0 1 2\n"));
    let cases: Vec<(&str, Vec<u8>, &str)> =
        vec![
        (
            "truncated.ply",
            good[..good.len() - 3].to_vec(),
            "FILE: byte 215: not a valid PLY file: Unexpected end of file while reading binary element \
             'face' (expected 1, got 0): Couldn't find a list element at index 2: failed to fill \
             whole buffer",
        ),
        (
            "int-coords.ply",
            ply_bytes(&tri, &face, Encoding { coord: "int", ..le }),
            "FILE:3: vertex property `x` is int; expected float or double",
        ),
        (
            "float-indices.ply",
            ply_bytes(&tri, &face, Encoding { index: "float", ..le }),
            "FILE:7: face property `vertex_indices` is list uchar float; expected a list of integers",
        ),
        (
            "out-of-range.ply",
            ply_bytes(&tri, &[vec![0, 1, 3]], le),
            "FILE: byte 205: face 0 refers to vertex 3; the mesh has 3 vertices",
        ),
        (
            "negative.ply",
            ply_bytes(&tri, &[vec![0, 1, 2], vec![0, -1, 2]], le),
            "FILE: byte 218: face 1 refers to vertex -1; the mesh has 3 vertices",
        ),
        (
            "nan.ply",
            ply_bytes(&[Vec3::ZERO, Vec3::X, Vec3::NAN], &face, le),
            "FILE: byte 193: vertex 2 is not finite: [NaN, NaN, NaN]",
        ),
        (
            "no-faces.ply",
            ply_bytes(&tri, &[], le),
            "FILE:7: the mesh has no triangles",
        ),
        (
            "two-corners.ply",
            ply_bytes(&tri, &[vec![0, 1]], ASCII),
            "FILE:13: face 0 has 2 vertices; a face needs at least 3",
        ),
        (
            "no-face-element.ply",
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
              property float z\nend_header\n0 0 0\n"
                .to_vec(),
            "FILE:7: no `face` element: the mesh has no triangles",
        ),
        (
            "no-z.ply",
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
              element face 0\nproperty list uchar int vertex_indices\nend_header\n0 0\n"
                .to_vec(),
            "FILE:3: vertex property `z` is missing",
        ),
        (
            "no-list.ply",
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
              property float z\nelement face 0\nproperty int flags\nend_header\n0 0 0\n"
                .to_vec(),
            "FILE:7: the `face` element has no `vertex_indices` list",
        ),
        (
            "empty.ply",
            Vec::new(),
            "FILE:1: not a valid PLY file: Unexpected end of file while reading magic number",
        ),
        (
            // `end_header` joined to the line before: the header runs into binary data.
            "no-end.ply",
            {
                let at = good.windows(11).position(|w| w == b"\nend_header").unwrap();
                [&good[..at], &good[at + 1..]].concat()
            },
            "FILE:9: not a valid PLY file: the header has invalid UTF-8 at byte 182",
        ),
        (
            "not-ply.ply",
            b"v 0 0 0\n".to_vec(),
            "FILE:1: not a valid PLY file: Expected magic number 'ply'",
        ),
        (
            "bad-number.ply",
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
              property float z\nelement face 0\nproperty list uchar int vertex_indices\n\
              end_header\n0 0 zero\n"
                .to_vec(),
            "FILE:10: not a valid PLY file: Couldn't read element line: Couldn't parse element \
             line: error at 1:5",
        ),
        (
            "short-vertex.ply",
            String::from_utf8(ascii.clone()).unwrap().replace("\n1 0 0\n", "\n1 0\n").into_bytes(),
            "FILE:11: not a valid PLY file: Couldn't read element line: Expected element of type \
             'Scalar(Float)', but found nothing",
        ),
        (
            "short-ascii.ply",
            ascii[..ascii.len() - "3 0 1 2\n".len()].to_vec(),
            "FILE:13: not a valid PLY file: Unexpected end of file while reading element 'face' \
             (expected 1, got 0)",
        ),
    ];
    let mut wrong = Vec::new();
    for (name, bytes, expect) in &cases {
        let got = message(&dir, name, bytes);
        if got != *expect {
            wrong.push(format!("{name}: {got:?}"));
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");

    let missing = dir.join("missing.ply");
    let e = read_ply(&missing).unwrap_err().to_string();
    let expect = format!(
        "{}: cannot read: No such file or directory (os error 2)",
        missing.display()
    );
    assert_eq!(e, expect);
}

/// Through a TOML scene, the error names the scene file, the `file` key's line and field,
/// then the PLY file and what is wrong with it.
#[test]
fn a_bad_ply_in_a_scene_names_the_scene_line() {
    let dir = common::scratch("scene");
    let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
    write(&dir, "bad.ply", &ply_bytes(&tri, &[vec![0, 1, 5]], ASCII));
    let e = mesh_scene(&dir, "bad.ply", "").unwrap_err();
    let expect = format!(
        "test.toml:7: shapes[0].file: {}:13: face 0 refers to vertex 5; the mesh has 3 vertices",
        dir.join("bad.ply").display()
    );
    assert_eq!(e.to_string(), expect);
    assert!(matches!(e, Error::Scene { line: 7, .. }));
}

/// Every truncation of a binary and an ASCII file, and a header promising billions of
/// elements, is an error, never a panic (nor an allocation of the promised size).
#[test]
fn every_truncation_is_an_error() {
    let dir = common::scratch("cut");
    let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
    for format in [Format::Ascii, Format::Le, Format::Be] {
        let e = Encoding { format, ..ASCII };
        let bytes = ply_bytes(&tri, &[vec![0, 1, 2]], e);
        for len in 0..bytes.len() - 1 {
            let path = write(&dir, "cut.ply", &bytes[..len]);
            assert!(read_ply(&path).is_err(), "{len} of {} bytes", bytes.len());
        }
        let whole = write(&dir, "whole.ply", &bytes);
        assert_eq!(read_ply(&whole).unwrap().triangles, [[0, 1, 2]]);
    }
    let huge = String::from_utf8(ply_bytes(&tri, &[vec![0, 1, 2]], ASCII))
        .unwrap()
        .replace("element vertex 3", "element vertex 4000000000");
    let e = message(&dir, "huge.ply", huge.as_bytes());
    // The face line is read as a fourth vertex; the file ends on line 14.
    let expect = "FILE:14: not a valid PLY file: Unexpected end of file while reading element \
                  'vertex' (expected 4000000000, got 4)";
    assert_eq!(e, expect);
}

/// `gpu-photon render` on a scene with a bad PLY mesh exits 1 with the message, no panic;
/// with the good twin it renders.
#[test]
fn the_cli_reports_a_bad_ply_and_renders_a_good_one() {
    let dir = common::scratch("cli");
    let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
    write(&dir, "bad.ply", &ply_bytes(&tri, &[vec![0, 1, 9]], ASCII));
    let twin = root().join("tests/data/light.ply");
    let text = std::fs::read_to_string(root().join("scenes/mesh-light.toml")).unwrap();
    let good = text.replace("meshes/light.obj", twin.to_str().unwrap());
    let bad = text.replace("meshes/light.obj", "bad.ply");
    let run = |scene: &str, text: &str| {
        let path = write(&dir, scene, text.as_bytes());
        let out = dir.join("out.png");
        let o = std::process::Command::new(env!("CARGO_BIN_EXE_gpu-photon"))
            .args([
                "render",
                path.to_str().unwrap(),
                "-o",
                out.to_str().unwrap(),
            ])
            .args([
                "--width",
                "16",
                "--height",
                "16",
                "--spp",
                "1",
                "--backend",
                "cpu",
                "-q",
            ])
            .output()
            .expect("run gpu-photon");
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
            out,
        )
    };
    let (code, err, _) = run("bad.toml", &bad);
    assert_eq!(code, Some(1), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    let expect = format!(
        "{}:13: face 0 refers to vertex 9; the mesh has 3 vertices",
        dir.join("bad.ply").display()
    );
    assert!(err.contains(&expect), "{err}");
    let (code, err, out) = run("good.toml", &good);
    assert_eq!(code, Some(0), "{err}");
    assert!(out.exists());
}

/// A PLY quad with custom vertex and face properties, for Mitsuba's attribute grouping.
const ATTRIBUTE_PLY: &str = "ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
property uchar red
property uchar green
property uchar blue
property float temp_0
property float uv_x
property float uv_y
property float w_1
property float w_2
property float w_3
property float bad
element face 1
property list uchar int vertex_indices
property float color_r
property float color_g
property float color_b
property float weight_0
end_header
0 0 0 255 128 0 1.5 1 2 1 2 3 9
1 0 0 0 0 0 2.5 1 2 4 5 6 9
1 1 0 0 0 0 3.5 1 2 7 8 9 9
0 1 0 0 0 0 4.5 1 2 1 1 1 9
4 0 1 2 3 0.1 0.2 0.3 0.7
";

#[test]
fn custom_attributes_group_as_mitsuba_groups_them() {
    // Mitsuba 3.9.1's PLY reader (scripts/mitsuba_mesh_attribute_probe.py, the quad as two
    // triangles): red/green/blue as vertex_color (integers as they are: 255, not 1); temp_0
    // one field; uv_x uv_y (two fields) and `bad` (no postfix) ignored; w_1 w_2 w_3; the
    // face's color_r/g/b as face_color_color and weight_0, one row per triangle.
    let dir = std::env::temp_dir().join(format!("gpu-photon-ply-attr-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let mesh = read_ply(&write(&dir, "a.ply", ATTRIBUTE_PLY.as_bytes())).unwrap();
    let got: Vec<(&str, usize, &[f32])> = (mesh.attributes.iter())
        .map(|a| (a.name.as_str(), a.dim, &a.values[..]))
        .collect();
    let colour = [255.0, 128.0, 0.0, 0., 0., 0., 0., 0., 0., 0., 0., 0.];
    let want: Vec<(&str, usize, &[f32])> = vec![
        ("vertex_color", 3, &colour),
        ("vertex_temp", 1, &[1.5, 2.5, 3.5, 4.5]),
        (
            "vertex_w",
            3,
            &[1., 2., 3., 4., 5., 6., 7., 8., 9., 1., 1., 1.],
        ),
        ("face_color_color", 3, &[0.1, 0.2, 0.3, 0.1, 0.2, 0.3]),
        ("face_weight", 1, &[0.7, 0.7]),
    ];
    assert_eq!(got, want);
    // A value that is not finite (1e39 overflows a float) is kept: a mesh_attribute texture
    // that reads it refuses it (tests/mitsuba.rs).
    let inf = ATTRIBUTE_PLY.replace("1.5 1 2", "1e39 1 2");
    let mesh = read_ply(&write(&dir, "n.ply", inf.as_bytes())).unwrap();
    assert_eq!(mesh.attributes[1].values[0], f32::INFINITY);
}

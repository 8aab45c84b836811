//! Mitsuba's `serialized` meshes: the suite's file reads as Mitsuba 3.9.1 reads it
//! (`scripts/mitsuba_serialized_probe.py`); `shape_index` finds a mesh of a multi-mesh file
//! through its dictionary (versions 3 and 4), with `face_normals`, `flip_normals`,
//! `to_world`, double precision and colours; and hostile files (truncated, bad zlib, wrong
//! counts, huge counts, NaN) are errors naming the file, the byte and the field, never a
//! panic or an unbounded allocation.

use flate2::write::ZlibEncoder;
use flate2::Compression;
use glam::{Vec2, Vec3};
use gpu_photon::error::Error;
use gpu_photon::importers::mitsuba::{import, Imported};
use gpu_photon::scene::{Scene, Triangle, FLAT};
use std::io::Write;
use std::path::{Path, PathBuf};

/// A fresh directory for one test's files.
fn dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!(
        "gpu-photon-serialized-{test}-{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// One mesh of a serialized file.
#[derive(Clone, Default)]
struct Mesh {
    positions: Vec<f64>,
    normals: Option<Vec<f64>>,
    uvs: Option<Vec<f64>>,
    colors: Option<Vec<f64>>,
    faces: Vec<u32>,
    double: bool,
    /// Overrides the vertex and face counts written.
    counts: Option<(u64, u64)>,
}

/// A unit right triangle in z = 0, front +z, with one normal per vertex and uvs.
fn triangle() -> Mesh {
    Mesh {
        positions: vec![0., 0., 0., 1., 0., 0., 0., 1., 0.],
        normals: Some(vec![0., 0., 1., 0., 0., 1., 0., 0., 1.]),
        uvs: Some(vec![0., 0., 1., 0., 0., 1.]),
        faces: vec![0, 1, 2],
        ..Mesh::default()
    }
}

impl Mesh {
    /// The mesh's decompressed data (after its header) in `version`.
    fn payload(&self, version: u16) -> Vec<u8> {
        let mut flags = 0u32;
        flags |= if self.normals.is_some() { 0x1 } else { 0 };
        flags |= if self.uvs.is_some() { 0x2 } else { 0 };
        flags |= if self.colors.is_some() { 0x8 } else { 0 };
        flags |= if self.double { 0x2000 } else { 0x1000 };
        let mut out = flags.to_le_bytes().to_vec();
        if version == 4 {
            out.extend(b"mesh\0");
        }
        let (v, f) = self.counts.unwrap_or((
            (self.positions.len() / 3) as u64,
            (self.faces.len() / 3) as u64,
        ));
        out.extend(v.to_le_bytes());
        out.extend(f.to_le_bytes());
        let arrays = [
            &Some(self.positions.clone()),
            &self.normals,
            &self.uvs,
            &self.colors,
        ];
        for values in arrays.into_iter().flatten() {
            for &x in values {
                if self.double {
                    out.extend(x.to_le_bytes());
                } else {
                    out.extend((x as f32).to_le_bytes());
                }
            }
        }
        for i in &self.faces {
            out.extend(i.to_le_bytes());
        }
        out
    }

    /// The mesh's header and zlib stream.
    fn stream(&self, version: u16) -> Vec<u8> {
        let mut out = vec![0x1C, 0x04];
        out.extend(version.to_le_bytes());
        let mut z = ZlibEncoder::new(Vec::new(), Compression::default());
        z.write_all(&self.payload(version)).unwrap();
        out.extend(z.finish().unwrap());
        out
    }
}

/// A serialized file of `meshes` in `version`, with its dictionary.
fn file(meshes: &[Mesh], version: u16) -> Vec<u8> {
    let mut out = Vec::new();
    let mut offsets = Vec::new();
    for m in meshes {
        offsets.push(out.len() as u64);
        out.extend(m.stream(version));
    }
    for o in offsets {
        if version == 4 {
            out.extend(o.to_le_bytes());
        } else {
            out.extend((o as u32).to_le_bytes());
        }
    }
    out.extend((meshes.len() as u32).to_le_bytes());
    out
}

/// Imports a scene whose one shape (line 2) is the serialized file `name` in `d`, with the
/// extra parameters `params` (on line 3).
fn try_load(d: &Path, name: &str, params: &str) -> Result<Imported, Error> {
    let text = format!(
        "<scene version=\"3.0.0\"><sensor type=\"perspective\"/>\n<shape type=\"serialized\">\
         <string name=\"filename\" value=\"{name}\"/>\n{params}</shape></scene>\n"
    );
    import(&text, "t.xml", d)
}

fn load(d: &Path, name: &str, params: &str) -> Imported {
    try_load(d, name, params).unwrap_or_else(|e| panic!("{e}"))
}

/// The error of loading `bytes` as `t.serialized` with `params`, the directory left out.
fn error(test: &str, bytes: &[u8], params: &str) -> String {
    let d = dir(test);
    std::fs::write(d.join("t.serialized"), bytes).unwrap();
    let shown = match try_load(&d, "t.serialized", params) {
        Ok(_) => panic!("{test}: loaded"),
        Err(e) => e.to_string(),
    };
    shown.replace(&format!("{}/", d.display()), "")
}

/// The unit shading normal at `t`'s first corner: its vertex normal, or for a flat triangle
/// (also a smooth one whose normals all are its face's) its face normal.
fn normal_at(s: &Scene, t: &Triangle) -> Vec3 {
    if t.shading == FLAT {
        (t.v1 - t.v0).cross(t.v2 - t.v0).normalize()
    } else {
        s.shading_normals[t.shading as usize][0].normalize()
    }
}

fn close(a: Vec3, b: Vec3) -> bool {
    (a - b).abs().max_element() <= 1e-6
}

#[test]
fn suite_file_reads_as_mitsuba_reads_it() {
    // scripts/mitsuba_serialized_probe.py: Mitsuba 3.9.1's arrays for the suite's file.
    let positions = [
        Vec3::new(-2.85, 0.0, -7.6),
        Vec3::new(-2.85, 0.0, 0.599999),
        Vec3::new(2.85, 0.0, 0.599999),
        Vec3::new(2.85, 0.0, -7.6),
    ];
    let uvs = [
        Vec2::new(0.950589, 0.011584),
        Vec2::new(0.025105, 0.011584),
        Vec2::new(0.025105, 0.310873),
        Vec2::new(0.950589, 0.310873),
    ];
    let faces = [[0, 1, 2], [0, 2, 3]];
    let d = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mitsuba-suite/tests");
    let s = load(&d, "serialized/rectangle_normals_uv.serialized", "").scene;
    assert_eq!(s.triangles.len(), 2);
    for (t, f) in s.triangles.iter().zip(faces) {
        for (p, i) in [t.v0, t.v1, t.v2].into_iter().zip(f) {
            assert!(close(p, positions[i]), "{p} vs Mitsuba's {}", positions[i]);
        }
        // The file's normals (all +y).
        assert!(close(normal_at(&s, t), Vec3::Y), "{t:?}");
    }
    for (uv, f) in s.uvs.iter().zip(faces) {
        for (a, i) in uv.iter().zip(f) {
            let b = uvs[i];
            assert!((*a - b).abs().max_element() < 1e-6, "{a} vs Mitsuba's {b}");
        }
    }
}

#[test]
fn shape_index_finds_each_mesh_in_both_versions() {
    let d = dir("index");
    // Mesh 0 the triangle; mesh 1 the triangle moved to z = 2, in double precision, with
    // colours (read past) and no normals; mesh 2 without uvs.
    let mut second = triangle();
    second.positions = vec![0., 0., 2., 1., 0., 2., 0., 1., 2.];
    second.double = true;
    second.normals = None;
    second.colors = Some(vec![0.5; 9]);
    let mut third = triangle();
    third.uvs = None;
    third.positions = vec![0., 0., 3., 2., 0., 3., 0., 2., 3.];
    for version in [3, 4] {
        let name = format!("v{version}.serialized");
        let meshes = [triangle(), second.clone(), third.clone()];
        std::fs::write(d.join(&name), file(&meshes, version)).unwrap();
        for (index, z) in [(0, 0.0), (1, 2.0), (2, 3.0)] {
            let param = format!("<integer name=\"shape_index\" value=\"{index}\"/>");
            let s = load(&d, &name, &param).scene;
            assert_eq!(s.triangles.len(), 1);
            let t = s.triangles[0];
            let scale = if index == 2 { 2.0 } else { 1.0 };
            assert!(
                close(t.v1, Vec3::new(scale, 0.0, z)),
                "v{version} {index}: {t:?}"
            );
            // Mesh 1 has no normals: smooth from its face, as Mitsuba recomputes them.
            let n = normal_at(&s, &t);
            assert!(close(n, Vec3::Z), "v{version} {index}: {n}");
            assert_eq!(s.uvs.is_empty(), index == 2, "v{version} {index}");
        }
    }
    // face_normals: flat; flip_normals: the winding reversed; to_world: moved.
    let s = load(
        &d,
        "v4.serialized",
        "<boolean name=\"face_normals\" value=\"true\"/><boolean name=\"flip_normals\" \
         value=\"true\"/><transform name=\"to_world\"><translate x=\"5\"/></transform>",
    )
    .scene;
    let t = s.triangles[0];
    assert_eq!(t.shading, FLAT);
    let normal = (t.v1 - t.v0).cross(t.v2 - t.v0).normalize();
    assert!(close(normal, Vec3::NEG_Z), "{t:?}");
    assert!(close(t.v0, Vec3::new(5.0, 0.0, 0.0)), "{t:?}");
}

#[test]
fn hostile_files_are_located_errors() {
    let good = file(&[triangle(), triangle()], 4);
    let at = "t.xml:2: shape[0].filename: t.serialized";
    let cases: Vec<(&str, Vec<u8>, &str, String)> = vec![
        (
            "magic",
            [&[0x1D, 0x04], &good[2..]].concat(),
            "",
            format!(
                "{at}: byte 0: not a Mitsuba serialized mesh (format id 0x041D, expected 0x041C)"
            ),
        ),
        (
            "version",
            [&good[..2], &[5, 0], &good[4..]].concat(),
            "",
            format!("{at}: byte 2: unsupported serialized version 5 (Mitsuba 3 reads 3 and 4)"),
        ),
        (
            "header",
            good[..3].to_vec(),
            "",
            format!("{at}: byte 3: the file ends in its 4-byte header"),
        ),
        (
            "zlib",
            [&good[..4], b"not a zlib stream at all"].concat(),
            "",
            format!(
                "{at}: byte 4 (mesh 0's zlib stream), decompressed byte 0: flags: bad zlib \
                 data: corrupt deflate stream"
            ),
        ),
        (
            "truncated",
            triangle().stream(4)[..30].to_vec(),
            "",
            format!(
                "{at}: byte 4 (mesh 0's zlib stream), decompressed byte 0: flags: bad zlib \
                 data: incomplete deflate stream"
            ),
        ),
        (
            "index",
            file(
                &[Mesh {
                    faces: vec![0, 1, 3],
                    ..triangle()
                }],
                4,
            ),
            "",
            format!(
                "{at}: byte 4 (mesh 0's zlib stream), decompressed byte 121: faces: triangle \
                 0: vertex indices [0, 1, 3], not all below the vertex count 3"
            ),
        ),
        (
            "nan",
            file(
                &[Mesh {
                    positions: vec![0., 0., 0., f64::NAN, 0., 0., 0., 1., 0.],
                    ..triangle()
                }],
                3,
            ),
            "",
            format!(
                "{at}: byte 4 (mesh 0's zlib stream), decompressed byte 32: positions: \
                 vertex 1: [NaN, 0.0, 0.0] is not finite"
            ),
        ),
        (
            "normal",
            file(
                &[Mesh {
                    normals: Some(vec![0., 0., 1., 0., 0., 0., 0., 0., 1.]),
                    ..triangle()
                }],
                4,
            ),
            "",
            format!(
                "{at}: byte 4 (mesh 0's zlib stream), decompressed byte 73: normals: vertex \
                 1: [0.0, 0.0, 0.0] is not a finite, non-zero normal"
            ),
        ),
        (
            "more-faces",
            file(
                &[Mesh {
                    counts: Some((3, 2)),
                    ..triangle()
                }],
                4,
            ),
            "",
            format!(
                "{at}: byte 4 (mesh 0's zlib stream), decompressed byte 133: faces: the \
                 compressed stream ends here"
            ),
        ),
        (
            "no-faces",
            file(
                &[Mesh {
                    faces: vec![],
                    ..triangle()
                }],
                4,
            ),
            "",
            format!(
                "{at}: byte 4 (mesh 0's zlib stream), decompressed byte 17: face_count: the \
                 mesh has no triangles"
            ),
        ),
        (
            "out-of-range",
            good.clone(),
            "<integer name=\"shape_index\" value=\"2\"/>",
            format!(
                "t.xml:2: shape[0].filename: t.serialized: byte {}: shape_index 2 is out of \
                 range: the file's dictionary counts 2 meshes",
                good.len() - 4
            ),
        ),
        (
            "dictionary",
            [&good[..good.len() - 4], &1000u32.to_le_bytes()].concat(),
            "<integer name=\"shape_index\" value=\"1\"/>",
            format!(
                "{at}: byte {}: the dictionary's 1000 meshes do not fit in the file ({} bytes)",
                good.len() - 4,
                good.len()
            ),
        ),
        (
            "offset",
            [
                &good[..good.len() - 12],
                &u64::MAX.to_le_bytes(),
                &good[good.len() - 4..],
            ]
            .concat(),
            "<integer name=\"shape_index\" value=\"1\"/>",
            format!(
                "{at}: byte {}: the dictionary's offset of mesh 1 (18446744073709551615) is \
                 past the file's end ({} bytes)",
                good.len() - 12,
                good.len()
            ),
        ),
        (
            "negative",
            good.clone(),
            "<integer name=\"shape_index\" value=\"-1\"/>",
            "t.xml:3: shape[0].shape_index: -1 is not a mesh index (an integer >= 0)".into(),
        ),
    ];
    for (test, bytes, params, want) in cases {
        assert_eq!(error(test, &bytes, params), want, "{test}");
    }
    // Counts far past the budget are refused before anything is allocated.
    for (counts, field) in [
        ((3, u64::MAX), "17: face_count"),
        ((u64::MAX, 1), "9: vertex_count"),
    ] {
        let bytes = file(
            &[Mesh {
                counts: Some(counts),
                ..triangle()
            }],
            4,
        );
        let e = error("huge", &bytes, "");
        let want = format!("{at}: byte 4 (mesh 0's zlib stream), decompressed byte {field}: ");
        assert!(e.starts_with(&want), "{e}");
        assert!(
            e.ends_with("the scene's budget has room for")
                || e.contains("more than the scene's budget has room for"),
            "{e}"
        );
    }
    // Every prefix of a good file, and every single-byte change of one, is a mesh or an
    // error, never a panic.
    let d = dir("prefixes");
    for end in 0..good.len() {
        std::fs::write(d.join("t.serialized"), &good[..end]).unwrap();
        let _ = try_load(
            &d,
            "t.serialized",
            "<integer name=\"shape_index\" value=\"1\"/>",
        );
    }
    for i in 0..good.len() {
        let mut bad = good.clone();
        bad[i] ^= 0x5A;
        std::fs::write(d.join("t.serialized"), &bad).unwrap();
        let _ = try_load(&d, "t.serialized", "");
    }
    // Not a regular file.
    let d = dir("zero");
    let e = try_load(&d, "/dev/zero", "").unwrap_err().to_string();
    assert_eq!(
        e,
        "t.xml:2: shape[0].filename: /dev/zero: cannot read: not a regular file"
    );
}

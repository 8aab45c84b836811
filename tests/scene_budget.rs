//! The scene's budget (issue 44): what an importer is about to add is counted, with every
//! instance and repeated reference, and refused with a located error before it is allocated.
//! A glTF scene whose root list names a mesh node thousands of times once aborted on a failed
//! allocation under a 4 GiB address-space limit. `GPU_PHOTON_MEMORY` stands in for the
//! machine's memory in the command-line cases, so their messages do not depend on it.

mod common;

use common::{bin, scratch as dir};
use glam::Vec3;
use gpu_photon::importers::load;
use gpu_photon::scene::{Material, MeshCost, Origin, SceneBudgets, SceneBuilder, Surface};
use std::path::{Path, PathBuf};

/// The fuzzer's glTF sphere seed (4,096 smooth triangles) in `d`, its root list naming the
/// sphere's node `copies` times (then the camera's and the light's); the scene file's path
/// and the line of its `scenes[0].nodes`.
fn spheres(d: &Path, copies: usize) -> (PathBuf, usize) {
    let seed = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz/gltf/sphere");
    std::fs::copy(seed.join("scene.bin"), d.join("scene.bin")).unwrap();
    let text = std::fs::read_to_string(seed.join("scene.gltf")).unwrap();
    let mut json: serde_json::Value = serde_json::from_str(&text).unwrap();
    let mut roots = vec![serde_json::json!(0); copies];
    roots.extend([serde_json::json!(1), serde_json::json!(2)]);
    json["scenes"][0]["nodes"] = serde_json::Value::Array(roots);
    let text = serde_json::to_string_pretty(&json).unwrap();
    let scenes = text.lines().position(|l| l.contains("\"scenes\"")).unwrap();
    let line = scenes
        + 1
        + text
            .lines()
            .skip(scenes)
            .position(|l| l.contains("\"nodes\""))
            .unwrap();
    let path = d.join("scene.gltf");
    std::fs::write(&path, text).unwrap();
    (path, line)
}

/// `gpu-photon render FILE` on the CPU with `GPU_PHOTON_MEMORY=memory`: its stderr and exit
/// status.
fn render(file: &Path, memory: &str) -> (String, Option<i32>) {
    let out = file.with_extension("png");
    let o = bin()
        .arg("render")
        .arg(file)
        .args([
            "--backend",
            "cpu",
            "--width",
            "8",
            "--height",
            "8",
            "--spp",
            "1",
        ])
        .args(["--photons", "1000", "--passes", "0", "-q", "-o"])
        .arg(&out)
        .env("GPU_PHOTON_MEMORY", memory)
        .output()
        .unwrap();
    (
        String::from_utf8_lossy(&o.stderr).into_owned(),
        o.status.code(),
    )
}

#[test]
fn gltf_node_references_are_counted_before_any_is_built() {
    let d = dir("gltf-nodes");
    // 1,000 references: 4,096,000 smooth triangles, 84 bytes each, against half of 256 MiB.
    let (path, line) = spheres(&d, 1000);
    let (stderr, code) = render(&path, "256M");
    assert_eq!(
        stderr,
        format!(
            "error: {}:{line}: scenes[0].nodes: its 1002 node instances would need 4096000 \
             triangles / 328.1 MiB, over the scene's budget of 128.0 MiB (half the 256.0 MiB \
             available: GPU_PHOTON_MEMORY)\n",
            path.display()
        )
    );
    assert_eq!(code, Some(1));
    // 20,000 references pass the triangle count every machine has: 81,920,000 > 2^26.
    let (path, line) = spheres(&d, 20_000);
    let e = load(&path).map(|_| ()).unwrap_err().to_string();
    assert_eq!(
        e,
        format!(
            "{}:{line}: scenes[0].nodes: the scene would have 81920000 triangles (81920000 \
             from its 20002 node instances), more than the 67108864 a scene may have",
            path.display()
        )
    );
    // Within the budget it renders, the copies at the one place left out but the first.
    let (path, _) = spheres(&d, 3);
    let (stderr, code) = render(&path, "256M");
    assert_eq!(code, Some(0), "{stderr}");
    assert!(
        stderr.contains("nodes[0]: instanced again at the place of an earlier instance"),
        "{stderr}"
    );
    let one = load(&spheres(&d, 1).0).unwrap();
    let three = load(&spheres(&d, 3).0).unwrap();
    assert_eq!(one.triangles.len(), 4096);
    assert_eq!(three.triangles, one.triangles);
}

#[test]
fn gltf_buffers_are_counted_however_often_one_is_named() {
    // The external fuzzer's glTF naming its 1.8 MB buffer file 10,000 times aborted.
    let d = dir("gltf-buffers");
    let (path, _) = spheres(&d, 1);
    let mut json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    let buffer = json["buffers"][0].clone();
    json["buffers"] = serde_json::Value::Array(vec![buffer; 3]);
    let text = serde_json::to_string_pretty(&json).unwrap();
    std::fs::write(&path, &text).unwrap();
    let buffers = text
        .lines()
        .position(|l| l.contains("\"buffers\""))
        .unwrap();
    // The third: 3 x 100,632 bytes, past half of 400 KiB.
    let (stderr, code) = render(&path, "400K");
    assert_eq!(
        stderr,
        format!(
            "error: {}:{}: buffers[2]: the buffers so far take 301896 bytes, more than the \
             scene's budget of 204800 bytes\n",
            path.display(),
            buffers + 10
        )
    );
    assert_eq!(code, Some(1));
}

/// A TOML scene naming the mesh file `mesh` twice (lines 10 and 14).
fn two_meshes(d: &Path, mesh: &str) -> PathBuf {
    let text = format!(
        "[camera]\neye = [0, 0, 3]\ntarget = [0, 0, 0]\nfov = 40\n[materials.w]\n\
         type = \"diffuse\"\nalbedo = [1, 1, 1]\n[[shapes]]\ntype = \"mesh\"\nfile = \"{mesh}\"\n\
         material = \"w\"\n[[shapes]]\ntype = \"mesh\"\nfile = \"{mesh}\"\nmaterial = \"w\"\n\
         [[lights]]\ntype = \"point\"\nposition = [0, 2, 0]\nintensity = [1, 1, 1]\n"
    );
    let path = d.join("t.toml");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn mesh_files_are_refused_before_their_triangles_are_built() {
    let d = dir("mesh-files");
    // Three pentagons: 9 triangles. Half of 800 bytes is room for 8 flat ones (48 bytes).
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0\nv 0 1 0\n\
               f 1 2 3 4 5\nf 1 2 3 4 5\nf 1 2 3 4 5\n";
    std::fs::write(d.join("m.obj"), obj).unwrap();
    let (stderr, code) = render(&two_meshes(&d, "m.obj"), "800");
    let (toml, mesh) = (d.join("t.toml"), d.join("m.obj"));
    assert_eq!(
        stderr,
        format!(
            "error: {}:10: shapes[0].file: {}:8: the faces so far make 9 triangles, more than \
             the 8 the scene's budget has room for\n",
            toml.display(),
            mesh.display()
        )
    );
    assert_eq!(code, Some(1));
    // Room for the first reference (6 triangles, 288 bytes of 400), not for the second.
    let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0.5 1.5 0\nv 0 1 0\nf 1 2 3 4 5\nf 1 2 3 4 5\n";
    std::fs::write(d.join("m.obj"), obj).unwrap();
    let (stderr, _) = render(&two_meshes(&d, "m.obj"), "800");
    assert!(
        stderr.ends_with(&format!(
            "{}:6: the faces so far make 3 triangles, more than the 2 the scene's budget has \
             room for\n",
            mesh.display()
        )) && stderr.contains("t.toml:14: shapes[1].file: "),
        "{stderr}"
    );
    // PLY: rows the parser would keep past the room (416 bytes a vertex of three floats,
    // 224 a face), refused at the element's header line before the payload is read;
    // polygons that triangulate past the room, at the row that passes it.
    let ply = |faces: usize, corners: usize| {
        let mut t = format!(
            "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\n\
             property float z\nelement face {faces}\nproperty list uchar int vertex_indices\n\
             end_header\n0 0 0\n1 0 0\n1 1 0\n0.5 1.5 0\n0 1 0\n"
        );
        for _ in 0..faces {
            let list: Vec<String> = (0..corners).map(|i| (i % 5).to_string()).collect();
            t += &format!("{corners} {}\n", list.join(" "));
        }
        std::fs::write(d.join("m.ply"), t).unwrap();
    };
    let mesh = d.join("m.ply");
    ply(9, 3);
    let (stderr, _) = render(&two_meshes(&d, "m.ply"), "800");
    assert!(
        stderr.ends_with(&format!(
            "{}:3: element `vertex` has 5 rows: read, the elements so far take about 2.0 KiB, \
             more than the 384 bytes the scene's budget has room for\n",
            mesh.display()
        )),
        "{stderr}"
    );
    // One face of 100 corners, 98 triangles; half of 8000 bytes is room for 83.
    ply(1, 100);
    let (stderr, _) = render(&two_meshes(&d, "m.ply"), "8000");
    assert!(
        stderr.ends_with(&format!(
            "{}:15: the faces so far make 98 triangles, more than the 83 the scene's budget \
             has room for\n",
            mesh.display()
        )),
        "{stderr}"
    );
}

#[test]
fn shapes_and_textures_share_one_byte_budget() {
    let at = |line: usize, field: &str| Origin {
        file: "t.toml".into(),
        line,
        field: field.into(),
    };
    let mut b = SceneBuilder::new();
    // 10 flat triangles of 48 bytes, and 1 smooth one of 48 + 36.
    b.set_budgets(SceneBudgets {
        max_bytes: 10 * 48 + 84,
        memory: None,
        ..SceneBudgets::default()
    });
    let white = b
        .add_material(None, Material::diffuse(Vec3::ONE), &at(1, "materials.w"))
        .unwrap();
    let tri = [Vec3::ZERO, Vec3::X, Vec3::Y];
    b.add_mesh(vec![tri; 10], Surface::of(white), &at(3, "shapes[0]"))
        .unwrap();
    let refused = |r: gpu_photon::Result<()>, at: &str, n: usize, bytes: usize| {
        let want = format!(
            "t.toml:{at}: this shape would need {n} triangles / {bytes} bytes, over the \
             scene's budget of 564 bytes; the scene holds 480 bytes already"
        );
        assert_eq!(r.unwrap_err().to_string(), want);
    };
    let normals = Some(vec![[Vec3::Z, Vec3::Y, Vec3::X]; 2]);
    let smooth = b.add_smooth_mesh(vec![tri; 2], normals, Surface::of(white), &at(5, "s[1]"));
    refused(smooth, "5: s[1]", 2, 168);
    // Texture coordinates are kept for every triangle once one has them: 11 x 24 more.
    let uvs = vec![[glam::Vec2::ZERO; 3]];
    let textured = b.add_uv_mesh(vec![tri], None, uvs, Surface::of(white), &at(7, "s[2]"));
    refused(textured, "7: s[2]", 1, 312);
    // An instance list is checked by the same function, before it is built.
    let mesh = MeshCost::mesh(77_792, true, false, false);
    let e = b
        .check_geometry(mesh.times(1000), "1000 instances", &at(9, "nodes"))
        .unwrap_err();
    assert!(e
        .to_string()
        .starts_with("t.toml:9: nodes: the scene would have 77792010 triangles"));
}

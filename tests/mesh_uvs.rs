//! Texture coordinates from mesh files: OBJ `vt` (v flipped, Mitsuba's default for OBJ) and
//! PLY `u v` and its synonyms (kept, Mitsuba's default for PLY) through the TOML `mesh`
//! shape, Mitsuba's `obj` and `ply` shapes with and without `flip_tex_coords`, each corner's
//! uv following its vertex through fan triangulation and mirroring; and the exact messages
//! of malformed `vt` records, indices and PLY properties.

mod common;

use glam::{Vec2, Vec3};
use gpu_photon::importers::{load, load_str};
use gpu_photon::scene::Scene;
use gpu_photon::Error;
use std::path::Path;

/// A fresh scratch directory for one test.
/// The file's uv of the unit square's vertex at (x, y): distinct in u and v, never
/// symmetric under v -> 1 - v.
fn file_uv(x: f32, y: f32) -> Vec2 {
    Vec2::new(0.1 + 0.7 * x, 0.2 + 0.5 * y)
}

/// A TOML scene with one `mesh` shape of `file` and `extra` keys, loaded from `dir`.
fn toml_mesh(dir: &Path, file: &str, extra: &str) -> Result<Scene, Error> {
    let text = format!(
        "[camera]\neye = [0, 0, 3]\ntarget = [0, 0, 0]\nfov = 40\n\
         [materials.w]\ntype = \"diffuse\"\nalbedo = [1, 1, 1]\n\
         [[shapes]]\ntype = \"mesh\"\nmaterial = \"w\"\nfile = \"{file}\"\n{extra}"
    );
    load_str(&text, "test.toml", dir)
}

/// A Mitsuba scene with one `kind` shape of `file` and `extra` parameters, written to `dir`.
fn mitsuba_mesh(dir: &Path, kind: &str, file: &str, extra: &str) -> Scene {
    let text = format!(
        r#"<scene version="3.0.0"><sensor type="perspective"><float name="fov" value="40"/>
<transform name="to_world"><lookat origin="0, 0, 3" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
<shape type="{kind}"><string name="filename" value="{file}"/>{extra}</shape></scene>"#
    );
    let path = dir.join(format!("{kind}-{}.xml", extra.len()));
    std::fs::write(&path, text).unwrap();
    load(&path).unwrap_or_else(|e| panic!("{e}"))
}

/// Checks that every corner of every triangle has the uv `uv_of` its position, and that
/// there are `n` triangles.
fn check_uvs(s: &Scene, n: usize, uv_of: impl Fn(Vec3) -> Vec2, what: &str) {
    assert_eq!(s.triangles.len(), n, "{what}");
    assert_eq!(s.uvs.len(), n, "{what}");
    for (t, uvs) in s.triangles.iter().zip(&s.uvs) {
        for (p, uv) in [t.v0, t.v1, t.v2].into_iter().zip(uvs) {
            let want = uv_of(p);
            assert!(
                (*uv - want).abs().max_element() < 1e-6,
                "{what}: corner {p}: uv {uv}, expected {want}"
            );
        }
    }
}

/// The unit square as an OBJ quad whose `vt` records are listed in reverse vertex order
/// (so a `vt` index is not its `v` index), named by positive indices, then again by
/// negative ones.
fn square_obj() -> String {
    let mut s = String::from("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n");
    for (x, y) in [(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)] {
        let uv = file_uv(x, y);
        s += &format!("vt {} {}\n", uv.x, uv.y);
    }
    s + "f 1/4 2/3 3/2 4/1\nf 1/-1/ 2/-2/ 3/-3/ 4/-4/\n"
}

#[test]
fn obj_vt_lands_on_the_scene_with_v_flipped() {
    let dir = common::scratch("obj");
    std::fs::write(dir.join("square.obj"), square_obj()).unwrap();
    let flipped = |p: Vec3| {
        let uv = file_uv(p.x, p.y);
        Vec2::new(uv.x, 1.0 - uv.y)
    };
    let s = toml_mesh(&dir, "square.obj", "").unwrap();
    check_uvs(&s, 4, flipped, "TOML mesh");
    // The quad's fans: (v1, v2, v3), (v1, v3, v4), corners in order.
    assert_eq!(s.triangles[1].v1, Vec3::new(1.0, 1.0, 0.0));
    assert_eq!(s.uvs[1][1], flipped(Vec3::new(1.0, 1.0, 0.0)));
    // A mirroring scale swaps corners 1 and 2; each uv stays with its vertex.
    let m = toml_mesh(&dir, "square.obj", "scale = [-1, 1, 1]\n").unwrap();
    check_uvs(&m, 4, |p| flipped(Vec3::new(-p.x, p.y, p.z)), "mirrored");
    assert_eq!(m.triangles[0].v1, Vec3::new(-1.0, 1.0, 0.0));

    // Mitsuba's `obj`: flip_tex_coords defaults to true; false keeps the file's v.
    let d = mitsuba_mesh(&dir, "obj", "square.obj", "");
    check_uvs(&d, 4, flipped, "Mitsuba obj, default");
    let t = r#"<boolean name="flip_tex_coords" value="true"/>"#;
    check_uvs(
        &mitsuba_mesh(&dir, "obj", "square.obj", t),
        4,
        flipped,
        "true",
    );
    let f = r#"<boolean name="flip_tex_coords" value="false"/>"#;
    let kept = mitsuba_mesh(&dir, "obj", "square.obj", f);
    check_uvs(&kept, 4, |p| file_uv(p.x, p.y), "Mitsuba obj, false");
}

#[test]
fn obj_corners_without_vt_get_zero_and_meshes_without_vt_have_none() {
    let dir = common::scratch("obj-partial");
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0.25 0.75\nvt 0.5\nf 1/1 2 3/2\n";
    std::fs::write(dir.join("partial.obj"), text).unwrap();
    let s = toml_mesh(&dir, "partial.obj", "").unwrap();
    // vt 0.5 has v = 0, flipped to 1; the corner without vt is (0, 0), not flipped.
    let want = [Vec2::new(0.25, 0.25), Vec2::ZERO, Vec2::new(0.5, 1.0)];
    assert_eq!(s.uvs, vec![want]);
    std::fs::write(
        dir.join("plain.obj"),
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 1 1\nf 1 2 3\n",
    )
    .unwrap();
    let s = toml_mesh(&dir, "plain.obj", "").unwrap();
    assert!(s.uvs.is_empty(), "{:?}", s.uvs);
}

/// An ASCII PLY unit square (two triangles) with uv properties `names`, of type `ty`.
fn square_ply(names: [&str; 2], ty: &str, v1: &str) -> String {
    let mut s = format!(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n\
         property float z\nproperty {ty} {}\nproperty {ty} {}\nelement face 2\n\
         property list uchar int vertex_indices\nend_header\n",
        names[0], names[1]
    );
    for (i, (x, y)) in [(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]
        .iter()
        .enumerate()
    {
        let uv = file_uv(*x, *y);
        let v = if i == 1 {
            v1.to_string()
        } else {
            uv.y.to_string()
        };
        s += &format!("{x} {y} 0 {} {v}\n", uv.x);
    }
    s + "3 0 1 2\n3 0 2 3\n"
}

#[test]
fn ply_uvs_land_on_the_scene_unflipped() {
    let dir = common::scratch("ply");
    let v1 = file_uv(1.0, 0.0).y.to_string();
    for names in [
        ["u", "v"],
        ["s", "t"],
        ["texture_u", "texture_v"],
        ["texture_s", "texture_t"],
    ] {
        let file = format!("{}.ply", names[0]);
        std::fs::write(dir.join(&file), square_ply(names, "float", &v1)).unwrap();
        let s = toml_mesh(&dir, &file, "").unwrap();
        check_uvs(&s, 2, |p| file_uv(p.x, p.y), &file);
    }
    std::fs::write(dir.join("d.ply"), square_ply(["u", "v"], "double", &v1)).unwrap();
    check_uvs(
        &toml_mesh(&dir, "d.ply", "").unwrap(),
        2,
        |p| file_uv(p.x, p.y),
        "double",
    );
    // Mitsuba's `ply`: flip_tex_coords defaults to false.
    let d = mitsuba_mesh(&dir, "ply", "u.ply", "");
    check_uvs(&d, 2, |p| file_uv(p.x, p.y), "Mitsuba ply, default");
    let t = r#"<boolean name="flip_tex_coords" value="true"/>"#;
    let flipped = |p: Vec3| {
        let uv = file_uv(p.x, p.y);
        Vec2::new(uv.x, 1.0 - uv.y)
    };
    check_uvs(
        &mitsuba_mesh(&dir, "ply", "u.ply", t),
        2,
        flipped,
        "Mitsuba ply, true",
    );
    // Only one of a pair: no texture coordinates.
    let lone = square_ply(["u", "w"], "float", &v1);
    std::fs::write(dir.join("lone.ply"), lone).unwrap();
    assert!(toml_mesh(&dir, "lone.ply", "").unwrap().uvs.is_empty());
}

/// The message of a TOML mesh scene that must fail at `shapes[0].file` (line 11).
fn mesh_error(dir: &Path, file: &str, text: &str) -> String {
    std::fs::write(dir.join(file), text).unwrap();
    match toml_mesh(dir, file, "") {
        Err(Error::Scene {
            line,
            field,
            message,
            ..
        }) => {
            assert_eq!((line, field.as_str()), (11, "shapes[0].file"), "{message}");
            message
        }
        Err(e) => panic!("{file}: not a scene error: {e}"),
        Ok(_) => panic!("{file} loaded"),
    }
}

#[test]
fn malformed_texture_coordinates_give_exact_messages() {
    let dir = common::scratch("errors");
    let path = |f: &str| dir.join(f).display().to_string();
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let cases = [
        (
            "range.obj",
            format!("{tri}vt 0 0\nf 1/1 2/2 3/1\n"),
            "OBJ face corner `2/2`: texture coordinate index out of range (1 vt records before it)",
        ),
        (
            "negative.obj",
            format!("{tri}vt 0 0\nf 1/1 2/-2 3/1\n"),
            "OBJ face corner `2/-2`: texture coordinate index out of range (1 vt records before it)",
        ),
        (
            "later.obj",
            format!("{tri}f 1/1 2/1 3/1\nvt 0 0\n"),
            "OBJ face corner `1/1`: texture coordinate index out of range (0 vt records before it)",
        ),
        (
            "word.obj",
            format!("{tri}vt 0 x\nf 1/1 2/1 3/1\n"),
            "OBJ texture coordinate `vt 0 x`: `x` is not a number",
        ),
        (
            "empty.obj",
            format!("{tri}vt\nf 1/1 2/1 3/1\n"),
            "OBJ texture coordinate `vt` has no u",
        ),
        (
            "inf.obj",
            format!("{tri}vt inf 0\nf 1/1 2/1 3/1\n"),
            "OBJ texture coordinate (vt) [inf, 0] is not finite",
        ),
    ];
    // The line of the record at fault: the face, or the `vt` record.
    for ((file, text, want), line) in cases.into_iter().zip([5, 5, 4, 4, 4, 4]) {
        assert_eq!(
            mesh_error(&dir, file, &text),
            format!("{}:{line}: {want}", path(file))
        );
    }
    let int = square_ply(["u", "v"], "int", "0");
    assert_eq!(
        mesh_error(&dir, "int.ply", &int),
        format!(
            "{}:3: vertex property `u` is int; expected float or double",
            path("int.ply")
        )
    );
    let inf = square_ply(["s", "t"], "float", "1e39");
    assert_eq!(
        mesh_error(&dir, "inf.ply", &inf),
        format!(
            "{}:13: vertex 1: the texture coordinate (s, t) [{}, inf] is not finite",
            path("inf.ply"),
            file_uv(1.0, 0.0).x
        )
    );
}

/// The shading frame's tangent (`Hit::tangent`, the BSDF frame's x, along which an
/// anisotropic BSDF's `alpha_u` runs) equals Mitsuba 3.9.1's `si.sh_frame.s` at the hits
/// `scripts/mitsuba_shading_frame.py` measured: the per-triangle dp/du of a rotated uv sphere
/// mesh made orthogonal to its interpolated normal, the first edge of a mesh without uvs, and
/// an analytic sphere's azimuth direction.
#[test]
fn shading_frame_tangents_are_mitsubas() {
    let dir = common::scratch("shading-frame");
    let suite = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mitsuba-suite/common");
    let nouv = "v -1 -1 0\nv 1 -1 0.2\nv 1 1 0\nv -1 1 -0.3\nvn 0.1 0 1\nvn 0 0.2 1\n\
                vn -0.1 0.1 1\nvn 0.2 -0.1 1\nf 1//1 2//2 3//3\nf 1//1 3//3 4//4\n";
    std::fs::write(dir.join("nouv.obj"), nouv).unwrap();
    let sphere = suite.join("meshes/sphere.obj");
    let rotate = r#"<transform name="to_world"><rotate z="1" angle="30"/><rotate y="1" angle="30"/>
        <rotate x="1" angle="30"/></transform>"#;
    let shapes = [
        ("uv", format!(r#"<shape type="obj"><string name="filename" value="{}"/>{rotate}</shape>"#, sphere.display())),
        ("nouv", r#"<shape type="obj"><string name="filename" value="nouv.obj"/></shape>"#.into()),
        ("sphere", r#"<shape type="sphere"><point name="center" value="0.3, -0.2, 0.1"/><float name="radius" value="0.8"/></shape>"#.into()),
    ];
    let mut worst = 0f32;
    common::mitsuba_hits(
        &dir,
        "mitsuba_shading_frame.csv",
        &shapes,
        |name, _, hit, r| {
            let want = Vec3::new(r[9], r[10], r[11]);
            let e = (hit.tangent - want).abs().max_element();
            assert!(
                e < 1e-4,
                "{name} at {}: tangent {} vs Mitsuba's {want}",
                hit.position,
                hit.tangent,
            );
            worst = worst.max(e);
        },
    );
    eprintln!("worst tangent difference from Mitsuba 3.9.1: {worst:e}");
}

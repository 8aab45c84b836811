//! Our textures against Mitsuba 3.9.1 (values from `scripts/mitsuba_texture_values.py`):
//! the `bitmap` texture on PNG, EXR and HDR files with every filter, wrap mode and encoding
//! and a `to_uv` transform, the `checkerboard`, and the uv of Mitsuba's analytic shapes.

use glam::{Vec2, Vec3};
use gpu_photon::textures::{
    uv, Checkerboard, Encoding, Filter, Sampler, Texture, UvTransform, Wrap,
};
use std::collections::HashMap;
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/textures")
        .join(name)
}

fn rows(name: &str) -> Vec<Vec<String>> {
    let text = std::fs::read_to_string(data(name)).expect("reference csv");
    text.lines()
        .skip(1)
        .filter(|l| !l.is_empty())
        .map(|l| l.split(',').map(String::from).collect())
        .collect()
}

fn num(s: &str) -> f32 {
    s.parse().unwrap_or_else(|_| panic!("not a number: {s}"))
}

/// Within 1e-5, relative for values above 1.
fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (0..3).all(|c| (a[c] - b[c]).abs() <= tol * b[c].abs().max(1.0))
}

#[test]
fn bitmap_and_checkerboard_equal_mitsuba() {
    let mut images: HashMap<(String, String), Texture> = HashMap::new();
    let (mut checked, mut failures, mut worst) = (0, Vec::new(), 0.0f32);
    for r in rows("mitsuba_bitmap.csv") {
        let m: Vec<f32> = r[4..10].iter().map(|s| num(s)).collect();
        let to_uv =
            UvTransform::from_mitsuba([[m[0], m[1], m[2]], [m[3], m[4], m[5]], [0.0, 0.0, 1.0]]);
        let uv = Vec2::new(num(&r[10]), num(&r[11]));
        let want = Vec3::new(num(&r[12]), num(&r[13]), num(&r[14]));
        let got = if r[0] == "checkerboard" {
            let c = Checkerboard {
                color0: Vec3::new(0.1, 0.2, 0.3),
                color1: Vec3::new(0.9, 0.8, 0.7),
                to_uv,
            };
            c.eval(uv)
        } else {
            let enc = if r[1] == "raw" {
                Encoding::Raw
            } else {
                Encoding::Srgb
            };
            let tex = images
                .entry((r[0].clone(), r[1].clone()))
                .or_insert_with(|| Texture::load(&data(&r[0]), enc).expect("test image"));
            let s = Sampler::mitsuba(
                Filter::from_mitsuba(&r[2]).unwrap(),
                Wrap::from_mitsuba(&r[3]).unwrap(),
                to_uv,
            );
            tex.clone().with_sampler(s).eval(uv)
        };
        checked += 1;
        worst = worst.max((got - want).abs().max_element());
        if !close(got, want, 1e-5) {
            failures.push(format!(
                "{} {} {} {} uv {uv}: ours {got}, Mitsuba {want}",
                r[0], r[1], r[2], r[3]
            ));
        }
    }
    eprintln!("{checked} values, largest difference {worst:e}");
    assert!(checked > 4000, "only {checked} reference values");
    assert!(
        failures.is_empty(),
        "{} of {checked} differ:\n{}",
        failures.len(),
        failures[..failures.len().min(30)].join("\n")
    );
}

#[test]
fn shape_uvs_equal_mitsuba() {
    let (mut failures, mut worst) = (Vec::new(), 0.0f32);
    let rows = rows("mitsuba_uv.csv");
    for r in &rows {
        let p = Vec3::new(num(&r[1]), num(&r[2]), num(&r[3]));
        let want = Vec2::new(num(&r[4]), num(&r[5]));
        let got = match r[0].as_str() {
            "rectangle" => uv::rectangle(p),
            "disk" => uv::disk(p),
            "sphere" => uv::sphere(p),
            "cube" => uv::cube(p),
            s => panic!("unknown shape {s}"),
        };
        // Mitsuba's hit points are f32 and its angles f32: 1e-5 in uv.
        worst = worst.max((got - want).abs().max_element());
        if (got - want).abs().max_element() > 1e-5 {
            failures.push(format!("{} at {p}: ours {got}, Mitsuba {want}", r[0]));
        }
    }
    eprintln!(
        "{} shape points, largest uv difference {worst:e}",
        rows.len()
    );
    assert_eq!(rows.len(), 240);
    assert!(
        failures.is_empty(),
        "{} differ:\n{}",
        failures.len(),
        failures.join("\n")
    );
}

/// The Mitsuba importer's `cube` carries Mitsuba's per-face uvs: a ray from outside through
/// each cube point of the table hits it with Mitsuba's uv there (barycentric interpolation:
/// 1e-5).
#[test]
fn imported_cube_has_mitsuba_uvs() {
    let dir = std::env::temp_dir().join(format!("gpu_photon_cube_uv_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("cube.xml");
    let xml = r#"<scene version="3.0.0">
    <sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
    <shape type="cube"><bsdf type="diffuse"><texture name="reflectance" type="checkerboard"/></bsdf></shape>
</scene>"#;
    std::fs::write(&file, xml).unwrap();
    let scene = gpu_photon::importers::load(&file).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    let bvh = gpu_photon::bvh::CpuBvh::build(&scene);
    let mut checked = 0;
    for r in rows("mitsuba_uv.csv").iter().filter(|r| r[0] == "cube") {
        let p = Vec3::new(num(&r[1]), num(&r[2]), num(&r[3]));
        let want = Vec2::new(num(&r[4]), num(&r[5]));
        let ray = gpu_photon::math::geometry::Ray {
            origin: 3.0 * p,
            dir: -p.normalize(),
        };
        let hit = bvh
            .intersect(&scene, &ray, f32::INFINITY)
            .expect("the cube");
        assert!(
            (hit.position - p).abs().max_element() < 1e-4,
            "{p}: hit {}",
            hit.position
        );
        let got = hit.uv;
        assert!(
            (got - want).abs().max_element() < 1e-5,
            "{p}: ours {got}, Mitsuba {want}"
        );
        checked += 1;
    }
    assert_eq!(checked, 60);
}

/// A sphere's uv under a rotating `to_world` (various_shapes' sphere: scale 1.5, rotate x -35,
/// rotate y -25, translate): Mitsuba's parameterisation is its object space's
/// (`scripts/mitsuba_rotated_sphere_uv.py`: world hit point, u, v). The frame is held at
/// snorm16 precision: 1e-4 in uv.
#[test]
fn rotated_sphere_uv_equals_mitsuba() {
    #[rustfmt::skip]
    const HITS: &[([f32; 3], f32, f32)] = &[
        ([1.5, -5.0, -2.0], 0.04159446, 0.6125243),
        ([0.8074949, -4.533792, -0.8250096], 0.9957036, 0.305604),
        ([0.75, -3.700962, -2.0], 0.1705125, 0.3950942),
        ([5.709395e-17, -4.067585, -3.17499], 0.305173, 0.5722396),
        ([-0.75, -3.700962, -2.0], 0.3544741, 0.2663687),
        ([-0.8074949, -4.533792, -0.8250096], 0.6694788, 0.1049079),
        ([-1.5, -5.0, -2.0], 0.5415945, 0.3874758),
        ([-0.8074951, -5.466208, -3.17499], 0.4957037, 0.694396),
        ([-0.7499999, -6.299038, -2.0], 0.6705125, 0.6049058),
        ([-1.712819e-16, -5.932415, -0.8250095], 0.805173, 0.4277604),
        ([0.7499999, -6.299038, -2.0], 0.8544742, 0.7336314),
        ([0.8074951, -5.466208, -3.17499], 0.1694787, 0.8950921),
    ];
    let dir = std::env::temp_dir().join(format!("gpu_photon_sphere_uv_{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("sphere.xml");
    let xml = r#"<scene version="3.0.0">
    <sensor type="perspective"><transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>
    <shape type="sphere">
        <bsdf type="diffuse"><texture name="reflectance" type="checkerboard"/></bsdf>
        <transform name="to_world">
            <scale x="1.5" y="1.5" z="1.5"/>
            <rotate x="1.0" angle="-35"/>
            <rotate y="1.0" angle="-25"/>
            <translate x="0.0" y="-5.0" z="-2.0"/>
        </transform>
    </shape>
</scene>"#;
    std::fs::write(&file, xml).unwrap();
    let scene = gpu_photon::importers::load(&file).unwrap();
    std::fs::remove_dir_all(&dir).unwrap();
    let bvh = gpu_photon::bvh::CpuBvh::build(&scene);
    let centre = Vec3::new(0.0, -5.0, -2.0);
    assert_eq!(HITS.len(), 12);
    for &(p, u, v) in HITS {
        let n = (Vec3::from(p) - centre).normalize();
        let ray = gpu_photon::math::geometry::Ray {
            origin: centre + 4.0 * n,
            dir: -n,
        };
        let hit = bvh
            .intersect(&scene, &ray, f32::INFINITY)
            .expect("the sphere");
        let want = Vec2::new(u, v);
        let d = (hit.uv - want).abs();
        // u wraps at the seam.
        let du = d.x.min(1.0 - d.x);
        assert!(
            du < 1e-4 && d.y < 1e-4,
            "{p:?}: ours {}, Mitsuba {want}",
            hit.uv
        );
    }
}

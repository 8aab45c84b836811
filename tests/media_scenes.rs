//! The participating-media example scenes (issue 24) and their Mitsuba 3 twins, the files
//! Mitsuba rendered their references from (`scripts/media_references.py`): each TOML
//! (`scenes/fog-cornell.toml`, `scenes/volume-caustic.toml`) and its XML
//! (`scenes/mitsuba/*.xml`) load to the same media, camera medium, shapes, materials (media
//! interfaces included), light power, triangle and sphere counts and camera, to 1e-5.

use glam::Vec3;
use gpu_photon::bsdfs::{Bsdf, BsdfKind};
use gpu_photon::importers::load;
use gpu_photon::media::{MediumInterface, NO_MEDIUM};
use gpu_photon::scene::{Material, Scene};
use std::path::{Path, PathBuf};

const TOL: f32 = 1e-5;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn scene(path: &str) -> Scene {
    let path: PathBuf = root().join(path);
    load(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

/// Rounded to 1e-4, so that equal geometry compares equal.
fn key(v: Vec3) -> [i64; 3] {
    v.to_array().map(|c| (c * 1e4).round() as i64)
}

/// A shape: its corners (sorted; a sphere's centre and radius), its front normal (zero for a
/// sphere) and its material's index.
type Shape = (Vec<[i64; 3]>, [i64; 3], u32);

/// The shapes of `scene`, sorted: every pair of consecutive triangles of one material and
/// normal (a quad's, a rectangle's) and every sphere.
fn shapes(scene: &Scene) -> Vec<Shape> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < scene.triangles.len() {
        let t = scene.triangles[i];
        let mut corners = vec![key(t.v0), key(t.v1), key(t.v2)];
        let mut j = i + 1;
        if let Some(u) = scene.triangles.get(j) {
            if u.material == t.material && close(u.normal(), t.normal(), 1e-4) {
                corners.extend([key(u.v0), key(u.v1), key(u.v2)]);
                j += 1;
            }
        }
        corners.sort();
        corners.dedup();
        out.push((corners, key(t.normal()), t.material));
        i = j;
    }
    for s in &scene.spheres {
        out.push((
            vec![key(s.center), key(Vec3::splat(s.radius))],
            [0; 3],
            s.material,
        ));
    }
    out.sort();
    out
}

/// The same material: kind, media, emission, and every parameter (as its GPU words: the
/// numbers within `TOL`, the codes and textures equal).
fn same_material(a: &Material, b: &Material) -> bool {
    use gpu_photon::bsdfs::param::GpuWords;
    let words = |m: &Material| {
        let mut w = GpuWords::default();
        m.bsdf.gpu_words(&mut w);
        w.words
    };
    let (wa, wb) = (words(a), words(b));
    let word_close = |x: &[u32; 4], y: &[u32; 4]| {
        x.iter()
            .zip(y)
            .all(|(&p, &q)| p == q || (f32::from_bits(p) - f32::from_bits(q)).abs() <= TOL)
    };
    a.bsdf.code() == b.bsdf.code()
        && a.media == b.media
        && a.two_sided_emission == b.two_sided_emission
        && close(
            a.emission,
            b.emission,
            TOL * b.emission.max_element().max(1.0),
        )
        && wa.len() == wb.len()
        && wa.iter().zip(&wb).all(|(x, y)| word_close(x, y))
}

/// The TOML scene and the XML scene are the same scene, media included.
fn assert_same_scene(toml: &Scene, xml: &Scene) {
    assert_eq!(xml.triangles.len(), toml.triangles.len(), "triangles");
    assert_eq!(xml.spheres.len(), toml.spheres.len(), "spheres");
    let (a, b) = (shapes(toml), shapes(xml));
    assert_eq!(a.len(), b.len());
    for (s, t) in a.iter().zip(&b) {
        assert_eq!((&s.0, s.1), (&t.0, t.1), "geometry");
        let (m, n) = (&toml.materials[s.2 as usize], &xml.materials[t.2 as usize]);
        assert!(same_material(m, n), "shape {:?}: {m:?} vs {n:?}", s.0);
    }
    assert_eq!(xml.media.len(), toml.media.len(), "media");
    for (m, n) in toml.media.iter().zip(&xml.media) {
        assert!(close(m.sigma_t, n.sigma_t, TOL), "{m:?} vs {n:?}");
        assert!(close(m.albedo, n.albedo, TOL), "{m:?} vs {n:?}");
        assert!((m.phase.g - n.phase.g).abs() <= TOL, "{m:?} vs {n:?}");
    }
    assert_eq!(xml.camera_medium, toml.camera_medium);
    assert_eq!(xml.lights.len(), toml.lights.len(), "lights");
    for (l, k) in toml.lights.iter().zip(&xml.lights) {
        let tol = TOL * l.power.max_element();
        assert!(close(l.power, k.power, tol), "light power {l:?} vs {k:?}");
    }
    let (c, d) = (&toml.camera, &xml.camera);
    for (u, v) in [
        (c.eye, d.eye),
        (c.forward, d.forward),
        (c.right, d.right),
        (c.up, d.up),
    ] {
        assert!(close(u, v, 1e-6), "camera {c:?} vs {d:?}");
    }
    assert_eq!(
        (xml.settings.width, xml.settings.height),
        (toml.settings.width, toml.settings.height)
    );
    assert_eq!((toml.settings.width, toml.settings.height), (128, 128));
}

/// `scene` has one medium of `sigma_t` (grey), `albedo`, isotropic, holding the camera.
fn assert_fog(scene: &Scene, sigma_t: f32, albedo: f32) {
    assert_eq!(scene.media.len(), 1);
    let fog = &scene.media[0];
    assert!(close(fog.sigma_t, Vec3::splat(sigma_t), TOL), "{fog:?}");
    assert!(close(fog.albedo, Vec3::splat(albedo), TOL), "{fog:?}");
    assert_eq!(fog.phase.g, 0.0);
    assert_eq!(scene.camera_medium, 0);
}

/// Every shape of `scene` has the fog outside; which have it inside too.
fn interfaces(scene: &Scene) -> Vec<MediumInterface> {
    let of = |m: u32| scene.materials[m as usize].media;
    let mut all: Vec<MediumInterface> = scene.triangles.iter().map(|t| of(t.material)).collect();
    all.extend(scene.spheres.iter().map(|s| of(s.material)));
    for m in &all {
        assert_eq!(m.exterior, 0, "every shape has the fog outside");
    }
    all
}

#[test]
fn fog_cornell_toml_is_its_xml() {
    let toml = scene("scenes/fog-cornell.toml");
    let xml = scene("scenes/mitsuba/fog-cornell.xml");
    assert_same_scene(&toml, &xml);
    assert_fog(&toml, 0.3, 0.8);
    // The walls and the light (6 quads, 12 triangles) have fog on both sides, the blocks'
    // faces (10 quads) outside only.
    let both = interfaces(&toml).iter().filter(|m| m.interior == 0).count();
    assert_eq!((both, toml.triangles.len()), (12, 32));
}

/// fog-cornell is the default scene's box, materials and light, in fog.
#[test]
fn fog_cornell_is_the_cornell_box() {
    let fog = scene("scenes/fog-cornell.toml");
    let plain = scene("scenes/cornell-box.toml");
    let key_of = |s: &Scene| -> Vec<_> {
        shapes(s)
            .into_iter()
            .map(|(c, n, m)| {
                let mat = &s.materials[m as usize];
                let kd = mat.bsdf.base_colour().map_or(Vec3::ZERO, |p| p.get());
                (c, n, key(kd * 10.0), key(mat.emission))
            })
            .collect()
    };
    assert_eq!(key_of(&fog), key_of(&plain));
    assert_eq!(fog.lights.len(), plain.lights.len());
    for (l, k) in fog.lights.iter().zip(&plain.lights) {
        assert!(close(l.power, k.power, TOL * k.power.max_element()));
    }
    assert_eq!(format!("{:?}", fog.camera), format!("{:?}", plain.camera));
}

#[test]
fn volume_caustic_toml_is_its_xml() {
    let toml = scene("scenes/volume-caustic.toml");
    let xml = scene("scenes/mitsuba/volume-caustic.xml");
    assert_same_scene(&toml, &xml);
    assert_fog(&toml, 0.4, 0.9);
    interfaces(&toml);
    // One glass sphere, vacuum inside, fog outside.
    assert_eq!(toml.spheres.len(), 1);
    let glass = &toml.materials[toml.spheres[0].material as usize];
    assert!(
        matches!(glass.bsdf, Bsdf::Glass(g) if (g.eta - 1.5).abs() <= TOL),
        "{glass:?}"
    );
    assert_eq!(
        glass.media,
        MediumInterface {
            interior: NO_MEDIUM,
            exterior: 0
        }
    );
    // One small light: 0.15 x 0.15, radiance (160, 130, 90), one-sided: power pi A L.
    assert_eq!(toml.lights.len(), 1);
    let power = std::f32::consts::PI * 0.15 * 0.15 * Vec3::new(160.0, 130.0, 90.0);
    let got = toml.lights[0].power;
    assert!(
        close(got, power, TOL * power.max_element()),
        "{got} vs {power}"
    );
}

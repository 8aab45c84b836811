//! Mitsuba's `disk` and `cylinder` as meshes (`src/importers/mitsuba/round.rs`): placed as
//! Mitsuba places them, with their areas (so an area emitter's power is Mitsuba's pi A L),
//! facing out unless `flip_normals`, one warning each.

use glam::Vec3;
use gpu_photon::importers::mitsuba::{import, Imported};
use gpu_photon::scene::NO_LIGHT;
use std::f32::consts::PI;
use std::path::Path;

fn load(shapes: &str) -> Result<Imported, String> {
    let text = format!(
        "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><film type=\"hdrfilm\">\
         <integer name=\"width\" value=\"8\"/><integer name=\"height\" value=\"8\"/></film>\
         </sensor>\n{shapes}\n</scene>\n"
    );
    import(&text, "t.xml", Path::new(".")).map_err(|e| e.to_string())
}

#[test]
fn a_disk_emitter_has_mitsubas_power_and_faces_its_way() {
    let im = load(
        r#"<shape type="disk"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="180"/><translate z="2"/></transform>
<emitter type="area"><rgb name="radiance" value="2"/></emitter></shape>"#,
    )
    .unwrap();
    let s = &im.scene;
    assert_eq!(s.lights.len(), 1);
    let want = PI * (PI * 0.25) * 2.0;
    let power = s.lights[0].power;
    assert!(
        (power - Vec3::splat(want)).abs().max_element() < 1e-4 * want,
        "{power}"
    );
    for t in &s.triangles {
        assert_ne!(t.light, NO_LIGHT);
        assert!(
            (t.v1 - t.v0).cross(t.v2 - t.v0).z < 0.0,
            "rotated to face -z"
        );
        assert!((t.v0.z - 2.0).abs() < 1e-6);
    }
    assert_eq!(
        im.warnings,
        ["t.xml:3: shape[0]: a `disk` is rendered as 128 facets around (its area kept)"]
    );
}

#[test]
fn a_cylinder_lies_on_its_axis_with_its_area_facing_out() {
    for flip in [false, true] {
        let im = load(&format!(
            r#"<shape type="cylinder"><point name="p0" value="1, 0, 0"/><point name="p1" value="1, 0, 2"/>
<float name="radius" value="0.5"/><boolean name="flip_normals" value="{flip}"/></shape>"#
        ))
        .unwrap();
        let s = &im.scene;
        let area: f32 = s
            .triangles
            .iter()
            .map(|t| 0.5 * (t.v1 - t.v0).cross(t.v2 - t.v0).length())
            .sum();
        assert!((area - 2.0 * PI).abs() < 1e-4, "{area}");
        assert_eq!(s.uvs.len(), s.triangles.len());
        for t in &s.triangles {
            let c = (t.v0 + t.v1 + t.v2) / 3.0;
            let out = Vec3::new(c.x - 1.0, c.y, 0.0);
            let facing = (t.v1 - t.v0).cross(t.v2 - t.v0).dot(out) > 0.0;
            assert_eq!(facing, !flip);
            assert!(c.z > 0.0 && c.z < 2.0);
            for v in [t.v0, t.v1, t.v2] {
                let r = Vec3::new(v.x - 1.0, v.y, 0.0).length();
                assert!((r - 0.5).abs() < 2e-4, "{r}");
            }
        }
    }
}

#[test]
fn a_cylinder_without_length_is_an_error() {
    let e =
        load(r#"<shape type="cylinder"><point name="p1" value="0, 0, 0"/></shape>"#).unwrap_err();
    assert_eq!(e, "t.xml:3: shape[0].p1: p1 must differ from p0");
}

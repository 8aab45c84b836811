//! Scenes written for Mitsuba 0.x (`<scene version>` below 2.0.0) read as Mitsuba 3 reads
//! them: after its in-memory upgrade (camelCase names to snake_case, a diffuse bsdf's
//! `diffuseReflectance`, the `uscale`/`vscale`/`uoffset`/`voffset` floats as a `to_uv`
//! transform; Mitsuba 3.9.1's behaviour, `scripts/mitsuba_upgrade_probe.py`), file by file.

use gpu_photon::error::Error;
use gpu_photon::importers::mitsuba::{import_with, Imported};
use std::path::Path;

/// A scene in Mitsuba 3's names, each line as the old one below it will be.
const NEW: &str = r#"<scene version="3.0.0">
<integrator type="path"><integer name="max_depth" value="-1"/></integrator>
<sensor type="perspective"><float name="near_clip" value="0.1"/><float name="far_clip" value="100"/>
<transform name="to_world"><lookat origin="3,3,3" target="0,0,0" up="0,0,1"/></transform>
<float name="fov" value="25"/><string name="fov_axis" value="y"/>
<sampler type="ldsampler"><integer name="sample_count" value="64"/></sampler>
<film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="32"/><rfilter type="gaussian"/><boolean name="banner" value="false"/></film>
</sensor>
<bsdf type="roughplastic" id="floor"><string name="distribution" value="ggx"/><float name="alpha" value="0.05"/>
<float name="int_ior" value="1.46"/><rgb name="diffuse_reflectance" value="1,1,1"/></bsdf>
<shape type="sphere"><float name="radius" value="0.3"/><bsdf type="diffuse"><rgb name="reflectance" value="0.2,0.5,0.7"/></bsdf></shape>
<shape type="sphere"><float name="radius" value="0.2"/><transform name="to_world"><translate x="0.5" y="0" z="0"/></transform>
<bsdf type="diffuse"><texture type="checkerboard" name="reflectance">
<transform name="to_uv"><translate x="0.5" y="0"/><scale x="4" y="3"/></transform>
</texture></bsdf></shape>
<shape type="rectangle"><ref name="bsdf" id="floor"/><transform name="to_world"><scale x="10" y="10" z="1"/><translate x="0" y="0" z="-0.5"/></transform></shape>
<shape type="rectangle"><transform name="to_world"><scale x="10" y="10" z="1"/><lookat origin="-4,4,20" target="0,0,0" up="0,0,1"/></transform>
<emitter type="area"><rgb name="radiance" value="6,6,6"/></emitter></shape>
</scene>
"#;

/// [`NEW`] as a Mitsuba 0.5 file writes it, line for line.
fn old() -> String {
    NEW.replace("version=\"3.0.0\"", "version=\"0.5.0\"")
        .replace("max_depth", "maxDepth")
        .replace("near_clip", "nearClip")
        .replace("far_clip", "farClip")
        .replace("to_world", "toWorld")
        .replace("fov_axis", "fovAxis")
        .replace("sample_count", "sampleCount")
        .replace("int_ior", "intIOR")
        .replace("diffuse_reflectance", "diffuseReflectance")
        .replace(
            r#"<rgb name="reflectance" value="0.2,0.5,0.7"/>"#,
            r#"<rgb name="diffuseReflectance" value="0.2,0.5,0.7"/>"#,
        )
        .replace(
            r#"<transform name="to_uv"><translate x="0.5" y="0"/><scale x="4" y="3"/></transform>"#,
            r#"<float name="uscale" value="4"/><float name="vscale" value="3"/><float name="uoffset" value="0.5"/>"#,
        )
}

fn load(text: &str) -> Result<Imported, Error> {
    import_with(text.to_string(), "t.xml", Path::new("."), &[])
}

#[test]
fn a_mitsuba_0_5_scene_is_the_scene_mitsuba_3_reads() {
    let old = old();
    assert_eq!(old.lines().count(), NEW.lines().count());
    assert!(
        !old.contains("to_world") && old.contains("toWorld"),
        "{old}"
    );
    let new = load(NEW).unwrap();
    let upgraded = load(&old).unwrap();
    assert_eq!(format!("{:?}", upgraded.scene), format!("{:?}", new.scene));
    assert_eq!(upgraded.warnings, new.warnings);
}

#[test]
fn from_2_0_0_on_names_are_read_as_written() {
    let e = load(&old().replace("0.5.0", "2.0.0"))
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("t.xml:6: sensor[0].sampler.sampleCount: unsupported"),
        "{e}"
    );
}

#[test]
fn errors_in_an_upgraded_file_name_its_own_lines() {
    let old = old().replace(
        r#"<float name="fov" value="25"/>"#,
        r#"<float name="fov" value="25"/><float name="fooBar" value="1"/>"#,
    );
    let e = load(&old).unwrap_err().to_string();
    assert!(
        e.starts_with("t.xml:5: sensor[0].foo_bar: unsupported"),
        "{e}"
    );
    let bad = old.replace(r#"name="uscale" value="4""#, r#"name="uscale" value="x""#);
    let e = load(&bad).unwrap_err().to_string();
    assert_eq!(e, "t.xml:14: texture.uscale: `x` is not a number");
}

#[test]
fn an_included_file_is_upgraded_by_its_own_version() {
    let dir = std::env::temp_dir().join(format!("gp-mupgrade-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let with = |version: &str, name: &str| {
        let frag = format!(
            "<scene version=\"{version}\">\n<shape type=\"sphere\"><float name=\"radius\" \
             value=\"0.3\"/><bsdf type=\"diffuse\"><rgb name=\"{name}\" value=\"0.2\"/></bsdf>\
             </shape>\n</scene>\n"
        );
        std::fs::write(dir.join("frag.xml"), frag).unwrap();
        // The including file is Mitsuba 3's: its own names are not upgraded.
        let main = NEW.replace("</scene>", "<include filename=\"frag.xml\"/>\n</scene>");
        import_with(main, "t.xml", &dir, &[])
    };
    let new = with("3.0.0", "reflectance").unwrap();
    let old = with("0.6.0", "diffuseReflectance").unwrap();
    assert_eq!(format!("{:?}", old.scene), format!("{:?}", new.scene));
    let e = with("3.0.0", "diffuseReflectance").unwrap_err().to_string();
    assert!(
        e.contains("frag.xml:2:") && e.contains("diffuseReflectance"),
        "{e}"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

//! Mitsuba 3 XML as Mitsuba reads it: `<include>`, `<path>`, `<default>` with `--define`,
//! `<ref>` to any top-level object, spectra to RGB (values from Mitsuba 3.9.1 itself,
//! `scripts/mitsuba_spectra.py`), sensor parameters and integrator hints. Each test writes
//! its own small files.

use glam::Vec3;
use gpu_photon::bsdfs::Bsdf;
use gpu_photon::error::Error;
use gpu_photon::importers::load_with_options;
use gpu_photon::importers::mitsuba::{import, import_with, Imported, MAX_INCLUDE_DEPTH};
use gpu_photon::scene::{Scene, NO_TEXTURE};
use gpu_photon::settings::RenderSettings;
use std::path::{Path, PathBuf};
use std::process::Command;

/// A scratch directory unique to one test, removed when dropped.
struct Dir(PathBuf);

impl Dir {
    fn new(test: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("gp-mxml-{test}-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        Dir(dir)
    }
    /// Writes `text` to `name` (directories created) and returns its path.
    fn write(&self, name: &str, text: &str) -> PathBuf {
        let path = self.0.join(name);
        std::fs::create_dir_all(path.parent().unwrap()).unwrap();
        std::fs::write(&path, text).unwrap();
        path
    }
    fn path(&self, name: &str) -> String {
        self.0.join(name).display().to_string()
    }
}

impl Drop for Dir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A 64 x 32 camera, on line 2 of a scene from [`scene`].
const SENSOR: &str = r#"<sensor type="perspective"><float name="fov" value="40"/><film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="32"/><rfilter type="box"/></film></sensor>"#;

/// A scene: line 1 `<scene>`, line 2 the sensor, `body` from line 3.
fn scene(body: &str) -> String {
    format!("<scene version=\"3.0.0\">\n{SENSOR}\n{body}\n</scene>\n")
}

/// An included file: line 1 `<scene>`, `body` from line 2.
fn frag(body: &str) -> String {
    format!("<scene version=\"3.0.0\">\n{body}\n</scene>\n")
}

fn load_in(dir: &Path, text: &str, defines: &[(&str, &str)]) -> Result<Imported, Error> {
    let owned = |(n, v): &(&str, &str)| (n.to_string(), v.to_string());
    let defines: Vec<(String, String)> = defines.iter().map(owned).collect();
    import_with(text.to_string(), "t.xml", dir, &defines)
}

fn ok(body: &str) -> Imported {
    import(&scene(body), "t.xml", Path::new(".")).unwrap_or_else(|e| panic!("{e}"))
}

fn error(r: Result<Imported, Error>) -> String {
    r.map(|_| ()).expect_err("accepted").to_string()
}

#[track_caller]
fn assert_close(a: Vec3, b: [f32; 3], tol: f32) {
    assert!(
        (a - Vec3::from(b)).abs().max_element() <= tol,
        "{a} vs {b:?}"
    );
}

/// The diffuse albedo of the first triangle's material.
fn albedo(s: &Scene) -> Vec3 {
    s.materials[s.triangles[0].material as usize]
        .bsdf
        .base_colour()
        .map_or(Vec3::ZERO, |p| p.get())
}

const RECT: &str = r#"<shape type="rectangle"><ref id="white"/></shape>"#;

#[test]
fn include_splices_a_fragment_and_locates_its_errors() {
    let d = Dir::new("include");
    let white = r#"<bsdf type="diffuse" id="white"><rgb name="reflectance" value="0.25"/></bsdf>"#;
    d.write("fragments/base.xml", &frag(white));
    let text = scene(&format!(
        "<include filename=\"fragments/base.xml\"/>\n{RECT}"
    ));
    let im = load_in(&d.0, &text, &[]).unwrap();
    assert_eq!(albedo(&im.scene), Vec3::splat(0.25));
    assert_eq!(im.scene.triangles.len(), 2);

    // An error inside the included file names it and its line.
    d.write("bad.xml", &frag("\n<shape type=\"cone\"/>"));
    let text = scene("<include filename=\"bad.xml\"/>");
    let want = format!(
        "{}:3: shape[0]: unsupported shape `cone`",
        d.path("bad.xml")
    );
    assert_eq!(error(load_in(&d.0, &text, &[])), want);
    // So does a syntax error in it.
    d.write("broken.xml", &frag("<bsdf type=\"diffuse\">"));
    let text = scene("<include filename=\"broken.xml\"/>");
    let got = error(load_in(&d.0, &text, &[]));
    assert!(
        got.starts_with(&format!("{}:3: xml: ", d.path("broken.xml"))),
        "{got}"
    );
    // A missing file is an error at the include.
    let text = scene("<include filename=\"nowhere.xml\"/>");
    let want = "t.xml:3: include: included file `nowhere.xml` not found (searched: ";
    assert_eq!(
        error(load_in(&d.0, &text, &[])),
        format!("{want}{})", d.0.display())
    );
}

#[test]
fn include_cycles_and_depth_are_located_errors() {
    let d = Dir::new("cycle");
    d.write("a.xml", &frag("<include filename=\"b.xml\"/>"));
    d.write("b.xml", &frag("\n<include filename=\"a.xml\"/>"));
    let text = scene("<include filename=\"a.xml\"/>");
    let want = format!(
        "{}:3: include: include cycle: `{}` includes itself",
        d.path("b.xml"),
        d.path("a.xml")
    );
    assert_eq!(error(load_in(&d.0, &text, &[])), want);

    // A chain of includes: MAX_INCLUDE_DEPTH (Mitsuba's 15) nested files load, one more fails.
    let chain = |n: usize| {
        for i in 0..n {
            let next = match i + 1 < n {
                true => format!("<include filename=\"c{}.xml\"/>", i + 1),
                false => r#"<bsdf type="diffuse" id="white"/>"#.to_string(),
            };
            d.write(&format!("c{i}.xml"), &frag(&next));
        }
        load_in(
            &d.0,
            &scene(&format!("<include filename=\"c0.xml\"/>\n{RECT}")),
            &[],
        )
    };
    chain(MAX_INCLUDE_DEPTH).unwrap();
    let want = format!(
        "{}:2: include: more than 15 nested <include>s",
        d.path(&format!("c{}.xml", MAX_INCLUDE_DEPTH - 1))
    );
    assert_eq!(error(chain(MAX_INCLUDE_DEPTH + 1)), want);
}

#[test]
fn path_directories_are_searched_first_latest_first() {
    let d = Dir::new("path");
    let white = |v: &str| {
        frag(&format!(
            "<bsdf type=\"diffuse\" id=\"white\"><rgb name=\"reflectance\" value=\"{v}\"/></bsdf>"
        ))
    };
    // The same name in the scene's directory and in two <path> directories.
    d.write("scene/frag.xml", &white("0.1"));
    d.write("common/frag.xml", &white("0.2"));
    d.write("other/frag.xml", &white("0.3"));
    d.write("common/tri.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let dir = d.0.join("scene");
    let load = |paths: &str| {
        let text = scene(&format!(
            "{paths}<include filename=\"frag.xml\"/>\n{RECT}\n<shape type=\"obj\"><string name=\"filename\" value=\"tri.obj\"/></shape>"
        ));
        load_in(&dir, &text, &[])
    };
    let with_common = r#"<path value="../common"/>"#;
    let both = r#"<path value="../common"/><path value="../other"/>"#;
    // The scene's own directory comes after every <path> (Mitsuba's resolver).
    assert_eq!(albedo(&load(with_common).unwrap().scene), Vec3::splat(0.2));
    assert_eq!(albedo(&load(both).unwrap().scene), Vec3::splat(0.3));
    assert_eq!(load(both).unwrap().scene.triangles.len(), 3);
    let got = error(load(r#"<path value="../missing"/>"#));
    assert_eq!(
        got,
        "t.xml:3: path: folder `../missing` not found beside the scene file or in an earlier <path>"
    );
}

#[test]
fn defaults_and_defines() {
    let d = Dir::new("defaults");
    let text = scene(&format!(
        "<default name=\"r\" value=\"0.25\"/><default name=\"r\" value=\"0.5\"/>\n\
         <bsdf type=\"diffuse\" id=\"white\"><rgb name=\"reflectance\" value=\"$r\"/></bsdf>\n{RECT}"
    ));
    // The first <default> wins (Mitsuba keeps the first); a define overrides both.
    assert_eq!(
        albedo(&load_in(&d.0, &text, &[]).unwrap().scene),
        Vec3::splat(0.25)
    );
    let defined = load_in(&d.0, &text, &[("r", "0.75")]).unwrap();
    assert_eq!(albedo(&defined.scene), Vec3::splat(0.75));
    // The longest defined name matches (`$r5` is `$r` then 5, as in Mitsuba); `\$` is `$`.
    d.write("a$b.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    let text = scene(&format!(
        "<default name=\"r\" value=\"0.2\"/>\n<bsdf type=\"diffuse\" id=\"white\"><rgb name=\"reflectance\" value=\"$r5\"/></bsdf>\n{RECT}<shape type=\"obj\"><string name=\"filename\" value=\"a\\$b.obj\"/></shape>"
    ));
    let im = load_in(&d.0, &text, &[]).unwrap();
    assert_eq!(
        (albedo(&im.scene), im.scene.triangles.len()),
        (Vec3::splat(0.25), 3)
    );
    // Defines reach included file names too.
    d.write("v2.xml", &frag("<bsdf type=\"diffuse\" id=\"white\"/>"));
    let text = scene(&format!("<include filename=\"$part.xml\"/>\n{RECT}"));
    assert!(load_in(&d.0, &text, &[("part", "v2")]).is_ok());
    let got = error(load_in(&d.0, &text, &[]));
    assert_eq!(
        got,
        "t.xml:3: include: `$part` has no <default name=\"part\" .../>"
    );

    // The library entry: defines for a TOML scene are refused, for XML used.
    let toml = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.toml");
    let defines = [("spp".to_string(), "4".to_string())];
    let got = load_with_options(&toml, None, &defines)
        .unwrap_err()
        .to_string();
    assert!(
        got.contains("--define spp=... sets a Mitsuba .xml scene's $name"),
        "{got}"
    );
}

#[test]
fn define_on_the_command_line() {
    let d = Dir::new("cli");
    let xml = d.write(
        "s.xml",
        &scene("<default name=\"r\" value=\"2\"/><shape type=\"sphere\"><float name=\"radius\" value=\"$r\"/><emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter></shape>"),
    );
    let run = |scene: &Path, define: &str| {
        let out = d.path("o.png");
        let args = "-o OUT --width 8 --height 8 --spp 1 --passes 0 --photons 100 --backend cpu -q";
        let args = args
            .split(' ')
            .map(|a| if a == "OUT" { out.as_str() } else { a });
        Command::new(env!("CARGO_BIN_EXE_gpu-photon"))
            .args(["render", scene.to_str().unwrap()])
            .args(args)
            .args(["--define", define])
            .output()
            .unwrap()
    };
    let o = run(&xml, "r=-1");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(
        err.contains(":3: shape[0].radius: must be positive"),
        "{err}"
    );
    assert!(run(&xml, "r=0.5").status.success());
    let bad = String::from_utf8_lossy(&run(&xml, "r").stderr).into_owned();
    assert!(bad.contains("`r` is not NAME=VALUE"), "{bad}");
    let toml = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes/cornell-box.toml");
    let err = String::from_utf8_lossy(&run(&toml, "r=1").stderr).into_owned();
    assert!(
        err.starts_with("error: ") && err.contains("has no parameters"),
        "{err}"
    );
}

#[test]
fn refs_reach_any_top_level_object_in_any_order() {
    let im = ok(
        r#"<shape type="rectangle"><ref id="white"/><ref id="lamp"/></shape>
<shape type="rectangle"><bsdf type="diffuse"><ref name="reflectance" id="checks"/></bsdf></shape>
<bsdf type="twosided" id="white"><ref id="inner"/></bsdf>
<bsdf type="diffuse" id="inner"><rgb name="reflectance" value="0.3"/></bsdf>
<texture type="checkerboard" id="checks"/>
<emitter type="area" id="lamp"><rgb name="radiance" value="2, 3, 4"/></emitter>"#,
    );
    let s = &im.scene;
    let first = &s.materials[s.triangles[0].material as usize];
    assert_eq!(
        first.bsdf.base_colour().map(|p| p.get()),
        Some(Vec3::splat(0.3))
    );
    assert_eq!(first.emission, Vec3::new(2.0, 3.0, 4.0));
    assert_eq!(s.lights.len(), 1);
    assert_ne!(
        s.materials[s.triangles[2].material as usize]
            .bsdf
            .base_colour()
            .map_or(NO_TEXTURE, |p| p.texture),
        NO_TEXTURE
    );
    // The bsdfs are added once each, however often they are referenced.
    let twice = ok(
        r#"<shape type="rectangle"><ref id="white"/></shape><shape type="cube"><ref id="white"/></shape>
<bsdf type="diffuse" id="white"/>"#,
    );
    assert_eq!(twice.scene.materials.len(), 1);

    let text = scene(
        r#"<shape type="rectangle"><ref id="whit"/></shape><bsdf type="diffuse" id="white"/>"#,
    );
    let got = error(import(&text, "t.xml", Path::new(".")));
    assert_eq!(
        got,
        "t.xml:3: shape[0].ref: unknown id `whit` (the scene's ids: `white`)"
    );
    let text = scene("<bsdf type=\"diffuse\" id=\"a\"/>\n<bsdf type=\"diffuse\" id=\"a\"/>");
    let got = error(import(&text, "t.xml", Path::new(".")));
    assert_eq!(got, "t.xml:4: bsdf[a]: duplicate id `a` (first at t.xml:3)");
}

#[test]
fn echoed_ids_and_names_have_their_control_characters_escaped() {
    // Issue 44: a tab and a newline in an id (character references: literal ones read as
    // spaces in an attribute) split the message over two lines.
    let text = scene(
        "<shape type=\"rectangle\"><ref id=\"&#9;&#10;1\"/></shape>\n\
         <bsdf type=\"diffuse\" id=\"white&#x9b;2J\"/>",
    );
    let got = error(import(&text, "t.xml", Path::new(".")));
    assert_eq!(
        got,
        "t.xml:3: shape[0].ref: unknown id `\\t\\n1` (the scene's ids: `white\\u{9b}2J`)"
    );
    // In the field path too, and in a warning.
    let text = scene(
        "<bsdf type=\"diffuse\" id=\"w\"><rgb name=\"reflect&#13;ance\" value=\"1\"/></bsdf>",
    );
    let got = error(import(&text, "t.xml", Path::new(".")));
    assert_eq!(
        got,
        "t.xml:3: bsdf[w].reflect\\rance: unsupported parameter of `diffuse`"
    );
    let (_, warnings) = gpu_photon::warning::collect(|| {
        gpu_photon::warning::warn("pixel filter `gaussian\r\u{85}` approximated");
    });
    assert_eq!(
        warnings[0].message,
        "pixel filter `gaussian\\r\\u{85}` approximated"
    );
}

/// The colour Mitsuba gives `<spectrum value>` as a diffuse reflectance.
fn reflectance(value: &str) -> Vec3 {
    let im = ok(&format!(
        r#"<shape type="rectangle"><bsdf type="diffuse"><spectrum name="reflectance" value="{value}"/></bsdf></shape>"#
    ));
    albedo(&im.scene)
}

/// The colour Mitsuba gives a spectrum element as a point light's intensity.
fn intensity(element: &str) -> Vec3 {
    let im = ok(&format!(r#"<emitter type="point">{element}</emitter>"#));
    im.scene.lights[0].power / (4.0 * std::f32::consts::PI)
}

#[test]
fn spectra_convert_as_in_mitsuba_rgb_variants() {
    // Mitsuba 3.9.1's scalar_rgb values (scripts/mitsuba_spectra.py).
    let curve = "400:0.343, 404:0.445, 450:0.3, 500:0.15, 560:0.6, 610:0.7, 700:0.8";
    assert_close(reflectance(curve), [0.855588, 0.428645, 0.259356], 2e-5);
    assert_eq!(reflectance("0.5"), Vec3::splat(0.5));
    // The same pairs from a file (Mitsuba's spectrum file: a pair per line, # comments).
    let d = Dir::new("spd");
    d.write(
        "c.spd",
        "# nm value\n400 0.343\n404 0.445\n450 0.3\n500 0.15\n560 0.6\n610 0.7\n700 0.8\n",
    );
    let body = r#"<shape type="rectangle"><bsdf type="diffuse"><spectrum name="reflectance" filename="c.spd"/></bsdf></shape>"#;
    let from_file = albedo(&load_in(&d.0, &scene(body), &[]).unwrap().scene);
    assert_eq!(from_file, reflectance(curve));
    assert_close(
        reflectance("360:1, 830:1"),
        [0.998985, 0.998874, 0.998802],
        2e-5,
    );

    let e = |v: &str| intensity(&format!(r#"<spectrum name="intensity" value="{v}"/>"#));
    let got = e("400:1.5, 500:3, 600:2, 700:0.5");
    assert_close(got, [1.77618, 2.54095, 2.05345], 1e-4);
    // A constant emission is the equal-energy spectrum, not sRGB white.
    let got = e("7");
    assert_close(got, [8.43356, 6.63804, 6.36241], 1e-4);

    let im = ok(
        r#"<shape type="rectangle"><bsdf type="conductor"><spectrum name="eta" value="400:1.5, 700:1.8"/><spectrum name="k" value="0"/></bsdf></shape>"#,
    );
    let Bsdf::Conductor(gpu_photon::bsdfs::conductor::Conductor { eta, k, .. }) =
        im.scene.materials[0].bsdf
    else {
        panic!("not a conductor");
    };
    assert_close(eta, [1.73426, 1.64257, 1.53318], 2e-5);
    assert_eq!(k, Vec3::ZERO);

    // A blackbody (refused by Mitsuba's RGB variants) as its spectral variants record it.
    let bb = |t: &str| {
        let m3 = intensity(&format!(
            r#"<spectrum type="blackbody" name="intensity"><float name="temperature" value="{t}"/></spectrum>"#
        ));
        assert_eq!(
            m3,
            intensity(&format!(
                r#"<blackbody name="intensity" temperature="{t}"/>"#
            ))
        );
        m3
    };
    let rel = |a: Vec3, b: Vec3| ((a - b) / b).abs().max_element();
    assert!(
        rel(bb("2700"), Vec3::new(314.191, 130.498, 31.1683)) < 1e-4,
        "{}",
        bb("2700")
    );
    assert!(
        rel(bb("6500"), Vec3::new(43918.6, 41407.2, 43582.8)) < 1e-4,
        "{}",
        bb("6500")
    );

    let err = |b: &str| error(import(&scene(b), "t.xml", Path::new(".")));
    let bsdf = |s: &str| format!(r#"<bsdf type="diffuse" id="x">{s}</bsdf>"#);
    assert_eq!(
        err(&bsdf(
            r#"<spectrum name="reflectance" value="500:1, 400:1"/>"#
        )),
        "t.xml:3: bsdf[x].reflectance: the wavelengths must increase"
    );
    assert_eq!(
        err(&bsdf(
            r#"<blackbody name="reflectance" temperature="3000"/>"#
        )),
        "t.xml:3: bsdf[x].reflectance: a blackbody is an emission spectrum (only in an <emitter>)"
    );
    assert_eq!(
        err(&bsdf(r#"<spectrum name="reflectance" value="400:x"/>"#)),
        "t.xml:3: bsdf[x].reflectance: `400:x` is not a finite wavelength:value pair"
    );
}

/// The vertical fov (degrees) of a sensor with `params` and a `w` x `h` film.
fn fov_of(params: &str, w: u32, h: u32) -> f32 {
    let text = format!(
        r#"<scene version="3.0.0"><sensor type="perspective">{params}
<film type="hdrfilm"><integer name="width" value="{w}"/><integer name="height" value="{h}"/><rfilter type="box"/></film></sensor></scene>"#
    );
    let cam = import(&text, "t.xml", Path::new(".")).unwrap().scene.camera;
    2.0 * cam.up.length().atan().to_degrees()
}

/// The vertical fov of a `fov` on `axis` (with clip planes and a focus distance).
fn fov_y(fov: f32, axis: &str, w: u32, h: u32) -> f32 {
    let params = format!(
        r#"<float name="fov" value="{fov}"/><string name="fov_axis" value="{axis}"/>
<float name="near_clip" value="0.1"/><float name="far_clip" value="50"/><float name="focus_distance" value="3"/>"#
    );
    fov_of(&params, w, h)
}

#[test]
fn sensor_fov_axes_and_clip_planes() {
    let t = (30f32.to_radians()).tan(); // fov 60
    let deg = |x: f32| 2.0 * x.atan().to_degrees();
    // A tall 32 x 64 film: x and smaller are the width, y and larger the height.
    for (axis, want) in [
        ("x", deg(t * 2.0)),
        ("smaller", deg(t * 2.0)),
        ("y", 60.0),
        ("larger", 60.0),
        ("diagonal", deg(t * 64.0 / 5120f32.sqrt())), // sqrt(32^2 + 64^2)
    ] {
        let got = fov_y(60.0, axis, 32, 64);
        assert!((got - want).abs() < 1e-3, "{axis}: {got} vs {want}");
    }
    // Without a fov, a focal length (default 50mm) on the 36 x 24 mm diagonal.
    let focal = |f: &str| fov_of(f, 30, 40);
    let diag = |mm: f32| deg(1872f32.sqrt() / (2.0 * mm) * 40.0 / 50.0);
    assert!((focal("") - diag(50.0)).abs() < 1e-3, "{}", focal(""));
    let f35 = focal(r#"<string name="focal_length" value="35mm"/>"#);
    assert!((f35 - diag(35.0)).abs() < 1e-3, "{f35}");
    // A wide one: larger is the width.
    assert!((fov_y(60.0, "larger", 64, 32) - deg(t / 2.0)).abs() < 1e-3);
    let text = |near: &str, far: &str| {
        scene("").replace(
            "<float name=\"fov\" value=\"40\"/>",
            &format!("<float name=\"fov\" value=\"40\"/><float name=\"near_clip\" value=\"{near}\"/><float name=\"far_clip\" value=\"{far}\"/>"),
        )
    };
    let got = error(import(&text("1", "0.5"), "t.xml", Path::new(".")));
    assert_eq!(
        got,
        "t.xml:2: sensor[0].far_clip: must be greater than near_clip (1)"
    );
    let got = error(import(&text("0", "5"), "t.xml", Path::new(".")));
    assert_eq!(got, "t.xml:2: sensor[0].near_clip: must be positive");
}

#[test]
fn any_integrator_is_one_warning() {
    for (integrator, hint) in [
        (
            r#"<integrator type="path"><integer name="max_depth" value="8"/><integer name="rr_depth" value="3"/></integrator>"#,
            "; rr_depth 3 changes only noise, not used",
        ),
        (
            r#"<integrator type="direct"/>"#,
            "; paths capped at 2 segments: mode `direct`",
        ),
        (
            r#"<integrator type="aov"><string name="aovs" value="dd.y:depth"/><integrator type="ptracer"/></integrator>"#,
            "",
        ),
        (
            r#"<integrator type="moment"><integrator type="path"/></integrator>"#,
            "",
        ),
    ] {
        let im = ok(integrator);
        // A nest is named innermost first: `path` in `moment`.
        let types: Vec<&str> = integrator
            .split("type=\"")
            .skip(1)
            .map(|t| t.split('"').next().unwrap())
            .collect();
        let kind = types
            .iter()
            .rev()
            .copied()
            .collect::<Vec<_>>()
            .join("` in `");
        let want = format!(
            "t.xml:3: integrator[0]: integrator `{kind}` rendered with our photon mapping (the render mode: [render] mode, --mode){hint}"
        );
        assert_eq!(im.warnings, vec![want]);
    }
}

/// Mitsuba's `max_depth` M bounds path segments: camera paths get M - 1 bounces (-1,
/// unbounded: our most), photon paths M - 1 but never more than our default.
#[test]
fn integrator_max_depth_caps_path_lengths() {
    let d = RenderSettings::default();
    let most = gpu_photon::settings::MAX_BOUNCES;
    for (depth, photon, camera) in [
        ("-1", d.max_photon_bounces, most),
        ("64", d.max_photon_bounces, 63),
        ("100", d.max_photon_bounces, most),
        ("8", 7, 7),
        ("3", 2, 2),
        ("2", 1, 1),
    ] {
        let xml = format!(
            r#"<integrator type="path"><integer name="max_depth" value="{depth}"/></integrator>"#
        );
        let s = ok(&xml).scene.settings;
        assert_eq!(
            (s.max_photon_bounces, s.max_depth),
            (photon, camera),
            "max_depth {depth}"
        );
    }
    let bad = r#"<integrator type="path"><integer name="max_depth" value="0"/></integrator>"#;
    assert_eq!(
        error(import(&scene(bad), "t.xml", Path::new("."))),
        "t.xml:3: integrator[0].max_depth: must be -1 or a positive integer (got `0`)"
    );
}

/// `sample_count` is the total per pixel: the planned passes x spp equals it exactly
/// (`settings::split_samples`: the most passes up to 4 that divide it with at least 16 spp
/// each, else one pass).
#[test]
fn sample_count_is_the_total_over_the_planned_passes() {
    for (count, passes, spp) in [
        (256, 4, 64),
        (64, 4, 16),
        (100, 4, 25),
        (48, 3, 16),
        (40, 2, 20),
        (16, 1, 16),
        (8, 1, 8),
        (1, 1, 1),
        (257, 1, 257),
    ] {
        let text = format!(
            r#"<scene version="3.0.0"><sensor type="perspective"><float name="fov" value="40"/>
<sampler type="independent"><integer name="sample_count" value="{count}"/></sampler>
<film type="hdrfilm"><rfilter type="box"/></film></sensor></scene>"#
        );
        let s = import(&text, "t.xml", Path::new("."))
            .unwrap()
            .scene
            .settings;
        assert_eq!((s.passes, s.spp), (passes, spp), "sample_count {count}");
        assert_eq!(s.passes * s.spp, count);
        // What `gpu-photon render` runs: passes 0..passes at spp each.
        assert_eq!(s.as_default_render().pass_range, Some((0, passes)));
    }
}

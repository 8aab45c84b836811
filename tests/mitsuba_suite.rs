//! Mitsuba 3's own render-regression suite (`tests/data/mitsuba-suite/`: mitsuba-data's
//! `tests/scenes/`, the 41 scenes Mitsuba's `src/render/tests/test_renders.py` renders, with
//! their RGB references and variance images; README.md there names the commit).
//!
//! Every scene is loaded by our importer (a refusal is reported with its error) and rendered
//! at its film's resolution in a fixed budget of progressive passes, each pass an independent
//! estimate, so our own noise is measured from pass to pass. The mean of the passes is then
//! judged against Mitsuba's reference by two checks that fail on bias:
//! - **means**: each channel's image mean within 2% of the reference's, or within 4 standard
//!   errors (ours from pass to pass, the reference's from its variance image) when that is
//!   larger;
//! - **blocks**: a Z-test of every 4 x 4-block mean per channel, the difference over the
//!   standard error of ours and of the reference's (its per-sample variance image over its
//!   sample count, floored at 1e-4 per sample as Mitsuba's test floors it, plus its
//!   systematic colour error, [`reference_colour_bias`], squared). Ours is measured two ways
//!   and a block passes when either test passes it: the pass-to-pass variance (P - 1 degrees
//!   of freedom, hence Student's t with Welch-Satterthwaite's degrees of freedom), and the
//!   variance Mitsuba's own test assumes of any render it judges, the reference's floored
//!   per-sample variance over the render's samples per pixel ([`pixel_variance`],
//!   known: a normal test). A few passes underestimate the variance of a block whose rare
//!   paths none of them drew (a silhouette pixel 0.4% covered, a caustic's firefly): its mean
//!   is then low and looks certain, and such a render, which Mitsuba's test accepts at the
//!   same sample count, failed ours;
//!   Sidak-corrected at 1% over the blocks, and passed, as Mitsuba's test passes a render,
//!   when at least 99.75% of the block-channel tests are above that level.
//!
//! Renders are deterministic (fixed seeds and pass counts), so a scene's verdict changes only
//! with the code. The ratchet: [`KNOWN_CPU`] lists every scene that does not pass yet, each
//! with what was measured (the importer's refusal, or the worst channel-mean error). A scene
//! not listed must pass; a listed scene that passes, or that is refused when listed as
//! rendered (or loads when listed as refused), fails the test and asks for the list to be
//! updated; a listed scene whose mean error grows past its recorded one (by more than a
//! quarter of it plus 1%) fails as a regression. The figures are in docs/conformance.md.
//! `MITSUBA_SUITE=substring` runs only the scenes whose path contains it (the ratchet then
//! checks those alone); `MITSUBA_SUITE_OUT=DIR` writes each render there as EXR.
//!
//! The GPU suites (lavapipe in CI) render at a shorter budget ([`GPU_BUDGET`]) with their own
//! ratchet ([`KNOWN_GPU`]), the scenes without media and the media scenes as two tests; most
//! of their time on lavapipe is each feature set's first kernel compile, so scenes whose
//! features differ only in shareable ones render on kernels compiled for their union
//! (`GpuContext::with_feature_floor`), and each suite renders on a device per core
//! (`on_gpu_workers`). On a real GPU run them at the CPU's
//! budget: `MITSUBA_SUITE_BUDGET=8,16,100000 cargo test --release --test mitsuba_suite --
//! gpu`. `MITSUBA_SUITE_BUDGET=PASSES,SPP,PHOTONS` sets any suite's budget
//! (docs/conformance.md compares both backends at one budget).
//! `MITSUBA_SUITE_SEED=N` renders at seed N instead of 1 (the ratchet's figures hold at seed
//! 1 only) and `MITSUBA_SUITE_BLOCKS=1` prints each failing block (its position in blocks,
//! channel, our mean over the reference's): to tell chance from bias.

mod common;

use gpu_photon::importers::load;
use gpu_photon::integrators::gpu::pipelines::{scene_features, shareable_features};
use gpu_photon::integrators::gpu::{GpuContext, GpuRenderer};
use gpu_photon::render::film::Image;
use gpu_photon::render::progressive::pass_settings;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{open, BackendChoice, PassRenderer};
use gpu_photon::settings::{RenderSettings, MIN_PASS_SPP};
use statrs::distribution::{ContinuousCDF, StudentsT};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::Mutex;
use std::time::Instant;

/// What was measured for a scene that does not pass yet.
#[derive(Clone, Copy, Debug)]
enum Known {
    /// The importer refuses it: a part of its error message (the feature we lack). Every
    /// scene of the suite loads now; kept for the ratchet's rule on a scene that regresses
    /// to a refusal.
    #[allow(dead_code)]
    Refused(&'static str),
    /// Rendered but off: the worst channel's |our mean / the reference's - 1| measured
    /// (a scene off only in the block test has a small one). No scene is, on the CPU.
    #[allow(dead_code)]
    Off(f64),
}

/// The scenes (paths below `tests/scenes/`) the CPU backend does not pass yet, in the
/// [`CPU_BUDGET`], as measured (docs/conformance.md has the table).
#[rustfmt::skip]
const KNOWN_CPU: &[(&str, Known)] = &[
];

/// The scenes the GPU backend does not pass yet, in the [`GPU_BUDGET`], as measured on
/// lavapipe (docs/conformance.md).
#[rustfmt::skip]
const KNOWN_GPU: &[(&str, Known)] = &[
];

/// A render's budget: `passes` progressive passes of `spp` camera samples and `photons`
/// global (and `photons / 2` caustic) photon paths each.
#[derive(Clone, Copy, Debug)]
struct Budget {
    passes: u32,
    spp: u32,
    photons: u32,
}

/// The CPU budget: a few minutes for the whole suite on 2 cores.
const CPU_BUDGET: Budget = Budget {
    passes: 8,
    spp: 16,
    photons: 100_000,
};

/// The GPU budget: smaller, for lavapipe on 2 cores in CI.
const GPU_BUDGET: Budget = Budget {
    passes: 6,
    spp: 8,
    photons: 50_000,
};

/// Samples per pixel of Mitsuba's references (test_renders.py's `--spp` default): the
/// reference pixel's own variance is its per-sample variance image over this.
const REFERENCE_SPP: f64 = 32_000.0;
/// Mitsuba's test floors the per-sample variance image at this.
const VARIANCE_FLOOR: f64 = 1e-4;
/// The block side of the Z-test, in pixels.
const BLOCK: u32 = 4;
/// Mitsuba's significance level, Sidak-corrected over the blocks.
const SIGNIFICANCE: f64 = 0.01;
/// Mitsuba's test passes when at least this fraction of the tests do.
const PASS_FRACTION: f64 = 0.9975;
/// A channel mean may be this far off, relatively (or 4 standard errors if more).
const MEAN_TOLERANCE: f64 = 0.02;

/// One suite at a time: the CPU and GPU suites would otherwise share the cores and each
/// other's render times.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());
/// The most GPU workers (devices) a GPU suite renders on at once (each compiles a kernel on
/// one core; more would need the memory of as many compiles).
const GPU_WORKERS: usize = 4;

fn suite_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/mitsuba-suite/tests/scenes")
}

/// The suite's scenes: `tests/scenes/*/*.xml` (not the fragments and includes below them),
/// as Mitsuba's test lists them, sorted.
fn scenes() -> Vec<String> {
    let root = suite_root();
    let mut out = Vec::new();
    for dir in std::fs::read_dir(&root).expect("tests/data/mitsuba-suite is missing") {
        let dir = dir.unwrap().path();
        if !dir.is_dir() {
            continue;
        }
        for f in std::fs::read_dir(&dir).unwrap() {
            let f = f.unwrap().path();
            if f.extension().is_some_and(|e| e == "xml") {
                out.push(f.strip_prefix(&root).unwrap().display().to_string());
            }
        }
    }
    out.sort();
    out
}

/// The references' own colour bias, relative: they are spectral renders written as RGB, so a
/// white emitter of radiance 1 seen directly is not exactly 1 in them, where an RGB renderer
/// (ours, and Mitsuba's `rgb` variants, which its own test lets through by its per-pixel
/// variance at the test's sample count) gives exactly 1. Measured here on the background of
/// `bsdf_spheres/test_constant` (a `constant` emitter of radiance 1 seen at every pixel of a
/// 4x4 block in a corner): the largest |channel - 1| there, at most 0.2% (it is 0.108%: 1.00108,
/// 0.99971, 0.99970). The block test counts it as a systematic error of the reference.
fn reference_colour_bias() -> f64 {
    static BIAS: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
    *BIAS.get_or_init(|| {
        let file = suite_root().join("bsdf_spheres/refs/test_constant_ref_rgb.exr");
        let image = Image::read(&file).unwrap();
        let mut bias = 0.0f64;
        for y in 0..4 {
            for x in 0..4 {
                let p = image.pixels[(y * image.width + x) as usize];
                for c in p {
                    bias = bias.max((f64::from(c) - 1.0).abs());
                }
            }
        }
        assert!(
            bias < 2e-3,
            "{file:?}: the background is {bias} off radiance 1"
        );
        bias
    })
}

/// The reference and variance images of `scene` (test_renders.py's `get_ref_fname`:
/// `refs/<name without its _integrator suffix>_ref_rgb.exr`).
fn reference_of(scene: &Path) -> (PathBuf, PathBuf) {
    let stem = scene.file_stem().unwrap().to_str().unwrap();
    let name = stem.rsplit_once('_').map_or(stem, |(a, _)| a);
    let refs = scene.parent().unwrap().join("refs");
    (
        refs.join(format!("{name}_ref_rgb.exr")),
        refs.join(format!("{name}_ref_rgb_var.exr")),
    )
}

/// What became of one scene.
enum Status {
    /// The importer refused it: its error.
    Refused(String),
    /// Rendered; the reason it failed, if it did.
    Rendered(Option<String>),
    /// Loaded, but the render failed: its error.
    Error(String),
}

struct Outcome {
    scene: String,
    status: Status,
    /// Our channel means over the reference's.
    ratio: [f64; 3],
    /// The block Z-test: fraction of block-channel tests passed, and the smallest p-value.
    z: Option<(f64, f64)>,
    seconds: f64,
}

/// Renders `settings`' progressive passes one by one: each pass's image.
fn render_passes(
    scene: &gpu_photon::scene::Scene,
    settings: &RenderSettings,
    backend: BackendChoice,
    passes: u32,
    device: Option<&GpuContext>,
) -> gpu_photon::Result<Vec<Image>> {
    let quiet = Progress { enabled: false };
    let mut renderer: Box<dyn PassRenderer + '_> = match device {
        Some(ctx) => Box::new(GpuRenderer::on_context(ctx.clone(), scene, settings)?),
        None => open(backend, scene, settings)?,
    };
    (0..passes)
        .map(|p| renderer.pass(p, &pass_settings(scene, settings, p), &quiet))
        .collect()
}

/// Mean and variance of the mean of `xs` (sample variance over n).
fn mean_and_var(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let m = xs.iter().sum::<f64>() / n;
    let v = xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0) / n;
    (m, v)
}

/// Two-sided p-value of the difference `d` between our estimate (variance `ours`, from
/// `dof` degrees of freedom) and the reference's (variance `theirs`, known): Student's t with
/// Welch-Satterthwaite's degrees of freedom.
fn p_value(d: f64, ours: f64, theirs: f64, dof: f64) -> f64 {
    let var = ours + theirs;
    if var <= 0.0 {
        return if d == 0.0 { 1.0 } else { 0.0 };
    }
    let nu = if ours > 0.0 {
        (var * var * dof / (ours * ours)).min(1e6)
    } else {
        1e6
    };
    let t = StudentsT::new(0.0, 1.0, nu).unwrap();
    2.0 * t.cdf(-(d.abs() / var.sqrt()))
}

/// Sums of `f` over each `BLOCK` x `BLOCK` block of a `w` x `h` image per channel, the
/// blocks row by row (a partial block at the right or bottom edge is left out).
fn block_sums(w: u32, h: u32, f: impl Fn(usize, usize) -> f64) -> Vec<[f64; 3]> {
    let (bw, bh) = (w / BLOCK, h / BLOCK);
    let mut out = vec![[0.0; 3]; (bw * bh) as usize];
    for y in 0..bh * BLOCK {
        for x in 0..bw * BLOCK {
            let b = &mut out[((y / BLOCK) * bw + x / BLOCK) as usize];
            for (c, v) in b.iter_mut().enumerate() {
                *v += f((y * w + x) as usize, c);
            }
        }
    }
    out
}

/// The variance of a pixel's mean over `samples` samples as Mitsuba's test (`z_test` in its
/// `test_renders.py`) takes it: the reference's per-sample variance, floored as it floors it,
/// over `samples`. The reference's own (over [`REFERENCE_SPP`]), and the one the test
/// assumes of any render it judges (over that render's samples per pixel).
fn pixel_variance(per_sample: f32, samples: f64) -> f64 {
    f64::from(per_sample).max(VARIANCE_FLOOR) / samples
}

/// Judges the passes against the reference: the failure, if any; the mean ratios; the
/// block test's pass fraction and smallest p-value.
fn judge(
    passes: &[Image],
    samples: f64,
    reference: &Image,
    variance: &Image,
) -> (Option<String>, [f64; 3], (f64, f64)) {
    let (w, h) = (reference.width, reference.height);
    let n_px = (w * h) as f64;
    let dof = (passes.len() - 1) as f64;
    let ref_mean = reference.mean();
    let ref_var = |i: usize, c: usize| pixel_variance(variance.pixels[i][c], REFERENCE_SPP);
    let mut failures = Vec::new();
    let mut ratio = [0.0; 3];
    for c in 0..3 {
        let means: Vec<f64> = passes.iter().map(|p| p.mean()[c]).collect();
        let (m, v) = mean_and_var(&means);
        let v_ref = (0..(w * h) as usize).map(|i| ref_var(i, c)).sum::<f64>() / (n_px * n_px);
        ratio[c] = m / ref_mean[c];
        let allowed = (MEAN_TOLERANCE * ref_mean[c].abs()).max(4.0 * (v + v_ref).sqrt());
        if (m - ref_mean[c]).abs() > allowed {
            failures.push(format!(
                "channel {c} mean {m:.5} against {:.5} (ratio {:.4}; allowed +-{allowed:.5})",
                ref_mean[c], ratio[c]
            ));
        }
    }
    let area = f64::from(BLOCK * BLOCK);
    let theirs = block_sums(w, h, |i, c| reference.pixels[i][c] as f64 / area);
    let theirs_var = block_sums(w, h, |i, c| ref_var(i, c) / (area * area));
    // The reference's systematic colour error (reference_colour_bias) adds to its variance.
    let bias = reference_colour_bias();
    let theirs_var: Vec<[f64; 3]> = (theirs_var.iter().zip(&theirs))
        .map(|(v, t)| [0, 1, 2].map(|c| v[c] + (bias * t[c]).powi(2)))
        .collect();
    let model = block_sums(w, h, |i, c| {
        pixel_variance(variance.pixels[i][c], samples) / (area * area)
    });
    let ours: Vec<Vec<[f64; 3]>> = passes
        .iter()
        .map(|p| block_sums(w, h, |i, c| p.pixels[i][c] as f64 / area))
        .collect();
    let blocks = theirs.len();
    let alpha = 1.0 - (1.0 - SIGNIFICANCE).powf(1.0 / blocks as f64);
    let (mut passed, mut min_p) = (0usize, 1.0f64);
    for b in 0..blocks {
        for c in 0..3 {
            let xs: Vec<f64> = ours.iter().map(|o| o[b][c]).collect();
            let (m, v) = mean_and_var(&xs);
            // Either test passing passes the block: ours (pass to pass) or Mitsuba's (its
            // model's variance known: a normal Z-test, as its own).
            let d = m - theirs[b][c];
            let p = p_value(d, v, theirs_var[b][c], dof).max(p_value(
                d,
                model[b][c],
                theirs_var[b][c],
                f64::INFINITY,
            ));
            min_p = min_p.min(p);
            if p <= alpha && std::env::var_os("MITSUBA_SUITE_BLOCKS").is_some() {
                eprintln!(
                    "  failing block ({}, {}) channel {c}: ours / reference {:.4}, p {p:.2e}",
                    b as u32 % (w / BLOCK),
                    b as u32 / (w / BLOCK),
                    m / theirs[b][c]
                );
            }
            passed += usize::from(p > alpha);
        }
    }
    let fraction = passed as f64 / (3 * blocks) as f64;
    if fraction < PASS_FRACTION {
        failures.push(format!(
            "{:.2}% of the {} block tests passed at the Sidak level {alpha:.2e} (min p {min_p:.2e})",
            100.0 * fraction,
            3 * blocks
        ));
    }
    let failure = (!failures.is_empty()).then(|| failures.join("; "));
    (failure, ratio, (fraction, min_p))
}

/// The suite's scene `name` loaded by our importer, or its refusal.
fn load_scene(name: &str) -> Result<gpu_photon::scene::Scene, String> {
    load(&suite_root().join(name)).map_err(|e| e.to_string())
}

/// Renders and judges one scene, `loaded` by [`load_scene`] (on `device` when given: a GPU
/// worker's own).
fn run_scene(
    name: &str,
    loaded: &Result<gpu_photon::scene::Scene, String>,
    backend: BackendChoice,
    budget: Budget,
    device: Option<&GpuContext>,
) -> Outcome {
    let path = suite_root().join(name);
    let start = Instant::now();
    let mut outcome = Outcome {
        scene: name.to_string(),
        status: Status::Refused(String::new()),
        ratio: [f64::NAN; 3],
        z: None,
        seconds: 0.0,
    };
    let scene = match loaded {
        Ok(s) => s,
        Err(e) => {
            outcome.status = Status::Refused(e.clone());
            return outcome;
        }
    };
    let settings = RenderSettings {
        spp: budget.spp,
        photons: budget.photons,
        caustic_photons: budget.photons / 2,
        passes: budget.passes,
        seed: std::env::var("MITSUBA_SUITE_SEED")
            .map_or(1, |s| s.parse().expect("MITSUBA_SUITE_SEED: an integer")),
        ..scene.settings.clone()
    }
    .as_default_render();
    let passes = render_passes(scene, &settings, backend, budget.passes, device);
    outcome.seconds = start.elapsed().as_secs_f64();
    let passes = match passes {
        Ok(p) => p,
        Err(e) => {
            outcome.status = Status::Error(e.to_string());
            return outcome;
        }
    };
    if let Some(dir) = std::env::var_os("MITSUBA_SUITE_OUT") {
        let mut mean = Image::new(settings.width, settings.height);
        for p in &passes {
            for (m, q) in mean.pixels.iter_mut().zip(&p.pixels) {
                for c in 0..3 {
                    m[c] += q[c] / passes.len() as f32;
                }
            }
        }
        let file = name.replace(['/', '.'], "_") + ".exr";
        mean.write(&Path::new(&dir).join(file), 0.0).unwrap();
    }
    let (ref_file, var_file) = reference_of(&path);
    let reference = Image::read(&ref_file).unwrap();
    let variance = Image::read(&var_file).unwrap();
    if (reference.width, reference.height) != (settings.width, settings.height) {
        outcome.status = Status::Error(format!(
            "rendered {}x{}, the reference is {}x{}",
            settings.width, settings.height, reference.width, reference.height
        ));
        return outcome;
    }
    let samples = f64::from(budget.passes * budget.spp);
    let (failure, ratio, z) = judge(&passes, samples, &reference, &variance);
    outcome.status = Status::Rendered(failure);
    outcome.ratio = ratio;
    outcome.z = Some(z);
    outcome
}

/// The worst channel's |ratio - 1| of an outcome (NaN when it did not render).
fn mean_error(o: &Outcome) -> f64 {
    o.ratio
        .iter()
        .map(|r| (r - 1.0).abs())
        .fold(f64::NAN, f64::max)
}

/// What is wrong with `o` given what `known` recorded for it (`None`: must pass) in the
/// list named `list`.
fn ratchet(o: &Outcome, known: Option<Known>, list: &str) -> Option<String> {
    let list = format!("{list} in tests/mitsuba_suite.rs (and docs/conformance.md)");
    let err = mean_error(o);
    match (&o.status, known) {
        (Status::Rendered(None), None) => None,
        (Status::Rendered(None), Some(k)) => Some(format!(
            "{} now passes (mean error {err:.4}; listed as {k:?}): remove it from {list}",
            o.scene
        )),
        (Status::Refused(e), Some(Known::Refused(part))) if e.contains(part) => None,
        (Status::Refused(e), _) => Some(format!("{} is refused: {e}", o.scene)),
        (_, Some(Known::Refused(part))) => Some(format!(
            "{} loads now (listed as refused for {part}; mean error {err:.4}): update {list}",
            o.scene
        )),
        (Status::Rendered(Some(why)), Some(Known::Off(was))) => {
            // Deterministic renders: a growth past this slack is the code's (NaN is one).
            let worse = err.is_nan() || err > was + 0.25 * was + 0.01;
            worse.then(|| {
                format!(
                    "{} regressed: mean error {err:.4}, recorded {was:.4}: {why}",
                    o.scene
                )
            })
        }
        (Status::Rendered(Some(why)), None) => Some(format!("{} fails: {why}", o.scene)),
        (Status::Error(e), _) => Some(format!("{} failed to render: {e}", o.scene)),
    }
}

/// The media scenes (issue 41's), which the GPU suite on lavapipe runs apart.
fn is_media(scene: &str) -> bool {
    scene.starts_with("participating_media/")
}

/// Runs the suite's scenes that `part` selects on `backend`, prints their table, and returns
/// their outcomes.
fn run_suite(
    label: &str,
    backend: BackendChoice,
    budget: Budget,
    part: fn(&str) -> bool,
) -> Vec<Outcome> {
    let filter = std::env::var("MITSUBA_SUITE").unwrap_or_default();
    let all = scenes();
    assert_eq!(all.len(), 41, "the suite has 41 scenes: {all:?}");
    let names: Vec<String> = all
        .into_iter()
        .filter(|s| s.contains(&filter) && part(s))
        .collect();
    assert!(budget.spp * budget.passes >= MIN_PASS_SPP);
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|e| e.into_inner());
    let outcomes = match backend {
        BackendChoice::Gpu => on_gpu_workers(label, &names, budget),
        _ => names
            .iter()
            .map(|name| {
                let o = run_scene(name, &load_scene(name), backend, budget, None);
                eprintln!("{label}: {name}: {:.1} s", o.seconds);
                o
            })
            .collect(),
    };
    println!(
        "\nMitsuba 3 suite on the {label} backend ({} passes x {} spp, {} photons per pass)",
        budget.passes, budget.spp, budget.photons
    );
    println!(
        "{:<58} {:<8} {:>7} {:>7} {:>7} {:>8} {:>9} {:>7}",
        "scene", "status", "R", "G", "B", "blocks", "min p", "time s"
    );
    let (mut pass, mut refused, mut total_s) = (0, 0, 0.0);
    for o in &outcomes {
        total_s += o.seconds;
        let (status, note) = match &o.status {
            Status::Refused(e) => {
                refused += 1;
                ("refused", e.clone())
            }
            Status::Error(e) => ("error", e.clone()),
            Status::Rendered(None) => {
                pass += 1;
                ("pass", String::new())
            }
            Status::Rendered(Some(why)) => ("fail", why.clone()),
        };
        let (frac, min_p) = o.z.unwrap_or((f64::NAN, f64::NAN));
        println!(
            "{:<58} {:<8} {:>7.4} {:>7.4} {:>7.4} {:>7.2}% {:>9.2e} {:>7.1}",
            o.scene,
            status,
            o.ratio[0],
            o.ratio[1],
            o.ratio[2],
            100.0 * frac,
            min_p,
            o.seconds
        );
        if !note.is_empty() {
            println!("    {note}");
        }
    }
    println!(
        "{label}: {pass} of {} scenes pass, {refused} refused, {} rendered and off; {total_s:.0} s in all",
        outcomes.len(),
        outcomes.len() - pass - refused,
    );
    outcomes
}

/// Renders and judges `names` on GPU workers, each with a device of its own, one per core
/// and per 3 GB of available memory (at most [`GPU_WORKERS`]), each taking the next scene as
/// it finishes one; the outcomes in the order of `names`. Lavapipe compiles a scene's
/// kernels at their first dispatch, on its device's queue thread, one at a time: that
/// compile is most of a scene's time, and devices of their own compile side by side. Each
/// render is the same as on the shared device (deterministic kernels).
fn on_gpu_workers(label: &str, names: &[String], budget: Budget) -> Vec<Outcome> {
    // A media scene's kernel compile holds up to about 2.7 GB on lavapipe.
    let by_memory = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|m| {
            let line = m.lines().find(|l| l.starts_with("MemAvailable:"))?;
            line.split_whitespace().nth(1)?.parse::<u64>().ok()
        })
        .map_or(1, |kib| (kib / (3 << 20)) as usize);
    let workers = std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .min(GPU_WORKERS)
        .min(by_memory)
        .min(names.len())
        .max(1);
    // Most of the suite's time on lavapipe is compiling kernels, one set per combination of
    // scene features (31 for 41 scenes). Scenes whose features differ only in shareable ones
    // (`pipelines::shareable_features`: presence flags whose code also checks the scene's
    // data) render on kernels compiled with the union of theirs (`with_feature_floor`):
    // each renders as on its own kernels, and the suite compiles a few sets. Scenes of one
    // set share their kernels, compiled once (Mesa's shader cache serves the other
    // devices): the first scene of each set goes first, so that two workers do not compile
    // the same kernels side by side.
    let scenes: Vec<_> = names.iter().map(|n| load_scene(n)).collect();
    let shareable = shareable_features();
    let features: Vec<Option<Vec<(&'static str, f64)>>> = scenes
        .iter()
        .map(|loaded| Some(scene_features(loaded.as_ref().ok()?, false)))
        .collect();
    let group = |f: &Option<Vec<(&'static str, f64)>>| -> Option<Vec<(&'static str, u64)>> {
        let f = f.as_ref()?.iter().filter(|(k, _)| !shareable.contains(k));
        Some(f.map(|&(k, v)| (k, v.to_bits())).collect())
    };
    let groups: Vec<_> = features.iter().map(group).collect();
    let floors: Vec<Vec<(&'static str, f64)>> = (0..names.len())
        .map(|i| {
            let members = (0..names.len()).filter(|&j| groups[j] == groups[i]);
            let mut floor: Vec<(&'static str, f64)> = Vec::new();
            for f in members.filter_map(|j| features[j].as_ref()) {
                for &(k, v) in f.iter().filter(|(k, _)| shareable.contains(k)) {
                    match floor.iter_mut().find(|(n, _)| *n == k) {
                        Some((_, m)) => *m = m.max(v),
                        None => floor.push((k, v)),
                    }
                }
            }
            floor
        })
        .collect();
    let mut order: Vec<usize> = (0..names.len()).collect();
    order.sort_by_key(|&i| groups[..i].contains(&groups[i]));
    let next = AtomicUsize::new(0);
    let done: Mutex<Vec<(usize, Outcome)>> = Mutex::new(Vec::new());
    std::thread::scope(|threads| {
        for _ in 0..workers {
            threads.spawn(|| {
                let device = GpuContext::new().expect("a GPU worker opens its device");
                while let Some(&i) = order.get(next.fetch_add(1, Ordering::SeqCst)) {
                    let name = &names[i];
                    let ctx = device.with_feature_floor(&floors[i]);
                    let o = run_scene(name, &scenes[i], BackendChoice::Gpu, budget, Some(&ctx));
                    eprintln!("{label}: {name}: {:.1} s", o.seconds);
                    done.lock().unwrap().push((i, o));
                }
            });
        }
    });
    let mut done = done.into_inner().unwrap();
    done.sort_by_key(|(i, _)| *i);
    done.into_iter().map(|(_, o)| o).collect()
}

/// Fails on every outcome the ratchet of `known` (the list named `list`) rejects.
fn check(outcomes: &[Outcome], known: &[(&str, Known)], list: &str) {
    for (name, _) in known {
        assert!(
            scenes().iter().any(|s| s == name),
            "{list} lists {name}, not in the suite"
        );
    }
    let problems: Vec<String> = outcomes
        .iter()
        .filter_map(|o| {
            let k = known.iter().find(|(n, _)| *n == o.scene).map(|(_, k)| *k);
            ratchet(o, k, list)
        })
        .collect();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

#[test]
fn mitsuba_suite_cpu() {
    let outcomes = run_suite("CPU", BackendChoice::Cpu, budget(CPU_BUDGET), |_| true);
    check(&outcomes, KNOWN_CPU, "KNOWN_CPU");
}

/// The suite's scenes without media on the GPU backend (lavapipe in CI), with its own
/// ratchet.
#[test]
fn mitsuba_suite_gpu() {
    if common::gpu().is_none() {
        return;
    }
    let part = |s: &str| !is_media(s);
    let outcomes = run_suite("GPU", BackendChoice::Gpu, budget(GPU_BUDGET), part);
    check(&outcomes, KNOWN_GPU, "KNOWN_GPU");
}

/// The suite's media scenes on the GPU backend, with the same ratchet (apart: their kernels'
/// first compile is most of the GPU suite's time on lavapipe).
#[test]
fn mitsuba_suite_gpu_media() {
    if common::gpu().is_none() {
        return;
    }
    let outcomes = run_suite("GPU", BackendChoice::Gpu, budget(GPU_BUDGET), is_media);
    check(&outcomes, KNOWN_GPU, "KNOWN_GPU");
}

/// Every scene renders through the command line from the suite's own folder layout (the
/// file named relative to its folder, as a user runs it there): a zero exit and an image of
/// the film's size with finite pixels. A short budget: the renders are judged above.
#[test]
fn every_scene_renders_from_the_command_line() {
    let out = std::env::temp_dir().join(format!("mitsuba_suite_cli_{}", std::process::id()));
    std::fs::create_dir_all(&out).unwrap();
    let mut problems = Vec::new();
    for name in scenes() {
        let path = suite_root().join(&name);
        let (dir, file) = (path.parent().unwrap(), path.file_name().unwrap());
        let image = out.join(name.replace(['/', '.'], "_") + ".exr");
        let run = std::process::Command::new(env!("CARGO_BIN_EXE_gpu-photon"))
            .current_dir(dir)
            .arg("render")
            .arg(file)
            .arg("-o")
            .arg(&image)
            .args(["--backend", "cpu", "--spp", "1", "--passes", "1"])
            .args(["--photons", "2000", "--caustic-photons", "1000"])
            .output()
            .unwrap();
        if !run.status.success() {
            let err = String::from_utf8_lossy(&run.stderr);
            problems.push(format!("{name}: {}: {err}", run.status));
            continue;
        }
        let film = load(&path).unwrap().settings;
        match Image::read(&image) {
            Ok(i) if (i.width, i.height) != (film.width, film.height) => problems.push(format!(
                "{name}: {}x{}, the film is {}x{}",
                i.width, i.height, film.width, film.height
            )),
            Ok(i) if i.pixels.iter().flatten().any(|v| !v.is_finite()) => {
                problems.push(format!("{name}: a pixel is not finite"))
            }
            Ok(_) => {}
            Err(e) => problems.push(format!("{name}: {e}")),
        }
    }
    std::fs::remove_dir_all(&out).unwrap();
    assert!(problems.is_empty(), "{}", problems.join("\n"));
}

/// `default`, or the budget `MITSUBA_SUITE_BUDGET=PASSES,SPP,PHOTONS` names: the suite at
/// another budget, e.g. the GPU suite's short one on the CPU to tell the budget's failures from
/// the backend's (the CPU ratchet's figures hold at [`CPU_BUDGET`] only).
fn budget(default: Budget) -> Budget {
    let Ok(v) = std::env::var("MITSUBA_SUITE_BUDGET") else {
        return default;
    };
    let n: Vec<u32> = v
        .split(',')
        .map(|x| {
            x.trim()
                .parse()
                .expect("MITSUBA_SUITE_BUDGET: PASSES,SPP,PHOTONS")
        })
        .collect();
    assert_eq!(
        n.len(),
        3,
        "MITSUBA_SUITE_BUDGET: PASSES,SPP,PHOTONS, got {v:?}"
    );
    Budget {
        passes: n[0],
        spp: n[1],
        photons: n[2],
    }
}

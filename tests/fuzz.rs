//! In-process fuzzing of every scene importer (issue 26): mutated copies of the seed corpus
//! `tests/data/fuzz/<format>/<seed>/` are loaded and, when they load, rendered at 8x8, one
//! sample per pixel, on the CPU. No case may panic, hang or abort (the process runs under a
//! 4 GiB address-space limit, so an unbounded allocation aborts it), and every error must
//! say where it is (`FILE:LINE: ...` or `FILE: byte N: ...`). A failing case is copied to
//! `tests/data/fuzz/regressions/`, which `regressions_stay_fixed` replays.
//!
//! `cargo test --release --test fuzz` runs a short fixed-seed run. For a long run, see
//! `docs/fuzzing.md`: `GPU_PHOTON_FUZZ_CASES` (cases per format), `GPU_PHOTON_FUZZ_SEED`
//! (the first case's number), `GPU_PHOTON_FUZZ_FORMATS` (a comma-separated subset) and
//! `GPU_PHOTON_FUZZ_KEEP` (where failing cases go instead of the regression corpus);
//! `GPU_PHOTON_FUZZ_SAVE=ply:42,obj:570` keeps those cases too (a fixed case that failed).

#[path = "fuzz/mutate.rs"]
mod mutate;

use gpu_photon::importers::load;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render, Backend};
use mutate::{mutate, Rng};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{mpsc, Mutex};
use std::time::{Duration, Instant};

/// The formats and the extensions of the files a case of each mutates.
const FORMATS: &[(&str, &[&str])] = &[
    ("toml", &["toml", "vol"]),
    ("xml", &["xml", "vol"]),
    ("gltf", &["gltf", "bin"]),
    ("glb", &["glb"]),
    ("ply", &["ply"]),
    ("obj", &["obj"]),
    ("serialized", &["serialized"]),
];

/// Cases per format of the CI run (about 25 s on two shared cores, release build).
const CI_CASES: u64 = 800;

/// Longest a case may take before it counts as a hang.
const DEADLINE: Duration = Duration::from_secs(20);

/// Address space the test process may use for data: an allocation past it aborts the run.
/// Each thread adds [`PER_THREAD`] for its stack and malloc arena, which reserve address
/// space they do not use.
const ADDRESS_SPACE: u64 = 4 << 30;
/// Address space reserved per hardware thread on top of [`ADDRESS_SPACE`].
const PER_THREAD: u64 = 128 << 20;

fn corpus() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/fuzz")
}

/// What happened to one case.
#[derive(Debug)]
enum Outcome {
    /// Loaded and rendered.
    Rendered,
    /// Refused with an error that names its place.
    Located(String),
    /// Refused with an error that does not.
    Unlocated(String),
    /// An error or warning that holds a control character (a value echoed unescaped: a
    /// newline in an id splits the message).
    Unescaped(String),
    /// A panic, with its message and place.
    Panic(String),
    /// Still running at the deadline.
    Hang,
}

/// One seed scene: its directory, the scene file to load, the files a case may mutate.
struct Seed {
    dir: PathBuf,
    entry: String,
    targets: Vec<String>,
}

/// The seeds of `format` (each a directory holding one `scene.*` file).
fn seeds(format: &str, exts: &[&str]) -> Vec<Seed> {
    let mut dirs: Vec<PathBuf> = std::fs::read_dir(corpus().join(format))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    dirs.sort();
    dirs.into_iter()
        .map(|dir| {
            let mut names = files(&dir);
            names.sort();
            let entry = names.iter().find(|n| is_scene(n)).unwrap().clone();
            let targets = names
                .into_iter()
                .filter(|n| exts.iter().any(|e| n.ends_with(&format!(".{e}"))))
                .collect();
            Seed {
                dir,
                entry,
                targets,
            }
        })
        .collect()
}

/// Whether `name` is a case's scene file (`scene.toml`, `.xml`, `.gltf` or `.glb`).
fn is_scene(name: &str) -> bool {
    ["toml", "xml", "gltf", "glb"]
        .iter()
        .any(|e| name == format!("scene.{e}"))
}

/// The names of the plain files in `dir`.
fn files(dir: &Path) -> Vec<String> {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect()
}

/// Whether an error message says where it is: it names a file of `dir`, and every file of
/// `dir` it names (the file at fault, the files that referred to it, an earlier definition)
/// is followed by `:LINE` or `: byte N`.
fn located(message: &str, dir: &Path) -> bool {
    let first = message.lines().next().unwrap_or("");
    let prefix = format!("{}/", dir.display());
    let digits = |s: &str| s.bytes().take_while(u8::is_ascii_digit).count() > 0;
    let mut named = first.match_indices(&prefix).peekable();
    named.peek().is_some()
        && named.all(|(at, _)| {
            let rest = &first[at + prefix.len()..];
            rest.find(':').is_some_and(|colon| {
                let after = &rest[colon..];
                after.strip_prefix(':').is_some_and(digits)
                    || after.strip_prefix(": byte ").is_some_and(digits)
                    || unreadable(after)
            })
        })
}

/// Whether the text after a file's name says the file could not be read at all (it is the
/// file referred to, and has no place to name): an operating-system error.
fn unreadable(after: &str) -> bool {
    let what = after.strip_prefix(": ").unwrap_or("");
    let what = what.strip_prefix("cannot read: ").unwrap_or(what);
    what.contains("(os error ") || what.starts_with("not a regular file")
}

/// Set while cases run: the panic hook then records panics instead of printing them.
static QUIET: AtomicBool = AtomicBool::new(false);
/// The last panic's message and place, as the hook saw it.
static LAST_PANIC: Mutex<Option<String>> = Mutex::new(None);

/// Installs the recording panic hook and the address-space limit, once.
fn prepare() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        let default = std::panic::take_hook();
        std::panic::set_hook(Box::new(move |info| {
            if QUIET.load(Ordering::SeqCst) {
                *LAST_PANIC.lock().unwrap() = Some(info.to_string());
            } else {
                default(info);
            }
        }));
        limit_address_space();
    });
}

/// Caps the process's address space at [`ADDRESS_SPACE`] plus [`PER_THREAD`] per hardware
/// thread (Linux; elsewhere a no-op).
fn limit_address_space() {
    #[cfg(target_os = "linux")]
    {
        let threads = std::thread::available_parallelism().map_or(1, |n| n.get()) as u64;
        let mut limit = libc::rlimit {
            rlim_cur: 0,
            rlim_max: 0,
        };
        // SAFETY: getrlimit and setrlimit read or write the one struct they are given.
        let rc = unsafe { libc::getrlimit(libc::RLIMIT_AS, &mut limit) };
        assert_eq!(rc, 0, "getrlimit(RLIMIT_AS)");
        // Lowered only: a tighter limit set from outside (`prlimit`) stays.
        limit.rlim_cur = limit.rlim_cur.min(ADDRESS_SPACE + PER_THREAD * threads);
        let rc = unsafe { libc::setrlimit(libc::RLIMIT_AS, &limit) };
        assert_eq!(rc, 0, "setrlimit(RLIMIT_AS)");
    }
}

/// Loads the scene at `entry` and renders it small (see [`load_and_render_quietly`]); a
/// warning with a control character in it makes the case [`Outcome::Unescaped`].
fn load_and_render(entry: &Path) -> Outcome {
    let (outcome, warnings) = gpu_photon::warning::collect(|| load_and_render_quietly(entry));
    match warnings.into_iter().find(|w| unescaped(&w.message)) {
        Some(w) => Outcome::Unescaped(format!("warning: {}", w.message)),
        None => outcome,
    }
}

/// Whether a message holds a character that must be escaped: a control character (C0, DEL or
/// C1; a newline included), a line or paragraph separator, a bidirectional formatting one.
fn unescaped(message: &str) -> bool {
    message.chars().any(|c| {
        c.is_control()
            || matches!(c, '\u{2028}' | '\u{2029}' | '\u{200e}' | '\u{200f}')
            || ('\u{202a}'..='\u{202e}').contains(&c)
            || ('\u{2066}'..='\u{2069}').contains(&c)
    })
}

/// Loads the scene at `entry` and renders it small: 8x8, 1 spp, at most 2,000 photons
/// (1,000 caustic) and two progressive passes, on the CPU.
fn load_and_render_quietly(entry: &Path) -> Outcome {
    let scene = match load(entry) {
        Ok(scene) => scene,
        Err(e) => return classify(e.to_string(), entry.parent().unwrap()),
    };
    let mut s = scene.settings.as_default_render();
    s.width = 8;
    s.height = 8;
    s.spp = 1;
    s.photons = s.photons.min(2000);
    s.caustic_photons = s.caustic_photons.min(1000);
    s.pass_range = s.pass_range.map(|(a, b)| (a, b.min(a + 2)));
    match render(&scene, &s, Backend::Cpu, Progress::default()) {
        Ok(_) => Outcome::Rendered,
        Err(e) => classify(e.to_string(), entry.parent().unwrap()),
    }
}

fn classify(message: String, dir: &Path) -> Outcome {
    if std::env::var_os("GPU_PHOTON_FUZZ_VERBOSE").is_some() {
        eprintln!("{message}");
    }
    if unescaped(&message) {
        Outcome::Unescaped(message)
    } else if located(&message, dir) {
        Outcome::Located(message)
    } else {
        Outcome::Unlocated(message)
    }
}

/// Runs `entry` on a worker thread: its outcome, a caught panic, or [`Outcome::Hang`] at the
/// deadline (the worker is then left running).
fn run_case(entry: PathBuf) -> Outcome {
    let (tx, rx) = mpsc::channel();
    std::thread::Builder::new()
        .name("fuzz-case".into())
        .spawn(move || {
            let outcome = std::panic::catch_unwind(|| load_and_render(&entry));
            let outcome = outcome.unwrap_or_else(|_| {
                Outcome::Panic(LAST_PANIC.lock().unwrap().take().unwrap_or_default())
            });
            let _ = tx.send(outcome);
        })
        .unwrap();
    rx.recv_timeout(DEADLINE).unwrap_or(Outcome::Hang)
}

/// Builds case `n` of `format` in `work`: a copy of one seed with one file mutated. Returns
/// the scene file to load.
fn build_case(format: &str, seeds: &[Seed], n: u64, work: &Path) -> PathBuf {
    let mut rng = Rng::new(n ^ (format.len() as u64) << 56 ^ fnv(format));
    let seed = &seeds[rng.below(seeds.len())];
    let target = rng.pick(&seed.targets).clone();
    let donor_seed = &seeds[rng.below(seeds.len())];
    let donor = std::fs::read(donor_seed.dir.join(rng.pick(&donor_seed.targets))).unwrap();
    std::fs::create_dir_all(work).unwrap();
    for name in files(&seed.dir) {
        let bytes = std::fs::read(seed.dir.join(&name)).unwrap();
        let bytes = if name == target {
            mutate(&bytes, &donor, &mut rng)
        } else {
            bytes
        };
        std::fs::write(work.join(&name), bytes).unwrap();
    }
    work.join(&seed.entry)
}

/// FNV-1a of a name, to give each format its own case sequence.
fn fnv(s: &str) -> u64 {
    s.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ b as u64).wrapping_mul(0x100_0000_01b3)
    })
}

/// Counts of outcomes for one format.
#[derive(Default, Debug)]
struct Tally {
    rendered: u64,
    located: u64,
    unlocated: u64,
    unescaped: u64,
    panics: u64,
    hangs: u64,
    failures: Vec<String>,
    /// The slowest case: (seconds, case number).
    slowest: (f64, u64),
}

fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .map_or(default, |v| v.parse().expect(name))
}

/// Copies a failed case into the regression corpus.
fn keep(work: &Path, name: &str) {
    let to = std::env::var_os("GPU_PHOTON_FUZZ_KEEP")
        .map_or_else(|| corpus().join("regressions"), PathBuf::from)
        .join(name);
    std::fs::create_dir_all(&to).unwrap();
    for f in files(work) {
        std::fs::copy(work.join(&f), to.join(&f)).unwrap();
    }
}

#[test]
fn mutated_scenes_fail_cleanly() {
    prepare();
    let cases = env_u64("GPU_PHOTON_FUZZ_CASES", CI_CASES);
    let first = env_u64("GPU_PHOTON_FUZZ_SEED", 0);
    let only = std::env::var("GPU_PHOTON_FUZZ_FORMATS").ok();
    let save: Vec<String> = std::env::var("GPU_PHOTON_FUZZ_SAVE")
        .map(|v| v.split(',').map(String::from).collect())
        .unwrap_or_default();
    let root = std::env::temp_dir().join(format!("gpu-photon-fuzz-{}", std::process::id()));
    eprintln!(
        "fuzz: cases under {} (a crash leaves its case there)",
        root.display()
    );
    let mut failed = Vec::new();
    for &(format, exts) in FORMATS {
        if only
            .as_ref()
            .is_some_and(|o| !o.split(',').any(|f| f == format))
        {
            continue;
        }
        let seeds = seeds(format, exts);
        let mut t = Tally::default();
        let start = Instant::now();
        for n in first..first + cases {
            let work = root.join(format!("{format}-{n}"));
            let entry = build_case(format, &seeds, n, &work);
            QUIET.store(true, Ordering::SeqCst);
            let case_start = Instant::now();
            let outcome = run_case(entry);
            QUIET.store(false, Ordering::SeqCst);
            let took = case_start.elapsed().as_secs_f64();
            if took > t.slowest.0 {
                t.slowest = (took, n);
            }
            let bad = match &outcome {
                Outcome::Rendered => (t.rendered += 1, None).1,
                Outcome::Located(_) => (t.located += 1, None).1,
                Outcome::Unlocated(m) => {
                    (t.unlocated += 1, Some(format!("error without place: {m}"))).1
                }
                Outcome::Unescaped(m) => {
                    let why = format!("control character in a message: {m:?}");
                    (t.unescaped += 1, Some(why)).1
                }
                Outcome::Panic(m) => (t.panics += 1, Some(format!("panic: {m}"))).1,
                Outcome::Hang => (t.hangs += 1, Some("hang".to_string())).1,
            };
            if save.contains(&format!("{format}:{n}")) {
                keep(&work, &format!("{format}-{n}"));
            }
            if let Some(why) = bad {
                keep(&work, &format!("{format}-{n}"));
                t.failures.push(format!("{format} case {n}: {why}"));
            }
            if matches!(outcome, Outcome::Hang) && t.hangs >= 3 {
                break;
            }
            let _ = std::fs::remove_dir_all(&work);
        }
        eprintln!(
            "fuzz {format}: {} cases in {:.1} s: {} rendered, {} located errors, {} unlocated, \
             {} unescaped, {} panics, {} hangs; slowest case {} ({:.2} s)",
            t.rendered + t.located + t.unlocated + t.unescaped + t.panics + t.hangs,
            start.elapsed().as_secs_f64(),
            t.rendered,
            t.located,
            t.unlocated,
            t.unescaped,
            t.panics,
            t.hangs,
            t.slowest.1,
            t.slowest.0
        );
        for f in &t.failures {
            eprintln!("  {f}");
        }
        failed.extend(t.failures);
    }
    let _ = std::fs::remove_dir_all(&root);
    assert!(
        failed.is_empty(),
        "{} failing cases (kept in tests/data/fuzz/regressions/):\n{}",
        failed.len(),
        failed.join("\n")
    );
}

#[test]
fn regressions_stay_fixed() {
    prepare();
    let dir = corpus().join("regressions");
    let mut cases: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.is_dir())
        .collect();
    cases.sort();
    let mut failed = Vec::new();
    for case in &cases {
        let entry = files(case).into_iter().find(|n| is_scene(n)).unwrap();
        QUIET.store(true, Ordering::SeqCst);
        let outcome = run_case(case.join(entry));
        QUIET.store(false, Ordering::SeqCst);
        // The issues' own cases (`issue26-*`, `issue44-*`) are all invalid: each must be
        // refused.
        let must_refuse = case
            .file_name()
            .unwrap()
            .to_string_lossy()
            .starts_with("issue");
        match outcome {
            Outcome::Located(m) if m.is_empty() => {
                failed.push(format!("{}: empty", case.display()))
            }
            Outcome::Located(_) => {}
            Outcome::Rendered if !must_refuse => {}
            other => failed.push(format!("{}: {other:?}", case.display())),
        }
    }
    assert!(failed.is_empty(), "{}", failed.join("\n"));
}

#[test]
fn seeds_render() {
    prepare();
    for &(format, exts) in FORMATS {
        for seed in seeds(format, exts) {
            let outcome = run_case(seed.dir.join(&seed.entry));
            assert!(
                matches!(outcome, Outcome::Rendered),
                "{}: {outcome:?}",
                seed.dir.display()
            );
        }
    }
}

#[test]
fn locations_are_recognised() {
    let d = Path::new("/a");
    assert!(located("/a/t.xml:3: shape[0]: bad", d));
    assert!(located("/a/m.ply: byte 120: element `face`: bad", d));
    assert!(located("/a/t.toml:3: shapes[0].file: /a/m.ply:7: bad", d));
    assert!(!located(
        "/a/t.toml:3: shapes[0].file: /a/m.ply: face 2: bad",
        d
    ));
    assert!(!located("/a/t.xml: stream did not contain valid UTF-8", d));
    let missing = "/a/t.gltf:9: buffers[0]: cannot read buffer /a/x.bin: No such file or \
                   directory (os error 2)";
    assert!(located(missing, d));
    assert!(!located("invalid setting spp: 0 is outside 1..=65536", d));
}

//! A render split over a real Slurm job array: a private one-node cluster
//! (scripts/slurm-cluster.sh: munged, slurmctld, slurmd in a scratch directory) runs
//! examples/slurm/submit.sh, an array of 4 slices plus the merge job that depends on it. The
//! merged image must be the bytes of a single `--passes` run; then one array task is cancelled
//! mid-render: Slurm's SIGTERM lets it finish its pass and write its slice (the merge job is
//! still cancelled, as the task was; the slice merges by hand into the same bytes, and
//! without it `merge` names the missing passes), it is resubmitted alone, and the result
//! must again be the same bytes.
//!
//! Needs Debian's slurmctld, slurmd, slurm-client and munge (`.ci/run` installs them) and
//! root. Without them it skips with a message, unless CI=true, where it fails.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

const PASSES: &str = "4";
const SLICES: &str = "4";
/// Passes heavy enough (about 0.5 s each on one core) that a task can be caught mid-render.
const RENDER: [&str; 12] = [
    "--backend",
    "cpu",
    "--width",
    "128",
    "--height",
    "128",
    "--spp",
    "16",
    "--photons",
    "300000",
    "--seed",
    "3",
];

fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn bin() -> PathBuf {
    PathBuf::from(env!("CARGO_BIN_EXE_gpu-photon"))
}

fn find(name: &str) -> Option<PathBuf> {
    let path = std::env::var_os("PATH").unwrap_or_default();
    std::env::split_paths(&path)
        .chain([PathBuf::from("/usr/sbin"), PathBuf::from("/usr/bin")])
        .map(|d| d.join(name))
        .find(|p| p.is_file())
}

/// Why this machine cannot run the cluster, if it cannot.
fn missing_requirements() -> Option<String> {
    let tools = [
        "munged",
        "mungekey",
        "slurmctld",
        "slurmd",
        "sbatch",
        "squeue",
        "scontrol",
        "scancel",
        "sinfo",
    ];
    let missing: Vec<&str> = tools.into_iter().filter(|t| find(t).is_none()).collect();
    if !missing.is_empty() {
        return Some(format!(
            "{} not installed (apt-get install --no-install-recommends slurmctld slurmd slurm-client munge)",
            missing.join(", ")
        ));
    }
    let uid = Command::new("id").arg("-u").output().ok()?;
    if String::from_utf8_lossy(&uid.stdout).trim() != "0" {
        return Some("not root (slurmd starts jobs as their user)".into());
    }
    None
}

fn free_port() -> u16 {
    let l = std::net::TcpListener::bind("127.0.0.1:0").unwrap();
    l.local_addr().unwrap().port()
}

/// A running private cluster, stopped (by the pids in its pid files) when dropped, also
/// when the test fails; its directory (with the daemons' and jobs' logs) is kept then.
struct Cluster {
    dir: PathBuf,
    conf: PathBuf,
}

impl Cluster {
    fn start() -> Cluster {
        let dir = std::env::temp_dir().join(format!("gpu-photon-slurm-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let cluster = Cluster {
            conf: dir.join("slurm.conf"),
            dir,
        };
        // From here on, Drop stops whatever part of the cluster started.
        let out = Command::new("bash")
            .arg(root().join("scripts/slurm-cluster.sh"))
            .arg("start")
            .arg(&cluster.dir)
            .env("SLURMCTLD_PORT", free_port().to_string())
            .env("SLURMD_PORT", free_port().to_string())
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "slurm-cluster.sh start failed: {}{}",
            String::from_utf8_lossy(&out.stderr),
            cluster.logs()
        );
        cluster
    }

    /// A Slurm client command (or a script calling them) aimed at this cluster.
    fn cmd(&self, program: impl AsRef<std::ffi::OsStr>) -> Command {
        let mut c = Command::new(program);
        c.env("SLURM_CONF", &self.conf)
            .env("GPU_PHOTON", bin())
            .env_remove("SLURM_ARRAY_TASK_ID")
            .current_dir(root());
        c
    }

    fn run(&self, program: &str, args: &[&str]) -> Output {
        self.cmd(program).args(args).output().unwrap()
    }

    /// The tail of the daemons' logs and every job log, for failure messages.
    fn logs(&self) -> String {
        let mut s = String::new();
        let mut files: Vec<PathBuf> = ["log/slurmctld.log", "log/slurmd.log"]
            .iter()
            .map(|f| self.dir.join(f))
            .collect();
        for sub in ["round1/logs", "round2/logs"] {
            if let Ok(rd) = std::fs::read_dir(self.dir.join(sub)) {
                files.extend(rd.flatten().map(|e| e.path()));
            }
        }
        for f in files {
            if let Ok(text) = std::fs::read_to_string(&f) {
                let lines: Vec<&str> = text.lines().collect();
                let tail = lines[lines.len().saturating_sub(15)..].join("\n");
                s.push_str(&format!("\n== {}\n{tail}", f.display()));
            }
        }
        s
    }

    /// Submits the example's array and merge job; returns their job ids.
    fn submit(&self, outdir: &Path, tasks: Option<&str>) -> (String, String) {
        let mut c = self.cmd("bash");
        c.arg(root().join("examples/slurm/submit.sh"));
        if let Some(t) = tasks {
            c.env("TASKS", t);
        }
        let out = c
            .arg(root().join("scenes/cornell-box.toml"))
            .args([PASSES, SLICES])
            .arg(outdir)
            .args(RENDER)
            .output()
            .unwrap();
        let stdout = String::from_utf8_lossy(&out.stdout).to_string();
        assert!(
            out.status.success(),
            "submit.sh: {}{}",
            String::from_utf8_lossy(&out.stderr),
            self.logs()
        );
        let ids: Vec<&str> = stdout.split_whitespace().collect();
        assert_eq!(ids.len(), 2, "submit.sh printed '{stdout}'");
        (ids[0].to_string(), ids[1].to_string())
    }

    /// Waits until none of `jobs` is pending or running (sbatch --wait is not enough: it
    /// returns 0 for a cancelled dependent job).
    fn wait(&self, jobs: &[&str]) {
        let start = Instant::now();
        loop {
            let out = self.run("squeue", &["-h", "-o", "%i", "-j", &jobs.join(",")]);
            if out.stdout.iter().all(|b| b.is_ascii_whitespace()) {
                return;
            }
            assert!(
                start.elapsed() < Duration::from_secs(100),
                "jobs {jobs:?} still queued after 100 s:\n{}{}",
                String::from_utf8_lossy(&out.stdout),
                self.logs()
            );
            std::thread::sleep(Duration::from_millis(100));
        }
    }

    /// `(ArrayTaskId or "-", JobState, Reason)` of each job (an array: each task) of `job`.
    fn states(&self, job: &str) -> Vec<(String, String, String)> {
        let out = self.run("scontrol", &["-o", "show", "job", job]);
        assert!(out.status.success(), "scontrol show job {job}");
        String::from_utf8_lossy(&out.stdout)
            .lines()
            .map(|l| {
                let field = |k: &str| {
                    l.split_whitespace()
                        .find_map(|f| f.strip_prefix(k))
                        .unwrap_or("-")
                        .to_string()
                };
                (field("ArrayTaskId="), field("JobState="), field("Reason="))
            })
            .collect()
    }

    fn assert_completed(&self, job: &str, tasks: usize) {
        let states = self.states(job);
        assert_eq!(states.len(), tasks, "job {job}: {states:?}");
        for s in &states {
            assert_eq!(s.1, "COMPLETED", "job {job}: {states:?}{}", self.logs());
        }
    }
}

impl Drop for Cluster {
    fn drop(&mut self) {
        let stopped = Command::new("bash")
            .arg(root().join("scripts/slurm-cluster.sh"))
            .arg("stop")
            .arg(&self.dir)
            .status();
        if !matches!(stopped, Ok(s) if s.success()) {
            eprintln!("slurm-cluster.sh stop {} failed", self.dir.display());
        }
        if std::thread::panicking() {
            eprintln!("kept {} (logs)", self.dir.display());
        } else {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}

/// The pid of the render process of task `task` of array job `array`, when it runs.
fn task_process(array: &str, task: &str) -> Option<u32> {
    let want = [
        format!("SLURM_ARRAY_JOB_ID={array}"),
        format!("SLURM_ARRAY_TASK_ID={task}"),
    ];
    let exe = std::fs::canonicalize(bin()).ok()?;
    for e in std::fs::read_dir("/proc").ok()?.flatten() {
        let Ok(pid) = e.file_name().to_string_lossy().parse::<u32>() else {
            continue;
        };
        if std::fs::read_link(e.path().join("exe")).ok().as_ref() != Some(&exe) {
            continue;
        }
        let Ok(env) = std::fs::read(e.path().join("environ")) else {
            continue;
        };
        let vars: Vec<String> = env
            .split(|&b| b == 0)
            .map(|v| String::from_utf8_lossy(v).into_owned())
            .collect();
        if want.iter().all(|w| vars.contains(w)) {
            return Some(pid);
        }
    }
    None
}

/// Whether process `pid` has a handler for SIGTERM (`SigCgt` in /proc/PID/status): the render
/// installs it once its renderer is open, just before its first pass.
fn catches_sigterm(pid: u32) -> bool {
    let Ok(status) = std::fs::read_to_string(format!("/proc/{pid}/status")) else {
        return false;
    };
    status
        .lines()
        .find_map(|l| l.strip_prefix("SigCgt:"))
        .and_then(|mask| u64::from_str_radix(mask.trim(), 16).ok())
        .is_some_and(|mask| mask & (1 << (15 - 1)) != 0)
}

fn same_bytes(a: &Path, b: &Path) -> bool {
    std::fs::read(a).unwrap() == std::fs::read(b).unwrap()
}

#[test]
fn slurm_array_renders_merges_and_recovers_a_killed_task() {
    if let Some(why) = missing_requirements() {
        if std::env::var("CI").as_deref() == Ok("true") {
            panic!("the Slurm test must run in CI: {why}");
        }
        eprintln!("skipping the Slurm test: {why}");
        return;
    }
    let start = Instant::now();
    let cluster = Cluster::start();
    let (round1, round2) = (cluster.dir.join("round1"), cluster.dir.join("round2"));
    // The reference renders beside the array.
    let whole = cluster.dir.join("whole.exr");
    let reference = Command::new(bin())
        .arg("render")
        .arg(root().join("scenes/cornell-box.toml"))
        .args(["--passes", PASSES, "-q", "-o"])
        .arg(&whole)
        .args(RENDER)
        .spawn()
        .unwrap();

    // Round 1: every task runs; the merge job follows.
    let (array, merge) = cluster.submit(&round1, None);
    cluster.wait(&[&array, &merge]);
    cluster.assert_completed(&array, 4);
    cluster.assert_completed(&merge, 1);
    let out = reference.wait_with_output().unwrap();
    assert!(out.status.success(), "the reference render failed");
    assert!(
        same_bytes(&round1.join("merged.exr"), &whole),
        "the merged slices differ from the single --passes run"
    );

    // Round 2: task 2 is stopped mid-render (SIGSTOP, so it cannot finish while it is being
    // cancelled; once its renderer is open and its signal handler installed, so the pass is
    // in flight), then cancelled: Slurm sends SIGCONT and SIGTERM, then SIGKILL after
    // KillWait (30 s, Slurm's default).
    let (array, merge) = cluster.submit(&round2, None);
    let t = Instant::now();
    let pid = loop {
        if let Some(pid) = task_process(&array, "2").filter(|&p| catches_sigterm(p)) {
            break pid;
        }
        let st = cluster.states(&format!("{array}_2"));
        assert!(
            st.iter().all(|s| s.1 == "PENDING" || s.1 == "RUNNING"),
            "task 2 ended before it could be caught mid-render: {st:?}"
        );
        assert!(t.elapsed() < Duration::from_secs(100), "task 2 never ran");
        std::thread::sleep(Duration::from_millis(10));
    };
    let stop = Command::new("kill")
        .args(["-STOP", &pid.to_string()])
        .status()
        .unwrap();
    assert!(stop.success());
    let slice2 = round2.join("slice-2.exr");
    assert!(
        !slice2.exists(),
        "task 2 wrote its slice before it was stopped"
    );
    let cancel = cluster.run("scancel", &[&format!("{array}_2")]);
    assert!(cancel.status.success(), "scancel");
    cluster.wait(&[&array, &merge]);
    let t = Instant::now();
    while task_process(&array, "2").is_some() {
        assert!(
            t.elapsed() < Duration::from_secs(20),
            "the cancelled render (pid {pid}) is still there"
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    for (task, state, _) in cluster.states(&array) {
        let want = if task == "2" {
            "CANCELLED"
        } else {
            "COMPLETED"
        };
        assert_eq!(state, want, "task {task}{}", cluster.logs());
    }
    // --kill-on-invalid-dep=yes: the merge job is cancelled, not left pending forever.
    let merge_state = cluster.states(&merge);
    assert_eq!(merge_state[0].1, "CANCELLED", "{merge_state:?}");
    assert!(!round2.join("merged.exr").exists());
    // The cancelled task finished its pass in flight and wrote it: a whole, valid slice.
    let log = std::fs::read_to_string(round2.join(format!("logs/slice-2-{array}.out")))
        .unwrap_or_default();
    assert!(
        log.contains(&format!(
            "{}: stopped by SIGTERM after passes 2..3 of 2..3; wrote them",
            slice2.display()
        )),
        "task 2's log: {log}{}",
        cluster.logs()
    );
    let by_hand = cluster.dir.join("by-hand.exr");
    let merged = Command::new(bin())
        .arg("merge")
        .args((0..4).map(|i| round2.join(format!("slice-{i}.exr"))))
        .arg("-o")
        .arg(&by_hand)
        .output()
        .unwrap();
    assert!(merged.status.success(), "{merged:?}");
    assert!(
        same_bytes(&by_hand, &whole),
        "the cancelled task's slice does not merge into the single --passes run"
    );
    // Without it (as a task killed outright, before its first pass ended, leaves the
    // directory), a merge names the missing passes.
    std::fs::remove_file(&slice2).unwrap();
    let slices: Vec<PathBuf> = [0, 1, 3]
        .iter()
        .map(|i| round2.join(format!("slice-{i}.exr")))
        .collect();
    let refused = Command::new(bin())
        .arg("merge")
        .args(&slices)
        .arg("-o")
        .arg(round2.join("early.exr"))
        .output()
        .unwrap();
    assert_eq!(refused.status.code(), Some(1));
    assert!(
        String::from_utf8_lossy(&refused.stderr).contains("passes 2..3 of the render's 0..4"),
        "{}",
        String::from_utf8_lossy(&refused.stderr)
    );

    // Task 2 alone again, with a new merge job.
    let (array, merge) = cluster.submit(&round2, Some("2"));
    cluster.wait(&[&array, &merge]);
    cluster.assert_completed(&array, 1);
    cluster.assert_completed(&merge, 1);
    assert!(
        same_bytes(&round2.join("merged.exr"), &whole),
        "after the resubmission the merged slices differ from the single --passes run"
    );
    eprintln!(
        "slurm test: cluster, 2 rounds and a resubmission in {:.1} s",
        start.elapsed().as_secs_f64()
    );
}

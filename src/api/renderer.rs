//! [`Renderer`]: a backend opened once on a [`Scene`], asked for pass after pass.
//!
//! The backends borrow the scene they render (`session::open`); a renderer that owns what it
//! needs runs that borrow on a worker thread which owns a share of the scene, and hands it
//! one pass at a time. The caller's thread keeps the running mean, so a progress callback,
//! a cancellation flag or Python's interpreter are never on the rendering thread.

use crate::api::{Backend, Scene};
use crate::error::{Error, Result};
use crate::render::film::Image;
use crate::render::progressive::{pass_settings, Accumulator, Flow};
use crate::render::report::{Progress, RenderReport};
use crate::render::session::open;
use crate::settings::{validate, RenderSettings, MAX_PASSES};
use crate::warning::{collect, Warning};
use std::ops::Range;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, Receiver, Sender};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// When [`Renderer::run`] stops early (it always stops at the end of the planned passes).
#[derive(Clone, Copy, Debug, Default)]
pub struct Stop {
    /// After the pass that ends past this long since the renderer opened.
    pub time: Option<Duration>,
    /// At the first even pass count whose estimated relative noise is at most this.
    pub noise: Option<f64>,
}

/// Where a render stands after a pass, as the progress callback sees it.
#[derive(Clone, Copy, Debug)]
pub struct PassInfo {
    /// The pass just rendered (the RNG's pass index).
    pub pass: u32,
    /// Passes in the running mean.
    pub done: u32,
    /// Passes planned (`None`: until a time or noise target).
    pub planned: Option<u32>,
    /// Estimated relative noise of the mean (see [`Renderer::noise`]).
    pub noise: Option<f64>,
    /// Time since the renderer opened.
    pub elapsed: Duration,
}

enum Job {
    Pass(u32, Box<RenderSettings>, Progress),
    Report,
}

enum Reply {
    Pass(Result<Image>, Vec<Warning>),
    Report(Result<RenderReport>),
}

/// A renderer opened on a scene: one classic pass when `settings.passes` is 0, else the
/// progressive passes `0..passes` (or `settings.pass_range`), averaged as they come.
pub struct Renderer {
    settings: RenderSettings,
    shared: Arc<crate::scene::Scene>,
    jobs: Sender<Job>,
    replies: Receiver<Reply>,
    acc: Accumulator,
    next: u32,
    end: u32,
    classic: bool,
    /// A classic render's image, as the pass gave it.
    classic_image: Option<Image>,
    cancel: Arc<AtomicBool>,
    warnings: Vec<Warning>,
    bars: bool,
    opened: Instant,
}

impl Renderer {
    /// Opens `backend` for `scene` with `settings` (checked against the setting ranges):
    /// builds the BVH, light table and photon plan (and on the GPU the device, buffers and
    /// pipelines) once. `Backend::Auto` takes the faster backend of this machine and falls
    /// back to the CPU with a [`Warning`].
    pub fn new(scene: &Scene, settings: &RenderSettings, backend: Backend) -> Result<Renderer> {
        validate(settings)?;
        let opened = Instant::now();
        let planned = match settings.pass_range {
            Some(r) => Some(r),
            None => settings.as_default_render().pass_range,
        };
        let classic = planned.is_none();
        let (first, end) = planned.unwrap_or((0, 1));
        if first >= end {
            return Err(Error::Setting {
                field: "pass-range",
                message: format!("{first}..{end} holds no pass"),
            });
        }
        let (jobs, job_rx) = channel::<Job>();
        let (reply_tx, replies) = channel::<Reply>();
        let (shared, render_settings) = (scene.shared(), settings.clone());
        let worker_scene = shared.clone();
        std::thread::Builder::new()
            .name("gpu-photon renderer".into())
            .spawn(move || work(worker_scene, render_settings, backend, job_rx, reply_tx))
            .map_err(|e| Error::Gpu(format!("no renderer thread: {e}")))?;
        let warnings = match replies.recv() {
            Ok(Reply::Pass(Ok(_), w)) => w,
            Ok(Reply::Pass(Err(e), _)) => return Err(e),
            _ => return Err(gone()),
        };
        Ok(Renderer {
            settings: settings.clone(),
            shared,
            jobs,
            replies,
            acc: Accumulator::new(settings.width, settings.height, first),
            next: first,
            end,
            classic,
            classic_image: None,
            cancel: Arc::new(AtomicBool::new(false)),
            warnings,
            bars: false,
            opened,
        })
    }

    /// Draws progress bars on stderr while rendering (off by default; for command lines).
    pub fn show_progress_bars(&mut self, on: bool) {
        self.bars = on;
    }

    /// The passes planned: `first..end` (`end` is `u32::MAX >> 8` for a render until a time
    /// or noise target).
    pub fn passes(&self) -> Range<u32> {
        self.acc.first..self.end
    }

    /// Renders the next planned pass into the running mean; `Ok(false)` when none is left.
    pub fn render_pass(&mut self) -> Result<bool> {
        if self.next >= self.end {
            return Ok(false);
        }
        let p = self.next;
        let s = if self.classic {
            self.settings.clone()
        } else {
            pass_settings(&self.shared, &self.settings, p)
        };
        // A classic pass shows its own bar of rows; progressive ones a bar of passes (run).
        let progress = Progress {
            enabled: self.bars && self.classic,
        };
        let image = match self.ask(Job::Pass(p, Box::new(s), progress))? {
            Reply::Pass(image, w) => {
                self.warnings.extend(w);
                image?
            }
            Reply::Report(_) => return Err(gone()),
        };
        self.acc.add(&image);
        if self.classic {
            self.classic_image = Some(image);
        }
        self.next += 1;
        Ok(true)
    }

    /// Renders the planned passes until `stop`, the cancellation flag
    /// ([`Renderer::cancel_flag`]) or `on_pass` (called after every pass with where the
    /// render stands and the renderer, e.g. to save its running mean) returning
    /// [`Flow::Stop`] ends them, each checked after a pass (so the mean always holds whole
    /// passes).
    pub fn run(
        &mut self,
        stop: &Stop,
        mut on_pass: impl FnMut(&PassInfo, &Renderer) -> Flow,
    ) -> Result<()> {
        let planned = (self.end < MAX_PASSES).then(|| self.end - self.acc.first);
        let bar = Progress {
            enabled: self.bars && !self.classic,
        }
        .bar(u64::from(self.end - self.next), "passes");
        while self.render_pass()? {
            bar.inc(1);
            let info = self.info(planned);
            let out_of_time = stop.time.is_some_and(|t| info.elapsed >= t);
            let quiet = stop.noise.zip(info.noise).is_some_and(|(t, n)| n <= t);
            let flow = on_pass(&info, self);
            if flow == Flow::Stop || self.cancel.load(Ordering::SeqCst) || out_of_time || quiet {
                break;
            }
        }
        bar.finish_and_clear();
        Ok(())
    }

    fn info(&self, planned: Option<u32>) -> PassInfo {
        PassInfo {
            pass: self.next - 1,
            done: self.acc.count,
            planned,
            noise: self.noise(),
            elapsed: self.elapsed(),
        }
    }

    /// A flag that, once set (from any thread, e.g. a Ctrl-C handler), stops
    /// [`Renderer::run`] after the pass in progress.
    pub fn cancel_flag(&self) -> Arc<AtomicBool> {
        self.cancel.clone()
    }

    /// The mean of the passes rendered so far (black before the first).
    pub fn image(&self) -> Image {
        match &self.classic_image {
            Some(image) => image.clone(),
            None => self.acc.mean(),
        }
    }

    /// The passes in the mean: `first..first + count`.
    pub fn done(&self) -> Range<u32> {
        self.acc.first..self.acc.first + self.acc.count
    }

    /// The running mean's estimated relative noise (RMS standard error over mean value),
    /// after an even number of progressive passes; `None` otherwise.
    pub fn noise(&self) -> Option<f64> {
        self.acc.noise()
    }

    /// Time since the renderer started opening.
    pub fn elapsed(&self) -> Duration {
        self.opened.elapsed()
    }

    /// The settings the renderer was opened with.
    pub fn settings(&self) -> &RenderSettings {
        &self.settings
    }

    /// The running sum, for a slice file's tags.
    pub(crate) fn accumulator(&self) -> &Accumulator {
        &self.acc
    }

    /// Takes the warnings of the render so far (opening included).
    pub fn take_warnings(&mut self) -> Vec<Warning> {
        std::mem::take(&mut self.warnings)
    }

    /// Timings and counts of the passes so far, and which backend ran them.
    pub fn report(&mut self) -> Result<RenderReport> {
        match self.ask(Job::Report)? {
            Reply::Report(r) => r,
            Reply::Pass(..) => Err(gone()),
        }
    }

    fn ask(&mut self, job: Job) -> Result<Reply> {
        self.jobs.send(job).map_err(|_| gone())?;
        self.replies.recv().map_err(|_| gone())
    }
}

fn gone() -> Error {
    Error::Gpu("the renderer thread ended".into())
}

/// The worker: opens the backend on its share of the scene, says so, then renders what it
/// is asked until the [`Renderer`] is dropped.
fn work(
    scene: Arc<crate::scene::Scene>,
    settings: RenderSettings,
    backend: Backend,
    jobs: Receiver<Job>,
    replies: Sender<Reply>,
) {
    let (renderer, warnings) = collect(|| open(backend, &scene, &settings));
    let mut renderer = match renderer {
        Ok(r) => {
            let _ = replies.send(Reply::Pass(Ok(Image::new(0, 0)), warnings));
            r
        }
        Err(e) => {
            let _ = replies.send(Reply::Pass(Err(e), warnings));
            return;
        }
    };
    for job in jobs {
        let reply = match job {
            Job::Pass(p, s, progress) => {
                let (image, w) = collect(|| renderer.pass(p, &s, &progress));
                Reply::Pass(image, w)
            }
            Job::Report => Reply::Report(renderer.report()),
        };
        if replies.send(reply).is_err() {
            return;
        }
    }
}

//! A batch's command recording: every stage of a pass goes into one encoder and one
//! submission, nothing waited for or read back until the pass ends. Where the device has
//! timestamp queries (`GpuContext::timestamps`; lavapipe has them) a timestamp between
//! phases gives each phase's device time, read back with the image. Without them the phases
//! are not timed apart, unless `RenderSettings::timed_phases` (`bench`) asks: then each
//! phase is a submission of its own, waited for, and its wall time recorded. A `bench`
//! recording on a device with timestamps also times each kernel (a timestamp after each
//! kernel's compute pass).

use crate::error::Result;
use crate::integrators::gpu::buffers::{empty_buffer, read_back, wait};
use crate::integrators::gpu::context::GpuContext;
use crate::integrators::gpu::faults::{injected, lose_after, Fault};
use crate::render::report::RenderReport;
use std::time::{Duration, Instant};

/// Timestamps one recording can write after its first: a pass has four phases and about
/// twenty kernels (two maps' trace and seven grid kernels, three of the cache, the gather).
const MAX_STAMPS: u32 = 40;
/// Stamps kept for phases: kernels take a timestamp only while more than this many are left.
const PHASE_RESERVE: u32 = 8;

/// An injected `device-lost` (`gpu::faults`): the device destroyed after the render's
/// `lose_after()`-th submission (the first by default), while its work is in flight.
fn lose_device_once(ctx: &GpuContext) {
    use std::sync::atomic::{AtomicU32, Ordering};
    static SUBMITTED: AtomicU32 = AtomicU32::new(0);
    if injected() == Some(Fault::DeviceLost)
        && SUBMITTED.fetch_add(1, Ordering::SeqCst) + 1 == lose_after()
    {
        ctx.device.destroy();
    }
}

/// The timestamps of one recording: one at its start, one after each phase and (`bench`)
/// each kernel, named, `true` for a phase.
struct Stamps {
    set: wgpu::QuerySet,
    resolved: wgpu::Buffer,
    names: Vec<(&'static str, bool)>,
}

/// The encoder of the work not yet submitted, and how its phases are timed.
pub struct Recorder {
    ctx: GpuContext,
    enc: Option<wgpu::CommandEncoder>,
    timed: bool,
    start: Instant,
    stamps: Option<Stamps>,
}

impl Recorder {
    /// An empty recording; phases are timed on the device when it has timestamps, else with
    /// `timed` one submission each.
    pub fn new(ctx: GpuContext, timed: bool) -> Self {
        let stamps = ctx.timestamps.then(|| Stamps {
            set: ctx.device.create_query_set(&wgpu::QuerySetDescriptor {
                label: Some("phase timestamps"),
                ty: wgpu::QueryType::Timestamp,
                count: MAX_STAMPS + 1,
            }),
            resolved: empty_buffer(
                &ctx.device,
                "phase timestamps resolved",
                8 * (MAX_STAMPS as u64 + 1),
                wgpu::BufferUsages::QUERY_RESOLVE | wgpu::BufferUsages::COPY_SRC,
            ),
            names: Vec::new(),
        });
        let mut r = Recorder {
            ctx,
            enc: None,
            timed,
            start: Instant::now(),
            stamps,
        };
        if let Some(s) = r.stamps.take() {
            r.enc().write_timestamp(&s.set, 0);
            r.stamps = Some(s);
        }
        r
    }

    /// The encoder to record into.
    pub fn enc(&mut self) -> &mut wgpu::CommandEncoder {
        let dev = &self.ctx.device;
        self.enc.get_or_insert_with(|| {
            dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("render pass"),
            })
        })
    }

    /// Ends kernel `name` (its compute pass recorded just before): a timestamp in a `timed`
    /// recording on a device with timestamps; otherwise nothing.
    pub fn kernel(&mut self, name: &'static str) {
        if !self.timed {
            return;
        }
        if let Some(mut s) = self.stamps.take() {
            let at = s.names.len() as u32 + 1;
            if at + PHASE_RESERVE <= MAX_STAMPS {
                self.enc().write_timestamp(&s.set, at);
                s.names.push((name, false));
            }
            self.stamps = Some(s);
        }
    }

    /// Ends phase `name`: a timestamp; or, without timestamps but `timed`, submits what was
    /// recorded, waits for it and adds its wall time to `report`; otherwise nothing.
    pub fn phase(&mut self, name: &'static str, report: &mut RenderReport) -> Result<()> {
        if let Some(mut s) = self.stamps.take() {
            let at = s.names.len() as u32 + 1;
            if at <= MAX_STAMPS {
                self.enc().write_timestamp(&s.set, at);
                s.names.push((name, true));
            }
            self.stamps = Some(s);
        } else if self.timed {
            self.submit();
            wait(&self.ctx)?;
            self.ctx.check()?;
            report.phase(name, self.start);
            self.start = Instant::now();
        }
        Ok(())
    }

    /// Submits what was recorded (not waited for), with the timestamps' resolution.
    pub fn submit(&mut self) {
        if let Some(s) = &self.stamps {
            let n = s.names.len() as u32 + 1;
            let (set, resolved) = (s.set.clone(), s.resolved.clone());
            self.enc().resolve_query_set(&set, 0..n, &resolved, 0);
        }
        if let Some(enc) = self.enc.take() {
            self.ctx.queue.submit([enc.finish()]);
            lose_device_once(&self.ctx);
        }
    }

    /// Whether the phases are timed on the device (`times` reports them).
    pub fn on_device(&self) -> bool {
        self.stamps.is_some()
    }

    /// After the submission completed: each phase's device time (since the previous
    /// phase's timestamp) and each kernel's (since the previous timestamp) into `report`.
    pub fn times(&self, report: &mut RenderReport) -> Result<()> {
        let Some(s) = &self.stamps else {
            return Ok(());
        };
        let n = s.names.len() as u64 + 1;
        let ticks: Vec<u64> = read_back(&self.ctx, &s.resolved, 8 * n)?;
        let ns = self.ctx.queue.get_timestamp_period() as f64;
        let took = |from: usize, to: usize| {
            let d = ticks[to].saturating_sub(ticks[from]) as f64 * ns;
            Duration::from_nanos(d as u64)
        };
        let mut phase_start = 0;
        for (i, &(name, is_phase)) in s.names.iter().enumerate() {
            if is_phase {
                report.phase_took(name, took(phase_start, i + 1));
                phase_start = i + 1;
            } else {
                report.kernel_took(name, took(i, i + 1));
            }
        }
        Ok(())
    }
}

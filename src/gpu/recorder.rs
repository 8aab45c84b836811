//! A pass's command recording: every stage of a batch goes into one encoder and one
//! submission, nothing waited for or read back until the pass ends; or, for `bench`
//! (`RenderSettings::timed_phases`), one submission per phase, each waited for and its wall
//! time recorded (lavapipe has no timestamp queries).

use super::buffers::wait;
use super::context::GpuContext;
use crate::error::Result;
use crate::report::RenderReport;
use std::time::Instant;

/// The encoder of the work not yet submitted.
pub struct Recorder {
    ctx: GpuContext,
    enc: Option<wgpu::CommandEncoder>,
    timed: bool,
    start: Instant,
}

impl Recorder {
    /// An empty recording; with `timed`, each `phase` is submitted and timed on its own.
    pub fn new(ctx: GpuContext, timed: bool) -> Self {
        Recorder {
            ctx,
            enc: None,
            timed,
            start: Instant::now(),
        }
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

    /// Ends phase `name`: when timed, submits what was recorded, waits for it and adds its
    /// wall time to `report`; otherwise recording goes on in the same encoder.
    pub fn phase(&mut self, name: &'static str, report: &mut RenderReport) -> Result<()> {
        if self.timed {
            self.submit();
            wait(&self.ctx)?;
            self.ctx.check()?;
            report.phase(name, self.start);
            self.start = Instant::now();
        }
        Ok(())
    }

    /// Submits what was recorded (not waited for).
    pub fn submit(&mut self) {
        if let Some(enc) = self.enc.take() {
            self.ctx.queue.submit([enc.finish()]);
        }
    }
}

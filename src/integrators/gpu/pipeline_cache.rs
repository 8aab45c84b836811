//! Pipelines already compiled in this process, reused by later renders on the same device.
//!
//! Creating the pipelines is most of a small render's cost on a software adapter (about 3 s
//! of CPU on lavapipe, against milliseconds of device work at 8x8), and a process often
//! renders several times: a Python session, `bench --runs`, a test binary. A render's
//! pipelines depend only on the device and what specialised them (the override constants,
//! which kernels exist), so an entry is keyed by exactly those: the device by its context's
//! number (`GpuContext::id`). Bounded: the oldest entries go first; a lost device's entries
//! age out with it.

use crate::integrators::gpu::bindings::Layouts;
use crate::integrators::gpu::context::GpuContext;
use crate::integrators::gpu::pipelines::Pipelines;
use std::sync::Mutex;

/// Entries kept at most (each holds one render's compiled kernels).
pub const CAPACITY: usize = 24;

/// What specialises a render's pipelines besides the device.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PipelineKey {
    /// The override constants, values by their bits.
    pub constants: Vec<(String, u64)>,
    /// The radiance cache's kernels exist.
    pub final_gather: bool,
    /// The K-nearest kernels exist.
    pub knn: bool,
}

impl PipelineKey {
    /// The key of pipelines compiled with `constants`, `final_gather` and `knn`.
    pub fn new(constants: &[(&str, f64)], final_gather: bool, knn: bool) -> Self {
        PipelineKey {
            constants: constants
                .iter()
                .map(|(n, v)| (n.to_string(), v.to_bits()))
                .collect(),
            final_gather,
            knn,
        }
    }
}

struct Entry {
    context: u64,
    /// Keeps the device (and so the pipelines) alive.
    _device: wgpu::Device,
    key: PipelineKey,
    layouts: Layouts,
    pipelines: Pipelines,
}

static CACHE: Mutex<Vec<Entry>> = Mutex::new(Vec::new());

/// The layouts and pipelines compiled on the device of `ctx` for `key`, if any (the entry
/// becomes the newest).
pub fn get(ctx: &GpuContext, key: &PipelineKey) -> Option<(Layouts, Pipelines)> {
    let mut cache = CACHE.lock().ok()?;
    let i = cache
        .iter()
        .position(|e| e.context == ctx.id && &e.key == key)?;
    let e = cache.remove(i);
    let found = (e.layouts.clone(), e.pipelines.clone());
    cache.push(e);
    Some(found)
}

/// Keeps `layouts` and `pipelines`, compiled on the device of `ctx` for `key`, for later
/// renders.
pub fn put(ctx: &GpuContext, key: PipelineKey, layouts: Layouts, pipelines: Pipelines) {
    let Ok(mut cache) = CACHE.lock() else {
        return;
    };
    cache.retain(|e| !(e.context == ctx.id && e.key == key));
    if cache.len() >= CAPACITY {
        cache.remove(0);
    }
    cache.push(Entry {
        context: ctx.id,
        _device: ctx.device.clone(),
        key,
        layouts,
        pipelines,
    });
}

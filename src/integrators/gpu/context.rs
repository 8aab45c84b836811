//! The wgpu instance, adapter, device and queue: opened once per process and shared by its
//! renders (`GpuContext::shared`), again only after the device was lost.

use crate::error::{Error, Result};
use crate::integrators::gpu::shape::{AdapterFacts, KernelShape};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

/// Largest storage binding the backend asks for: 2 GiB (every word index stays far inside a
/// u32), or the adapter's own limit where that is lower (lavapipe: 128 MiB). Photon maps and
/// textures are batched or refused only beyond what the adapter grants.
pub const MAX_BINDING: u64 = 2 << 30;

/// A device ready for compute work (a handle: clones share the device).
#[derive(Clone)]
pub struct GpuContext {
    /// The adapter the device was opened on.
    pub adapter: wgpu::Adapter,
    /// The logical device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// Storage binding size in bytes that every buffer stays within.
    pub max_binding: u64,
    /// The first error the device reported outside an error scope (instead of a panic), or
    /// its loss, which replaces any other.
    pub uncaptured: Arc<Mutex<Option<String>>>,
    /// The device was lost (a shared context is then opened anew).
    pub lost: Arc<AtomicBool>,
    /// This context's number in the process, unique (wgpu's own ids repeat between
    /// instances, and each context has its own instance).
    pub id: u64,
    /// The kernel shape (workgroup widths, cache lanes, loop guard) the pipelines are
    /// created with: the adapter's, or the one `GPU_PHOTON_KERNEL_SHAPE` forces.
    pub shape: KernelShape,
    /// The device was opened with timestamp queries inside encoders (an optional feature):
    /// a pass's phases are then timed on the device, in one submission. Clearing it makes
    /// renders take the fallback (see `gpu::recorder`).
    pub timestamps: bool,
    /// Scene features the kernels of renders on this context are compiled with even where a
    /// scene lacks them ([`GpuContext::with_feature_floor`]); empty by default.
    pub feature_floor: Vec<(&'static str, f64)>,
}

/// One adapter, described for `gpu-photon adapters` and `bench --json`.
#[derive(Clone, Debug, serde::Serialize)]
pub struct AdapterSummary {
    /// Adapter name.
    pub name: String,
    /// Graphics API (Vulkan).
    pub backend: String,
    /// Discrete, integrated, CPU (software), ...
    pub device_type: String,
    /// Driver name and version.
    pub driver: String,
    /// Largest storage binding, in bytes.
    pub max_storage_buffer_binding_size: u64,
    /// Largest buffer, in bytes.
    pub max_buffer_size: u64,
    /// Most workgroups per dispatch dimension.
    pub max_compute_workgroups_per_dimension: u32,
    /// Most invocations per workgroup.
    pub max_compute_invocations_per_workgroup: u32,
    /// Most storage buffers one stage may bind.
    pub max_storage_buffers_per_shader_stage: u32,
    /// Most workgroup memory, in bytes.
    pub max_compute_workgroup_storage_size: u32,
    /// Smallest and largest subgroup (SIMD group, warp) the adapter reports.
    pub subgroup_size: (u32, u32),
    /// The kernel shape a render on this adapter gets (`GPU_PHOTON_KERNEL_SHAPE` included;
    /// the adapter's own when that variable does not parse).
    pub kernel_shape: KernelShape,
}

impl AdapterSummary {
    /// What `gpu-photon adapters` prints for adapter number `index`.
    pub fn lines(&self, index: usize) -> Vec<String> {
        vec![
            format!(
                "[{index}] {} ({}, {})",
                self.name, self.backend, self.device_type
            ),
            format!("    driver: {}", self.driver),
            format!(
                "    max_storage_buffer_binding_size: {} MiB",
                self.max_storage_buffer_binding_size >> 20
            ),
            format!("    max_buffer_size: {} MiB", self.max_buffer_size >> 20),
            format!(
                "    max_storage_buffers_per_shader_stage: {}",
                self.max_storage_buffers_per_shader_stage
            ),
            format!(
                "    max_compute_workgroups_per_dimension: {}",
                self.max_compute_workgroups_per_dimension
            ),
            format!(
                "    max_compute_invocations_per_workgroup: {}",
                self.max_compute_invocations_per_workgroup
            ),
            format!(
                "    max_compute_workgroup_storage_size: {} KiB",
                self.max_compute_workgroup_storage_size >> 10
            ),
            format!(
                "    subgroup size: {}..{}",
                self.subgroup_size.0, self.subgroup_size.1
            ),
            format!("    kernel shape: {}", self.kernel_shape.describe()),
        ]
    }
}

fn instance() -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = wgpu::Backends::VULKAN;
    wgpu::Instance::new(desc)
}

/// Every Vulkan adapter wgpu finds.
pub fn list_adapters() -> Vec<AdapterSummary> {
    let adapters = pollster::block_on(instance().enumerate_adapters(wgpu::Backends::VULKAN));
    adapters
        .iter()
        .map(|a| {
            let info = a.get_info();
            let l = a.limits();
            let facts = AdapterFacts::from_parts(&info, &l);
            let kernel_shape =
                KernelShape::from_env(&facts).unwrap_or_else(|_| KernelShape::for_adapter(&facts));
            AdapterSummary {
                name: info.name,
                backend: format!("{:?}", info.backend),
                device_type: format!("{:?}", info.device_type),
                driver: format!("{} {}", info.driver, info.driver_info),
                max_storage_buffer_binding_size: l.max_storage_buffer_binding_size,
                max_buffer_size: l.max_buffer_size,
                max_compute_workgroups_per_dimension: l.max_compute_workgroups_per_dimension,
                max_compute_invocations_per_workgroup: l.max_compute_invocations_per_workgroup,
                max_storage_buffers_per_shader_stage: l.max_storage_buffers_per_shader_stage,
                max_compute_workgroup_storage_size: l.max_compute_workgroup_storage_size,
                subgroup_size: (info.subgroup_min_size, info.subgroup_max_size),
                kernel_shape,
            }
        })
        .collect()
}

/// The adapter `--backend auto` measures against the CPU (`crate::render::calibration`): a hardware
/// one when there is one (the GPU backend asks for high performance), else the first.
pub fn preferred_adapter() -> std::result::Result<AdapterSummary, String> {
    let all = list_adapters();
    all.iter()
        .find(|a| a.device_type != "Cpu")
        .or(all.first())
        .cloned()
        .ok_or_else(|| "no Vulkan adapter found".into())
}

/// Storage buffers the kernels bind in one stage: the scene group and the larger of the map
/// and gather groups (every binding is a storage buffer, see `bindings`).
pub const STORAGE_BUFFERS_NEEDED: u32 = {
    use crate::integrators::gpu::bindings::{GATHER_GROUP, MAP_GROUP, SCENE_GROUP};
    let (map, gather) = (MAP_GROUP.entries.len(), GATHER_GROUP.entries.len());
    (SCENE_GROUP.entries.len() + if map > gather { map } else { gather }) as u32
};

impl GpuContext {
    /// Photons one storage binding holds.
    pub fn max_photons(&self) -> u32 {
        (self.max_binding / std::mem::size_of::<crate::integrators::photon::Photon>() as u64) as u32
    }

    /// Opens the default adapter (high performance preferred).
    pub fn new() -> Result<Self> {
        let instance = instance();
        let adapter = pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
            power_preference: wgpu::PowerPreference::HighPerformance,
            force_fallback_adapter: false,
            compatible_surface: None,
            apply_limit_buckets: false,
        }))
        .map_err(|e| Error::Gpu(format!("no Vulkan adapter found ({e}); install mesa-vulkan-drivers for lavapipe, or use --backend cpu")))?;
        let limits = adapter.limits();
        let shape = KernelShape::from_env(&AdapterFacts::of(&adapter)).map_err(Error::Gpu)?;
        if limits.max_storage_buffers_per_shader_stage < STORAGE_BUFFERS_NEEDED {
            return Err(Error::Gpu(format!(
                "adapter {} allows {} storage buffers per stage; {STORAGE_BUFFERS_NEEDED} are needed",
                adapter.get_info().name,
                limits.max_storage_buffers_per_shader_stage
            )));
        }
        let max_binding = (limits.max_storage_buffer_binding_size as u64)
            .min(limits.max_buffer_size)
            .min(MAX_BINDING);
        let mut required = wgpu::Limits::downlevel_defaults();
        required.max_storage_buffers_per_shader_stage = STORAGE_BUFFERS_NEEDED;
        // wgpu counts storage and uniform buffers together in this one too.
        required.max_buffers_and_acceleration_structures_per_shader_stage = STORAGE_BUFFERS_NEEDED
            .max(required.max_buffers_and_acceleration_structures_per_shader_stage)
            .min(limits.max_buffers_and_acceleration_structures_per_shader_stage);
        required.max_storage_buffer_binding_size = max_binding as _;
        required.max_buffer_size = max_binding;
        required.max_compute_workgroups_per_dimension = limits.max_compute_workgroups_per_dimension;
        required.max_compute_invocations_per_workgroup =
            256.min(limits.max_compute_invocations_per_workgroup);
        required.max_compute_workgroup_size_x = 256.min(limits.max_compute_workgroup_size_x);
        // The cache build's workgroup memory grows with its lanes (`shape::cache_build_bytes`):
        // ask for all the adapter grants.
        required.max_compute_workgroup_storage_size = limits.max_compute_workgroup_storage_size;
        required.max_bind_groups = 2;
        // Optional: per-phase device times where the adapter has them.
        let stamps =
            wgpu::Features::TIMESTAMP_QUERY | wgpu::Features::TIMESTAMP_QUERY_INSIDE_ENCODERS;
        let timestamps = adapter.features().contains(stamps);
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("gpu-photon device"),
            required_features: if timestamps {
                stamps
            } else {
                wgpu::Features::empty()
            },
            required_limits: required,
            experimental_features: wgpu::ExperimentalFeatures::disabled(),
            memory_hints: wgpu::MemoryHints::Performance,
            trace: wgpu::Trace::Off,
        }))
        .map_err(|e| Error::Gpu(format!("could not open the device: {e}")))?;
        let uncaptured: Arc<Mutex<Option<String>>> = Arc::default();
        let slot = uncaptured.clone();
        device.on_uncaptured_error(Arc::new(move |e: wgpu::Error| {
            if let Ok(mut s) = slot.lock() {
                s.get_or_insert_with(|| crate::integrators::gpu::faults::describe(&e));
            }
        }));
        // A lost device explains every error after it: its reason replaces theirs.
        let slot = uncaptured.clone();
        let lost = Arc::new(AtomicBool::new(false));
        let flag = lost.clone();
        device.set_device_lost_callback(move |reason, message| {
            flag.store(true, Ordering::SeqCst);
            if let Ok(mut s) = slot.lock() {
                let why = match reason {
                    wgpu::DeviceLostReason::Destroyed => "destroyed".to_string(),
                    wgpu::DeviceLostReason::Unknown if message.is_empty() => "by the driver".into(),
                    wgpu::DeviceLostReason::Unknown => format!("by the driver: {message}"),
                };
                *s = Some(format!("the device was lost ({why})"));
            }
        });
        Ok(GpuContext {
            adapter,
            device,
            queue,
            max_binding,
            uncaptured,
            lost,
            id: {
                static NEXT: std::sync::atomic::AtomicU64 = std::sync::atomic::AtomicU64::new(0);
                NEXT.fetch_add(1, Ordering::SeqCst)
            },
            shape,
            timestamps,
            feature_floor: Vec::new(),
        })
    }

    /// This context (the same device) with its renders' kernels compiled with at least the
    /// features of `floor` on: scenes whose features differ only in those then share one
    /// compile, each rendering as with its own (slower where a feature it lacks is on). Only
    /// the features in `pipelines::shareable_features` are raised (`pipelines::with_floor`:
    /// the others change what a kernel computes, or need buffers a scene without them lacks).
    pub fn with_feature_floor(&self, floor: &[(&'static str, f64)]) -> Self {
        let mut ctx = self.clone();
        ctx.feature_floor = floor.to_vec();
        ctx
    }

    /// The process's context, opened by the first call and shared by every render after it
    /// (so their pipelines can be reused, `gpu::pipeline_cache`); opened anew once its
    /// device is lost. Renders on one context run side by side; an error the device reports
    /// outside an error scope reaches whichever of them checks first.
    pub fn shared() -> Result<Self> {
        let mut slot = SHARED
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some(ctx) = slot.as_ref().filter(|c| !c.lost.load(Ordering::SeqCst)) {
            return Ok(ctx.clone());
        }
        let ctx = GpuContext::new()?;
        *slot = Some(ctx.clone());
        Ok(ctx)
    }

    /// Waits, at most `limit`, until the process's shared context (if one was opened) has
    /// finished the work submitted to it; errors are ignored. After a failed render the
    /// device may still be running what it was given (a wait that timed out) while the
    /// process goes on without it: this lets that work end before the process does, rather
    /// than run in the driver's threads while the process exits.
    pub fn drain_shared(limit: std::time::Duration) {
        let slot = SHARED
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some(ctx) = slot.as_ref().filter(|c| !c.lost.load(Ordering::SeqCst)) {
            let _ = ctx.device.poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: Some(limit),
            });
        }
    }

    /// Fails with the first uncaptured device error, if there was one.
    pub fn check(&self) -> Result<()> {
        match self.uncaptured.lock().ok().and_then(|mut s| s.take()) {
            Some(e) => Err(Error::Gpu(e)),
            None => Ok(()),
        }
    }

    /// "name (backend, type)".
    pub fn describe(&self) -> String {
        let i = self.adapter.get_info();
        format!("gpu: {} ({:?}, {:?})", i.name, i.backend, i.device_type)
    }
}

/// The process's shared context ([`GpuContext::shared`]).
static SHARED: Mutex<Option<GpuContext>> = Mutex::new(None);

/// Mesa's Vulkan drivers print an error on every device creation when XDG_RUNTIME_DIR is
/// unset (headless machines); this gives them a private directory instead. Call it at
/// start-up, before any thread exists (it sets an environment variable).
pub fn quiet_headless_vulkan() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some() {
        return;
    }
    let dir = std::env::temp_dir().join("gpu-photon-runtime");
    if std::fs::create_dir_all(&dir).is_ok() {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700));
        std::env::set_var("XDG_RUNTIME_DIR", &dir);
    }
}

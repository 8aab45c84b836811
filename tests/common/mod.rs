//! Helpers shared by the integration tests: the GPU (or a skip), a deterministic generator
//! for test inputs, CPU photon tracing without a render, the analytic image of a plane lit
//! by a point light, and the "no farther than another seed" statistic used to compare
//! backends.
#![allow(dead_code)]

use glam::DVec3;
use gpu_photon::bvh::CpuBvh;
use gpu_photon::camera::Camera;
use gpu_photon::integrators::cpu::photons::{trace_photons, TraceContext};
use gpu_photon::integrators::gpu::GpuContext;
use gpu_photon::integrators::photon::{Budget, Photon};
use gpu_photon::lights::table::LightTable;
use gpu_photon::render::image_diff::DiffStats;
use gpu_photon::scene::Scene;
use gpu_photon::settings::RenderSettings;
use std::f64::consts::PI;

/// One GPU pass (pass 0) of `scenes/cornell-box.toml` with settings `s` on `ctx`: the run
/// (its maps kept in `map_cache`), the image, the report and the pass's wall time in seconds
/// (without the upload and pipelines).
pub fn cornell_gpu_pass(
    ctx: GpuContext,
    s: &RenderSettings,
) -> (
    gpu_photon::integrators::gpu::run::GpuRun,
    gpu_photon::render::film::Image,
    gpu_photon::render::report::RenderReport,
    f64,
) {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let scene = gpu_photon::importers::load(&root.join("scenes/cornell-box.toml")).unwrap();
    let mut run = gpu_photon::integrators::gpu::run::GpuRun::new(ctx, &scene, s, 0).unwrap();
    let accum = run.accum_buffer(s.width as u64 * s.height as u64 * 16);
    let mut report = gpu_photon::render::report::RenderReport::default();
    let progress = gpu_photon::render::report::Progress::default();
    let t = std::time::Instant::now();
    let img = run
        .render_pass(&scene, s, 0, &accum, &progress, &mut report)
        .unwrap();
    (run, img, report, t.elapsed().as_secs_f64())
}

/// Opens the GPU. Without an adapter the test is skipped, except under CI (CI=true), where
/// lavapipe is installed and a missing adapter is a failure.
pub fn gpu() -> Option<GpuContext> {
    // The process's shared device, as renders use: pipelines compiled by one test are
    // reused by the next (gpu::pipeline_cache).
    match GpuContext::shared() {
        Ok(ctx) => Some(ctx),
        Err(e) if std::env::var("CI").is_ok_and(|v| v == "true" || v == "1") => {
            panic!("CI must have a Vulkan adapter (lavapipe): {e}")
        }
        Err(e) => {
            eprintln!("skipping: {e}");
            None
        }
    }
}

/// A small deterministic generator for test inputs: SplitMix64 (Steele, Lea, Flood 2014).
pub struct TestRng(pub u64);

impl TestRng {
    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1) with 24 bits, exactly representable in f32 (like the library's).
    pub fn f32(&mut self) -> f32 {
        (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32
    }

    /// Uniform in [lo, hi).
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.f32()
    }

    /// A direction uniform on the unit sphere.
    pub fn dir(&mut self) -> glam::Vec3 {
        let z = 2.0 * self.f32() - 1.0;
        let phi = 2.0 * std::f32::consts::PI * self.f32();
        let s = (1.0 - z * z).max(0.0).sqrt();
        glam::Vec3::new(s * phi.cos(), s * phi.sin(), z)
    }
}

/// Traces the global photon paths of `settings` (pass 0) in `scene` on the CPU, with the
/// BVH, light table and budget built here: the budget and every stored photon.
pub fn trace_global(scene: &Scene, settings: &RenderSettings) -> (Budget, Vec<Photon>) {
    let bvh = CpuBvh::build(scene);
    let lights = LightTable::new(scene);
    let ctx = TraceContext {
        scene,
        bvh: &bvh,
        lights: &lights,
        settings,
        pass: 0,
    };
    let budget = Budget::split(scene, settings.photons);
    let photons = trace_photons(&ctx, &budget);
    (budget, photons)
}

/// Radiance at `x` on the Lambertian plane y = 0 of `albedo` lit only by a point light of
/// `intensity` at `light`: L = albedo / pi * I cos(theta) / r^2 = albedo / pi * I h / r^3.
pub fn point_lit_plane_radiance(
    albedo: f64,
    intensity: [f64; 3],
    light: DVec3,
    x: DVec3,
) -> [f64; 3] {
    let r = (light - x).length();
    intensity.map(|i| albedo / PI * i * light.y / r.powi(3))
}

/// The exact mean of the image at `w` x `h` of the plane y = 0, the square |x|, |z| <=
/// `half`, seen by `cam` and lit as in [`point_lit_plane_radiance`]: each pixel the mean over
/// its square (a 16 x 16 grid of points, f64), 0 where the ray misses the square.
pub fn point_lit_plane_mean(
    cam: &Camera,
    albedo: f64,
    intensity: [f64; 3],
    light: DVec3,
    half: f64,
    w: u32,
    h: u32,
) -> [f64; 3] {
    let (eye, fwd, right, up) = (
        cam.eye.as_dvec3(),
        cam.forward.as_dvec3(),
        cam.right.as_dvec3(),
        cam.up.as_dvec3(),
    );
    let n = 16;
    let mut sum = [0.0f64; 3];
    for py in 0..h * n {
        for px in 0..w * n {
            let (x, y) = ((px as f64 + 0.5) / n as f64, (py as f64 + 0.5) / n as f64);
            let sx = (2.0 * x / w as f64 - 1.0) * (w as f64 / h as f64);
            let sy = 1.0 - 2.0 * y / h as f64;
            let d = (fwd + sx * right + sy * up).normalize();
            if d.y >= 0.0 {
                continue;
            }
            let p = eye + d * (-eye.y / d.y);
            if p.x.abs() > half || p.z.abs() > half {
                continue;
            }
            let l = point_lit_plane_radiance(albedo, intensity, light, p);
            for c in 0..3 {
                sum[c] += l[c];
            }
        }
    }
    sum.map(|v| v / (w * h * n * n) as f64)
}

/// How much farther than the seed-to-seed noise an independent render of the same image may
/// be: per-pixel RMSE (1.0 expected; the slack covers the GPU's stochastic Fresnel choice at
/// glass) ...
pub const SEED_NOISE_RMSE_SLACK: f64 = 1.3;
/// ... and RMSE of 8x8 block means.
pub const SEED_NOISE_BLOCK_SLACK: f64 = 1.5;

/// Whether an image is no farther from a second CPU seed than the first CPU seed is: `d` is
/// its diff against that seed, `noise` the two CPU seeds' diff; `eps` absolute slack (for
/// images whose noise is ~0). Returns (per-pixel RMSE within, block RMSE within); acne, a
/// shifted shadow or lost light fail them.
pub fn within_seed_noise(d: &DiffStats, noise: &DiffStats, eps: f64) -> (bool, bool) {
    (
        d.rmse <= SEED_NOISE_RMSE_SLACK * noise.rmse + eps,
        d.block_rmse <= SEED_NOISE_BLOCK_SLACK * noise.block_rmse + eps,
    )
}

/// Standard base64 with padding (glTF data URIs in the tests).
pub fn b64(bytes: &[u8]) -> String {
    const T: &[u8] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut s = String::new();
    for c in bytes.chunks(3) {
        let n = (c[0] as u32) << 16
            | (*c.get(1).unwrap_or(&0) as u32) << 8
            | *c.get(2).unwrap_or(&0) as u32;
        for i in 0..=c.len() {
            s.push(T[(n >> (18 - 6 * i) & 63) as usize] as char);
        }
    }
    while !s.len().is_multiple_of(4) {
        s.push('=');
    }
    s
}

/// A GLB file of `json` and `bin` (chunks padded to 4 bytes).
pub fn glb(json: &str, bin: &[u8]) -> Vec<u8> {
    let mut j = json.as_bytes().to_vec();
    while !j.len().is_multiple_of(4) {
        j.push(b' ');
    }
    let mut b = bin.to_vec();
    while !b.len().is_multiple_of(4) {
        b.push(0);
    }
    let total = 12 + 8 + j.len() + 8 + b.len();
    let mut out = b"glTF".to_vec();
    for n in [2, total as u32, j.len() as u32, 0x4E4F534A] {
        out.extend(u32::to_le_bytes(n));
    }
    out.extend(j);
    out.extend(
        [b.len() as u32, 0x004E4942]
            .iter()
            .flat_map(|n| n.to_le_bytes()),
    );
    out.extend(b);
    out
}

/// An image (e.g. a reference) averaged over `f` x `f` blocks: exactly the pixel means of an image `f`
/// times smaller (pixels are box-filtered mean radiance).
pub fn downsample(
    img: &gpu_photon::render::film::Image,
    f: u32,
) -> gpu_photon::render::film::Image {
    let (w, h) = (img.width / f, img.height / f);
    let mut out = gpu_photon::render::film::Image::new(w, h);
    for y in 0..h {
        for x in 0..w {
            let mut s = [0.0f64; 3];
            for yy in 0..f {
                for xx in 0..f {
                    let p = img.pixels[((y * f + yy) * img.width + x * f + xx) as usize];
                    for c in 0..3 {
                        s[c] += p[c] as f64;
                    }
                }
            }
            out.pixels[(y * w + x) as usize] = s.map(|v| (v / (f * f) as f64) as f32);
        }
    }
    out
}

/// Runs WGSL compute entry point `entry` of `source` (bindings 0: the read-only `inputs`,
/// 1: the read-write results, `result_bytes` long) over `n` queries in workgroups of 64, and
/// returns the results' bytes: the device half of a device = Rust oracle test.
pub fn run_probe(
    ctx: &GpuContext,
    source: &str,
    entry: &str,
    inputs: &[u8],
    n: u32,
    result_bytes: u64,
) -> Vec<u8> {
    use wgpu::util::DeviceExt;
    let dev = &ctx.device;
    let scope = dev.push_error_scope(wgpu::ErrorFilter::Validation);
    let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some(entry),
        source: wgpu::ShaderSource::Wgsl(source.into()),
    });
    let pipeline = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some(entry),
        layout: None,
        module: &module,
        entry_point: Some(entry),
        compilation_options: Default::default(),
        cache: None,
    });
    if let Some(e) = pollster::block_on(scope.pop()) {
        panic!("{entry} pipeline: {e}");
    }
    let inputs = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some("probe queries"),
        contents: inputs,
        usage: wgpu::BufferUsages::STORAGE,
    });
    let buffer = |label: &str, usage| {
        dev.create_buffer(&wgpu::BufferDescriptor {
            label: Some(label),
            size: result_bytes,
            usage,
            mapped_at_creation: false,
        })
    };
    let results = buffer(
        "probe results",
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    );
    let staging = buffer(
        "probe readback",
        wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
    );
    let bind_group = dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("probe bind group"),
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: inputs.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: results.as_entire_binding(),
            },
        ],
    });
    let mut enc =
        dev.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(entry) });
    {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(entry),
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind_group, &[]);
        pass.dispatch_workgroups(n.div_ceil(64), 1, 1);
    }
    enc.copy_buffer_to_buffer(&results, 0, &staging, 0, result_bytes);
    ctx.queue.submit([enc.finish()]);
    staging.map_async(wgpu::MapMode::Read, .., |r| r.expect("mapping the results"));
    dev.poll(wgpu::PollType::wait_indefinitely())
        .expect("waiting for the device");
    ctx.check().expect("device error");
    let view = staging.get_mapped_range(..).expect("mapped results");
    view.to_vec()
}

/// Direct-light renders of `s` at `side` x `side`, 4 spp, on the CPU and (where there is a
/// device) on the GPU, with the same random numbers.
pub fn direct_renders(
    s: &Scene,
    side: u32,
) -> (
    gpu_photon::render::film::Image,
    Option<gpu_photon::render::film::Image>,
) {
    use gpu_photon::render::report::Progress;
    use gpu_photon::render::session::{render, Backend};
    let settings = RenderSettings {
        width: side,
        height: side,
        spp: 4,
        mode: gpu_photon::settings::Mode::DirectOnly,
        ..s.settings.clone()
    };
    let (cpu, _) = render(s, &settings, Backend::Cpu, Progress::default()).unwrap();
    let gpu = gpu().map(|_| {
        render(s, &settings, Backend::Gpu, Progress::default())
            .unwrap()
            .0
    });
    (cpu, gpu)
}

/// The GPU's render of `s` (seed 1) against the CPU's with seed 2, and the two CPU seeds'
/// own difference: the yardstick of [`within_seed_noise`] (`(gpu vs cpu seed 2, cpu seed 2
/// vs seed 1)`, 8 x 8 blocks).
pub fn gpu_and_seed_diffs(scene: &Scene, s: &RenderSettings) -> (DiffStats, DiffStats) {
    use gpu_photon::render::report::Progress;
    use gpu_photon::render::session::{render, Backend};
    let at = |seed: u32, backend: Backend| {
        let s = RenderSettings { seed, ..s.clone() };
        render(scene, &s, backend, Progress::default()).unwrap().0
    };
    let (cpu, cpu2, gpu) = (
        at(1, Backend::Cpu),
        at(2, Backend::Cpu),
        at(1, Backend::Gpu),
    );
    let noise = gpu_photon::render::image_diff::diff(&cpu2, &cpu, 8).unwrap();
    let d = gpu_photon::render::image_diff::diff(&gpu, &cpu2, 8).unwrap();
    (d, noise)
}

/// The example scenes in scenes/, sorted, less the media scenes (`fog-cornell.toml`,
/// `volume-caustic.toml`): `tests/media_gpu.rs` compares the backends on them at a size
/// lavapipe renders in CI's time (its beam queries run lane by lane, about 19x the CPU's).
pub fn example_scenes_without_media() -> Vec<std::path::PathBuf> {
    let mut paths: Vec<_> =
        std::fs::read_dir(std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes"))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "toml"))
            .filter(|p| {
                !gpu_photon::importers::load(p)
                    .unwrap()
                    .has_media_transport()
            })
            .collect();
    paths.sort();
    paths
}

/// An example scene's own settings at `size` x `size`, 4 spp, 40,000 global and 20,000
/// caustic photon paths, seed `seed`: the CPU-vs-GPU image tests' renders.
pub fn example_settings(
    scene: &gpu_photon::scene::Scene,
    size: u32,
    seed: u32,
) -> gpu_photon::settings::RenderSettings {
    gpu_photon::settings::RenderSettings {
        width: size,
        height: size,
        spp: 4,
        photons: 40_000,
        caustic_photons: 20_000,
        seed,
        ..scene.settings.clone()
    }
}

/// The `gpu-photon` binary the tests run.
pub fn bin() -> std::process::Command {
    std::process::Command::new(env!("CARGO_BIN_EXE_gpu-photon"))
}

/// A fresh, empty scratch directory `name` for this test process.
pub fn scratch(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("gpu-photon-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A Mitsuba `.vol` file's bytes (float32, box [0, 1]^3): `res` voxels of `channels` values,
/// value `i` (x fastest, channels innermost) from `value(i)`.
pub fn vol_file(res: [i32; 3], channels: i32, value: impl Fn(usize) -> f32) -> Vec<u8> {
    let mut b = b"VOL\x03".to_vec();
    for v in [1, res[0], res[1], res[2], channels] {
        b.extend(v.to_le_bytes());
    }
    for v in [0.0f32, 0.0, 0.0, 1.0, 1.0, 1.0] {
        b.extend(v.to_le_bytes());
    }
    for i in 0..(res[0] * res[1] * res[2] * channels) as usize {
        b.extend(value(i).to_le_bytes());
    }
    b
}

/// The hits at which a script of `scripts/` measured Mitsuba 3.9.1 (`tests/data/{csv}`, rows
/// `shape,ox,oy,oz,dx,dy,dz,px,py,pz,...`): for each `(name, shape)` the scene of that
/// `<shape>` element under a camera (written to `dir`, where its relative files resolve), and
/// each of the 12 rows named for it intersected along its ray, the hit within 1e-4 of
/// Mitsuba's point; `check(name, scene, hit, row)` gets the row's values after the name.
pub fn mitsuba_hits(
    dir: &std::path::Path,
    csv: &str,
    shapes: &[(&str, String)],
    mut check: impl FnMut(&str, &Scene, &gpu_photon::bvh::hit::Hit, &[f32]),
) {
    use glam::Vec3;
    use gpu_photon::math::geometry::Ray;
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let csv = std::fs::read_to_string(root.join("tests/data").join(csv)).unwrap();
    for (name, shape) in shapes {
        let text = format!(
            r#"<scene version="3.0.0"><sensor type="perspective"><float name="fov" value="40"/>
<transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform></sensor>{shape}</scene>"#
        );
        let path = dir.join(format!("{name}.xml"));
        std::fs::write(&path, text).unwrap();
        let scene = gpu_photon::importers::load(&path).unwrap_or_else(|e| panic!("{e}"));
        let bvh = gpu_photon::bvh::Bvh::build(&scene);
        let rows: Vec<Vec<f32>> = (csv.lines())
            .filter(|l| l.starts_with(&format!("{name},")))
            .map(|l| l.split(',').skip(1).map(|v| v.parse().unwrap()).collect())
            .collect();
        assert_eq!(rows.len(), 12, "{name}");
        for r in rows {
            let v = |i: usize| Vec3::new(r[i], r[i + 1], r[i + 2]);
            let ray = Ray {
                origin: v(0),
                dir: v(3),
            };
            let hit = bvh.intersect(&scene, &ray, f32::INFINITY).expect(name);
            let p = v(6);
            assert!(
                (hit.position - p).length() < 1e-4,
                "{name}: {} vs {p}",
                hit.position
            );
            check(name, &scene, &hit, &r);
        }
    }
}

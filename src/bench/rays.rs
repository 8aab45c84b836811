//! The ray-throughput benchmark (`gpu-photon bench --rays`): the four kinds of rays the CPU
//! renderer casts, made as it makes them, traced one at a time on one thread by each
//! tracer in turn (rounds alternate between tracers; medians reported), in rays per second
//! per core.
//!
//! The rays: one camera ray per pixel in the camera pass's row order (jittered, through the
//! lens when there is one); from each camera hit a shadow ray to a point drawn on a light
//! (`LightTable::sample`, stopping short of it as the camera pass does) and one
//! cosine-distributed gather ray (as `final_gather` casts); photon paths from the lights
//! (`LightTable::emit`) with up to three diffuse bounces, every segment a ray.

use crate::bvh::{Bvh, Isa, WideBvh};
use crate::lights::table::LightTable;
use crate::math::geometry::{offset_origin, Ray, OFFSET_FLOOR, OFFSET_SCALE};
use crate::math::rng::{Rng, Stream};
use crate::math::sampling::cosine_hemisphere;
use crate::scene::Scene;
use std::time::Instant;

/// What a ray is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RayKind {
    /// From the camera, closest hit.
    Camera,
    /// From a camera hit to a light, any hit.
    Shadow,
    /// From a camera hit in a cosine-distributed direction, closest hit.
    Gather,
    /// A photon path's segments, closest hit.
    Photon,
}

impl RayKind {
    /// Its name in tables.
    pub fn name(self) -> &'static str {
        match self {
            RayKind::Camera => "camera",
            RayKind::Shadow => "shadow",
            RayKind::Gather => "gather",
            RayKind::Photon => "photon",
        }
    }
}

/// One kind's rays, each with its `t_max`.
#[derive(Clone, Debug)]
pub struct RaySet {
    /// The kind.
    pub kind: RayKind,
    /// The rays.
    pub rays: Vec<Ray>,
    /// Their `t_max`.
    pub t_max: Vec<f32>,
}

impl RaySet {
    fn new(kind: RayKind) -> Self {
        RaySet {
            kind,
            rays: Vec::new(),
            t_max: Vec::new(),
        }
    }
    fn push(&mut self, ray: Ray, t_max: f32) {
        self.rays.push(ray);
        self.t_max.push(t_max);
    }
}

/// The four sets for `scene` at `width` x `height` (one camera sample per pixel) and as
/// many photon rays, drawn with `seed`.
pub fn ray_sets(scene: &Scene, width: u32, height: u32, seed: u32) -> Vec<RaySet> {
    let bvh = WideBvh::build(scene);
    let lights = LightTable::new(scene);
    let mut camera = RaySet::new(RayKind::Camera);
    let mut shadow = RaySet::new(RayKind::Shadow);
    let mut gather = RaySet::new(RayKind::Gather);
    let cam = &scene.camera;
    for y in 0..height {
        for x in 0..width {
            let pixel = y * width + x;
            let mut rng = Rng::new(seed, Stream::Camera, 0, pixel);
            let (fx, fy) = rng.next2();
            let lens = rng.next2();
            let (origin, dir) = cam.ray(x as f32 + fx, y as f32 + fy, width, height, lens);
            let ray = Ray { origin, dir };
            camera.push(ray, f32::INFINITY);
            let Some(hit) = bvh.intersect(scene, &ray, f32::INFINITY) else {
                continue;
            };
            let f = hit.facing(dir);
            if !scene.lights.is_empty() {
                let l = (rng.next() * scene.lights.len() as f32) as usize % scene.lights.len();
                let u = [rng.next(), rng.next(), rng.next()];
                let ls = lights.sample(scene, l, hit.position, f.ns, u);
                let wi = (ls.point - hit.position).normalize_or_zero();
                if wi != glam::Vec3::ZERO {
                    let origin = offset_origin(hit.position, hit.normal, wi);
                    if ls.distant {
                        shadow.push(Ray { origin, dir: wi }, f32::INFINITY);
                    } else {
                        let end = OFFSET_SCALE * (ls.point.abs().max_element() + OFFSET_FLOOR);
                        let to = ls.point - origin;
                        let len = to.length();
                        if len > 4.0 * end {
                            shadow.push(
                                Ray {
                                    origin,
                                    dir: to / len,
                                },
                                len - 4.0 * end,
                            );
                        }
                    }
                }
            }
            let (u1, u2) = rng.next2();
            let dir = cosine_hemisphere(f.ns, u1, u2);
            let origin = offset_origin(hit.position, hit.normal, dir);
            gather.push(Ray { origin, dir }, f32::INFINITY);
        }
    }
    let photon = photon_rays(scene, &bvh, &lights, (width * height) as usize, seed);
    vec![camera, shadow, gather, photon]
}

/// At least `n` photon-path segments: emitted, then up to three cosine bounces.
fn photon_rays(scene: &Scene, bvh: &WideBvh, lights: &LightTable, n: usize, seed: u32) -> RaySet {
    let mut set = RaySet::new(RayKind::Photon);
    if scene.lights.is_empty() {
        return set;
    }
    let mut path = 0;
    while set.rays.len() < n {
        let mut rng = Rng::new(seed, Stream::Photon, 0, path);
        let l = path as usize % scene.lights.len();
        path += 1;
        let u = [rng.next(), rng.next(), rng.next(), rng.next(), rng.next()];
        let e = lights.emit(scene, l, u);
        let origin = match e.normal == glam::Vec3::ZERO {
            true => e.origin,
            false => offset_origin(e.origin, e.normal, e.dir),
        };
        let mut ray = Ray { origin, dir: e.dir };
        for _ in 0..4 {
            set.push(ray, f32::INFINITY);
            let Some(hit) = bvh.intersect(scene, &ray, f32::INFINITY) else {
                break;
            };
            let f = hit.facing(ray.dir);
            let (u1, u2) = rng.next2();
            let dir = cosine_hemisphere(f.ns, u1, u2);
            ray = Ray {
                origin: offset_origin(hit.position, hit.normal, dir),
                dir,
            };
        }
    }
    set
}

/// Something that traces rays: closest hit as (primitive id as in `Bvh::prim_ids`, t), and
/// any hit.
pub trait Tracer {
    /// Its name in tables.
    fn name(&self) -> String;
    /// The closest hit before `t_max`.
    fn closest(&self, ray: &Ray, t_max: f32) -> Option<(u32, f32)>;
    /// Whether anything is hit before `t_max`.
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool;
}

/// The binary hierarchy (the GPU's, and the CPU's before the wide one).
pub struct BinaryTracer<'s>(pub &'s Scene, pub Bvh);

impl Tracer for BinaryTracer<'_> {
    fn name(&self) -> String {
        "binary".into()
    }
    fn closest(&self, ray: &Ray, t_max: f32) -> Option<(u32, f32)> {
        self.1.closest(self.0, ray, t_max).map(|h| (h.0, h.1))
    }
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.1.occluded(self.0, ray, t_max)
    }
}

/// The wide hierarchy with one instruction set.
pub struct WideTracer<'s>(pub &'s Scene, pub WideBvh);

impl Tracer for WideTracer<'_> {
    fn name(&self) -> String {
        format!("wide {}", self.1.isa.name())
    }
    fn closest(&self, ray: &Ray, t_max: f32) -> Option<(u32, f32)> {
        self.1.closest(self.0, ray, t_max).map(|h| (h.0, h.1))
    }
    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.1.occluded(self.0, ray, t_max)
    }
}

/// How long a hierarchy took to build (medians of `runs` builds) and its size.
#[derive(Clone, Copy, Debug, Default)]
pub struct BuildCost {
    /// Wall-clock seconds.
    pub wall_s: f64,
    /// CPU seconds of the whole process (all threads).
    pub cpu_s: f64,
    /// Bytes of the hierarchy.
    pub bytes: usize,
}

/// Builds with `build` `runs` times; returns the last result and the median costs.
pub fn timed<T>(
    runs: usize,
    mut build: impl FnMut() -> T,
    bytes: impl Fn(&T) -> usize,
) -> (T, BuildCost) {
    let (mut walls, mut cpus) = (Vec::new(), Vec::new());
    let mut out = None;
    for _ in 0..runs.max(1) {
        let (w, c) = (Instant::now(), cpu_seconds(CpuClock::Process));
        out = Some(build());
        walls.push(w.elapsed().as_secs_f64());
        cpus.push(cpu_seconds(CpuClock::Process) - c);
    }
    let median = |mut v: Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let out = out.expect("one build at least");
    let cost = BuildCost {
        wall_s: median(walls),
        cpu_s: median(cpus),
        bytes: bytes(&out),
    };
    (out, cost)
}

/// Our tracers with their build costs (medians of `runs` builds): the binary hierarchy,
/// then the wide one with each instruction set this CPU has, best first.
pub fn our_tracers(scene: &Scene, runs: usize) -> Vec<(Box<dyn Tracer + '_>, BuildCost)> {
    let (bin, bin_cost) = timed(
        runs,
        || Bvh::build(scene),
        |b| b.nodes.len() * std::mem::size_of::<crate::bvh::BvhNode>() + b.prim_ids.len() * 4,
    );
    let (wide, wide_cost) = timed(runs, || WideBvh::build(scene), WideBvh::memory_bytes);
    let mut out: Vec<(Box<dyn Tracer>, BuildCost)> =
        vec![(Box::new(BinaryTracer(scene, bin)), bin_cost)];
    for isa in Isa::ALL.into_iter().rev().filter(|i| i.available()) {
        out.push((
            Box::new(WideTracer(scene, wide.clone().with_isa(isa))),
            wide_cost,
        ));
    }
    out
}

/// One tracer's median over rounds on one set.
#[derive(Clone, Debug)]
pub struct RayRate {
    /// The tracer's name.
    pub tracer: String,
    /// The set's kind.
    pub kind: RayKind,
    /// Rays in the set.
    pub rays: usize,
    /// Median rays per second (one thread).
    pub rays_per_s: f64,
    /// Rays that hit something.
    pub hits: usize,
    /// Rays whose closest primitive (or occlusion) agrees with the first tracer's.
    pub agree: usize,
}

/// Traces every set with every tracer, `rounds` times (tracers alternating within each
/// round), on the calling thread, timed by the thread's CPU time (on a shared machine the
/// wall time also counts the other processes' turns).
pub fn measure(sets: &[RaySet], tracers: &[&dyn Tracer], rounds: usize) -> Vec<RayRate> {
    let mut out = Vec::new();
    for set in sets {
        let answers: Vec<Vec<Option<u32>>> = tracers.iter().map(|t| answers(*t, set)).collect();
        let mut times = vec![Vec::new(); tracers.len()];
        for _ in 0..rounds.max(1) {
            for (i, t) in tracers.iter().enumerate() {
                let start = cpu_seconds(CpuClock::Thread);
                let n = trace(*t, set);
                times[i].push(cpu_seconds(CpuClock::Thread) - start);
                std::hint::black_box(n);
            }
        }
        for (i, t) in tracers.iter().enumerate() {
            let mut ts = std::mem::take(&mut times[i]);
            ts.sort_by(f64::total_cmp);
            let median = ts[ts.len() / 2];
            out.push(RayRate {
                tracer: t.name(),
                kind: set.kind,
                rays: set.rays.len(),
                rays_per_s: set.rays.len() as f64 / median.max(1e-12),
                hits: answers[i].iter().filter(|a| a.is_some()).count(),
                agree: (answers[i].iter().zip(&answers[0]))
                    .filter(|(a, b)| a == b)
                    .count(),
            });
        }
    }
    out
}

/// Each ray's answer: the closest primitive, or `Some(0)` when occluded.
fn answers(t: &dyn Tracer, set: &RaySet) -> Vec<Option<u32>> {
    let pairs = set.rays.iter().zip(&set.t_max);
    match set.kind {
        RayKind::Shadow => pairs.map(|(r, &m)| t.occluded(r, m).then_some(0)).collect(),
        _ => pairs.map(|(r, &m)| t.closest(r, m).map(|h| h.0)).collect(),
    }
}

/// Traces the set; returns the number of hits.
fn trace(t: &dyn Tracer, set: &RaySet) -> usize {
    let pairs = set.rays.iter().zip(&set.t_max);
    match set.kind {
        RayKind::Shadow => pairs.filter(|(r, &m)| t.occluded(r, m)).count(),
        _ => pairs.filter(|(r, &m)| t.closest(r, m).is_some()).count(),
    }
}

/// Which CPU time [`cpu_seconds`] reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CpuClock {
    /// The calling thread's.
    Thread,
    /// The whole process's (all threads).
    Process,
}

/// CPU time in seconds (wall time where the platform has no such clock).
#[allow(unsafe_code)]
pub fn cpu_seconds(clock: CpuClock) -> f64 {
    #[cfg(unix)]
    {
        let id = match clock {
            CpuClock::Thread => libc::CLOCK_THREAD_CPUTIME_ID,
            CpuClock::Process => libc::CLOCK_PROCESS_CPUTIME_ID,
        };
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: clock_gettime writes one timespec, which lives on this stack frame.
        if unsafe { libc::clock_gettime(id, &mut ts) } == 0 {
            return ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9;
        }
    }
    use std::sync::OnceLock;
    static START: OnceLock<Instant> = OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_secs_f64()
}

//! Oracle probe of the shading interface on one uploaded scene (`probe_shading` in
//! tests/probes/probe_shading.wgsl, through [`SceneProbes`]): `bsdf_at` at a ray's nearest hit
//! and every question the integrators ask of the surface (class, emission, the diffuse
//! part's albedo, store weight, value and estimate BRDF, the lobe's flags, value, density
//! and sample, a delta bounce, a photon's bounce), the power heuristic and the radiance of
//! an escaping ray, for tests/shading_gpu.rs to compare with `gpu_photon::bsdfs::shading` at the same
//! hit (the device's hit is read back, so both sides shade the same bits).

use super::light::SceneProbes;
use glam::{Vec2, Vec3};
use gpu_photon::bvh::Hit;
use gpu_photon::error::Result;

/// One case of [`SceneProbes::shading`]: a ray, the directions the surface is asked
/// about and the random numbers it draws.
#[derive(Clone, Copy, Debug)]
pub struct ShadingCase {
    /// The ray's origin.
    pub origin: Vec3,
    /// Its unit direction (towards the surface).
    pub dir: Vec3,
    /// The nearest hit is looked for in (0, t_max).
    pub t_max: f32,
    /// The key of the random stream the lobe sample and the delta bounce draw from (each
    /// from dimension 0: `rng::Rng` with this key).
    pub key: u32,
    /// The light's direction the surface is evaluated for.
    pub wi: Vec3,
    /// The viewer's.
    pub wo: Vec3,
    /// The photon bounce's three uniforms.
    pub u: [f32; 3],
    /// The power heuristic's two densities.
    pub pdfs: [f32; 2],
}

/// The bit of each flag in [`ShadedSurface::flags`], in order: `surface_is_bsdf`,
/// `surface_has_lobe`, `surface_lobe_takes_point_lights`, `surface_lobe_is_glossy`,
/// `surface_stores_photons`.
pub const SHADING_FLAGS: [&str; 5] = [
    "is_bsdf",
    "has_lobe",
    "lobe_takes_point_lights",
    "lobe_is_glossy",
    "stores_photons",
];

/// What the device's shading gave at one [`ShadingCase`]'s hit.
#[derive(Clone, Copy, Debug)]
pub struct ShadedSurface {
    /// The hit the device shaded (`t`, position, normals, material, light, uv).
    pub hit: Hit,
    /// `surface_class` (`codes::CLASS_*`).
    pub class: u32,
    /// The flags of [`SHADING_FLAGS`], bit `k` the `k`-th.
    pub flags: u32,
    /// `surface_emitted(front)`, `surface_emitted(back)`.
    pub emitted: [Vec3; 2],
    /// `surface_store_weight(wi)`.
    pub store_weight: f32,
    /// `surface_pdf_lobe(wi, wo, ns)` (ns: the shading normal facing the ray).
    pub pdf_lobe: f32,
    /// `surface_diffuse_albedo(wo)`.
    pub diffuse_albedo: Vec3,
    /// `surface_eval_diffuse(wi, wo)`.
    pub eval_diffuse: Vec3,
    /// `surface_estimate_brdf(wo)`.
    pub estimate_brdf: Vec3,
    /// `surface_eval_lobe(wi, wo, ns)`.
    pub eval_lobe: Vec3,
    /// `surface_sample_lobe`'s ray: `(dir, weight, pdf)` when ok.
    pub sample_lobe: Option<(Vec3, Vec3, f32)>,
    /// `surface_delta` of a delta surface: the new direction, whether it does not leak,
    /// the throughput (from 1) and the new origin.
    pub delta: Option<(Vec3, bool, Vec3, Vec3)>,
    /// `surface_photon_bounce(u)`: direction, kind (`codes::BOUNCE_*`) and weight.
    pub bounce: (Vec3, u32, Vec3),
}

/// What the device gave for one [`ShadingCase`].
#[derive(Clone, Copy, Debug)]
pub struct ShadingProbe {
    /// `escape(dir)`.
    pub escape: Vec3,
    /// `power_heuristic(pdfs[0], pdfs[1])`.
    pub power_heuristic: f32,
    /// The surface at the nearest hit (`None`: the ray left the scene).
    pub surface: Option<ShadedSurface>,
}

/// vec4 slots per case of `probe_shading`.
const SLOTS: usize = 24;

impl SceneProbes {
    /// The device's shading functions (src/bsdfs/shading.wgsl) at each case's nearest
    /// hit (`probe_shading`).
    pub fn shading(&mut self, cases: &[ShadingCase]) -> Result<Vec<ShadingProbe>> {
        let n = cases.len().max(1);
        let mut init = vec![[0f32; 4]; SLOTS * n];
        for (i, c) in cases.iter().enumerate() {
            init[i] = c.origin.extend(c.t_max).to_array();
            init[n + i] = c.dir.extend(f32::from_bits(c.key)).to_array();
            init[2 * n + i] = c.wi.extend(c.pdfs[0]).to_array();
            init[3 * n + i] = c.wo.extend(c.pdfs[1]).to_array();
            init[4 * n + i] = [c.u[0], c.u[1], c.u[2], 0.0];
        }
        let out = self.dispatch("probe_shading", &init, n)?;
        let at = |k: usize, i: usize| out[k * n + i];
        let v = |a: [f32; 4]| Vec3::new(a[0], a[1], a[2]);
        Ok((0..cases.len())
            .map(|i| {
                let e = at(22, i);
                let p = at(5, i);
                let surface = (p[3] >= 0.0).then(|| {
                    let (n6, s7, m8) = (at(6, i), at(7, i), at(8, i));
                    let hit = Hit {
                        t: s7[3],
                        position: v(p),
                        normal: v(n6),
                        shading: v(s7),
                        material: p[3] as u32,
                        light: n6[3].to_bits(),
                        uv: Vec2::new(m8[0], m8[1]),
                        tangent: v(at(23, i)),
                    };
                    let (l, w, dl) = (at(15, i), at(16, i), at(17, i));
                    ShadedSurface {
                        hit,
                        class: m8[2] as u32,
                        flags: m8[3] as u32,
                        emitted: [v(at(9, i)), v(at(10, i))],
                        store_weight: at(9, i)[3],
                        pdf_lobe: at(10, i)[3],
                        diffuse_albedo: v(at(11, i)),
                        eval_diffuse: v(at(12, i)),
                        estimate_brdf: v(at(13, i)),
                        eval_lobe: v(at(14, i)),
                        sample_lobe: (l[3] == 1.0).then_some((v(l), v(w), w[3])),
                        delta: (dl[3] != -2.0).then_some((
                            v(dl),
                            dl[3] == 1.0,
                            v(at(18, i)),
                            v(at(19, i)),
                        )),
                        bounce: (v(at(20, i)), at(20, i)[3] as u32, v(at(21, i))),
                    }
                });
                ShadingProbe {
                    escape: v(e),
                    power_heuristic: e[3],
                    surface,
                }
            })
            .collect())
    }
}

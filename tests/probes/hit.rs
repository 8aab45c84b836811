//! Oracle probe of a hit's surface on one uploaded scene (`probe_hit` in
//! tests/probes/probe_geometry.wgsl, through [`SceneProbes`]): a triangle's shading normal, its uv
//! tangents (from its corner uvs, its vertex tangents, and the choice between them), the
//! alpha test of a candidate hit, the frame a ray sees at the nearest hit, a ray's offset
//! origin and its packed direction, for tests/hit_gpu.rs to compare with
//! `geometry::shading_normal`, `triangle_tangent`, `vertex_tangent`, `bvh::uv_tangent`,
//! `bvh::alpha_passes`, `Hit::facing`, `geometry::offset_origin` and `photon::pack_normal`.

use super::light::SceneProbes;
use gpu_photon::error::Result;

/// One case of [`SceneProbes::hits`]: a primitive, a point on it and a ray.
#[derive(Clone, Copy, Debug)]
pub struct HitCase {
    /// The ray's origin.
    pub origin: [f32; 3],
    /// Its unit direction.
    pub dir: [f32; 3],
    /// The nearest hit is looked for in (0, t_max).
    pub t_max: f32,
    /// The primitive: a triangle's index or `SPHERE_BIT | ` a sphere's.
    pub primitive: u32,
    /// The distance given to the alpha test.
    pub t: f32,
    /// The barycentrics (weights of `v1`, `v2`) given to the per-triangle functions and the
    /// alpha test.
    pub bc: [f32; 2],
    /// The geometric normal given to `shading_normal`.
    pub ng: [f32; 3],
}

/// What the device gave for one [`HitCase`]; a tangent is `(xyz, w)` with `w` 1 for a
/// flipped frame, 0 for an unflipped one, -1 for a degenerate mapping (`triangle_tangent`
/// and `uv_tangent`), and `None` where the function did not run (a sphere; a scene without
/// uvs, or without tangents for `vertex_tangent`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HitProbe {
    /// `shading_normal(ng, normals, bc)` of a smooth triangle; `None` for a flat one.
    pub shading: Option<[f32; 3]>,
    /// `triangle_tangent` of the triangle's edges and corner uvs.
    pub triangle_tangent: Option<[f32; 4]>,
    /// `vertex_tangent` of its tangents at `bc`.
    pub vertex_tangent: Option<[f32; 4]>,
    /// `uv_tangent` at `bc`.
    pub uv_tangent: Option<[f32; 4]>,
    /// `alpha_passes(primitive, t, bc, origin, dir)`.
    pub passes: bool,
    /// The nearest hit's material (`None`: no hit).
    pub material: Option<u32>,
    /// `facing(hit, dir . normal < 0)`: its geometric normal, shading normal and whether
    /// they differ.
    pub facing: ([f32; 3], [f32; 3], bool),
    /// `offset_origin(origin, ng, dir)`.
    pub offset: [f32; 3],
    /// `pack_normal(dir)`.
    pub packed: u32,
    /// The nearest hit's shading-frame tangent (`Hit::tangent`).
    pub tangent: [f32; 3],
}

impl SceneProbes {
    /// The device's surface functions at each case (`probe_hit`).
    pub fn hits(&mut self, cases: &[HitCase]) -> Result<Vec<HitProbe>> {
        let n = cases.len().max(1);
        let mut init = vec![[0f32; 4]; 13 * n];
        for (i, c) in cases.iter().enumerate() {
            let (o, d, ng) = (c.origin, c.dir, c.ng);
            init[i] = [o[0], o[1], o[2], c.t];
            init[n + i] = [d[0], d[1], d[2], f32::from_bits(c.primitive)];
            init[2 * n + i] = [ng[0], ng[1], ng[2], c.t_max];
            init[3 * n + i] = [c.bc[0], c.bc[1], 0.0, 0.0];
        }
        let out = self.dispatch("probe_hit", &init, n)?;
        let at = |k: usize, i: usize| out[k * n + i];
        let ran = |v: [f32; 4]| (v[3] != -2.0).then_some(v);
        let xyz = |v: [f32; 4]| [v[0], v[1], v[2]];
        Ok((0..cases.len())
            .map(|i| {
                let s = at(4, i);
                let h = at(8, i);
                HitProbe {
                    shading: (s[3] == 1.0).then_some(xyz(s)),
                    triangle_tangent: ran(at(5, i)),
                    vertex_tangent: ran(at(6, i)),
                    uv_tangent: ran(at(7, i)),
                    passes: h[0] == 1.0,
                    material: (h[1] == 1.0).then_some(h[2] as u32),
                    facing: (xyz(at(9, i)), xyz(at(10, i)), h[3] == 1.0),
                    offset: xyz(at(11, i)),
                    packed: at(11, i)[3].to_bits(),
                    tangent: xyz(at(12, i)),
                }
            })
            .collect())
    }
}

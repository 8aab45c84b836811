//! Light sampling: the power-proportional photon budget, photon emission, and the points
//! that shadow rays aim at. Twin: `src/lights/light.wgsl`.
//!
//! Spot lights emit from their position with directions drawn in proportion to their falloff
//! ([`SpotCone::sample_cos`](crate::scene::SpotCone::sample_cos)), so every photon of a light
//! carries the same power. Directional lights emit parallel photons from a disc of the radius
//! of the scene's bounding sphere, perpendicular to the light and two radii back from the
//! sphere's centre, so that every photon starts outside the scene. The environment's photons
//! start the same way, with their directions and weights from `crate::lights::environment::sampling`.

pub mod emission;
pub mod environment;
pub mod punctual;
pub mod spot;

use crate::lights::environment::sampling::{self as env, EnvDistribution};
use crate::math::geometry::Aabb;
use crate::math::sampling::{basis, cosine_hemisphere, to_world, uniform_sphere, uniform_triangle};
use crate::scene::{LightShape, Scene, NO_TEXTURE};
use glam::Vec3;

/// Scalar power used to split budgets: the mean of the three channels.
pub fn scalar_power(power: Vec3) -> f64 {
    (power.x as f64 + power.y as f64 + power.z as f64) / 3.0
}

/// Splits `total` photons between lights in proportion to their scalar power (largest
/// remainder method, so the counts add up to `total` exactly). Lights of zero power get none.
pub fn split_budget(powers: &[f64], total: u32) -> Vec<u32> {
    let sum: f64 = powers.iter().sum();
    if sum <= 0.0 || powers.is_empty() {
        return vec![0; powers.len()];
    }
    let exact: Vec<f64> = powers.iter().map(|p| p / sum * total as f64).collect();
    let mut counts: Vec<u32> = exact.iter().map(|e| e.floor() as u32).collect();
    let left = total - counts.iter().sum::<u32>();
    let mut order: Vec<usize> = (0..powers.len()).filter(|&i| powers[i] > 0.0).collect();
    order.sort_by(|&a, &b| {
        (exact[b] - exact[b].floor())
            .total_cmp(&(exact[a] - exact[a].floor()))
            .then(a.cmp(&b))
    });
    for &i in order.iter().cycle().take(left as usize) {
        counts[i] += 1;
    }
    counts
}

/// Sampling tables for every light of a scene.
#[derive(Clone, Debug)]
pub struct LightTable {
    /// Per light: cumulative area of its triangles (normalised to end at 1), into `tri_cdf`.
    pub cdf_start: Vec<u32>,
    /// Concatenated per-light triangle CDFs.
    pub tri_cdf: Vec<f32>,
    /// Per light: total emitting area (0 for point, spot and directional lights).
    pub area: Vec<f32>,
    /// The scene's bounding sphere (centre, radius): where directional lights' photons
    /// start ([`Scene::bounding_sphere`]).
    pub bounds: (Vec3, f32),
    /// Per light: its emission texture's mean over its surface (one without one), which its
    /// power includes (`crate::lights::emission`).
    pub texture_mean: Vec<Vec3>,
    /// An image environment's sampling distribution (`None` without one).
    pub env: Option<EnvDistribution>,
}

/// A photon leaving a light.
#[derive(Clone, Copy, Debug)]
pub struct Emission {
    /// Where it leaves the light.
    pub origin: Vec3,
    /// Unit direction it leaves in.
    pub dir: Vec3,
    /// Normal of the emitting surface (zero for point, spot and directional lights), for the
    /// ray offset.
    pub normal: Vec3,
    /// Factor on the photon's power: a textured emitter's texel at the origin over the
    /// texture's mean (one for every other light).
    pub scale: Vec3,
}

/// A point on a light seen from a shading point, for a shadow ray.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Position on the light.
    pub point: Vec3,
    /// Incident radiance times the geometry term over the pdf, excluding the receiver's cosine
    /// and BRDF: `Le cos_l / (d^2 pdf_A)` for area lights, `I / d^2` for point lights,
    /// `I att(cos) / d^2` for spot lights, the irradiance `E` for directional lights.
    pub weight: Vec3,
    /// Unit normal of the light surface at `point` (zero for the other lights).
    pub normal: Vec3,
    /// A directional light: `point` is one unit from the shading point towards the light,
    /// and the shadow ray runs to infinity.
    pub distant: bool,
}

impl LightTable {
    /// The solid-angle density with which [`sample`](Self::sample) picks `point` (normal
    /// `normal`) on area light `l` as seen from `x`: uniform over its area, `d^2 / (|cos_l|
    /// area)`; 0 for a point seen edge-on.
    pub fn solid_angle_pdf(&self, l: usize, x: Vec3, point: Vec3, normal: Vec3) -> f32 {
        let to_x = x - point;
        let d2 = to_x.length_squared();
        let cos_l = normal.dot(to_x).abs() / d2.sqrt();
        if cos_l > 0.0 && self.area[l] > 0.0 {
            d2 / (cos_l * self.area[l])
        } else {
            0.0
        }
    }

    /// The sampling tables of every light of `scene`.
    pub fn new(scene: &Scene) -> Self {
        let mut t = LightTable {
            cdf_start: vec![],
            tri_cdf: vec![],
            area: vec![],
            bounds: scene.bounding_sphere(),
            texture_mean: (0..scene.lights.len())
                .map(|l| emission::texture_mean(scene, l))
                .collect(),
            env: scene
                .environment()
                .and_then(|e| env::distribution(e, &scene.textures)),
        };
        for l in &scene.lights {
            t.cdf_start.push(t.tri_cdf.len() as u32);
            match l.shape {
                LightShape::Point { .. }
                | LightShape::Spot { .. }
                | LightShape::Directional { .. }
                | LightShape::Environment(_) => t.area.push(0.0),
                LightShape::Sphere { index } => {
                    let r = scene.spheres[index as usize].radius;
                    t.area.push(4.0 * std::f32::consts::PI * r * r);
                }
                LightShape::Triangles { first, count } => {
                    let tris = &scene.triangles[first as usize..(first + count) as usize];
                    let mut acc = 0.0f64;
                    let start = t.tri_cdf.len();
                    for tri in tris {
                        acc += tri.area() as f64;
                        t.tri_cdf.push(acc as f32);
                    }
                    for c in &mut t.tri_cdf[start..] {
                        *c = if acc > 0.0 {
                            (*c as f64 / acc) as f32
                        } else {
                            1.0
                        };
                    }
                    t.area.push(acc as f32);
                }
            }
        }
        t
    }

    /// Picks a triangle of light `l` (a triangle light) with probability proportional to
    /// area: the first whose CDF value exceeds `u` (the last for `u` at or past the end).
    pub fn pick_triangle(&self, scene: &Scene, l: usize, u: f32) -> usize {
        let LightShape::Triangles { first, count } = scene.lights[l].shape else {
            unreachable!()
        };
        let start = self.cdf_start[l] as usize;
        let cdf = &self.tri_cdf[start..start + count as usize];
        let i = cdf.partition_point(|&c| c <= u).min(count as usize - 1);
        first as usize + i
    }

    /// A uniform point on light `l`'s surface with its front normal (an area light's, or a
    /// point or spot light's position with a zero normal), and the emission texture's value
    /// there (one without a texture).
    fn surface_point(&self, scene: &Scene, l: usize, u: [f32; 3]) -> (Vec3, Vec3, Vec3) {
        let texture = emission::texture_of(scene, l);
        let texel = |uv| match texture {
            NO_TEXTURE => Vec3::ONE,
            t => scene.textures[t as usize].eval(uv),
        };
        match scene.lights[l].shape {
            LightShape::Point { position, .. } | LightShape::Spot { position, .. } => {
                (position, Vec3::ZERO, Vec3::ONE)
            }
            LightShape::Directional { .. } | LightShape::Environment(_) => {
                unreachable!("a distant light has no point")
            }
            LightShape::Sphere { index } => {
                let s = &scene.spheres[index as usize];
                let n = uniform_sphere(u[1], u[2]);
                let c = texel(crate::textures::uv::sphere(n));
                (s.center + s.radius * n, n, c)
            }
            LightShape::Triangles { .. } => {
                let t = self.pick_triangle(scene, l, u[0]);
                let tri = &scene.triangles[t];
                let (b1, b2) = uniform_triangle(u[1], u[2]);
                let c = texel(emission::triangle_uv(scene, t, b1, b2));
                (tri.point(b1, b2), tri.normal(), c)
            }
        }
    }

    /// Emits a photon from light `l` using five uniform numbers: area lights pick a triangle
    /// by area and a uniform point on it, then a cosine-weighted direction around the front
    /// normal (or a random face when two-sided); point lights emit uniformly over the sphere;
    /// spot lights by their falloff (`u[3]` the cosine to the axis, `u[4]` the azimuth);
    /// directional lights from a uniform point of their disc (`u[1]`, `u[2]`); the environment
    /// like a directional light, its direction from `u[0], u[3], u[4]`
    /// ([`env::emit_direction`]), its power scaled by `L pi R^2 / (pdf power)`.
    pub fn emit(&self, scene: &Scene, l: usize, u: [f32; 5]) -> Emission {
        match scene.lights[l].shape {
            LightShape::Environment(e) => {
                let dist = self.env.as_ref();
                let (w, pdf) = env::emit_direction(&e, dist, [u[0], u[3], u[4]]);
                let (centre, r) = self.bounds;
                let scale = match dist {
                    None => Vec3::ONE,
                    Some(_) if pdf <= 0.0 => Vec3::ZERO,
                    Some(_) => {
                        let flux =
                            e.eval(&scene.textures, w) * (std::f32::consts::PI * r * r / pdf);
                        let power = scene.lights[l].power;
                        Vec3::select(power.cmpgt(Vec3::ZERO), flux / power, Vec3::ZERO)
                    }
                };
                return Emission {
                    origin: centre + 2.0 * r * w + self.disc(-w, [u[1], u[2]]),
                    dir: -w,
                    normal: Vec3::ZERO,
                    scale,
                };
            }
            LightShape::Spot {
                position,
                direction,
                cone,
                ..
            } => {
                let c = cone.sample_cos(u[3]);
                let s = (1.0 - c * c).max(0.0).sqrt();
                let phi = 2.0 * std::f32::consts::PI * u[4];
                let local = Vec3::new(s * phi.cos(), s * phi.sin(), c);
                return Emission {
                    origin: position,
                    dir: to_world(local, direction),
                    normal: Vec3::ZERO,
                    scale: Vec3::ONE,
                };
            }
            LightShape::Directional { direction, .. } => {
                let (centre, r) = self.bounds;
                return Emission {
                    origin: centre - 2.0 * r * direction + self.disc(direction, [u[1], u[2]]),
                    dir: direction,
                    normal: Vec3::ZERO,
                    scale: Vec3::ONE,
                };
            }
            _ => {}
        }
        let (p, mut n, texel) = self.surface_point(scene, l, [u[0], u[1], u[2]]);
        if n == Vec3::ZERO {
            return Emission {
                origin: p,
                dir: uniform_sphere(u[3], u[4]),
                normal: n,
                scale: Vec3::ONE,
            };
        }
        let mean = self.texture_mean[l];
        let scale = Vec3::select(mean.cmpgt(Vec3::ZERO), texel / mean, Vec3::ZERO);
        let mut u3 = u[3];
        if self.two_sided(scene, l) {
            // Reuse u3: its lower half picks the front face, upper half the back.
            if u3 >= 0.5 {
                n = -n;
                u3 = u3 * 2.0 - 1.0;
            } else {
                u3 *= 2.0;
            }
        }
        Emission {
            origin: p,
            dir: cosine_hemisphere(n, u3, u[4]),
            normal: n,
            scale,
        }
    }

    /// A uniform point of the disc of the bounding sphere's radius across `direction`,
    /// relative to its centre.
    fn disc(&self, direction: Vec3, u: [f32; 2]) -> Vec3 {
        let (t, b) = basis(direction);
        let rho = self.bounds.1 * u[0].sqrt();
        let phi = 2.0 * std::f32::consts::PI * u[1];
        rho * (phi.cos() * t + phi.sin() * b)
    }

    /// The solid-angle density with which [`sample`](Self::sample) picks direction `dir`
    /// towards environment light `l` from a point of shading normal `ns`.
    pub fn direction_pdf(&self, scene: &Scene, l: usize, ns: Vec3, dir: Vec3) -> f32 {
        match &scene.lights[l].shape {
            LightShape::Environment(e) => env::direction_pdf(e, self.env.as_ref(), ns, dir),
            _ => 0.0,
        }
    }

    fn two_sided(&self, scene: &Scene, l: usize) -> bool {
        let mat = match scene.lights[l].shape {
            LightShape::Point { .. }
            | LightShape::Spot { .. }
            | LightShape::Directional { .. }
            | LightShape::Environment(_) => return false,
            LightShape::Sphere { index } => scene.spheres[index as usize].material,
            LightShape::Triangles { first, .. } => scene.triangles[first as usize].material,
        };
        scene.materials[mat as usize].two_sided_emission
    }

    /// The point [`sample`](Self::sample) picks on light `l` for the uniform numbers `u`
    /// whatever the shading point, where there is one: a point or spot light's position, the
    /// point drawn by area on an area light; `None` for directional and environment lights.
    /// Single scattering draws its distance along a segment towards it.
    pub fn anchor(&self, scene: &Scene, l: usize, u: [f32; 3]) -> Option<Vec3> {
        match scene.lights[l].shape {
            LightShape::Point { position, .. } | LightShape::Spot { position, .. } => {
                Some(position)
            }
            LightShape::Directional { .. } | LightShape::Environment(_) => None,
            LightShape::Sphere { .. } | LightShape::Triangles { .. } => {
                Some(self.surface_point(scene, l, u).0)
            }
        }
    }

    /// A shadow-ray target on light `l` for shading point `x` (shading normal `ns`), from
    /// three uniform numbers. Area lights are sampled uniformly by area, the environment by
    /// [`env::sample_direction`] (a distant target); the others are one point or direction.
    pub fn sample(&self, scene: &Scene, l: usize, x: Vec3, ns: Vec3, u: [f32; 3]) -> LightSample {
        let light = &scene.lights[l];
        let delta = |point, weight, distant| LightSample {
            point,
            weight,
            normal: Vec3::ZERO,
            distant,
        };
        match light.shape {
            LightShape::Point {
                position,
                intensity,
            } => {
                let d2 = (position - x).length_squared().max(1e-20);
                return delta(position, intensity / d2, false);
            }
            LightShape::Spot {
                position,
                direction,
                intensity,
                cone,
            } => {
                let to_x = x - position;
                let d2 = to_x.length_squared().max(1e-20);
                let att = cone.falloff(direction.dot(to_x) / d2.sqrt());
                return delta(position, intensity * (att / d2), false);
            }
            LightShape::Directional {
                direction,
                irradiance,
            } => return delta(x - direction, irradiance, true),
            LightShape::Environment(e) => {
                let (dir, pdf) = env::sample_direction(&e, self.env.as_ref(), ns, u);
                let weight = if pdf > 0.0 {
                    e.eval(&scene.textures, dir) / pdf
                } else {
                    Vec3::ZERO
                };
                return delta(x + dir, weight, true);
            }
            _ => {}
        }
        let (p, n, texel) = self.surface_point(scene, l, u);
        let mat = match light.shape {
            LightShape::Sphere { index } => scene.spheres[index as usize].material,
            LightShape::Triangles { .. } => {
                scene.triangles[self.pick_triangle(scene, l, u[0])].material
            }
            _ => unreachable!("handled above"),
        };
        let m = &scene.materials[mat as usize];
        let to_x = x - p;
        let d2 = to_x.length_squared();
        if d2 <= 0.0 {
            return LightSample {
                point: p,
                weight: Vec3::ZERO,
                normal: n,
                distant: false,
            };
        }
        let mut cos_l = n.dot(to_x) / d2.sqrt();
        if m.two_sided_emission {
            cos_l = cos_l.abs();
        }
        if cos_l <= 0.0 {
            return LightSample {
                point: p,
                weight: Vec3::ZERO,
                normal: n,
                distant: false,
            };
        }
        LightSample {
            point: p,
            weight: m.emission * texel * (cos_l * self.area[l] / d2),
            normal: n,
            distant: false,
        }
    }
}

/// Bounds of the surfaces that caustic photons are aimed at, those with a delta or glossy
/// lobe (`Material::casts_caustics`): one box per such material over its triangles, and
/// each such sphere's box.
pub fn specular_bounds(scene: &Scene) -> Vec<Aabb> {
    let mut per_material: Vec<Aabb> = vec![Aabb::EMPTY; scene.materials.len()];
    for t in &scene.triangles {
        if scene.materials[t.material as usize].casts_caustics() {
            per_material[t.material as usize] =
                per_material[t.material as usize].union(Aabb::of_triangle(t));
        }
    }
    let mut out: Vec<Aabb> = per_material.into_iter().filter(|b| !b.is_empty()).collect();
    for s in &scene.spheres {
        if scene.materials[s.material as usize].casts_caustics() {
            out.push(Aabb::of_sphere(s));
        }
    }
    out
}

/// Whether a ray from `origin` along `dir` enters any of `bounds`.
pub fn aims_at(bounds: &[Aabb], origin: Vec3, dir: Vec3) -> bool {
    let inv = dir.recip();
    bounds.iter().any(|b| b.hit(origin, inv, f32::INFINITY))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budget_split_is_proportional_and_exact() {
        let c = split_budget(&[3.0, 1.0, 0.0, 4.0], 1000);
        assert_eq!(c, vec![375, 125, 0, 500]);
        let c = split_budget(&[1.0, 1.0, 1.0], 100);
        assert_eq!(c.iter().sum::<u32>(), 100);
        assert!(c.iter().all(|&n| n == 33 || n == 34));
        assert_eq!(split_budget(&[], 10), Vec::<u32>::new());
        assert_eq!(split_budget(&[0.0], 10), vec![0]);
    }
}

//! The lights: one tagged union of every light kind ([`LightShape`]), the interface the kinds
//! implement ([`interface::LightKind`]), their sampling tables ([`table::LightTable`]) and the
//! power-proportional photon budget.
//!
//! Each kind is its Rust file (its parameters, emission, shadow-ray sampling and GPU words),
//! its WGSL file beside it (`<prefix>_emit`, `<prefix>_sample`, ...) and one entry of the
//! list below; `gpu.rs` generates the WGSL codes and dispatch from the list. A kind the scene
//! builder adds by a call of its own has that call in its folder's `build.rs`.

pub mod area;
pub mod directional;
pub mod emission;
pub mod environment;
pub mod gpu;
pub mod interface;
pub mod point;
pub mod projector;
pub mod sphere;
pub mod spot;
pub mod table;
pub mod triangles;

use crate::lights::interface::{Emission, LightContext, LightKind, LightSample, ParamWords};
use crate::scene::shapes::{Sphere, Triangle};
use crate::textures::SceneTexture;
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

/// One kind of the list, as the GPU's generated dispatch needs it.
#[derive(Clone, Copy, Debug)]
pub struct KindInfo {
    /// The variant's name (`Point`).
    pub name: &'static str,
    /// Its module, the prefix of its WGSL functions (`point_emit`).
    pub prefix: &'static str,
    /// Its WGSL file.
    pub wgsl: &'static str,
    /// Its path under `src/` (for the tests that read the files).
    pub path: &'static str,
    /// Whether it is a delta light ([`LightKind::is_delta`], the same for every light of it).
    pub delta: bool,
    /// Its generated WGSL constants, if any.
    pub consts: fn() -> String,
    /// Its pipeline override constants for a scene's lights, if any.
    pub overrides: fn(&[Light]) -> Vec<(&'static str, f64)>,
}

/// No generated WGSL constants.
fn no_consts() -> String {
    String::new()
}

/// No override constants of its own.
fn no_overrides(_: &[Light]) -> Vec<(&'static str, f64)> {
    Vec::new()
}

/// The list of kinds: the union's variants, in the order of their GPU codes.
macro_rules! light_kinds {
    ($($(#[$doc:meta])* $variant:ident($module:ident, $ty:ident, $path:literal, $delta:literal,
        $consts:path, $overrides:path)),+ $(,)?) => {
        /// What a light is: one variant per kind, each with its own parameters.
        #[derive(Clone, Copy, Debug, PartialEq)]
        pub enum LightShape {
            $($(#[$doc])* $variant($module::$ty)),+
        }

        /// The GPU code of each kind (its index in the list).
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        #[repr(u32)]
        pub enum KindCode {
            $(#[allow(missing_docs)] $variant),+
        }

        /// Every kind, in the order of their codes.
        pub const KINDS: &[KindInfo] = &[$(KindInfo {
            name: stringify!($variant),
            prefix: stringify!($module),
            wgsl: include_str!($path),
            path: concat!("lights/", $path),
            delta: $delta,
            consts: $consts,
            overrides: $overrides,
        }),+];

        impl LightShape {
            /// Its kind's GPU code.
            pub fn code(&self) -> u32 {
                match self {
                    $(LightShape::$variant(_) => KindCode::$variant as u32),+
                }
            }
        }

        // The union dispatches each method to its kind in one `match`.
        impl LightKind for LightShape {
            fn is_delta(&self) -> bool {
                match self { $(LightShape::$variant(k) => k.is_delta()),+ }
            }
            fn surface(&self, triangles: &[Triangle], spheres: &[Sphere]) -> (f32, Vec<f32>) {
                match self { $(LightShape::$variant(k) => k.surface(triangles, spheres)),+ }
            }
            fn distribution(&self, textures: &[SceneTexture]) -> Vec<f32> {
                match self { $(LightShape::$variant(k) => k.distribution(textures)),+ }
            }
            fn material(&self, triangles: &[Triangle], spheres: &[Sphere]) -> Option<u32> {
                match self { $(LightShape::$variant(k) => k.material(triangles, spheres)),+ }
            }
            fn emit(&self, c: &LightContext, u: [f32; 5]) -> Emission {
                match self { $(LightShape::$variant(k) => k.emit(c, u)),+ }
            }
            fn sample(&self, c: &LightContext, x: Vec3, ns: Vec3, u: [f32; 3]) -> LightSample {
                match self { $(LightShape::$variant(k) => k.sample(c, x, ns, u)),+ }
            }
            fn anchor(&self, c: &LightContext, u: [f32; 3]) -> Option<Vec3> {
                match self { $(LightShape::$variant(k) => k.anchor(c, u)),+ }
            }
            fn direction_pdf(&self, c: &LightContext, ns: Vec3, dir: Vec3) -> f32 {
                match self { $(LightShape::$variant(k) => k.direction_pdf(c, ns, dir)),+ }
            }
            fn gpu_words(&self, c: &LightContext) -> ParamWords {
                match self { $(LightShape::$variant(k) => k.gpu_words(c)),+ }
            }
        }
    };
}

light_kinds! {
    /// An isotropic point source.
    Point(point, Point, "point/point.wgsl", true, no_consts, no_overrides),
    /// Emissive triangles of one shape.
    Triangles(triangles, Triangles, "triangles.wgsl", false, no_consts, no_overrides),
    /// An emissive sphere.
    Sphere(sphere, SphereLight, "sphere.wgsl", false, no_consts, no_overrides),
    /// A point source with a cone.
    Spot(spot, Spot, "spot/spot.wgsl", true, spot::wgsl_consts, spot::gpu_overrides),
    /// Parallel light from a direction.
    Directional(directional, Directional, "directional/directional.wgsl", true, no_consts, no_overrides),
    /// A pinhole projecting an image.
    Projector(projector, Projector, "projector/projector.wgsl", true, no_consts, no_overrides),
    /// The environment: radiance from every direction that leaves the scene; always the last
    /// light.
    Environment(environment, Environment, "environment/environment.wgsl", false, no_consts, no_overrides),
}

impl LightShape {
    /// Lights without a surface ([`LightKind::is_delta`]).
    pub fn is_delta(&self) -> bool {
        LightKind::is_delta(self)
    }
}

/// A light source: what it is and its power.
#[derive(Clone, Debug, PartialEq)]
pub struct Light {
    /// What it is.
    pub shape: LightShape,
    /// Emitted power per channel (W), as each kind's builder sets it: 4 pi I for a point
    /// light, pi A L for a one-sided emitter, E pi R^2 for a directional light (R the radius of
    /// `Scene::bounding_sphere`), pi R^2 times the radiance's integral over directions for
    /// the environment, pi E A for a projector (`lights::projector`); times the emission
    /// texture's mean for a textured one (`lights::emission`).
    pub power: Vec3,
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

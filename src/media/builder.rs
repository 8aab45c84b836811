//! Participating media of the scene being built (issue 24): [`SceneBuilder::add_medium`]
//! checks a homogeneous medium and names it; shapes bound media through their
//! [`Surface::media`](crate::scene::Surface::media) and the camera may sit in one.
//! Every importer (TOML `[media.NAME]`, Mitsuba `homogeneous`) calls these.

use crate::error::Result;
use crate::media::grid::{Volume, VolumeGrid, VolumeKind};
use crate::media::heterogeneous::{Heterogeneous, MAX_OPTICAL_DEPTH};
use crate::media::phase::HenyeyGreenstein;
use crate::media::{Medium, MediumInterface, MediumKind, NO_MEDIUM};
use crate::scene::locate::{unknown_name, Locate, Part};
use crate::scene::SceneBuilder;
use glam::Vec3;
use std::collections::HashMap;
use std::sync::Arc;

/// A medium of the scene being built, as [`SceneBuilder::add_medium`] returns it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MediumId(u32);

impl MediumId {
    /// Index into `Scene::media`.
    pub fn index(self) -> u32 {
        self.0
    }
}

/// The builder's media, their names and the camera's medium.
#[derive(Debug)]
pub(crate) struct Media {
    pub(crate) media: Vec<Medium>,
    names: HashMap<String, MediumId>,
    pub(crate) camera: u32,
}

impl Default for Media {
    fn default() -> Self {
        Media {
            media: Vec::new(),
            names: HashMap::new(),
            camera: NO_MEDIUM,
        }
    }
}

/// A homogeneous medium as a file gives it, before checks: Mitsuba's `homogeneous`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MediumParams {
    /// Extinction per channel per unit length, before `scale`.
    pub sigma_t: Vec3,
    /// Single-scattering albedo per channel.
    pub albedo: Vec3,
    /// Multiplies `sigma_t` (Mitsuba's `scale`, for scenes in other units).
    pub scale: f32,
    /// The Henyey-Greenstein asymmetry (0: isotropic).
    pub g: f32,
}

impl SceneBuilder {
    /// Adds a homogeneous medium, findable by `name` through [`Self::medium_named`].
    /// `sigma_t` and `scale` must be finite and >= 0, the albedo in [0, 1], `g` in (-1, 1);
    /// errors are on `Part::Parameter("sigma_t" | "scale" | "albedo" | "g")`.
    pub fn add_medium(
        &mut self,
        name: Option<&str>,
        p: MediumParams,
        at: &dyn Locate,
    ) -> Result<MediumId> {
        let fail =
            |key: &'static str, message: String| Err(at.error(Part::Parameter(key), message));
        if !(p.sigma_t.is_finite() && p.sigma_t.min_element() >= 0.0) {
            return fail(
                "sigma_t",
                format!("must be finite and >= 0 (got {})", p.sigma_t),
            );
        }
        if !(p.scale.is_finite() && p.scale >= 0.0) {
            return fail(
                "scale",
                format!("must be finite and >= 0 (got {})", p.scale),
            );
        }
        if !(p.albedo.min_element() >= 0.0 && p.albedo.max_element() <= 1.0) {
            return fail("albedo", format!("must be in [0, 1] (got {})", p.albedo));
        }
        if !(p.g > -1.0 && p.g < 1.0) {
            return fail("g", format!("must be in (-1, 1) (got {})", p.g));
        }
        let sigma_t = p.sigma_t * p.scale;
        if !sigma_t.is_finite() {
            return fail("scale", "sigma_t x scale is not finite".into());
        }
        Ok(self.push_medium(
            name,
            Medium {
                sigma_t,
                albedo: p.albedo,
                phase: HenyeyGreenstein { g: p.g },
                kind: MediumKind::Homogeneous,
            },
        ))
    }

    fn push_medium(&mut self, name: Option<&str>, m: Medium) -> MediumId {
        self.media.media.push(m);
        let id = MediumId(self.media.media.len() as u32 - 1);
        if let Some(name) = name {
            self.media.names.insert(name.to_string(), id);
        }
        id
    }

    /// Adds a heterogeneous medium (Mitsuba's `heterogeneous`): extinction `scale *
    /// sigma_t(x)` (zero outside `sigma_t`'s box), albedo `albedo(x)`, Henyey-Greenstein `g`.
    /// Every value of `sigma_t` must be >= 0 and of `albedo` in [0, 1] (a grid's first
    /// offender is named by its byte offset), `scale` finite and >= 0, `g` in (-1, 1);
    /// errors are on `Part::Parameter("sigma_t" | "albedo" | "scale" | "g")`.
    pub fn add_heterogeneous_medium(
        &mut self,
        name: Option<&str>,
        sigma_t: Volume,
        albedo: Volume,
        scale: f32,
        g: f32,
        at: &dyn Locate,
    ) -> Result<MediumId> {
        let fail =
            |key: &'static str, message: String| Err(at.error(Part::Parameter(key), message));
        if let Some(m) = out_of_range(&sigma_t, 0.0, f32::INFINITY) {
            return fail("sigma_t", format!("must be >= 0: {m}"));
        }
        if let Some(m) = out_of_range(&albedo, 0.0, 1.0) {
            return fail("albedo", format!("must be in [0, 1]: {m}"));
        }
        if !(scale.is_finite() && scale >= 0.0) {
            return fail("scale", format!("must be finite and >= 0 (got {scale})"));
        }
        if !(g > -1.0 && g < 1.0) {
            return fail("g", format!("must be in (-1, 1) (got {g})"));
        }
        let h = Heterogeneous::new(sigma_t, albedo, scale);
        if !h.majorant.is_finite() {
            return fail("scale", "sigma_t x scale is not finite".into());
        }
        let depth = h.majorant * (h.sigma_t.hi - h.sigma_t.lo).length();
        if !(depth <= MAX_OPTICAL_DEPTH) {
            let message = format!(
                "sigma_t x scale reaches {:e} per unit, an optical depth of {depth:e} across the \
                 volume's box, more than {MAX_OPTICAL_DEPTH:e} (nothing would pass it)",
                h.majorant
            );
            return fail("sigma_t", message);
        }
        let bound = Vec3::splat(h.albedo.max().min(1.0));
        let m = Medium {
            sigma_t: Vec3::splat(h.majorant),
            albedo: bound,
            phase: HenyeyGreenstein { g },
            kind: MediumKind::Heterogeneous(Arc::new(h)),
        };
        Ok(self.push_medium(name, m))
    }

    /// Bytes a medium's grid file may still take: the scene's budget less its geometry,
    /// texels and the grids read so far. Read a grid against it before allocating
    /// ([`VolumeGrid::open`]).
    pub fn grid_room(&self) -> u64 {
        let grids: u64 = (self.media.media.iter())
            .filter_map(|m| match &m.kind {
                MediumKind::Heterogeneous(h) => Some(h.grid_bytes()),
                MediumKind::Homogeneous => None,
            })
            .sum();
        self.byte_room().saturating_sub(grids)
    }

    /// The medium called `name`; an unknown name is an error on `part` that lists the
    /// names defined.
    pub fn medium_named(&self, name: &str, part: Part, at: &dyn Locate) -> Result<MediumId> {
        if let Some(&id) = self.media.names.get(name) {
            return Ok(id);
        }
        let message = unknown_name("medium", name, self.media.names.keys());
        Err(at.error(part, message))
    }

    /// Puts the camera in medium `m`.
    pub fn set_camera_medium(&mut self, m: MediumId) {
        self.media.camera = m.0;
    }

    /// Medium `m` as added (its `sigma_t` already times `scale`).
    pub fn medium(&self, m: MediumId) -> &Medium {
        &self.media.media[m.0 as usize]
    }
}

/// Where a volume's value leaves `[lo, hi]`: the value and where (a grid's byte offset).
fn out_of_range(v: &Volume, lo: f32, hi: f32) -> Option<String> {
    let bad = |x: f32| !(x >= lo && x <= hi);
    match &v.kind {
        VolumeKind::Constant(c) => (c.to_array().into_iter().any(bad)).then(|| format!("{c}")),
        VolumeKind::Grid { grid, .. } => grid.data.iter().position(|&x| bad(x)).map(|i| {
            format!(
                "the grid's value {} at byte {}",
                grid.data[i],
                VolumeGrid::offset_of(i)
            )
        }),
    }
}

/// The interface of a shape with `interior` and `exterior` media (an absent one: vacuum), or
/// `None` when it names neither (the shape keeps its material's).
pub fn interface(
    interior: Option<MediumId>,
    exterior: Option<MediumId>,
) -> Option<MediumInterface> {
    (interior.is_some() || exterior.is_some()).then(|| MediumInterface {
        interior: interior.map_or(NO_MEDIUM, MediumId::index),
        exterior: exterior.map_or(NO_MEDIUM, MediumId::index),
    })
}

impl crate::scene::Scene {
    /// Whether any shape bounds a medium or the camera sits in one.
    pub fn uses_media(&self) -> bool {
        self.camera_medium != NO_MEDIUM || self.materials.iter().any(|m| !m.media.is_vacuum())
    }

    /// Whether rays must be carried through media: the scene uses a medium
    /// ([`Self::uses_media`]) or has an index-matched boundary (`Bsdf::Null`), which
    /// only media transport passes.
    pub fn has_media_transport(&self) -> bool {
        self.uses_media()
            || self
                .materials
                .iter()
                .any(|m| matches!(m.bsdf, crate::bsdfs::Bsdf::Null(_)))
    }
}

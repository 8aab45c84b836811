//! The scene builder's call for an SDF grid (`sdf_grid.rs`): placed in the world, or in the
//! shape group being recorded (each instance of the group then places a copy that shares
//! the grid's values).

use super::builder::{SceneBuilder, Surface};
use super::locate::{Locate, Part};
use super::sdf_grid::{SdfData, SdfGrid};
use crate::error::Result;
use glam::{Affine3A, Mat4};
use std::sync::Arc;

impl SceneBuilder {
    /// Adds the SDF grid `data` placed by `to_world` (affine, finite, invertible; errors on
    /// [`Part::Geometry`]) with `surface`, which may not emit (Mitsuba: an `sdfgrid` cannot
    /// be an area emitter; an error on [`Part::Emission`]); `smooth`: Mitsuba's `normals`.
    pub fn add_sdf_grid(
        &mut self,
        data: Arc<SdfData>,
        to_world: Mat4,
        smooth: bool,
        surface: Surface,
        at: &dyn Locate,
    ) -> Result<()> {
        let surface = self.resolve(surface, at)?;
        if surface.radiance.is_some() {
            let message = "an sdfgrid cannot be an area emitter (as in Mitsuba)";
            return Err(at.error(Part::Emission, message.into()));
        }
        let a = Affine3A::from_mat4(to_world);
        let det = a.matrix3.determinant();
        let ok = a.is_finite() && det.is_finite() && det != 0.0;
        if !ok || to_world.row(3) != glam::Vec4::W {
            let message = "the sdfgrid's to_world must be a finite, invertible affine transform";
            return Err(at.error(Part::Geometry, message.into()));
        }
        let material = self.commit(&surface);
        self.sdf_grids.push(SdfGrid::new(data, a, material, smooth));
        Ok(())
    }
}

//! A large generated mesh for the ray-throughput benchmark: a sphere tessellated into a
//! latitude-longitude grid, its radius displaced by a few sine waves (bumps at several
//! scales, so boxes overlap as on scanned meshes), deterministic for a triangle count.

use crate::scene::{Scene, Triangle};
use glam::Vec3;
use std::f32::consts::PI;

/// About `triangles` triangles (two per grid cell, rows twice the columns' density in
/// longitude) of a displaced sphere at `center` of mean radius `radius`, of `material`.
pub fn displaced_sphere(
    triangles: usize,
    center: Vec3,
    radius: f32,
    material: u32,
) -> Vec<Triangle> {
    let rows = (triangles as f64 / 4.0).sqrt().ceil() as usize + 1;
    let cols = 2 * rows;
    let point = |i: usize, j: usize| {
        let theta = PI * i as f32 / rows as f32;
        let phi = 2.0 * PI * (j % cols) as f32 / cols as f32;
        let bump = 0.08 * (7.0 * theta).sin() * (9.0 * phi).sin()
            + 0.02 * (31.0 * theta).sin() * (29.0 * phi).cos();
        let r = radius * (1.0 + bump);
        center
            + r * Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            )
    };
    let mut out = Vec::with_capacity(2 * rows * cols);
    for i in 0..rows {
        for j in 0..cols {
            let (a, b) = (point(i, j), point(i, j + 1));
            let (c, d) = (point(i + 1, j), point(i + 1, j + 1));
            // The poles' degenerate halves are left out.
            if i > 0 {
                out.push(Triangle::new(a, c, b, material));
            }
            if i + 1 < rows {
                out.push(Triangle::new(b, c, d, material));
            }
        }
    }
    out
}

/// `scene` with a displaced sphere of about `triangles` triangles added at the centre of its
/// bounds (three fifths of their smallest extent across, so that most rays meet it), of its
/// first material.
pub fn with_mesh(scene: &Scene, triangles: usize) -> Scene {
    let mut s = scene.clone();
    let bounds = (s
        .triangles
        .iter()
        .map(crate::math::geometry::Aabb::of_triangle))
    .chain(s.spheres.iter().map(crate::math::geometry::Aabb::of_sphere))
    .fold(crate::math::geometry::Aabb::EMPTY, |a, b| a.union(b));
    let (center, radius) = match bounds.is_empty() {
        true => (Vec3::ZERO, 1.0),
        false => (
            bounds.centroid(),
            (bounds.max - bounds.min).min_element().max(1e-3) * 0.3,
        ),
    };
    let mesh = displaced_sphere(triangles, center, radius, 0);
    if !s.uvs.is_empty() {
        s.uvs
            .resize(s.triangles.len() + mesh.len(), Default::default());
    }
    if !s.tangents.is_empty() {
        s.tangents
            .resize(s.triangles.len() + mesh.len(), Default::default());
    }
    s.triangles.extend(mesh);
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_mesh_has_about_the_asked_count_and_no_degenerate_triangle() {
        for n in [100, 10_000] {
            let m = displaced_sphere(n, Vec3::ZERO, 1.0, 0);
            assert!(m.len() >= n && m.len() < n + n / 5 + 40, "{n}: {}", m.len());
            assert!(m.iter().all(|t| t.area() > 0.0));
        }
    }
}

//! The medium outside every shape: where photons that start outside the scene (a directional
//! light's, the environment's) or that meet no boundary of a medium travel.

use super::Scene;
use crate::media::MediumInterface;

impl Scene {
    /// The medium outside every shape: the side facing +x of the surface bounding a medium
    /// that reaches farthest along +x (of several, the one whose normal is most nearly along
    /// x), which a ray from far along +x meets first among such surfaces; the camera's medium
    /// when no surface bounds one (fog filling the whole scene). Instanced meshes and SDF
    /// grids are not looked at.
    pub fn medium_outside(&self) -> u32 {
        let side = |m: u32, nx: f32| -> Option<MediumInterface> {
            let media = self.materials[m as usize].media;
            (!media.is_vacuum() && nx != 0.0).then_some(media)
        };
        // (farthest x, |normal.x|, the side seen from +x)
        let mut best: Option<(f32, f32, u32)> = None;
        let mut offer = |x: f32, nx: f32, media: MediumInterface| {
            let medium = match nx > 0.0 {
                true => media.exterior,
                false => media.interior,
            };
            let better = match best {
                None => true,
                Some((bx, bn, _)) => x > bx || (x == bx && nx.abs() > bn),
            };
            if better {
                best = Some((x, nx.abs(), medium));
            }
        };
        for t in &self.triangles {
            let nx = t.normal().x;
            if let Some(media) = side(t.material, nx) {
                offer(t.v0.x.max(t.v1.x).max(t.v2.x), nx, media);
            }
        }
        for s in &self.spheres {
            if let Some(media) = side(s.material, 1.0) {
                offer(s.center.x + s.radius, 1.0, media);
            }
        }
        best.map_or(self.camera_medium, |(_, _, m)| m)
    }
}

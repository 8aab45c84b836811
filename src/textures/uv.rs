//! The uv parameterisations of Mitsuba 3's analytic shapes, as functions of a point in the
//! shape's local frame (before its `to_world`). Checked against Mitsuba 3.9.1's ray hits by
//! `tests/texture_mitsuba.rs`. Angles are computed in f64 and rounded once.

use glam::{Vec2, Vec3};
use std::f64::consts::PI;

/// `rectangle`: the square `[-1, 1]^2` in the plane z = 0, `u = (x + 1) / 2`,
/// `v = (y + 1) / 2`.
pub fn rectangle(p: Vec3) -> Vec2 {
    Vec2::new(p.x * 0.5 + 0.5, p.y * 0.5 + 0.5)
}

/// `disk`: the unit disk in z = 0, `u` the distance from the centre, `v` the angle from +x
/// towards +y over 2 pi, in `[0, 1)`.
pub fn disk(p: Vec3) -> Vec2 {
    let (x, y) = (p.x as f64, p.y as f64);
    let mut v = y.atan2(x) / (2.0 * PI);
    if v < 0.0 {
        v += 1.0;
    }
    Vec2::new(x.hypot(y) as f32, v as f32)
}

/// `sphere`: the unit sphere, `u = phi / (2 pi)` with phi the azimuth from +x towards +y in
/// `[0, 2 pi)`, `v = theta / pi` with theta the angle from +z (v = 0 at the north pole).
/// `p` need not be normalised.
pub fn sphere(p: Vec3) -> Vec2 {
    let (x, y, z) = (p.x as f64, p.y as f64, p.z as f64);
    let mut phi = y.atan2(x);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    let theta = x.hypot(y).atan2(z);
    Vec2::new((phi / (2.0 * PI)) as f32, (theta / PI) as f32)
}

/// `cube`: the cube `[-1, 1]^3`, each face mapped onto the unit square (Mitsuba's cube
/// mesh): with `h(t) = (t + 1) / 2` and `g(t) = (1 - t) / 2`, face -y `(h z, h x)`, +y
/// `(g x, g z)`, +x `(h y, g z)`, +z `(h y, h x)`, -x `(h y, h z)`, -z `(g y, h x)`. The face
/// is that of the coordinate of largest magnitude (on an edge, the first of x, y, z).
pub fn cube(p: Vec3) -> Vec2 {
    let h = |t: f32| (t + 1.0) * 0.5;
    let g = |t: f32| (1.0 - t) * 0.5;
    let a = p.abs();
    if a.x >= a.y && a.x >= a.z {
        if p.x > 0.0 {
            Vec2::new(h(p.y), g(p.z))
        } else {
            Vec2::new(h(p.y), h(p.z))
        }
    } else if a.y >= a.z {
        if p.y > 0.0 {
            Vec2::new(g(p.x), g(p.z))
        } else {
            Vec2::new(h(p.z), h(p.x))
        }
    } else if p.z > 0.0 {
        Vec2::new(h(p.y), h(p.x))
    } else {
        Vec2::new(g(p.y), h(p.x))
    }
}

//! Mitsuba's `sensor`: a `perspective`, `thinlens` or `orthographic` camera with its
//! `hdrfilm`, `rfilter` and `sampler`.
//!
//! The field of view is converted exactly: Mitsuba's `fov` spans the `fov_axis` (`x`, `y`,
//! `diagonal`, `smaller` or `larger` of the film) and ours is vertical, so
//! `tan(fov_y / 2) = tan(fov / 2) * h / s`, `s` the film's extent along that axis (`w`, `h`
//! or `sqrt(w^2 + h^2)`).
//!
//! The sampler's `sample_count` is split into progressive passes (`split_samples`); the
//! caustic map's photons per pass follow the samples per pass ([`caustic_photons_for`]).
//!
//! An `orthographic` camera's view is camera space's x in [-1, 1] and y in
//! [-1 / aspect, 1 / aspect] (aspect = w / h) through `to_world`, whose x and y scale size it;
//! its rays start on the near clip plane (camera z = `near_clip`), as Mitsuba's do.

use crate::camera::pixel_filter::PixelFilter;
use crate::error::Result;
use crate::importers::mitsuba::plugin::Plugin;
use crate::importers::mitsuba::values::Cx;
use crate::importers::mitsuba::Importer;
use crate::scene::builder::SceneBuilder;
use crate::settings::{split_samples, RenderSettings};
use glam::{Mat4, Vec3};
use roxmltree::Node;

impl Importer<'_> {
    /// `<sensor type="perspective">` (or `thinlens`, `orthographic`) with its film and
    /// sampler: the camera, image size, spp.
    pub(crate) fn sensor(&mut self, node: Node, field: &str) -> Result<()> {
        let cx = &self.cx;
        let p = Plugin::new(cx, node, field.to_string())?;
        if !["perspective", "thinlens", "orthographic"].contains(&p.kind.as_str()) {
            let message = format!(
                "unsupported sensor `{}` (`perspective`, `thinlens`, `orthographic`)",
                p.kind
            );
            return Err(cx.err(node, field, message));
        }
        // Mitsuba's film when the file gives none: its default rfilter is a gaussian.
        let mut filter = PixelFilter::Gaussian { stddev: 0.5 };
        // Mitsuba's film size when the file gives none.
        self.b.settings().width = 768;
        self.b.settings().height = 576;
        // The camera's medium, read once the sensor's other parameters are.
        let mut medium = None;
        for child in &p.objects {
            let sub = format!("{field}.{}", child.tag_name().name());
            match child.tag_name().name() {
                "film" => filter = film(cx, *child, sub, &mut self.warnings, &mut self.b)?,
                "sampler" => {
                    let s = Plugin::new(cx, *child, sub)?;
                    s.setting(cx, "sample_count", "spp", self.b.settings())?;
                    // `sample_count` is the author's total per pixel: passes x spp equals
                    // it exactly (`settings::split_samples`).
                    let settings = self.b.settings();
                    (settings.passes, settings.spp) = split_samples(settings.spp, settings.passes);
                    settings.caustic_photons =
                        caustic_photons_for(settings.caustic_photons, settings.spp);
                    s.ignore(&["seed"]);
                    s.done(cx)?;
                }
                "medium" | "ref" if medium.is_none() => medium = Some((*child, sub)),
                other => {
                    let message = format!("unsupported <{other}> in a sensor");
                    return Err(cx.err(*child, field, message));
                }
            }
        }
        let fov_y = match p.kind.as_str() {
            "orthographic" => None,
            _ => Some(fov_y(cx, &p, node, self.b.settings())?),
        };
        let m = p.transform(cx, "to_world")?.unwrap_or(Mat4::IDENTITY);
        // Clipping planes clip nothing for us (a camera in a medium warns below); Mitsuba's
        // checks on them are kept. A perspective camera's focus distance is read and ignored;
        // a thin lens's defaults to far_clip (Mitsuba's), its aperture radius is required.
        let near = p.positive(cx, "near_clip", 1e-2)?;
        let far = p.float(cx, "far_clip")?.unwrap_or(1e4);
        if far <= near {
            let message = format!("must be greater than near_clip ({near})");
            return Err(cx.err(p.node_of("far_clip"), &p.at("far_clip"), message));
        }
        let focus = p.positive(cx, "focus_distance", far)?;
        let aperture = match p.kind.as_str() {
            "thinlens" => {
                let Some(a) = p.float(cx, "aperture_radius")?.filter(|a| *a >= 0.0) else {
                    let message = "a thinlens needs an aperture_radius >= 0";
                    let at = p.node_of("aperture_radius");
                    return Err(cx.err(at, &p.at("aperture_radius"), message));
                };
                a
            }
            _ => 0.0,
        };
        p.done(cx)?;
        self.b.optics(filter, aperture, focus);
        let eye = m.transform_point3(Vec3::ZERO);
        let forward = m.transform_vector3(Vec3::Z);
        let up = m.transform_vector3(Vec3::Y);
        let left = m.transform_vector3(Vec3::X).normalize_or_zero();
        if left.dot(up.cross(forward).normalize_or_zero()) < 0.999 {
            let message = "unsupported camera to_world (only rotation, translation, uniform scale)";
            return Err(cx.err(node, &p.at("to_world"), message));
        }
        let near_at = format!("{}: {}", cx.loc(p.node_of("near_clip")), p.at("near_clip"));
        let at = self.origin(node, field);
        let Some(fov_y) = fov_y else {
            // Mitsuba's view is x in [-1, 1], y in [-1/aspect, 1/aspect] before to_world: the
            // x and y scales must agree (our view keeps the film's aspect).
            let (sx, sy) = (
                m.transform_vector3(Vec3::X).length(),
                m.transform_vector3(Vec3::Y).length(),
            );
            if (sx - sy).abs() > 1e-4 * sx.max(sy) {
                let message = format!(
                    "unsupported orthographic to_world: its x and y scales differ ({sx} and \
                     {sy}); the view keeps the film's aspect"
                );
                return Err(cx.err(node, &p.at("to_world"), message));
            }
            if let Some((child, sub)) = medium {
                let m = self.medium_child(child, &sub)?;
                self.b.set_camera_medium(m);
            }
            let settings = self.b.settings();
            let aspect = settings.width as f32 / settings.height as f32;
            // The rays start on the near clip plane, as Mitsuba's.
            let start = m.transform_point3(Vec3::new(0.0, 0.0, near));
            return self
                .b
                .orthographic_camera(start, start + forward, up, sy / aspect, &at);
        };
        if let Some((child, sub)) = medium {
            let m = self.medium_child(child, &sub)?;
            self.b.set_camera_medium(m);
            // Mitsuba's rays start on the near clip plane, at near_clip / cos(theta) from the
            // eye; ours at the eye. In a medium that skips some of it: warn past 1e-4.
            let depth = near * self.b.medium(m).sigma_t.max_element();
            if depth > 1e-4 {
                self.warnings.push(format!(
                    "{near_at}: near_clip {near} in the camera's medium: Mitsuba's camera rays \
                     start on the near clip plane, skipping an optical depth of {depth:.2e} on \
                     the axis (up to {:.2}% more light), ours start at the eye",
                    100.0 * depth.exp_m1()
                ));
            }
        }
        self.b.camera(eye, eye + forward, up, fov_y, &at)
    }
}

/// Camera samples per pass that `caustic_photons` (the default's 100,000) is balanced for.
pub(crate) const CAUSTIC_SPP: u32 = 16;
/// Most that [`caustic_photons_for`] multiplies the caustic photons by.
pub(crate) const CAUSTIC_SCALE_MAX: u32 = 4;

/// The caustic photons per pass for `spp` camera samples per pass: a Mitsuba file gives a
/// sample budget and no photon counts, and a pass's caustic map is shared by all its camera
/// samples (its noise averages over passes only), so its photons follow the samples per pass
/// past [`CAUSTIC_SPP`], up to [`CAUSTIC_SCALE_MAX`] times. Measured on `materials.xml` (4
/// passes of 64 spp): 100,000 photons per pass gave RMSE 0.00445 in 23.3 s, 200,000 0.00429 in
/// 23.9 s, 400,000 0.00425 in 25.0 s against its reference (noise 0.0032): 13-14% less
/// squared error per second with the reference's noise taken out.
pub(crate) fn caustic_photons_for(photons: u32, spp: u32) -> u32 {
    let scale = (spp / CAUSTIC_SPP).clamp(1, CAUSTIC_SCALE_MAX);
    photons
        .saturating_mul(scale)
        .min(crate::settings::MAX_PHOTONS)
}

/// A `perspective` or `thinlens` sensor's vertical field of view, degrees, from Mitsuba's
/// `parse_fov`: a `fov` on `fov_axis`, or a 35 mm-equivalent `focal_length` (default 50mm)
/// on the 36 x 24 mm frame's diagonal, converted with the film's aspect.
fn fov_y(cx: &Cx, p: &Plugin, node: Node, settings: &RenderSettings) -> Result<f32> {
    let (fov, axis) = fov_and_axis(cx, p, node)?;
    // Our pinhole's principal point is the film's centre.
    for name in ["principal_point_offset_x", "principal_point_offset_y"] {
        if p.float(cx, name)?.is_some_and(|v| v != 0.0) {
            let message = "unsupported unless 0 (the principal point is the film's centre)";
            return Err(cx.err(p.node_of(name), &p.at(name), message));
        }
    }
    let (w, h) = (settings.width as f32, settings.height as f32);
    let ty = tan_half_y(cx, p, node, (fov, &axis), (w, h))?;
    Ok(2.0 * ty.atan().to_degrees())
}

/// `<film type="hdrfilm">`: the image size and the pixel filter: `box`, `tent` (`radius`,
/// default 1), `gaussian` (`stddev`, default 0.5, also without an `rfilter`); another
/// `rfilter` is approximated by our box, with a warning.
fn film(
    cx: &Cx,
    node: Node,
    field: String,
    warnings: &mut Vec<String>,
    b: &mut SceneBuilder,
) -> Result<PixelFilter> {
    let f = Plugin::new(cx, node, field)?;
    if f.kind != "hdrfilm" {
        let message = format!("unsupported film `{}` (only `hdrfilm`)", f.kind);
        return Err(cx.err(node, &f.field, message));
    }
    f.setting(cx, "width", "width", b.settings())?;
    f.setting(cx, "height", "height", b.settings())?;
    // `banner`: Mitsuba 0.6's logo in the image, which Mitsuba 3 accepts and ignores.
    f.ignore(&["pixel_format", "file_format", "component_format", "banner"]);
    f.done(cx)?;
    let mut filter = PixelFilter::Gaussian { stddev: 0.5 };
    for child in &f.objects {
        let sub = format!("{}.{}", f.field, child.tag_name().name());
        if child.tag_name().name() != "rfilter" {
            let message = format!("unsupported <{}> in a film", child.tag_name().name());
            return Err(cx.err(*child, &f.field, message));
        }
        let r = Plugin::new(cx, *child, sub.clone())?;
        filter = match r.kind.as_str() {
            "box" => PixelFilter::Box,
            "tent" => PixelFilter::Tent {
                radius: r.positive(cx, "radius", 1.0)?,
            },
            "gaussian" => PixelFilter::Gaussian {
                stddev: r.positive(cx, "stddev", 0.5)?,
            },
            other => {
                r.ignore(&["radius", "B", "C", "lobes"]);
                let what = format!("pixel filter `{other}` approximated by a one-pixel box");
                warnings.push(format!("{}: {sub}: {what}", cx.loc(*child)));
                PixelFilter::Box
            }
        };
        r.done(cx)?;
    }
    Ok(filter)
}

/// Mitsuba's `parse_fov` (sensors and the projector): a `fov` on `fov_axis` (default `x`),
/// or a 35 mm-equivalent `focal_length` (default 50mm) on the 36 x 24 mm frame's diagonal;
/// the angle in degrees, in (0, 180), and its axis.
pub(crate) fn fov_and_axis(cx: &Cx, p: &Plugin, node: Node) -> Result<(f32, String)> {
    let axis = p.string(cx, "fov_axis")?.map(|a| a.to_lowercase());
    let (fov, axis) = match (p.float(cx, "fov")?, p.string(cx, "focal_length")?) {
        (Some(_), Some(_)) => {
            let message = "give `fov` or `focal_length`, not both";
            return Err(cx.err(p.node_of("focal_length"), &p.at("focal_length"), message));
        }
        (Some(fov), None) => (fov, axis.unwrap_or_else(|| "x".into())),
        (None, focal) => {
            let focal = focal.unwrap_or_else(|| "50mm".into());
            let mm = focal
                .strip_suffix("mm")
                .unwrap_or(&focal)
                .trim()
                .parse::<f32>();
            let Some(mm) = mm.ok().filter(|f| *f > 0.0 && f.is_finite()) else {
                let message = format!("`{focal}` is not a positive length in mm (`50mm`)");
                return Err(cx.err(p.node_of("focal_length"), &p.at("focal_length"), message));
            };
            let fov = 2.0 * (1872f32.sqrt() / (2.0 * mm)).atan().to_degrees();
            (fov, "diagonal".into())
        }
    };
    if !(fov > 0.0 && fov < 180.0) {
        return Err(cx.err(node, &p.at("fov"), "must be in (0, 180) degrees"));
    }
    Ok((fov, axis))
}

/// `tan(fov_y / 2)` of an image of `w x h` whose `fov` (degrees) spans `axis` (the
/// module's docs).
pub(crate) fn tan_half_y(
    cx: &Cx,
    p: &Plugin,
    node: Node,
    (fov, axis): (f32, &str),
    (w, h): (f32, f32),
) -> Result<f32> {
    let t = (fov.to_radians() / 2.0).tan();
    Ok(match axis {
        "x" => t * h / w,
        "y" => t,
        "diagonal" => t * h / (w * w + h * h).sqrt(),
        "smaller" if w < h => t * h / w,
        "larger" if w > h => t * h / w,
        "smaller" | "larger" => t,
        other => {
            let message = format!("unknown fov_axis `{other}` (x, y, diagonal, smaller, larger)");
            return Err(cx.err(node, &p.at("fov_axis"), message));
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn caustic_photons_follow_the_samples_per_pass_within_bounds() {
        assert_eq!(caustic_photons_for(100_000, 1), 100_000);
        assert_eq!(caustic_photons_for(100_000, 16), 100_000);
        assert_eq!(caustic_photons_for(100_000, 40), 200_000);
        assert_eq!(caustic_photons_for(100_000, 64), 400_000);
        assert_eq!(caustic_photons_for(100_000, 4096), 400_000);
        assert_eq!(caustic_photons_for(0, 64), 0);
        let most = crate::settings::MAX_PHOTONS;
        assert_eq!(caustic_photons_for(most, 64), most);
        assert_eq!(caustic_photons_for(u32::MAX, 64), most);
    }
}

// camera: twin of src/camera/mod.rs and src/camera/pixel_filter.rs. The pixel filter's jitter (filter
// importance sampling: one inverse CDF per axis; the box returns the sample itself) and the
// pinhole or thin-lens camera ray. erf_inv_central and erf_inv_tail (Giles' polynomials) are
// generated before this file by pixel_filter::wgsl_library(); the codes come from the prelude.

fn erf_inv(x: f32) -> f32 {
    let w = -log((1.0 - x) * (1.0 + x));
    var p: f32;
    if w < 5.0 {
        p = erf_inv_central(w - 2.5);
    } else {
        p = erf_inv_tail(sqrt(w) - 3.0);
    }
    return p * x;
}

// A sample's offset from the pixel centre along one axis, u in [0, 1).
fn filter_offset(kind: u32, param: f32, u: f32) -> f32 {
    if kind == PIXEL_FILTER_TENT {
        if u < 0.5 {
            return param * (sqrt(2.0 * u) - 1.0);
        }
        return param * (1.0 - sqrt(2.0 - 2.0 * u));
    }
    if kind == PIXEL_FILTER_GAUSSIAN {
        return param * SQRT_2 * erf_inv((2.0 * u - 1.0) * ERF_2_SQRT_2);
    }
    return u - 0.5;
}

// The sample's position in its pixel's raster square.
fn filter_jitter(kind: u32, param: f32, u: vec2<f32>) -> vec2<f32> {
    if kind == PIXEL_FILTER_BOX {
        return u;
    }
    return vec2<f32>(0.5 + filter_offset(kind, param, u.x), 0.5 + filter_offset(kind, param, u.y));
}

// Shirley and Chiu's concentric map of [0, 1)^2 onto the unit disc.
fn concentric_disc(u: vec2<f32>) -> vec2<f32> {
    let a = 2.0 * u.x - 1.0;
    let b = 2.0 * u.y - 1.0;
    if a == 0.0 && b == 0.0 {
        return vec2<f32>(0.0);
    }
    let quarter = 0.25 * PI;
    var r: f32;
    var phi: f32;
    if abs(a) > abs(b) {
        r = a;
        phi = quarter * (b / a);
    } else {
        r = b;
        phi = 2.0 * quarter - quarter * (a / b);
    }
    return vec2<f32>(r * cos(phi), r * sin(phi));
}

struct CameraRay {
    origin: vec3<f32>,
    dir: vec3<f32>,
}

// The ray through raster (px, py) of a w x h image; `lens` picks the aperture point of a thin
// lens (aperture > 0), whose rays through (px, py) meet at depth `focus` along `forward`. An
// orthographic camera (ortho != 0) sends every ray along `forward` from its point of the view.
fn camera_ray(eye: vec3<f32>, forward: vec3<f32>, right: vec3<f32>, up: vec3<f32>, aperture: f32, focus: f32, ortho: u32, px: f32, py: f32, w: f32, h: f32, lens: vec2<f32>) -> CameraRay {
    let sx = (2.0 * px / w - 1.0) * (w / h);
    let sy = 1.0 - 2.0 * py / h;
    if ortho != 0u {
        return CameraRay(eye + sx * right + sy * up, forward);
    }
    let film = forward + sx * right + sy * up;
    if !(aperture > 0.0) {
        return CameraRay(eye, normalize(film));
    }
    let disc = concentric_disc(lens);
    let on_lens = aperture * (disc.x * normalize(right) + disc.y * normalize(up));
    return CameraRay(eye + on_lens, normalize(focus * film - on_lens));
}

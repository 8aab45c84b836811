// The projector (twin of src/lights/projector/mod.rs): p0 = (position, start of its image's
// distribution in light_cdf), p1 = (x half extent, irradiance r), p2 = (y half extent,
// irradiance g), p3 = (unit axis, irradiance b); its image is the light's emission_texture.
// Photons through its image plane (uniformly, or by the image: distribution.rs), shadow rays
// weighed pi E |x - p| / z^3 inside the image. Library, no entry point.

struct ProjectorUv {
    uv: vec2<f32>,
    z: f32,
    inside: bool,
}

// The image plane's uv of the direction through to_x and to_x's component along the axis
// (Projector::uv); not inside behind the projector or outside the image.
fn projector_uv(l: Light, to_x: vec3<f32>) -> ProjectorUv {
    let xh = light_vec(l.p1);
    let yh = light_vec(l.p2);
    let z = dot(to_x, light_vec(l.p3));
    let a = dot(to_x, xh) / (dot(xh, xh) * z);
    let b = dot(to_x, yh) / (dot(yh, yh) * z);
    let uv = vec2<f32>(0.5 - 0.5 * a, 0.5 - 0.5 * b);
    let inside = z > 0.0 && all(uv >= vec2<f32>(0.0)) && all(uv <= vec2<f32>(1.0));
    return ProjectorUv(uv, z, inside);
}

struct ProjectorCell {
    corner: vec2<f32>,
    size: vec2<f32>,
    pdf: f32,
}

// The cell u picks in the image distribution at light_cdf[start] (distribution::pick): the
// grid's size, then its CDF (bisected, bounded by 32 steps), then the cells' densities.
fn projector_cell(start: u32, u: f32) -> ProjectorCell {
    let gw = u32(light_cdf[start]);
    let gh = u32(light_cdf[start + 1u]);
    let n = gw * gh;
    let cdf = start + 2u;
    var lo = 0u;
    var hi = n;
    for (var i = 0u; i < 32u && lo < hi && spend(); i += 1u) {
        let mid = (lo + hi) / 2u;
        if light_cdf[cdf + mid] <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let k = min(lo, n - 1u);
    let size = vec2<f32>(1.0 / f32(gw), 1.0 / f32(gh));
    let corner = vec2<f32>(f32(k % gw) * size.x, f32(k / gw) * size.y);
    return ProjectorCell(corner, size, light_cdf[cdf + n + k]);
}

fn projector_emit(l: Light, u0: vec3<f32>, u3: f32, u4: f32) -> Emission {
    var uv = vec2<f32>(u3, u4);
    var pdf = 1.0;
    if l.emission_texture != NO_TEXTURE {
        let c = projector_cell(l.p0.w, u0.x);
        uv = vec2<f32>(c.corner.x + u3 * c.size.x, c.corner.y + u4 * c.size.y);
        pdf = c.pdf;
    }
    let a = 1.0 - 2.0 * uv.x;
    let b = 1.0 - 2.0 * uv.y;
    let dir = normalize(light_vec(l.p3) + a * light_vec(l.p1) + b * light_vec(l.p2));
    let m = l.texture_mean * pdf;
    let t = area_texel(l, uv);
    return Emission(light_vec(l.p0), dir, vec3<f32>(0.0), select(vec3<f32>(0.0), t / m, m > vec3<f32>(0.0)));
}

fn projector_sample(l: Light, x: vec3<f32>, ns: vec3<f32>, u: vec3<f32>) -> LightSample {
    let p = light_vec(l.p0);
    let to_x = x - p;
    let q = projector_uv(l, to_x);
    var weight = vec3<f32>(0.0);
    if q.inside {
        let e = bitcast<vec3<f32>>(vec3<u32>(l.p1.w, l.p2.w, l.p3.w));
        weight = e * area_texel(l, q.uv) * (PI * length(to_x) / (q.z * q.z * q.z));
    }
    return LightSample(p, weight, false, 0.0);
}

fn projector_anchor(l: Light, u: vec3<f32>) -> Anchor {
    return Anchor(light_vec(l.p0), true);
}

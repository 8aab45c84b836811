// The spot light (twin of src/lights/spot/mod.rs): p0 = (position, falloff code), p1 = (axis,
// cos inner), p2 = (on-axis intensity, cos outer), p3 = (local x axis, 0 without a projected
// texture, 1 with one, 2 with one in a mirrored frame); the texture is the light's
// emission_texture. The falloff and its sampling are the twins of SpotCone's. SPOT_* constants
// come from spot::wgsl_consts. Library, no entry point.

// Some spot light has Mitsuba's falloff, linear in the angle (spot_cos_linear).
override HAS_LINEAR_SPOTS: bool = true;

struct SpotCone {
    cos_inner: f32,
    cos_outer: f32,
    profile: u32,
}

fn spot_cone(l: Light) -> SpotCone {
    return SpotCone(bitcast<f32>(l.p1.w), bitcast<f32>(l.p2.w), l.p0.w);
}

// The spot falloff at cosine cd to the axis (SpotCone::falloff): glTF's reference form,
// quadratic in the cosine, or Mitsuba's, linear in the angle.
fn spot_falloff(c: SpotCone, cd: f32) -> f32 {
    if HAS_LINEAR_SPOTS && c.profile == SPOT_LINEAR_ANGLE {
        let inner = acos(c.cos_inner);
        let outer = acos(c.cos_outer);
        let ramp = clamp((outer - acos(clamp(cd, -1.0, 1.0))) / max(outer - inner, 1e-30), 0.0, 1.0);
        return select(select(0.0, ramp, cd > c.cos_outer), 1.0, cd >= c.cos_inner);
    }
    let scale = 1.0 / max(c.cos_inner - c.cos_outer, SPOT_MIN_RAMP);
    let offset = -c.cos_outer * scale;
    let a = clamp(cd * scale + offset, 0.0, 1.0);
    return a * a;
}

// The linear ramp's mass from the outer edge to x = outer - theta (spot::linear_ramp_mass).
fn spot_linear_mass(outer: f32, x: f32) -> f32 {
    return x * cos(outer - x) - 2.0 * cos(outer - 0.5 * x) * sin(0.5 * x);
}

// A cosine to the spot's axis drawn in proportion to the falloff (SpotCone::sample_cos):
// glTF's ramp holds (a - co)^3 / (3 w^2) of the falloff's integral over the cosine, the flat
// top 1 - a.
fn spot_cos(c: SpotCone, u: f32) -> f32 {
    if HAS_LINEAR_SPOTS && c.profile == SPOT_LINEAR_ANGLE {
        return spot_cos_linear(c, u);
    }
    let co = c.cos_outer;
    let w = max(c.cos_inner - co, SPOT_MIN_RAMP);
    let a = min(co + w, 1.0);
    let ramp = (a - co) * (a - co) * (a - co) / (3.0 * w * w);
    let t = u * (ramp + (1.0 - a));
    var x = a + (t - ramp);
    if t < ramp {
        x = co + select(0.0, pow(3.0 * w * w * t, 1.0 / 3.0), t > 0.0);
    }
    return min(x, 1.0);
}

// spot_cos for Mitsuba's linear ramp: its mass is bisected SPOT_BISECTIONS times.
fn spot_cos_linear(c: SpotCone, u: f32) -> f32 {
    let inner = acos(c.cos_inner);
    let outer = acos(c.cos_outer);
    let ramp = select(0.0, spot_linear_mass(outer, outer - inner) / (outer - inner), outer > inner);
    let t = u * (ramp + (1.0 - c.cos_inner));
    if t >= ramp {
        return min(c.cos_inner + (t - ramp), 1.0);
    }
    let want = t * (outer - inner);
    var lo = 0.0;
    var hi = outer - inner;
    for (var i = 0u; i < SPOT_BISECTIONS; i++) {
        let mid = 0.5 * (lo + hi);
        if spot_linear_mass(outer, mid) < want {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return min(cos(outer - 0.5 * (lo + hi)), 1.0);
}

// The uv of local direction local (z along the axis) for a cone of outer cosine cos_outer
// (spot::spot_uv).
fn spot_uv(local: vec3<f32>, cos_outer: f32) -> vec2<f32> {
    let tan_outer = sqrt(max(1.0 - cos_outer * cos_outer, 0.0)) / cos_outer;
    return vec2<f32>(0.5) + 0.5 * local.xy / (local.z * tan_outer);
}

// The projected texture's texel in unit direction w (Spot::texel; one without a texture).
fn spot_texel(l: Light, w: vec3<f32>) -> vec3<f32> {
    if l.p3.w == 0u {
        return vec3<f32>(1.0);
    }
    let z = light_vec(l.p1);
    let x = light_vec(l.p3);
    let y = cross(z, x) * select(1.0, -1.0, l.p3.w == 2u);
    return area_texel(l, spot_uv(vec3<f32>(dot(w, x), dot(w, y), dot(w, z)), bitcast<f32>(l.p2.w)));
}

// Photons by the falloff: u3 the cosine to the axis, u4 the azimuth; a projecting spot's
// carry their texel over the texture's mean.
fn spot_emit(l: Light, u0: vec3<f32>, u3: f32, u4: f32) -> Emission {
    let c = spot_cos(spot_cone(l), u3);
    let s = sqrt(max(1.0 - c * c, 0.0));
    let phi = 2.0 * PI * u4;
    let dir = to_world(vec3<f32>(s * cos(phi), s * sin(phi), c), light_vec(l.p1));
    var scale = vec3<f32>(1.0);
    if l.p3.w != 0u {
        let m = l.texture_mean;
        scale = select(vec3<f32>(0.0), spot_texel(l, dir) / m, m > vec3<f32>(0.0));
    }
    return Emission(light_vec(l.p0), dir, vec3<f32>(0.0), scale);
}

fn spot_sample(l: Light, x: vec3<f32>, ns: vec3<f32>, u: vec3<f32>) -> LightSample {
    let p = light_vec(l.p0);
    let to_x = x - p;
    let d2 = max(dot(to_x, to_x), 1e-20);
    let w = to_x / sqrt(d2);
    let att = spot_falloff(spot_cone(l), dot(light_vec(l.p1), w));
    let texel = select(vec3<f32>(1.0), spot_texel(l, w), att > 0.0);
    return LightSample(p, light_vec(l.p2) * texel * (att / d2), false, 0.0);
}

fn spot_anchor(l: Light, u: vec3<f32>) -> Anchor {
    return Anchor(light_vec(l.p0), true);
}

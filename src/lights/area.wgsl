// What the area lights share (twin of src/lights/area.rs): photons leaving a point of their
// surface by the cosine (either face of a two-sided emitter), carrying the emission texel over
// the texture's mean, and shadow rays to it. Library, no entry point.

struct SurfacePoint {
    p: vec3<f32>,
    n: vec3<f32>,
    material: u32,
    // The emission texture's value at p (one without a texture; crate::lights::emission).
    texel: vec3<f32>,
}

// The light's emission texture at uv (one without a texture; area::texel).
fn area_texel(l: Light, uv: vec2<f32>) -> vec3<f32> {
    if HAS_TEXTURES && l.emission_texture != NO_TEXTURE {
        return texture_eval(l.emission_texture, uv);
    }
    return vec3<f32>(1.0);
}

fn area_emit(l: Light, sp: SurfacePoint, u3: f32, u4: f32) -> Emission {
    var n = sp.n;
    var v = u3;
    if load_material(sp.material).two_sided != 0u {
        if v >= 0.5 {
            n = -n;
            v = v * 2.0 - 1.0;
        } else {
            v = v * 2.0;
        }
    }
    let scale = select(vec3<f32>(0.0), sp.texel / l.texture_mean, l.texture_mean > vec3<f32>(0.0));
    return Emission(sp.p, cosine_hemisphere(n, v, u4), n, scale);
}

fn area_sample(l: Light, sp: SurfacePoint, x: vec3<f32>) -> LightSample {
    let m = load_material(sp.material);
    let to_x = x - sp.p;
    let d2 = dot(to_x, to_x);
    if d2 <= 0.0 {
        return LightSample(sp.p, vec3<f32>(0.0), false, 0.0);
    }
    var cos_l = dot(sp.n, to_x) / sqrt(d2);
    if m.two_sided != 0u {
        cos_l = abs(cos_l);
    }
    if cos_l <= 0.0 {
        return LightSample(sp.p, vec3<f32>(0.0), false, 0.0);
    }
    return LightSample(sp.p, m.emission * sp.texel * (cos_l * l.area / d2), false, light_solid_angle_pdf(l, x, sp.p, sp.n));
}

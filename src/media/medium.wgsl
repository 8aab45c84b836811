// Participating media (issue 24): twin of src/media/mod.rs (transmittance, free flights, a
// distance in a camera segment), src/media/phase.rs (Henyey-Greenstein) and the medium rules of
// src/integrators/cpu/media.rs (MediumInterface::after at a surface, the medium a light's photons start
// in). Every caller is behind HAS_MEDIA, so scenes without media compile none of it.
// Library, no entry point; writes nothing.

// Medium i from its MEDIUM_WORDS words.
fn load_medium(i: u32) -> Medium {
    let a = media[MEDIUM_WORDS * i];
    let b = media[MEDIUM_WORDS * i + 1u];
    return Medium(a.xyz, a.w, b.xyz, bitcast<u32>(b.w));
}

// MediumInterface::after (Mitsuba's volpath rule): the medium a ray that was in `current` is
// in after a surface with interface `iface` (interior, exterior) and geometric normal `n`
// sent it along `dir`; a surface that bounds no medium leaves `current`.
fn medium_interface_after(iface: vec2<u32>, current: u32, n: vec3<f32>, dir: vec3<f32>) -> u32 {
    if iface.x == NO_MEDIUM && iface.y == NO_MEDIUM {
        return current;
    }
    return select(iface.x, iface.y, dot(dir, n) > 0.0);
}

// cpu::media::medium_after: the medium after the surface of `hit` sent a ray along `dir`.
fn medium_after(hit: Hit, current: u32, dir: vec3<f32>) -> u32 {
    return medium_interface_after(material_media[hit.material], current, hit.normal, dir);
}

// cpu::media::light_medium: an area light's photons start in its shape's medium on the side
// they leave towards; lights without a surface sit in the camera's.
fn light_medium(l: Light, e: Emission) -> u32 {
    let s = light_material(l);
    if !s.ok {
        return params.camera_medium;
    }
    return medium_interface_after(material_media[s.material], params.camera_medium, e.normal, e.dir);
}

// cpu::media::photon_medium: light_medium for an area light whose shape bounds a medium, else
// (a light without a surface, or a shape that bounds none; callers are behind HAS_MEDIA) the
// medium enclosing_medium finds along the photon's ray from o.
fn photon_medium(l: Light, e: Emission, o: vec3<f32>) -> u32 {
    let s = light_material(l);
    if s.ok && any(material_media[s.material] != vec2<u32>(NO_MEDIUM)) {
        return light_medium(l, e);
    }
    return enclosing_medium(o, e.dir);
}

// cpu::media::enclosing_medium: the side of the first surface bounding a medium along the ray
// from o (interior when leaving through its front), past at most MAX_CROSSINGS that bound
// none; the medium outside every shape (Scene::outer_medium) when there is none.
fn enclosing_medium(o_in: vec3<f32>, d: vec3<f32>) -> u32 {
    var o = o_in;
    for (var k = 0u; k < MAX_CROSSINGS && spend(); k += 1u) {
        let hit = trace_ray(o, d, 3.0e38, false);
        if !hit.found {
            break;
        }
        let iface = material_media[hit.material];
        if any(iface != vec2<u32>(NO_MEDIUM)) {
            return select(iface.y, iface.x, dot(d, hit.normal) > 0.0);
        }
        o = offset_origin(hit.position, hit.normal, d);
    }
    return params.outer_medium;
}

// Medium::transmittance: exp(-sigma_t t) per channel; a clear channel transmits everything
// (also over an endless run).
fn medium_transmittance(m: Medium, t: f32) -> vec3<f32> {
    return select(vec3<f32>(1.0), exp(-m.sigma_t * t), m.sigma_t > vec3<f32>(0.0));
}

// Medium::sample_flight's result: the distance, whether it ended in the medium, the weight.
struct Flight {
    t: f32,
    in_medium: bool,
    weight: vec3<f32>,
}

// Medium::sample_flight: one channel chosen by u_channel draws the distance from u; an event
// before the surface t_max away (a miss passes a t_max beyond every flight) is weighed
// sigma_s T(t) / pdf(t), the surface T(t_max) / P(t >= t_max), pdfs the channels' mean.
fn sample_flight(m: Medium, u_channel: f32, u: f32, t_max: f32) -> Flight {
    let c = min(u32(u_channel * 3.0), 2u);
    let sigma = m.sigma_t[c];
    let t = -log(max(1.0 - u, F32_MIN_POSITIVE)) / sigma;
    if sigma > 0.0 && t < t_max {
        let tr = medium_transmittance(m, t);
        let st = m.sigma_t * tr;
        let pdf = (st.x + st.y + st.z) / 3.0;
        return Flight(t, true, select(vec3<f32>(0.0), m.sigma_s * tr / pdf, pdf > 0.0));
    }
    let tr = medium_transmittance(m, t_max);
    let p = (tr.x + tr.y + tr.z) / 3.0;
    return Flight(t_max, false, select(vec3<f32>(0.0), tr / p, p > 0.0));
}

// Medium::transmittance_along, the one dispatch point of a transmittance on the medium's
// kind: over [0, t) of the ray from o along unit d, Beer-Lambert for a homogeneous medium (no
// number drawn), ratio tracking (hetero_transmittance) on rng for a heterogeneous one.
fn medium_transmittance_along(m: Medium, o: vec3<f32>, d: vec3<f32>, t: f32, rng: ptr<function, Rng>) -> vec3<f32> {
    if HAS_HETERO_MEDIA && m.grid != NO_MEDIUM {
        return hetero_transmittance(hetero_record(m), o, d, t, rng);
    }
    return medium_transmittance(m, t);
}

// Medium::flight, the one dispatch point of a free flight on the medium's kind: from o along
// unit d towards a surface t_max away, sample_flight from two numbers for a homogeneous
// medium, delta tracking (hetero_sample_flight, src/media/heterogeneous.wgsl) for a
// heterogeneous one; either draws from rng as the CPU does.
fn medium_flight(m: Medium, o: vec3<f32>, d: vec3<f32>, t_max: f32, rng: ptr<function, Rng>) -> Flight {
    if HAS_HETERO_MEDIA && m.grid != NO_MEDIUM {
        return hetero_sample_flight(hetero_record(m), o, d, t_max, rng);
    }
    let uc = rng_next(rng);
    let u = rng_next(rng);
    return sample_flight(m, uc, u, t_max);
}

// HenyeyGreenstein::eval: the density per steradian at cosine `c` between the travel
// directions before and after scattering (the floor on the denominator as in phase.rs).
fn hg_eval(g: f32, c: f32) -> f32 {
    let denom = max(1.0 + g * g - 2.0 * g * c, 1e-12);
    return (1.0 - g * g) / (4.0 * PI * denom * sqrt(denom));
}

// HenyeyGreenstein::sample_cos: the inverse CDF (isotropic below HG_ISOTROPIC_BELOW).
fn hg_sample_cos(g: f32, u: f32) -> f32 {
    if abs(g) < HG_ISOTROPIC_BELOW {
        return 1.0 - 2.0 * u;
    }
    let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
    return clamp((1.0 + g * g - s * s) / (2.0 * g), -1.0, 1.0);
}

// HenyeyGreenstein::sample: a direction to leave in after travelling along unit `dir`.
fn hg_sample(g: f32, dir: vec3<f32>, u1: f32, u2: f32) -> vec3<f32> {
    let c = hg_sample_cos(g, u1);
    let s = sqrt(max(1.0 - c * c, 0.0));
    let phi = 2.0 * PI * u2;
    return to_world(vec3<f32>(s * cos(phi), s * sin(phi), c), dir);
}

// Light emission (photon origins and directions) and shadow-ray targets on point, spot,
// directional, triangle and sphere lights and the environment (environment.wgsl); twin of
// src/lights/mod.rs (spot falloff: twin of src/lights/spot.rs). LIGHT_* kinds and SPOT_MIN_RAMP come from the generated prelude.
// Library, no entry point; writes nothing.

// Point, spot and directional lights: no surface, one shadow ray each, every BRDF lobe.
// (HAS_POINT_LIGHTS is set when the scene has any of them.)
fn is_delta_light(l: Light) -> bool {
    return HAS_POINT_LIGHTS && (l.kind == LIGHT_POINT || l.kind == LIGHT_SPOT || l.kind == LIGHT_DIRECTIONAL);
}

// The spot falloff at cosine cd to the axis (SpotCone::falloff): glTF's reference form,
// quadratic in the cosine, or Mitsuba's, linear in the angle.
fn spot_falloff(l: Light, cd: f32) -> f32 {
    if HAS_LINEAR_SPOTS && l.spot_profile == SPOT_LINEAR_ANGLE {
        let inner = acos(l.cos_inner);
        let outer = acos(l.cos_outer);
        let ramp = clamp((outer - acos(clamp(cd, -1.0, 1.0))) / max(outer - inner, 1e-30), 0.0, 1.0);
        return select(select(0.0, ramp, cd > l.cos_outer), 1.0, cd >= l.cos_inner);
    }
    let scale = 1.0 / max(l.cos_inner - l.cos_outer, SPOT_MIN_RAMP);
    let offset = -l.cos_outer * scale;
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
fn spot_cos(l: Light, u: f32) -> f32 {
    if HAS_LINEAR_SPOTS && l.spot_profile == SPOT_LINEAR_ANGLE {
        return spot_cos_linear(l, u);
    }
    let co = l.cos_outer;
    let w = max(l.cos_inner - co, SPOT_MIN_RAMP);
    let a = min(co + w, 1.0);
    let ramp = (a - co) * (a - co) * (a - co) / (3.0 * w * w);
    let t = u * (ramp + (1.0 - a));
    var c = a + (t - ramp);
    if t < ramp {
        c = co + select(0.0, pow(3.0 * w * w * t, 1.0 / 3.0), t > 0.0);
    }
    return min(c, 1.0);
}

// spot_cos for Mitsuba's linear ramp: its mass is bisected SPOT_BISECTIONS times.
fn spot_cos_linear(l: Light, u: f32) -> f32 {
    let inner = acos(l.cos_inner);
    let outer = acos(l.cos_outer);
    let ramp = select(0.0, spot_linear_mass(outer, outer - inner) / (outer - inner), outer > inner);
    let t = u * (ramp + (1.0 - l.cos_inner));
    if t >= ramp {
        return min(l.cos_inner + (t - ramp), 1.0);
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

struct SurfacePoint {
    p: vec3<f32>,
    n: vec3<f32>,
    material: u32,
    // The emission texture's value at p (one without a texture; crate::scene::emission).
    texel: vec3<f32>,
}

// The light that owns photon path i of the global map (or the caustic map): the last light
// whose budget offset is at most i, by binary search over the offsets (word 4 of a Light:
// area, global offset, count, caustic offset), bounded by 32 steps; twin of Budget::light_of.
// The lights' ranges are consecutive, so below the total it is the light whose range holds i
// (one without paths shares the next one's offset).
fn light_of(i: u32, caustic_map: bool) -> u32 {
    var lo = 0u;
    var hi = params.n_lights;
    for (var step = 0u; step < 32u && lo < hi && spend(); step += 1u) {
        let mid = (lo + hi) / 2u;
        let words = lights[LIGHT_WORDS * mid + 4u];
        if select(words.y, words.w, caustic_map) <= i {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return max(lo, 1u) - 1u;
}

// Triangle of light l by area: binary search of its CDF (bounded by 32 steps).
fn pick_triangle(l: Light, u: f32) -> u32 {
    var lo = 0u;
    var hi = l.count;
    for (var i = 0u; i < 32u && lo < hi && spend(); i += 1u) {
        let mid = (lo + hi) / 2u;
        if light_cdf[l.cdf_start + mid] <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return l.first + min(lo, l.count - 1u);
}

fn light_point(l: Light, u: vec3<f32>) -> SurfacePoint {
    var sp: SurfacePoint;
    sp.texel = vec3<f32>(1.0);
    let textured = HAS_TEXTURES && l.emission_texture != NO_TEXTURE;
    if HAS_POINT_LIGHTS && l.kind == LIGHT_POINT {
        sp.p = l.position;
        sp.n = vec3<f32>(0.0);
        sp.material = 0u;
    } else if HAS_SPHERES && l.kind == LIGHT_SPHERE {
        let s = load_sphere(l.first);
        let n = uniform_sphere(u.y, u.z);
        sp.p = s.center + s.radius * n;
        sp.n = n;
        sp.material = s.material;
        if textured {
            sp.texel = texture_eval(l.emission_texture, sphere_uv(n));
        }
    } else {
        let t = pick_triangle(l, u.x);
        let tri = load_triangle(t);
        let s = sqrt(u.y);
        let b1 = 1.0 - s;
        let b2 = u.z * s;
        let e1 = tri.v1 - tri.v0;
        let e2 = tri.v2 - tri.v0;
        sp.p = tri.v0 + b1 * e1 + b2 * e2;
        sp.n = normalize(cross(e1, e2));
        sp.material = tri.material;
        if textured {
            sp.texel = texture_eval(l.emission_texture, triangle_uv(t, vec2<f32>(b1, b2)));
        }
    }
    return sp;
}

struct Emission {
    origin: vec3<f32>,
    dir: vec3<f32>,
    normal: vec3<f32>,
    // Factor on the photon's power: a textured emitter's texel over its mean (else one).
    scale: vec3<f32>,
}

// A uniform point of the disc of radius l.radius across unit direction d (LightTable::disc).
fn light_disc(l: Light, d: vec3<f32>, u1: f32, u2: f32) -> vec3<f32> {
    let rho = l.radius * sqrt(u1);
    let phi = 2.0 * PI * u2;
    return rho * (cos(phi) * basis_t(d) + sin(phi) * basis_b(d));
}

fn emit(l: Light, u0: vec3<f32>, u3: f32, u4: f32) -> Emission {
    var e: Emission;
    e.scale = vec3<f32>(1.0);
    if HAS_ENVIRONMENT && l.kind == LIGHT_ENVIRONMENT {
        // From the disc two radii out towards w; an image's photon carries
        // L pi R^2 / (pdf power), texture_mean holding power / (pi R^2).
        let s = env_emit_dir(l, vec3<f32>(u0.x, u3, u4));
        e.origin = l.position + 2.0 * l.radius * s.dir + light_disc(l, -s.dir, u0.y, u0.z);
        e.normal = vec3<f32>(0.0);
        e.dir = -s.dir;
        if env_is_map(l) {
            let tm = l.texture_mean * s.pdf;
            e.scale = select(vec3<f32>(0.0), env_radiance(l, s.dir) / tm, tm > vec3<f32>(0.0));
        }
        return e;
    }
    if HAS_POINT_LIGHTS && l.kind == LIGHT_SPOT {
        let c = spot_cos(l, u3);
        let s = sqrt(max(1.0 - c * c, 0.0));
        let phi = 2.0 * PI * u4;
        e.origin = l.position;
        e.normal = vec3<f32>(0.0);
        e.dir = to_world(vec3<f32>(s * cos(phi), s * sin(phi), c), l.direction);
        return e;
    }
    if HAS_POINT_LIGHTS && l.kind == LIGHT_DIRECTIONAL {
        // A uniform point of the disc of radius l.radius, two radii back from the centre.
        e.origin = l.position - 2.0 * l.radius * l.direction + light_disc(l, l.direction, u0.y, u0.z);
        e.normal = vec3<f32>(0.0);
        e.dir = l.direction;
        return e;
    }
    let sp = light_point(l, u0);
    e.origin = sp.p;
    e.normal = sp.n;
    if HAS_POINT_LIGHTS && l.kind == LIGHT_POINT {
        e.dir = uniform_sphere(u3, u4);
        return e;
    }
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
    e.normal = n;
    e.dir = cosine_hemisphere(n, v, u4);
    e.scale = select(vec3<f32>(0.0), sp.texel / l.texture_mean, l.texture_mean > vec3<f32>(0.0));
    return e;
}

// A shadow-ray target: `distant` for a directional light, whose point is one unit from x
// towards the light and whose shadow ray has no end; `pdf` the solid-angle density of an area
// light's point (0 for the delta lights).
struct LightSample {
    point: vec3<f32>,
    weight: vec3<f32>,
    distant: bool,
    pdf: f32,
}

// The solid-angle density with which sample_light picks point p (normal n) of area light l
// seen from x (twin of LightTable::solid_angle_pdf).
fn light_solid_angle_pdf(l: Light, x: vec3<f32>, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let to_x = x - p;
    let d2 = dot(to_x, to_x);
    let cos_l = abs(dot(n, to_x)) / sqrt(d2);
    if cos_l > 0.0 && l.area > 0.0 {
        return d2 / (cos_l * l.area);
    }
    return 0.0;
}

// ns: the shading normal at x (the constant environment samples a cosine about it).
fn sample_light(l: Light, x: vec3<f32>, ns: vec3<f32>, u: vec3<f32>) -> LightSample {
    if HAS_ENVIRONMENT && l.kind == LIGHT_ENVIRONMENT {
        let s = env_sample(l, ns, u);
        if s.pdf <= 0.0 {
            return LightSample(x + s.dir, vec3<f32>(0.0), true, 0.0);
        }
        return LightSample(x + s.dir, env_radiance(l, s.dir) / s.pdf, true, s.pdf);
    }
    if HAS_POINT_LIGHTS && l.kind == LIGHT_POINT {
        let d = l.position - x;
        return LightSample(l.position, l.intensity / max(dot(d, d), 1e-20), false, 0.0);
    }
    if HAS_POINT_LIGHTS && l.kind == LIGHT_SPOT {
        let to_x = x - l.position;
        let d2 = max(dot(to_x, to_x), 1e-20);
        let att = spot_falloff(l, dot(l.direction, to_x) / sqrt(d2));
        return LightSample(l.position, l.intensity * (att / d2), false, 0.0);
    }
    if HAS_POINT_LIGHTS && l.kind == LIGHT_DIRECTIONAL {
        return LightSample(x - l.direction, l.intensity, true, 0.0);
    }
    let sp = light_point(l, u);
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

fn aims_at(o: vec3<f32>, d: vec3<f32>) -> bool {
    let inv = 1.0 / d;
    for (var i = 0u; i < params.n_bounds && spend(); i += 1u) {
        let b = spec_bounds[i];
        if hit_box(b.bmin, b.bmax, o, inv, 3.0e38) {
            return true;
        }
    }
    return false;
}

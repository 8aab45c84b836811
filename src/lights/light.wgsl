// What every light kind shares (twin of src/lights/interface.rs and table.rs): the photon
// (Emission) and shadow-ray target (LightSample) a kind returns, the light that owns a photon
// path, the distant lights' disc, an area light's solid-angle density, the aim at the caustic
// map's bounds, and the defaults of the generated dispatch (lights::gpu). Each kind's own code
// is in its file (point/point.wgsl, triangles.wgsl, ...). Library, no entry point.

// A light's parameter word as a vector (its first three words' bits).
fn light_vec(w: vec4<u32>) -> vec3<f32> {
    return bitcast<vec3<f32>>(w.xyz);
}

struct Emission {
    origin: vec3<f32>,
    dir: vec3<f32>,
    normal: vec3<f32>,
    // Factor on the photon's power: a textured emitter's texel over its mean (else one).
    scale: vec3<f32>,
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

// LightTable::anchor: the point sample_light picks on a light for u whatever the shading
// point (a delta light's position, an area light's point by area); not ok for distant
// lights (directional, environment).
struct Anchor {
    y: vec3<f32>,
    ok: bool,
}

// The material of an area light's surface (ok false for the other kinds).
struct LightSurface {
    material: u32,
    ok: bool,
}

// The light that owns photon path i of the global map (or the caustic map): the last light
// whose budget offset is at most i, by binary search over the offsets (word 0 of a Light:
// kind, global offset, global count, caustic offset), bounded by 32 steps; twin of
// Budget::light_of. The lights' ranges are consecutive, so below the total it is the light
// whose range holds i (one without paths shares the next one's offset).
fn light_of(i: u32, caustic_map: bool) -> u32 {
    var lo = 0u;
    var hi = params.n_lights;
    for (var step = 0u; step < 32u && lo < hi && spend(); step += 1u) {
        let mid = (lo + hi) / 2u;
        let words = lights[LIGHT_WORDS * mid];
        if select(words.y, words.w, caustic_map) <= i {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return max(lo, 1u) - 1u;
}

// A uniform point of the disc of radius r across unit direction d (LightContext::disc).
fn light_disc(r: f32, d: vec3<f32>, u1: f32, u2: f32) -> vec3<f32> {
    let rho = r * sqrt(u1);
    let phi = 2.0 * PI * u2;
    return rho * (cos(phi) * basis_t(d) + sin(phi) * basis_b(d));
}

// The solid-angle density with which sample_light picks point p (normal n) of area light l
// seen from x (twin of area::solid_angle_pdf).
fn light_solid_angle_pdf(l: Light, x: vec3<f32>, p: vec3<f32>, n: vec3<f32>) -> f32 {
    let to_x = x - p;
    let d2 = dot(to_x, to_x);
    let cos_l = abs(dot(n, to_x)) / sqrt(d2);
    if cos_l > 0.0 && l.area > 0.0 {
        return d2 / (cos_l * l.area);
    }
    return 0.0;
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

// The defaults of the dispatch: a kind compiled out (or none) emits and lights nothing.
fn light_default_emit(l: Light, u0: vec3<f32>, u3: f32, u4: f32) -> Emission {
    return Emission(vec3<f32>(0.0), vec3<f32>(0.0, 0.0, 1.0), vec3<f32>(0.0), vec3<f32>(0.0));
}

fn light_default_sample(l: Light, x: vec3<f32>, ns: vec3<f32>, u: vec3<f32>) -> LightSample {
    return LightSample(x, vec3<f32>(0.0), false, 0.0);
}

fn light_default_anchor(l: Light, u: vec3<f32>) -> Anchor {
    return Anchor(vec3<f32>(0.0), false);
}

fn light_default_material(l: Light) -> LightSurface {
    return LightSurface(0u, false);
}

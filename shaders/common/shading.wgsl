// The one shading interface between the kernels' integrators and the material kinds, twin of
// src/shading.rs: bsdf_at(hit) is the only code that reads a material for them; the class
// (material_class, generated from Rust), emission, delta event, diffuse part, lobe and
// escape(dir) are asked of it. Library, no entry point; writes nothing.

// The BSDF at a hit, parameters resolved.
fn bsdf_at(hit: Hit) -> Material {
    return load_material(hit.material);
}

// CLASS_BLACK, CLASS_DELTA or CLASS_SHADED (shading::SurfaceClass).
fn bsdf_class(b: Material) -> u32 {
    return material_class(b.kind);
}

// Radiance emitted towards a ray arriving from the front (or the back).
fn bsdf_emitted(b: Material, front: bool) -> vec3<f32> {
    return select(vec3<f32>(0.0), b.emission, front || b.two_sided != 0u);
}

// The diffuse part's albedo: photon estimates and gather rays weigh light by it / pi.
fn bsdf_diffuse_albedo(b: Material) -> vec3<f32> {
    return b.kd;
}

// The diffuse part's BSDF value.
fn bsdf_eval_diffuse(b: Material) -> vec3<f32> {
    return b.kd / PI;
}

// A non-delta lobe the camera path and gather rays trace.
fn bsdf_has_lobe(b: Material) -> bool {
    return b.kind == MAT_GLOSSY && max3(b.ks) > 0.0;
}

// Whether delta lights light the lobe through shadow rays without TERM_DIRECT.
fn bsdf_lobe_takes_point_lights(b: Material) -> bool {
    return b.kind == MAT_GLOSSY;
}

// The lobe part's value about the shading normal ns.
fn bsdf_eval_lobe(b: Material, wi: vec3<f32>, wo: vec3<f32>, ns: vec3<f32>) -> vec3<f32> {
    if b.kind != MAT_GLOSSY {
        return vec3<f32>(0.0);
    }
    return b.ks * phong_lobe_value(wi, wo, ns, b.exponent);
}

// The solid-angle density with which bsdf_sample_lobe draws wi (0 for a delta lobe).
fn bsdf_pdf_lobe(b: Material, wi: vec3<f32>, wo: vec3<f32>, ns: vec3<f32>) -> f32 {
    if b.kind != MAT_GLOSSY {
        return 0.0;
    }
    let cos_a = dot(reflect_dir(-wo, ns), wi);
    if cos_a <= 0.0 {
        return 0.0;
    }
    return (b.exponent + 1.0) / (2.0 * PI) * pow(cos_a, b.exponent);
}

// A glossy (not delta) lobe: light sampling and lobe sampling share area lights by multiple
// importance sampling.
fn bsdf_lobe_is_glossy(b: Material) -> bool {
    return bsdf_has_lobe(b);
}

// The power heuristic's weight of a strategy of density a against one of density b.
fn power_heuristic(a: f32, b: f32) -> f32 {
    let a2 = a * a;
    let b2 = b * b;
    return select(0.0, a2 / (a2 + b2), a2 + b2 > 0.0);
}

// One ray from the lobe about the mirror direction of d (towards the surface), normals f
// facing -d: direction, weight f cos / pdf and pdf; not ok below the shading or geometric
// surface.
struct LobeRay {
    dir: vec3<f32>,
    weight: vec3<f32>,
    ok: bool,
    pdf: f32,
}

fn bsdf_sample_lobe(b: Material, d: vec3<f32>, f: Facing, rng: ptr<function, Rng>) -> LobeRay {
    let u1 = rng_next(rng);
    let u2 = rng_next(rng);
    let dir = phong_lobe(reflect_dir(d, f.ns), b.exponent, u1, u2);
    let c = dot(dir, f.ns);
    let ok = c > 0.0 && !reflection_leaks(f, dir);
    return LobeRay(dir, b.ks * ((b.exponent + 2.0) / (b.exponent + 1.0) * c), ok, bsdf_pdf_lobe(b, dir, -d, f.ns));
}

// Whether photons are stored here (a diffuse part).
fn bsdf_stores_photons(b: Material) -> bool {
    return b.kind == MAT_DIFFUSE || b.kind == MAT_GLOSSY;
}

// One delta bounce of a ray along *d at `hit`: the mirror reflects about the shading normal
// facing the ray and scales *t by ks; glass takes one rng draw to choose the reflected
// (u < Fresnel reflectance) or refracted branch. *o becomes the offset origin of the new ray.
// False when the new direction leaks through the geometric surface.
fn bsdf_delta(hit: Hit, b: Material, d: ptr<function, vec3<f32>>, o: ptr<function, vec3<f32>>, t: ptr<function, vec3<f32>>, rng: ptr<function, Rng>) -> bool {
    let f = facing(hit, dot(*d, hit.normal) < 0.0);
    var leaks = false;
    if b.kind == MAT_MIRROR || !HAS_GLASS {
        *t *= b.ks;
        *d = reflect_dir(*d, f.ns);
        leaks = reflection_leaks(f, *d);
    } else {
        let g = dielectric(*d, hit.normal, hit.shading, b.ior);
        let u = rng_next(rng);
        let reflects = u < g.reflectance;
        *d = select(g.refracted, g.reflected, reflects);
        leaks = select(refraction_leaks(f, *d), reflection_leaks(f, *d), reflects);
    }
    *o = offset_origin(hit.position, hit.normal, *d);
    return !leaks;
}

// Radiance along a ray that leaves the scene: none (no environment light).
fn escape(d: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(0.0);
}

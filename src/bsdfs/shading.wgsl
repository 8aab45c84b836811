// The one shading interface between the kernels' integrators and the material kinds, twin of
// src/bsdfs/shading.rs: bsdf_at(hit) is the only code that reads a material (and its texture) for
// them; its class (material_class, generated from Rust), emission, delta event, diffuse part,
// lobe, photon bounce and escape(dir) are asked of the Surface it returns. Library, no entry
// point; writes nothing. The kinds of crate::bsdf go through bsdf.wgsl in the local frame.

// The BSDF at a hit: the material, kd with its texture looked up, the front shading normal
// (the local frame's z) and, for crate::bsdf's kinds, their parameters.
struct Surface {
    m: Material,
    kd: vec3<f32>,
    n: vec3<f32>,
    b: BsdfParams,
    // The emitted radiance, with the emitter's texture looked up.
    emission: vec3<f32>,
}

fn bsdf_at(hit: Hit) -> Surface {
    var s: Surface;
    s.m = load_material(hit.material);
    s.kd = s.m.kd;
    if HAS_TEXTURES && s.m.kd_texture != NO_TEXTURE {
        s.kd = texture_eval(s.m.kd_texture, hit.uv);
    }
    s.n = hit.shading;
    s.emission = s.m.emission;
    if HAS_TEXTURES && hit.light != NO_LIGHT {
        // An emitter's texture is its light's (one material per light).
        let t = lights[LIGHT_WORDS * hit.light + 6u].w;
        if t != NO_TEXTURE {
            s.emission *= texture_eval(t, hit.uv);
        }
    }
    if HAS_BSDFS && s.m.bsdf != NO_BSDF {
        s.b = bsdfs[s.m.bsdf];
        // A plastic's base reflectance is its kd (Plastic::with_diffuse).
        if HAS_TEXTURES && s.m.kd_texture != NO_TEXTURE && bsdf_is_plastic(s.b) {
            s.b.albedo = s.kd;
            let d_mean = (s.kd.x + s.kd.y + s.kd.z) / 3.0;
            let s_mean = (s.b.specular.x + s.b.specular.y + s.b.specular.z) / 3.0;
            s.b.specular_sampling_weight = s_mean / (d_mean + s_mean);
        }
        // glTF: the base colour is kd; the metallic-roughness texture's blue scales the
        // metalness, its green the roughness.
        if s.b.kind == BSDF_GLTF {
            if HAS_TEXTURES && s.m.kd_texture != NO_TEXTURE {
                s.b.albedo = s.kd;
            }
            if HAS_TEXTURES {
                s.b = gltf_textures(s.b, hit.uv);
            }
        }
    }
    return s;
}

// glTF's parameter textures at uv (twin of shading.rs's gltf_textures): metalness and
// roughness, transmission, the F0 colour, then the specular factor.
fn gltf_textures(b_in: BsdfParams, uv: vec2<f32>) -> BsdfParams {
    var b = b_in;
    if b.textures.x != NO_TEXTURE {
        let c = texture_eval(b.textures.x, uv);
        b.eta_c.x *= c.z;
        b.eta_c.y *= c.y;
    }
    if b.textures.y != NO_TEXTURE {
        b.eta_c.z *= texture_eval(b.textures.y, uv).x;
    }
    if b.textures.w != NO_TEXTURE {
        b.specular = min(b.specular * texture_eval(b.textures.w, uv), vec3<f32>(b.eta));
    }
    if b.textures.z != NO_TEXTURE {
        let a = texture_alpha(b.textures.z, uv);
        b.specular *= a;
        b.eta *= a;
    }
    return b;
}

// Whether the surface is one of crate::bsdf's kinds (Material.bsdf set).
fn surface_is_bsdf(s: Surface) -> bool {
    return HAS_BSDFS && s.m.bsdf != NO_BSDF;
}

fn surface_local(s: Surface, w: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(w, basis_t(s.n)), dot(w, basis_b(s.n)), dot(w, s.n));
}

// CLASS_BLACK, CLASS_DELTA or CLASS_SHADED (shading::SurfaceClass).
fn surface_class(s: Surface) -> u32 {
    return material_class(s.m.kind);
}

// Radiance emitted towards a ray arriving from the front (or the back).
fn surface_emitted(s: Surface, front: bool) -> vec3<f32> {
    return select(vec3<f32>(0.0), s.emission, front || s.m.two_sided != 0u);
}

// The diffuse part's albedo towards wo: photon estimates weigh light by it / pi, gather rays
// by it times surface_store_weight of their direction.
fn surface_diffuse_albedo(s: Surface, wo: vec3<f32>) -> vec3<f32> {
    if surface_is_bsdf(s) {
        return bsdf_diffuse_out(s.b, surface_local(s, wo));
    }
    return s.kd;
}

// The diffuse part's factor for light arriving from wi (a stored photon's power factor).
fn surface_store_weight(s: Surface, wi: vec3<f32>) -> f32 {
    if surface_is_bsdf(s) {
        return bsdf_store_weight(s.b, surface_local(s, wi));
    }
    return 1.0;
}

// The diffuse part's BSDF value f_D(wi, wo).
fn surface_eval_diffuse(s: Surface, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if surface_is_bsdf(s) {
        let li = surface_local(s, wi);
        let lo = surface_local(s, wo);
        if li.z * lo.z <= 0.0 {
            return vec3<f32>(0.0);
        }
        return bsdf_diffuse_out(s.b, lo) * (bsdf_store_weight(s.b, li) / PI);
    }
    return s.kd / PI;
}

// The constant BRDF a photon estimate seen from wo weighs its photons by.
fn surface_estimate_brdf(s: Surface, wo: vec3<f32>) -> vec3<f32> {
    if surface_is_bsdf(s) {
        return surface_diffuse_albedo(s, wo) / PI;
    }
    return s.kd / PI;
}

// A lobe the camera path and gather rays trace (delta or glossy).
fn surface_has_lobe(s: Surface) -> bool {
    if s.m.kind == MAT_GLOSSY {
        return max3(s.m.ks) > 0.0;
    }
    return s.m.kind != MAT_DIFFUSE && s.m.kind != MAT_BLACK;
}

// Whether delta lights light the lobe through shadow rays without TERM_DIRECT.
fn surface_lobe_takes_point_lights(s: Surface) -> bool {
    let k = s.m.kind;
    return k == MAT_GLOSSY || k == MAT_ROUGH_CONDUCTOR || k == MAT_ROUGH_DIELECTRIC || k == MAT_ROUGH_PLASTIC
        || k == MAT_METALLIC_ROUGHNESS;
}

// The lobe part's value about the shading normal ns.
fn surface_eval_lobe(s: Surface, wi: vec3<f32>, wo: vec3<f32>, ns: vec3<f32>) -> vec3<f32> {
    if s.m.kind == MAT_GLOSSY {
        return s.m.ks * phong_lobe_value(wi, wo, ns, s.m.exponent);
    }
    if surface_is_bsdf(s) {
        return bsdf_eval_lobe(s.b, surface_local(s, wi), surface_local(s, wo), true);
    }
    return vec3<f32>(0.0);
}

// The solid-angle density with which surface_sample_lobe draws wi (0 for a delta lobe).
fn surface_pdf_lobe(s: Surface, wi: vec3<f32>, wo: vec3<f32>, ns: vec3<f32>) -> f32 {
    if s.m.kind == MAT_GLOSSY {
        let cos_a = dot(reflect_dir(-wo, ns), wi);
        if cos_a <= 0.0 {
            return 0.0;
        }
        return (s.m.exponent + 1.0) / (2.0 * PI) * pow(cos_a, s.m.exponent);
    }
    if surface_is_bsdf(s) {
        return bsdf_pdf_lobe(s.b, surface_local(s, wi), surface_local(s, wo));
    }
    return 0.0;
}

// A glossy (not delta) lobe: light sampling and lobe sampling share area lights by multiple
// importance sampling.
fn surface_lobe_is_glossy(s: Surface) -> bool {
    if s.m.kind == MAT_GLOSSY {
        return surface_has_lobe(s);
    }
    return surface_is_bsdf(s) && bsdf_has_lobe(s.b) && !bsdf_lobe_is_delta(s.b);
}

// The power heuristic's weight of a strategy of density a against one of density b.
fn power_heuristic(a: f32, b: f32) -> f32 {
    let a2 = a * a;
    let b2 = b * b;
    return select(0.0, a2 / (a2 + b2), a2 + b2 > 0.0);
}

// One ray from the lobe for a path along d (towards the surface), normals f facing -d:
// direction, weight f cos / pdf and pdf (0 for a delta lobe); not ok below the shading or the
// geometric surface (or across it for a reflection).
struct LobeRay {
    dir: vec3<f32>,
    weight: vec3<f32>,
    ok: bool,
    pdf: f32,
}

// A local sample direction in world space; not ok when it leaks through the geometric
// surface (a reflection below it, a transmission above it) or carries nothing.
fn surface_world_ray(s: Surface, ls: LobeSampleW, f: Facing) -> LobeRay {
    let dir = normalize(to_world(ls.wi, s.n));
    let reflects = dot(dir, f.ns) > 0.0;
    var leaks = false;
    if reflects {
        leaks = reflection_leaks(f, dir) || dot(dir, f.ng) <= 0.0;
    } else {
        leaks = refraction_leaks(f, dir) || dot(dir, f.ng) >= 0.0;
    }
    return LobeRay(dir, ls.weight, ls.ok && !leaks && max3(ls.weight) > 0.0, ls.pdf);
}

// The Phong lobe takes two numbers from rng, crate::bsdf's kinds three.
fn surface_sample_lobe(s: Surface, d: vec3<f32>, f: Facing, rng: ptr<function, Rng>) -> LobeRay {
    if surface_is_bsdf(s) {
        let u = vec3<f32>(rng_next(rng), rng_next(rng), rng_next(rng));
        return surface_world_ray(s, bsdf_sample_lobe(s.b, surface_local(s, -d), u, true), f);
    }
    let m = s.m;
    let u1 = rng_next(rng);
    let u2 = rng_next(rng);
    let dir = phong_lobe(reflect_dir(d, f.ns), m.exponent, u1, u2);
    let c = dot(dir, f.ns);
    let ok = c > 0.0 && !reflection_leaks(f, dir);
    return LobeRay(dir, m.ks * ((m.exponent + 2.0) / (m.exponent + 1.0) * c), ok, surface_pdf_lobe(s, dir, -d, f.ns));
}

// Whether photons are stored here (a diffuse part).
fn surface_stores_photons(s: Surface) -> bool {
    let k = s.m.kind;
    if HAS_BSDFS && k == MAT_METALLIC_ROUGHNESS {
        // Material::stores_photons: a texture may leave some base diffuse, else the factors.
        let b = bsdfs[s.m.bsdf];
        return b.textures.x != NO_TEXTURE || b.textures.y != NO_TEXTURE || gltf_has_diffuse(b);
    }
    return k == MAT_DIFFUSE || k == MAT_GLOSSY || k == MAT_PLASTIC || k == MAT_ROUGH_PLASTIC;
}

// One delta bounce of a ray along *d at `hit`: a mirror or smooth conductor reflects about the
// shading normal facing the ray and scales *t; glass and the thin dielectric take one rng draw
// to choose reflection (u < reflectance) or transmission. *o becomes the offset origin of the
// new ray. False when the new direction leaks through the geometric surface.
fn surface_delta(hit: Hit, s: Surface, d: ptr<function, vec3<f32>>, o: ptr<function, vec3<f32>>, t: ptr<function, vec3<f32>>, rng: ptr<function, Rng>) -> bool {
    let f = facing(hit, dot(*d, hit.normal) < 0.0);
    let m = s.m;
    var leaks = false;
    if m.kind == MAT_MIRROR || (!HAS_GLASS && !HAS_BSDFS) {
        *t *= m.ks;
        *d = reflect_dir(*d, f.ns);
        leaks = reflection_leaks(f, *d);
    } else if HAS_BSDFS && m.kind == MAT_CONDUCTOR {
        let ls = bsdf_sample_lobe(s.b, surface_local(s, -*d), vec3<f32>(0.0), true);
        *t *= select(vec3<f32>(0.0), ls.weight, ls.ok);
        *d = reflect_dir(*d, f.ns);
        leaks = reflection_leaks(f, *d);
    } else if HAS_BSDFS && m.kind == MAT_THIN_DIELECTRIC {
        let r = fresnel_dielectric_mi(abs(dot(*d, f.ns)), s.b.eta).f;
        let reflectance = select(1.0, 2.0 * r / (1.0 + r), r < 1.0);
        let reflects = rng_next(rng) < reflectance;
        if reflects {
            *d = reflect_dir(*d, f.ns);
        }
        leaks = select(refraction_leaks(f, *d), reflection_leaks(f, *d), reflects);
    } else {
        let g = dielectric(*d, hit.normal, hit.shading, m.ior);
        let u = rng_next(rng);
        let reflects = u < g.reflectance;
        *d = select(g.refracted, g.reflected, reflects);
        leaks = select(refraction_leaks(f, *d), reflection_leaks(f, *d), reflects);
    }
    *o = offset_origin(hit.position, hit.normal, *d);
    return !leaks;
}

// Russian roulette for a photon along d at `hit` (three uniforms u), twin of
// SurfaceBsdf::photon_bounce: the Phong, mirror and glass kinds in material.wgsl; crate::bsdf's
// kinds sample their BSDF without roulette, a kind with both parts picking its lobe with
// bsdf_lobe_probability (u.x), then the lobe or a cosine diffuse direction.
fn surface_photon_bounce(s: Surface, d: vec3<f32>, hit: Hit, u: vec3<f32>) -> Bounce {
    if !surface_is_bsdf(s) {
        // The textured albedo at the hit.
        var m = s.m;
        m.kd = s.kd;
        return photon_bounce(m, d, hit, u);
    }
    var out = Bounce(vec3<f32>(0.0), BOUNCE_ABSORB, vec3<f32>(0.0));
    let f = facing(hit, dot(d, hit.normal) < 0.0);
    let wo = surface_local(s, -d);
    var ls: LobeSampleW;
    if bsdf_has_diffuse(s.b) {
        let p = bsdf_lobe_probability(s.b, wo);
        if u.x >= p {
            let dir = cosine_hemisphere(f.ns, u.y, u.z);
            if reflection_leaks(f, dir) {
                return out;
            }
            out.kind = BOUNCE_DIFFUSE;
            out.dir = dir;
            out.weight = bsdf_diffuse_out(s.b, wo) * (bsdf_store_weight(s.b, surface_local(s, dir)) / (1.0 - p));
            return out;
        }
        ls = bsdf_sample_lobe(s.b, wo, vec3<f32>(u.x / p, u.y, u.z), false);
        ls.weight = ls.weight / p;
    } else {
        ls = bsdf_sample_lobe(s.b, wo, u, false);
    }
    let r = surface_world_ray(s, ls, f);
    if r.ok {
        out.kind = select(BOUNCE_LOBE, BOUNCE_DELTA, ls.delta);
        out.dir = r.dir;
        out.weight = r.weight;
    }
    return out;
}

// Radiance along a ray that leaves the scene: the environment's, the last light (none
// without one).
fn escape(d: vec3<f32>) -> vec3<f32> {
    if HAS_ENVIRONMENT {
        return env_radiance(load_light(params.n_lights - 1u), d);
    }
    return vec3<f32>(0.0);
}

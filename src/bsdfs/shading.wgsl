// The one shading interface between the kernels' integrators and the BSDFs, twin of
// src/bsdfs/shading.rs: bsdf_at(hit, d) reads the material and its BSDF's words (textured slots
// looked up); the surface_* answers are the generated dispatch's (src/bsdfs/gpu.rs), falling
// back to the default_surface_* below. Library, no entry point; writes nothing.

// The BSDF at a hit for a ray along d: the material's header, its resolved BSDF (black for a
// one-sided material seen from the back), the front shading normal (the local frame's z) and
// the emitted radiance with the emitter's texture looked up.
struct Surface {
    m: Material,
    b: Bsdf,
    n: vec3<f32>,
    // The local frame's tangent (x; y is cross(n, t)): the hit's, made orthogonal to n.
    t: vec3<f32>,
    emission: vec3<f32>,
    // The normal map's shadowing (Material::normal_shadowing): the cosine of the perturbed to
    // the unperturbed (geometric) normal, 0 without it, and that normal.
    shadow_cos: f32,
    shadow_ng: vec3<f32>,
}

fn bsdf_at(hit: Hit, d: vec3<f32>) -> Surface {
    var s: Surface;
    s.m = load_material(hit.material);
    s.shadow_cos = 0.0;
    s.shadow_ng = hit.normal;
    if HAS_NORMAL_MAPS && s.m.normal_shadowing != 0u && s.m.normal_texture != NO_TEXTURE {
        s.shadow_cos = abs(dot(hit.shading, hit.normal));
    }
    s.n = hit.shading;
    s.t = frame_tangent(hit.shading, hit.tangent);
    s.emission = s.m.emission;
    if HAS_TEXTURES && hit.light != NO_LIGHT {
        // An emitter's texture is its light's (one material per light).
        let t = lights[LIGHT_WORDS * hit.light + LIGHT_EMISSION_WORD].w;
        if t != NO_TEXTURE {
            s.emission *= texture_eval(t, hit.uv);
        }
    }
    // A blend is the component its choice at this hit names (blend.wgsl): its kind, words
    // and sides; the rest of the header stays the blend's.
    var i = hit.material;
    if s.m.blend_first != NO_BLEND {
        i = blend_choose(i, s.m, hit.position, d, hit.uv);
        let c = load_material(i);
        s.m.kind = c.kind;
        s.m.textured = c.textured;
        s.m.one_sided = c.one_sided;
    }
    if s.m.one_sided != 0u && dot(d, hit.normal) >= 0.0 {
        // A one-sided material seen from the back reflects nothing (Material::one_sided).
        s.m.kind = BSDF_BLACK;
        s.m.blend_stores = 0u;
        s.b.kind = BSDF_BLACK;
        s.b.textured = 0u;
        return s;
    }
    s.b = bsdf_resolve(load_bsdf(i, s.m.kind, s.m.textured), hit.uv);
    return s;
}

// The local frame's tangent at unit normal n for a hit's tangent: it made orthogonal to n, else
// the basis of n (twin of Frame::new in src/bsdfs/interface.rs).
fn frame_tangent(n: vec3<f32>, tangent: vec3<f32>) -> vec3<f32> {
    let t = orthogonal_tangent(n, tangent);
    return select(t, basis_t(n), all(t == vec3<f32>(0.0)));
}

// w in the surface's local frame (Frame::local).
fn surface_local(s: Surface, w: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(dot(w, s.t), dot(w, cross(s.n, s.t)), dot(w, s.n));
}

// Local direction l in world space (Frame::world).
fn surface_world(s: Surface, l: vec3<f32>) -> vec3<f32> {
    return s.t * l.x + cross(s.n, s.t) * l.y + s.n * l.z;
}

// CLASS_BLACK, CLASS_DELTA, CLASS_SHADED or CLASS_NULL (shading::SurfaceClass).
fn surface_class(s: Surface) -> u32 {
    return material_class(s.m.kind);
}

// Radiance emitted towards a ray arriving from the front (or the back).
fn surface_emitted(s: Surface, front: bool) -> vec3<f32> {
    return select(vec3<f32>(0.0), s.emission, front || s.m.two_sided != 0u);
}

// The normal map's shadowing (Estevez et al. 2019, Mitsuba's normalmap): G1 of roughness
// alpha2 = min(tan^2(theta_p) / 8, 1) for light at cos_w; cos_p the perturbed normal's cosine.
fn terminator(cos_p: f32, cos_w: f32) -> f32 {
    let cp2 = max(cos_p * cos_p, 1e-12);
    let cw2 = max(cos_w * cos_w, 1e-12);
    let alpha2 = min(0.125 * max((1.0 - cp2) / cp2, 0.0), 1.0);
    return 2.0 / (1.0 + sqrt(1.0 + alpha2 * max((1.0 - cw2) / cw2, 0.0)));
}

// The shadowing of light arriving from wi at the surface (1 without a shadowing normal map).
fn surface_shadowing(s: Surface, wi: vec3<f32>) -> f32 {
    if s.shadow_cos == 0.0 {
        return 1.0;
    }
    return terminator(s.shadow_cos, dot(wi, s.shadow_ng));
}

// The kinds' answers with the normal map's shadowing on the light's side (SurfaceBsdf's).
fn surface_store_weight(s: Surface, wi: vec3<f32>) -> f32 {
    return surface_store_weight_unshadowed(s, wi) * surface_shadowing(s, wi);
}
fn surface_eval_diffuse(s: Surface, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    return surface_eval_diffuse_unshadowed(s, wi, wo) * surface_shadowing(s, wi);
}
fn surface_eval_lobe(s: Surface, wi: vec3<f32>, wo: vec3<f32>, ns: vec3<f32>) -> vec3<f32> {
    return surface_eval_lobe_unshadowed(s, wi, wo, ns) * surface_shadowing(s, wi);
}
fn surface_sample_lobe(s: Surface, d: vec3<f32>, f: Facing, rng: ptr<function, Rng>) -> LobeRay {
    var lr = surface_sample_lobe_unshadowed(s, d, f, rng);
    lr.weight *= surface_shadowing(s, lr.dir);
    return lr;
}

// Whether photons are stored at the surface: at a blend where either component stores them
// (blend.rs), else where the kind does.
fn surface_stores(s: Surface) -> bool {
    return s.m.blend_stores != 0u || surface_stores_photons(s);
}

// The constant BRDF a photon estimate seen from wo weighs its photons by.
fn surface_estimate_brdf(s: Surface, wo: vec3<f32>) -> vec3<f32> {
    return surface_diffuse_albedo(s, wo) / PI;
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

// Outcome of a photon's scattering: kind BOUNCE_ABSORB, _DIFFUSE, _LOBE or _DELTA.
struct Bounce {
    dir: vec3<f32>,
    kind: u32,
    weight: vec3<f32>,
}

// A local sample direction in world space; not ok when it leaks through the geometric
// surface (a reflection below it, a transmission above it) or carries nothing.
fn surface_world_ray(s: Surface, ls: LobeSampleW, f: Facing) -> LobeRay {
    let dir = normalize(surface_world(s, ls.wi));
    let reflects = dot(dir, f.ns) > 0.0;
    var leaks = false;
    if reflects {
        leaks = reflection_leaks(f, dir) || dot(dir, f.ng) <= 0.0;
    } else {
        leaks = refraction_leaks(f, dir) || dot(dir, f.ng) >= 0.0;
    }
    return LobeRay(dir, ls.weight, ls.ok && !leaks && max3(ls.weight) > 0.0, ls.pdf);
}

// One delta bounce of a ray along *d at `hit` (the kind's surface_delta_event: a mirror or
// smooth conductor reflects about the shading normal facing the ray and scales *t; glass and
// the thin dielectric take one rng draw). *o becomes the offset origin of the new ray. False
// when the new direction leaks through the geometric surface.
fn surface_delta(hit: Hit, s: Surface, d: ptr<function, vec3<f32>>, o: ptr<function, vec3<f32>>, t: ptr<function, vec3<f32>>, rng: ptr<function, Rng>) -> bool {
    let f = facing(hit, dot(*d, hit.normal) < 0.0);
    let ok = surface_delta_event(hit, s, f, d, t, rng);
    *o = offset_origin(hit.position, hit.normal, *d);
    return ok;
}

// Radiance along a ray that leaves the scene: the environment's, the last light (none
// without one).
fn escape(d: vec3<f32>) -> vec3<f32> {
    if HAS_ENVIRONMENT {
        return env_radiance(load_light(params.n_lights - 1u), d);
    }
    return vec3<f32>(0.0);
}

// ---- the surface's defaults, through the local frame (BsdfKind's) -------------------------
fn default_surface_diffuse_albedo(s: Surface, wo: vec3<f32>) -> vec3<f32> {
    return bsdf_diffuse_out(s.b, surface_local(s, wo));
}
fn default_surface_store_weight(s: Surface, wi: vec3<f32>) -> f32 {
    return bsdf_store_weight(s.b, surface_local(s, wi));
}
fn default_surface_eval_diffuse(s: Surface, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let li = surface_local(s, wi);
    let lo = surface_local(s, wo);
    if li.z * lo.z <= 0.0 {
        return vec3<f32>(0.0);
    }
    return bsdf_diffuse_out(s.b, lo) * (bsdf_store_weight(s.b, li) / PI);
}
fn default_surface_eval_lobe(s: Surface, wi: vec3<f32>, wo: vec3<f32>, ns: vec3<f32>) -> vec3<f32> {
    return bsdf_eval_lobe(s.b, surface_local(s, wi), surface_local(s, wo), true);
}
fn default_surface_pdf_lobe(s: Surface, wi: vec3<f32>, wo: vec3<f32>, ns: vec3<f32>) -> f32 {
    return bsdf_pdf_lobe(s.b, surface_local(s, wi), surface_local(s, wo));
}
fn default_surface_has_lobe(s: Surface) -> bool {
    return bsdf_has_lobe(s.b);
}
fn default_surface_lobe_is_glossy(s: Surface) -> bool {
    return bsdf_has_lobe(s.b) && !bsdf_lobe_is_delta(s.b);
}
fn default_surface_lobe_takes_point_lights(s: Surface) -> bool {
    return bsdf_has_lobe(s.b) && !bsdf_lobe_is_delta(s.b);
}
fn default_surface_stores_photons(s: Surface) -> bool {
    return bsdf_has_diffuse(s.b);
}
// Three numbers from rng through the local frame. A transmitting lobe's ray goes on on
// whichever side of the geometric surface it ends (Mitsuba's spawned rays); other lobes'
// rays that leak through it carry nothing.
fn default_surface_sample_lobe(s: Surface, d: vec3<f32>, f: Facing, rng: ptr<function, Rng>) -> LobeRay {
    let u = vec3<f32>(rng_next(rng), rng_next(rng), rng_next(rng));
    let ls = bsdf_sample_lobe(s.b, surface_local(s, -d), u, true);
    if bsdf_lobe_transmits(s.b) {
        let dir = normalize(surface_world(s, ls.wi));
        return LobeRay(dir, ls.weight, ls.ok && max3(ls.weight) > 0.0, ls.pdf);
    }
    return surface_world_ray(s, ls, f);
}
// The mirror direction, weighted by the lobe's own delta sample (a smooth conductor).
fn default_surface_delta(hit: Hit, s: Surface, f: Facing, d: ptr<function, vec3<f32>>, t: ptr<function, vec3<f32>>, rng: ptr<function, Rng>) -> bool {
    let ls = bsdf_sample_lobe(s.b, surface_local(s, -*d), vec3<f32>(0.0), true);
    *t *= select(vec3<f32>(0.0), ls.weight, ls.ok);
    *d = reflect_dir(*d, f.ns);
    return !reflection_leaks(f, *d);
}
// Kinds without a split (only glass and the thin dielectric have one).
fn default_surface_split(hit: Hit, s: Surface, f: Facing, d: vec3<f32>) -> Dielectric {
    return Dielectric(reflect_dir(d, f.ns), vec3<f32>(0.0), 1.0, 1.0);
}
// A photon along d at `hit` (three uniforms u), twin of BsdfKind::photon_bounce: the BSDF
// sampled without roulette, a kind with both parts picking its lobe with
// bsdf_lobe_probability (u.x), then the lobe or a cosine diffuse direction.
fn default_surface_photon_bounce(s: Surface, d: vec3<f32>, hit: Hit, u: vec3<f32>) -> Bounce {
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

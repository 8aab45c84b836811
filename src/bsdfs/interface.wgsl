// The BSDF interface's shared types and the local-frame defaults (twin of src/bsdfs/mod.rs and
// interface.rs): a kind's WGSL file defines <kind>_<method> for what differs, the generated
// dispatch (src/bsdfs/gpu.rs) calls it or default_<method>. Library, no entry point; writes
// nothing. Directions are local (z the front shading normal).

// Rust's Option<LobeSample>: ok false for None.
struct LobeSampleW { wi: vec3<f32>, weight: vec3<f32>, pdf: f32, delta: bool, ok: bool }
fn lobe_none() -> LobeSampleW { return LobeSampleW(vec3<f32>(0.0), vec3<f32>(0.0), 0.0, false, false); }

// to_front: two-sided kinds see both directions mirrored to the front when wo is below; ok false when wo.z == 0.
struct Front { wi: vec3<f32>, wo: vec3<f32>, flipped: bool, ok: bool }
fn to_front(wi: vec3<f32>, wo: vec3<f32>) -> Front {
    if wo.z > 0.0 { return Front(wi, wo, false, true); }
    if wo.z < 0.0 { return Front(flip_z(wi), flip_z(wo), true, true); }
    return Front(wi, wo, false, false);
}
fn back_to_side(s: LobeSampleW, flipped: bool) -> LobeSampleW {
    var r = s;
    if s.ok && flipped { r.wi = flip_z(s.wi); }
    return r;
}

fn default_diffuse_out(b: Bsdf, wo: vec3<f32>) -> vec3<f32> { return vec3<f32>(0.0); }
fn default_store_weight(b: Bsdf, wi: vec3<f32>) -> f32 { return 0.0; }
fn default_eval_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> { return vec3<f32>(0.0); }
fn default_pdf_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 { return 0.0; }
fn default_sample_lobe(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW { return lobe_none(); }
fn default_has_diffuse(b: Bsdf) -> bool { return false; }
fn default_has_lobe(b: Bsdf) -> bool { return true; }
fn default_lobe_is_delta(b: Bsdf) -> bool { return false; }
fn default_lobe_probability(b: Bsdf, wo: vec3<f32>) -> f32 {
    return clamp(1.0 - bsdf_store_weight(b, wo), 0.05, 0.95);
}
fn default_diffuse_value(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if !bsdf_has_diffuse(b) || wi.z * wo.z <= 0.0 { return vec3<f32>(0.0); }
    return bsdf_diffuse_out(b, wo) * (bsdf_store_weight(b, wi) * BSDF_FRAC_1_PI);
}
fn default_eval(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    return bsdf_diffuse_value(b, wi, wo) + bsdf_eval_lobe(b, wi, wo, radiance);
}
fn default_pdf(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 { return bsdf_pdf_lobe(b, wi, wo); }
fn default_sample(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    return bsdf_sample_lobe(b, wo, u, radiance);
}
// What a kind recomputes after its textured words are looked up (nothing by default).
fn default_finish(b: Bsdf) -> Bsdf { return b; }
// Whether shadow rays to delta lights also cross the surface (a transmitting lobe).
fn default_lobe_transmits(b: Bsdf) -> bool { return false; }
// Whether passing straight through is a null event (no bounce in scenes with media).
fn default_passes_null(b: Bsdf) -> bool { return false; }
// What a shadow ray keeps crossing a passes_null surface from wo (local); zero for the rest.
fn default_null_transmission(b: Bsdf, wo: vec3<f32>) -> vec3<f32> { return vec3<f32>(0.0); }

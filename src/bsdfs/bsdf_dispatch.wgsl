// The Bsdf methods (twin of src/bsdfs/mod.rs): each dispatches a resolved BsdfParams to its kind's functions in
// bsdf.wgsl and bsdf_gltf.wgsl, mirroring two-sided kinds to the front. Library, no entry point; writes nothing.
// Composed after bsdf.wgsl and bsdf_gltf.wgsl (the kernels and the oracle probe call these).

// ---- mod.rs: the Bsdf methods --------------------------------------------------------------
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
fn bsdf_is_plastic(b: BsdfParams) -> bool { return b.kind == BSDF_PLASTIC || b.kind == BSDF_ROUGH_PLASTIC; }
fn bsdf_has_diffuse(b: BsdfParams) -> bool {
    if b.kind == BSDF_GLTF { return gltf_has_diffuse(b); }
    return b.kind == BSDF_DIFFUSE || bsdf_is_plastic(b);
}
fn bsdf_has_lobe(b: BsdfParams) -> bool { return b.kind != BSDF_DIFFUSE; }
fn bsdf_lobe_is_delta(b: BsdfParams) -> bool {
    return b.kind == BSDF_CONDUCTOR || b.kind == BSDF_DIELECTRIC || b.kind == BSDF_THIN_DIELECTRIC || b.kind == BSDF_PLASTIC;
}
fn bsdf_eval(b: BsdfParams, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    return bsdf_diffuse_value(b, wi, wo) + bsdf_eval_lobe(b, wi, wo, radiance);
}
fn bsdf_pdf(b: BsdfParams, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if b.kind == BSDF_DIFFUSE || bsdf_is_plastic(b) || b.kind == BSDF_GLTF {
        let fr = to_front(wi, wo);
        if !fr.ok { return 0.0; }
        if b.kind == BSDF_DIFFUSE { return diffuse_pdf(fr.wi, fr.wo); }
        if b.kind == BSDF_GLTF { return gltf_pdf(b, fr.wi, fr.wo); }
        return plastic_pdf(b, fr.wi, fr.wo);
    }
    return bsdf_pdf_lobe(b, wi, wo);
}
fn bsdf_sample(b: BsdfParams, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    if b.kind == BSDF_DIFFUSE || bsdf_is_plastic(b) || b.kind == BSDF_GLTF {
        let fr = to_front(vec3<f32>(0.0, 0.0, 1.0), wo);
        if !fr.ok { return lobe_none(); }
        if b.kind == BSDF_DIFFUSE { return back_to_side(diffuse_sample(b.albedo, fr.wo, u), fr.flipped); }
        if b.kind == BSDF_GLTF { return back_to_side(gltf_sample(b, fr.wo, u), fr.flipped); }
        return back_to_side(plastic_sample(b, fr.wo, u), fr.flipped);
    }
    return bsdf_sample_lobe(b, wo, u, radiance);
}
fn bsdf_diffuse_out(b: BsdfParams, wo: vec3<f32>) -> vec3<f32> {
    if wo.z == 0.0 { return vec3<f32>(0.0); }
    if b.kind == BSDF_DIFFUSE { return b.albedo; }
    if bsdf_is_plastic(b) { return plastic_diffuse_out(b, abs(wo.z)); }
    if b.kind == BSDF_GLTF { return gltf_diffuse_out(b, abs(wo.z)); }
    return vec3<f32>(0.0);
}
fn bsdf_store_weight(b: BsdfParams, wi: vec3<f32>) -> f32 {
    if wi.z == 0.0 { return 0.0; }
    if b.kind == BSDF_DIFFUSE { return 1.0; }
    if bsdf_is_plastic(b) { return plastic_transmittance(b, abs(wi.z)); }
    if b.kind == BSDF_GLTF && gltf_has_diffuse(b) { return 1.0; }
    return 0.0;
}
fn bsdf_diffuse_value(b: BsdfParams, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if !bsdf_has_diffuse(b) || wi.z * wo.z <= 0.0 { return vec3<f32>(0.0); }
    return bsdf_diffuse_out(b, wo) * (bsdf_store_weight(b, wi) * BSDF_FRAC_1_PI);
}
fn bsdf_eval_lobe(b: BsdfParams, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    if b.kind == BSDF_ROUGH_DIELECTRIC {
        return dielectric_eval(bsdf_microfacet(b), b.eta, b.specular, b.transmittance, wi, wo, radiance);
    }
    if b.kind != BSDF_ROUGH_CONDUCTOR && !bsdf_is_plastic(b) && b.kind != BSDF_GLTF { return vec3<f32>(0.0); }
    let fr = to_front(wi, wo);
    if !fr.ok { return vec3<f32>(0.0); }
    if b.kind == BSDF_ROUGH_CONDUCTOR { return conductor_eval(bsdf_microfacet(b), b.eta_c, b.k_c, b.specular, fr.wi, fr.wo); }
    if b.kind == BSDF_GLTF { return gltf_eval_lobe(b, fr.wi, fr.wo); }
    return plastic_eval_lobe(b, fr.wi, fr.wo);
}
fn bsdf_pdf_lobe(b: BsdfParams, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if b.kind == BSDF_ROUGH_DIELECTRIC { return dielectric_pdf(bsdf_microfacet(b), b.eta, wi, wo); }
    if b.kind != BSDF_ROUGH_CONDUCTOR && !bsdf_is_plastic(b) && b.kind != BSDF_GLTF { return 0.0; }
    let fr = to_front(wi, wo);
    if !fr.ok { return 0.0; }
    if b.kind == BSDF_ROUGH_CONDUCTOR { return conductor_pdf(bsdf_microfacet(b), fr.wi, fr.wo); }
    if b.kind == BSDF_GLTF { return gltf_pdf_lobe(b, fr.wi, fr.wo); }
    return plastic_pdf_lobe(b, fr.wi, fr.wo);
}
fn bsdf_sample_lobe(b: BsdfParams, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    switch b.kind {
        case BSDF_ROUGH_DIELECTRIC: {
            return dielectric_sample(bsdf_microfacet(b), b.eta, b.specular, b.transmittance, wo, u, radiance);
        }
        case BSDF_DIELECTRIC: { return dielectric_sample_smooth(b.eta, b.specular, b.transmittance, wo, u, radiance); }
        case BSDF_THIN_DIELECTRIC: { return dielectric_sample_thin(b.eta, b.specular, b.transmittance, wo, u); }
        case BSDF_CONDUCTOR, BSDF_ROUGH_CONDUCTOR, BSDF_PLASTIC, BSDF_ROUGH_PLASTIC, BSDF_GLTF: {
            let fr = to_front(vec3<f32>(0.0, 0.0, 1.0), wo);
            if !fr.ok { return lobe_none(); }
            var s: LobeSampleW;
            if b.kind == BSDF_CONDUCTOR {
                s = conductor_sample_smooth(b.eta_c, b.k_c, b.specular, fr.wo);
            } else if b.kind == BSDF_ROUGH_CONDUCTOR {
                s = conductor_sample(bsdf_microfacet(b), b.eta_c, b.k_c, b.specular, fr.wo, u);
            } else if b.kind == BSDF_GLTF {
                s = gltf_sample_lobe(b, fr.wo, u);
            } else {
                s = plastic_sample_lobe(b, fr.wo, u);
            }
            return back_to_side(s, fr.flipped);
        }
        default: { return lobe_none(); }
    }
}
// Bsdf::lobe_probability: a photon's chance of following the lobe part (kinds with both parts).
fn bsdf_lobe_probability(b: BsdfParams, wo: vec3<f32>) -> f32 {
    if b.kind == BSDF_GLTF { return gltf_lobe_probability(b, abs(wo.z)); }
    return clamp(1.0 - bsdf_store_weight(b, wo), 0.05, 0.95);
}

// A smooth conductor (twin of src/bsdfs/conductor.rs): the mirror direction weighted by the
// complex-index Fresnel reflectance times a tint, two-sided; its delta event is the default's.
// Words: 0 eta (xyz), 1 k (xyz), 2 the tint slot. Library, no entry point; writes nothing.

fn conductor_smooth_sample(eta: vec3<f32>, k: vec3<f32>, specular: vec3<f32>, wo: vec3<f32>) -> LobeSampleW {
    return LobeSampleW(reflect_z(wo), fresnel_conductor(wo.z, eta, k) * specular, 0.0, true, true);
}
fn conductor_lobe_is_delta(b: Bsdf) -> bool { return true; }
fn conductor_sample_lobe(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let fr = to_front(vec3<f32>(0.0, 0.0, 1.0), wo);
    if !fr.ok { return lobe_none(); }
    return back_to_side(conductor_smooth_sample(w_rgb(b.w0), w_rgb(b.w1), w_rgb(b.w2), fr.wo), fr.flipped);
}

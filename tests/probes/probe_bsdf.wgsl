// Oracle probe of the BSDF library (src/bsdfs/*.wgsl, the generated dispatch) for
// tests/bsdf_gpu.rs, never used by a render. One invocation per case i < width: inputs in
// slots 0-5 (wi and the material, wo and radiance, u, the microfacet and eta, a conductor's
// eta and k), the material's BSDF as load_bsdf reads it; writes BSDF_PROBE_OUT vec4s from
// slot 6: every method, then the microfacet, Fresnel and erf helpers alone.

const BSDF_PROBE_OUT: u32 = 12u;

fn probe_flags(s: LobeSampleW) -> f32 { return select(0.0, 1.0, s.ok) + select(0.0, 2.0, s.delta); }
fn out_slot(k: u32, i: u32) -> u32 { return slot(6u + k, i); }

@compute @workgroup_size(WG_SIZE)
fn probe_bsdf(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let a0 = accum[slot(0u, i)];
    let a1 = accum[slot(1u, i)];
    let wi = a0.xyz;
    let wo = a1.xyz;
    let u = accum[slot(2u, i)].xyz;
    let a3 = accum[slot(3u, i)];
    let mat = bitcast<u32>(a0.w);
    let rad = a1.w != 0.0;
    let m = load_material(mat);
    let b = load_bsdf(mat, m.kind, m.textured);
    accum[out_slot(0u, i)] = vec4<f32>(bsdf_eval(b, wi, wo, rad), bsdf_pdf(b, wi, wo));
    accum[out_slot(1u, i)] = vec4<f32>(bsdf_eval_lobe(b, wi, wo, rad), bsdf_pdf_lobe(b, wi, wo));
    let s = bsdf_sample(b, wo, u, rad);
    accum[out_slot(2u, i)] = vec4<f32>(s.wi, s.pdf);
    accum[out_slot(3u, i)] = vec4<f32>(s.weight, probe_flags(s));
    let l = bsdf_sample_lobe(b, wo, u, rad);
    accum[out_slot(4u, i)] = vec4<f32>(l.wi, l.pdf);
    accum[out_slot(5u, i)] = vec4<f32>(l.weight, probe_flags(l));
    accum[out_slot(6u, i)] = vec4<f32>(bsdf_diffuse_out(b, wo), bsdf_store_weight(b, wi));
    // The microfacet and Fresnel functions alone, on the inputs' distribution and indices.
    let mf = Microfacet(bitcast<u32>(a3.x), a3.y, a3.z);
    let h0 = bsdf_normalize(wi + wo);
    let h = mulsign(h0, h0.z);
    let wof = mulsign(wo, wo.z);
    accum[out_slot(7u, i)] = vec4<f32>(mf_d(mf, h), mf_smith_g1(mf, wi, h), mf_g(mf, wi, wo, h), mf_pdf_visible(mf, wof, h));
    let ms = mf_sample_visible(mf, wof, u.yz);
    accum[out_slot(8u, i)] = vec4<f32>(ms.m, ms.pdf);
    let fr = fresnel_dielectric_mi(wo.z, a3.w);
    accum[out_slot(9u, i)] = vec4<f32>(fr.f, fr.cos_t, fr.eta_it, fr.eta_ti);
    let c = fresnel_conductor(abs(wo.z), accum[slot(4u, i)].xyz, accum[slot(5u, i)].xyz);
    accum[out_slot(10u, i)] = vec4<f32>(c, erfinv(2.0 * u.x - 1.0));
    accum[out_slot(11u, i)] = vec4<f32>(erf(4.0 * u.y - 2.0), square_to_cosine_hemisphere(u.yz));
}

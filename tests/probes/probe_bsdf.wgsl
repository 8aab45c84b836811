// Oracle probe of src/bsdfs/bsdf.wgsl for tests/bsdf_gpu.rs (never used by a render).
// One invocation per case: every BsdfParams function on the case's (wi, wo, u), PROBE_SLOTS vec4s out.
// Composed by gpu::bsdf_params::probe_source() after the prelude, the generated BSDF codes and bsdf.wgsl;
// declares the library's `bsdf_tables` (binding 1).

struct ProbeCase { wi: vec3<f32>, bsdf: u32, wo: vec3<f32>, radiance: u32, u: vec3<f32>, pad: u32 }

const PROBE_SLOTS: u32 = 12u;

@group(0) @binding(0) var<storage, read> bsdfs: array<BsdfParams>;
@group(0) @binding(1) var<storage, read> bsdf_tables: array<f32>;
@group(0) @binding(2) var<storage, read> cases: array<ProbeCase>;
@group(0) @binding(3) var<storage, read_write> probe_out: array<vec4<f32>>;

fn probe_flags(s: LobeSampleW) -> f32 { return select(0.0, 1.0, s.ok) + select(0.0, 2.0, s.delta); }

@compute @workgroup_size(64)
fn probe_bsdf(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= arrayLength(&cases) { return; }
    let c = cases[i];
    let b = bsdfs[c.bsdf];
    let rad = c.radiance != 0u;
    let o = i * PROBE_SLOTS;
    probe_out[o] = vec4<f32>(bsdf_eval(b, c.wi, c.wo, rad), bsdf_pdf(b, c.wi, c.wo));
    probe_out[o + 1u] = vec4<f32>(bsdf_eval_lobe(b, c.wi, c.wo, rad), bsdf_pdf_lobe(b, c.wi, c.wo));
    let s = bsdf_sample(b, c.wo, c.u, rad);
    probe_out[o + 2u] = vec4<f32>(s.wi, s.pdf);
    probe_out[o + 3u] = vec4<f32>(s.weight, probe_flags(s));
    let l = bsdf_sample_lobe(b, c.wo, c.u, rad);
    probe_out[o + 4u] = vec4<f32>(l.wi, l.pdf);
    probe_out[o + 5u] = vec4<f32>(l.weight, probe_flags(l));
    probe_out[o + 6u] = vec4<f32>(bsdf_diffuse_out(b, c.wo), bsdf_store_weight(b, c.wi));
    // The microfacet and Fresnel functions alone (meaningful for the kinds that have them).
    let mf = bsdf_microfacet(b);
    let h0 = bsdf_normalize(c.wi + c.wo);
    let h = mulsign(h0, h0.z);
    let wof = mulsign(c.wo, c.wo.z);
    probe_out[o + 7u] = vec4<f32>(mf_d(mf, h), mf_smith_g1(mf, c.wi, h), mf_g(mf, c.wi, c.wo, h), mf_pdf_visible(mf, wof, h));
    let ms = mf_sample_visible(mf, wof, c.u.yz);
    probe_out[o + 8u] = vec4<f32>(ms.m, ms.pdf);
    let fr = fresnel_dielectric_mi(c.wo.z, b.eta);
    probe_out[o + 9u] = vec4<f32>(fr.f, fr.cos_t, fr.eta_it, fr.eta_ti);
    probe_out[o + 10u] = vec4<f32>(fresnel_conductor(abs(c.wo.z), b.eta_c, b.k_c), erfinv(2.0 * c.u.x - 1.0));
    probe_out[o + 11u] = vec4<f32>(erf(4.0 * c.u.y - 2.0), square_to_cosine_hemisphere(c.u.yz));
}

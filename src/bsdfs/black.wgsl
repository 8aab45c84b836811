// Black (twin of src/bsdfs/black.rs): reflects nothing: a path ends here (after its emission), photons are absorbed. It has no parameters (no words);
// the integrators read its class and stop or pass, so only the answers that differ from the
// defaults are here. Library, no entry point; writes nothing.

fn black_has_lobe(b: Bsdf) -> bool { return false; }
fn black_surface_diffuse_albedo(s: Surface, wo: vec3<f32>) -> vec3<f32> { return vec3<f32>(0.0); }
fn black_surface_store_weight(s: Surface, wi: vec3<f32>) -> f32 { return 1.0; }
fn black_surface_eval_diffuse(s: Surface, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> { return vec3<f32>(0.0); }

// Null (twin of src/bsdfs/null.rs): an index-matched boundary: rays and photons pass straight through (the class, generated, says so). It has no parameters (no words);
// the integrators read its class and stop or pass, so only the answers that differ from the
// defaults are here. Library, no entry point; writes nothing.

fn null_has_lobe(b: Bsdf) -> bool { return false; }
fn null_surface_diffuse_albedo(s: Surface, wo: vec3<f32>) -> vec3<f32> { return vec3<f32>(0.0); }
fn null_surface_store_weight(s: Surface, wi: vec3<f32>) -> f32 { return 1.0; }
fn null_surface_eval_diffuse(s: Surface, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> { return vec3<f32>(0.0); }

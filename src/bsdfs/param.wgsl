// A BSDF parameter's slot word (twin of src/bsdfs/param.rs): the value in xyz, the texture in w
// (its index in the low PARAM_TEXTURE_BITS bits, the channel above; NO_TEXTURE untextured).
// param_eval is the one evaluation of a textured parameter on the device. Library, no entry
// point; writes nothing.

// A slot word's value times its texture's channel at uv, as an untextured word.
fn param_eval(w: vec4<u32>, uv: vec2<f32>) -> vec4<u32> {
    let v = bitcast<vec3<f32>>(w.xyz);
    // Without textures in the scene the specialised kernel keeps no texture code.
    if !HAS_TEXTURES || w.w == NO_TEXTURE {
        return w;
    }
    let t = w.w & ((1u << PARAM_TEXTURE_BITS) - 1u);
    let channel = w.w >> PARAM_TEXTURE_BITS;
    // One lookup for every channel (drivers inline each call site's whole texture code).
    let c = texture_eval_rgba(t, uv);
    var r: vec3<f32>;
    switch channel {
        case PARAM_CHANNEL_R: { r = v * c.x; }
        case PARAM_CHANNEL_G: { r = v * c.y; }
        case PARAM_CHANNEL_B: { r = v * c.z; }
        case PARAM_CHANNEL_A: { r = v * c.w; }
        case PARAM_CHANNEL_LUMINANCE: { r = v * (0.212671 * c.x + 0.71516 * c.y + 0.072169 * c.z); }
        default: { r = v * c.xyz; }
    }
    return vec4<u32>(bitcast<vec3<u32>>(r), NO_TEXTURE);
}

// A word's colour, and its first number.
fn w_rgb(w: vec4<u32>) -> vec3<f32> {
    return bitcast<vec3<f32>>(w.xyz);
}
fn w_f(w: vec4<u32>) -> f32 {
    return bitcast<f32>(w.x);
}

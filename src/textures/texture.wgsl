// Image and checkerboard textures looked up at a uv: the twin of `texture::SceneTexture::eval`
// (src/textures/mod.rs, checker.rs, sampler.rs), packed by src/integrators/gpu/textures.rs, whose
// wgsl_library() prefixes this file with its TEX_* constants. A library, no entry points: the
// composing module declares `var<storage, read> tex_table: array<TextureRecord>` and
// `var<storage, read> tex_words: array<u32>`. No loops. `id` must index tex_table.

// One texture (src/integrators/gpu/textures.rs GpuTexture).
struct TextureRecord {
    offset: u32,
    width: u32,
    height: u32,
    format: u32,
    filter_mode: u32,
    wrap_u: u32,
    wrap_v: u32,
    pad: u32,
    uv_u: vec4<f32>,
    uv_v: vec4<f32>,
    color0: vec4<f32>,
    color1: vec4<f32>,
}

// `i` modulo `n` in 0..n (n > 0).
fn tex_rem(i: i32, n: i32) -> i32 {
    let r = i % n;
    return select(r, r + n, r < 0);
}

// `texture::Wrap::index`: the texel in 0..n that integer coordinate i reads.
fn tex_wrap(i: i32, n: i32, mode: u32) -> i32 {
    if mode == TEX_WRAP_CLAMP {
        return clamp(i, 0, n - 1);
    }
    if mode == TEX_WRAP_MIRROR {
        let m = tex_rem(i, 2 * n);
        return select(m, 2 * n - 1 - m, m >= n);
    }
    return tex_rem(i, n);
}

// A pixel coordinate within +-TEX_COORD_LIMIT (NaN, where the device keeps it, becomes 0).
fn tex_coord(p: f32) -> f32 {
    return select(clamp(p, -TEX_COORD_LIMIT, TEX_COORD_LIMIT), 0.0, p != p);
}

fn tex_lut(base: u32, byte: u32) -> f32 {
    return bitcast<f32>(tex_words[base + byte]);
}

// `Texture::texel`: texel (x, y), wrapped, decoded to linear RGB and alpha.
fn tex_texel(t: TextureRecord, x: i32, y: i32) -> vec4<f32> {
    let xi = u32(tex_wrap(x, i32(t.width), t.wrap_u));
    let yi = u32(tex_wrap(y, i32(t.height), t.wrap_v));
    let i = yi * t.width + xi;
    if t.format == TEX_FORMAT_RGBA8_SRGB || t.format == TEX_FORMAT_RGBA8_RAW {
        let w = tex_words[t.offset + i];
        let lut = select(TEX_LUT_RAW, TEX_LUT_SRGB, t.format == TEX_FORMAT_RGBA8_SRGB);
        return vec4<f32>(
            tex_lut(lut, w & 255u),
            tex_lut(lut, (w >> 8u) & 255u),
            tex_lut(lut, (w >> 16u) & 255u),
            tex_lut(TEX_LUT_RAW, w >> 24u),
        );
    }
    if t.format == TEX_FORMAT_RGB32F {
        let k = t.offset + 3u * i;
        return vec4<f32>(
            bitcast<f32>(tex_words[k]),
            bitcast<f32>(tex_words[k + 1u]),
            bitcast<f32>(tex_words[k + 2u]),
            1.0,
        );
    }
    let k = t.offset + 4u * i;
    return vec4<f32>(
        bitcast<f32>(tex_words[k]),
        bitcast<f32>(tex_words[k + 1u]),
        bitcast<f32>(tex_words[k + 2u]),
        bitcast<f32>(tex_words[k + 3u]),
    );
}

// The four texels a bilinear lookup of t at transformed uv p blends ((x0, y0), (x0 + 1, y0),
// (x0, y0 + 1), (x0 + 1, y0 + 1)) and the weights f of the second column and row.
struct TexQuad {
    c00: vec4<f32>,
    c10: vec4<f32>,
    c01: vec4<f32>,
    c11: vec4<f32>,
    f: vec2<f32>,
}

fn tex_quad(t: TextureRecord, p: vec2<f32>) -> TexQuad {
    let size = vec2<f32>(f32(t.width), f32(t.height));
    let px = tex_coord(p.x * size.x - 0.5);
    let py = tex_coord(p.y * size.y - 0.5);
    let fx = floor(px);
    let fy = floor(py);
    let x0 = i32(fx);
    let y0 = i32(fy);
    return TexQuad(tex_texel(t, x0, y0), tex_texel(t, x0 + 1, y0), tex_texel(t, x0, y0 + 1),
        tex_texel(t, x0 + 1, y0 + 1), vec2<f32>(px - fx, py - fy));
}

// uv after texture t's uv transform.
fn tex_uv(t: TextureRecord, uv: vec2<f32>) -> vec2<f32> {
    return vec2<f32>(
        (t.uv_u.x * uv.x + t.uv_u.z) + t.uv_u.y * uv.y,
        (t.uv_v.x * uv.x + t.uv_v.z) + t.uv_v.y * uv.y,
    );
}

// Linear RGB and alpha of texture `id` at `uv` (before its uv transform).
fn texture_eval_rgba(id: u32, uv: vec2<f32>) -> vec4<f32> {
    let t = tex_table[id];
    let p = tex_uv(t, uv);
    if t.format == TEX_FORMAT_CHECKERBOARD {
        let fx = p.x - floor(p.x) > 0.5;
        let fy = p.y - floor(p.y) > 0.5;
        return select(t.color1, t.color0, fx == fy);
    }
    let size = vec2<f32>(f32(t.width), f32(t.height));
    if t.filter_mode == TEX_FILTER_NEAREST {
        let px = floor(tex_coord(p.x * size.x));
        let py = floor(tex_coord(p.y * size.y));
        return tex_texel(t, i32(px), i32(py));
    }
    let q = tex_quad(t, p);
    let row0 = q.c00 * (1.0 - q.f.x) + q.c10 * q.f.x;
    let row1 = q.c01 * (1.0 - q.f.x) + q.c11 * q.f.x;
    return row0 * (1.0 - q.f.y) + row1 * q.f.y;
}

// The gradient of texture id's luminance at uv with respect to u and v (Mitsuba's bitmap
// eval_1_grad; twin of Texture::eval_grad in src/textures/mod.rs, which documents the order);
// zero for a nearest lookup or a checkerboard.
fn texture_grad(id: u32, uv: vec2<f32>) -> vec2<f32> {
    let t = tex_table[id];
    if t.format == TEX_FORMAT_CHECKERBOARD || t.filter_mode == TEX_FILTER_NEAREST {
        return vec2<f32>(0.0);
    }
    let q = tex_quad(t, tex_uv(t, uv));
    let y = vec3<f32>(0.212671, 0.715160, 0.072169);
    let f00 = dot(q.c00.xyz, y);
    let f10 = dot(q.c10.xyz, y);
    let f01 = dot(q.c01.xyz, y);
    let f11 = dot(q.c11.xyz, y);
    let dx = (1.0 - q.f.y) * (f10 - f00) + q.f.y * (f11 - f01);
    let dy = (1.0 - q.f.x) * (f01 - f00) + q.f.x * (f11 - f10);
    let du = t.uv_u.x * dx + t.uv_v.x * dy;
    let dv = t.uv_u.y * dx + t.uv_v.y * dy;
    return vec2<f32>(f32(t.width) * du, f32(t.height) * dv);
}

// Linear RGB of texture `id` at `uv`.
fn texture_eval(id: u32, uv: vec2<f32>) -> vec3<f32> {
    return texture_eval_rgba(id, uv).xyz;
}

// Alpha of texture `id` at `uv` (1 without alpha; filtered like the colour).
fn texture_alpha(id: u32, uv: vec2<f32>) -> f32 {
    return texture_eval_rgba(id, uv).w;
}

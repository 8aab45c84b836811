// The environment light: its radiance along a direction leaving the scene, its direction
// sampling for shadow rays and photons, and the light kind's methods; twin of
// src/lights/environment/mod.rs (lookup), sampling.rs (sampling) and kind.rs (the kind). An image's distribution (EnvDistribution::gpu_words) lies in
// light_cdf from the light's cdf_start: ENV_HEADER_WORDS of header, the cell CDF, the grid.
// Library, no entry point; writes nothing.

struct EnvDir {
    dir: vec3<f32>,
    pdf: f32,
}

fn env_is_map(l: Light) -> bool {
    return HAS_TEXTURES && l.p2.w != NO_TEXTURE;
}

fn env_word(l: Light, i: u32) -> f32 {
    return light_cdf[l.p1.w + i];
}

// The 3x3 matrix stored column-major at word w, times d.
fn env_mat(l: Light, w: u32, d: vec3<f32>) -> vec3<f32> {
    let c0 = vec3<f32>(env_word(l, w), env_word(l, w + 1u), env_word(l, w + 2u));
    let c1 = vec3<f32>(env_word(l, w + 3u), env_word(l, w + 4u), env_word(l, w + 5u));
    let c2 = vec3<f32>(env_word(l, w + 6u), env_word(l, w + 7u), env_word(l, w + 8u));
    return c0 * d.x + c1 * d.y + c2 * d.z;
}

// Mitsuba's direction_to_uv and uv_to_direction (scene::latlong_uv, latlong_dir).
fn latlong_uv(d: vec3<f32>) -> vec2<f32> {
    return vec2<f32>(atan2(d.x, -d.z) * (0.5 / PI), acos(clamp(d.y, -1.0, 1.0)) * (1.0 / PI));
}

fn latlong_dir(uv: vec2<f32>) -> vec3<f32> {
    let t = uv.y * PI;
    let p = uv.x * 2.0 * PI;
    return vec3<f32>(sin(p) * sin(t), cos(t), -cos(p) * sin(t));
}

// scene::latlong_lookup: u periodic with column i at (i + 0.5) / W, v clamped with row j at
// j / (H - 1), bilinear.
fn env_lookup(id: u32, uv: vec2<f32>) -> vec3<f32> {
    let t = tex_table[id];
    let w = i32(t.width);
    let h = i32(t.height);
    let x = (uv.x - floor(uv.x)) * f32(w) - 0.5;
    let y = clamp(uv.y, 0.0, 1.0) * f32(max(h - 1, 0));
    let fx = floor(x);
    let fy = floor(y);
    let tx = x - fx;
    let ty = y - fy;
    let x0 = tex_rem(i32(fx), w);
    let x1 = tex_rem(i32(fx) + 1, w);
    let y0 = clamp(i32(fy), 0, h - 1);
    let y1 = clamp(i32(fy) + 1, 0, h - 1);
    let row0 = tex_texel(t, x0, y0).xyz * (1.0 - tx) + tex_texel(t, x1, y0).xyz * tx;
    let row1 = tex_texel(t, x0, y1).xyz * (1.0 - tx) + tex_texel(t, x1, y1).xyz * tx;
    return row0 * (1.0 - ty) + row1 * ty;
}

// Radiance arriving from world direction d (Environment::eval).
fn env_radiance(l: Light, d: vec3<f32>) -> vec3<f32> {
    if !env_is_map(l) {
        return light_vec(l.p1);
    }
    return light_vec(l.p1) * env_lookup(l.p2.w, latlong_uv(env_mat(l, 13u, d)));
}

// Grid vertex (x, y) of the map's distribution.
fn env_grid(l: Light, x: u32, y: u32) -> f32 {
    let w = u32(env_word(l, 0u));
    let h = u32(env_word(l, 1u));
    return env_word(l, ENV_HEADER_WORDS + w * (h - 1u) + y * (w + 1u) + x);
}

// EnvDistribution::pdf_uv.
fn env_pdf_uv(l: Light, uv: vec2<f32>) -> f32 {
    let integral = env_word(l, 2u);
    if integral <= 0.0 {
        return 0.0;
    }
    let wf = env_word(l, 0u);
    let w = u32(wf);
    let h = u32(env_word(l, 1u));
    let g = uv.x - 0.5 / wf;
    let gx = (g - floor(g)) * wf;
    let gy = clamp(uv.y, 0.0, 1.0) * f32(h - 1u);
    let cx = min(u32(floor(gx)), w - 1u);
    let cy = min(u32(floor(gy)), h - 2u);
    let tx = gx - f32(cx);
    let ty = gy - f32(cy);
    let top = mix(env_grid(l, cx, cy), env_grid(l, cx + 1u, cy), tx);
    let bottom = mix(env_grid(l, cx, cy + 1u), env_grid(l, cx + 1u, cy + 1u), tx);
    return mix(top, bottom, ty) / integral;
}

// environment::sample_linear: t in [0, 1) with density proportional to (1 - t) a + t b.
fn env_sample_linear(u: f32, a: f32, b: f32) -> f32 {
    if a + b <= 0.0 {
        return u;
    }
    if u == 0.0 && a == 0.0 {
        return 0.0;
    }
    let x = u * (a + b) / (a + sqrt(max(a * a + u * (b * b - a * a), 0.0)));
    return min(x, 1.0 - 1.1920929e-7);
}

// A world direction from the map's distribution and its solid-angle density
// (EnvDistribution::sample, environment::image_sample); cells by binary search (32 steps).
fn env_sample_map(l: Light, u: vec3<f32>) -> EnvDir {
    var out = EnvDir(vec3<f32>(0.0, 0.0, 1.0), 0.0);
    let integral = env_word(l, 2u);
    if integral <= 0.0 {
        return out;
    }
    let w = u32(env_word(l, 0u));
    let h = u32(env_word(l, 1u));
    let n = w * (h - 1u);
    var lo = 0u;
    var hi = n;
    for (var i = 0u; i < 32u && lo < hi && spend(); i += 1u) {
        let mid = (lo + hi) / 2u;
        if env_word(l, ENV_HEADER_WORDS + mid) <= u.x {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    let cell = min(lo, n - 1u);
    let cx = cell % w;
    let cy = cell / w;
    let a = env_grid(l, cx, cy);
    let b = env_grid(l, cx + 1u, cy);
    let c = env_grid(l, cx, cy + 1u);
    let d = env_grid(l, cx + 1u, cy + 1u);
    let ty = env_sample_linear(u.y, a + b, c + d);
    let p0 = a + (c - a) * ty;
    let p1 = b + (d - b) * ty;
    let tx = env_sample_linear(u.z, p0, p1);
    let pdf_uv = (p0 + (p1 - p0) * tx) / integral;
    let uv = vec2<f32>((f32(cx) + tx + 0.5) / f32(w), (f32(cy) + ty) / f32(h - 1u));
    let sin_t = max(sin(uv.y * PI), 1.1920929e-7);
    out.dir = normalize(env_mat(l, 4u, latlong_dir(uv)));
    out.pdf = pdf_uv / (2.0 * PI * PI * sin_t);
    return out;
}

// The solid-angle density of world direction d under the map (environment::image_pdf).
fn env_pdf_map(l: Light, d: vec3<f32>) -> f32 {
    let dl = env_mat(l, 13u, d);
    let sin_t = sqrt(max(dl.x * dl.x + dl.z * dl.z, 1.4210855e-14));
    return env_pdf_uv(l, latlong_uv(dl)) / (2.0 * PI * PI * sin_t);
}

// A shadow-ray direction (environment::sample_direction): cosine about ns for a constant
// environment, else the map's distribution.
fn env_sample(l: Light, ns: vec3<f32>, u: vec3<f32>) -> EnvDir {
    if env_is_map(l) {
        return env_sample_map(l, u);
    }
    let dir = cosine_hemisphere(ns, u.y, u.z);
    return EnvDir(dir, max(dot(dir, ns), 0.0) / PI);
}

// environment::direction_pdf.
fn env_pdf(l: Light, ns: vec3<f32>, d: vec3<f32>) -> f32 {
    if env_is_map(l) {
        return env_pdf_map(l, d);
    }
    return max(dot(d, ns), 0.0) / PI;
}

// environment::emit_direction: uniform for a constant environment, else the map's.
fn env_emit_dir(l: Light, u: vec3<f32>) -> EnvDir {
    if env_is_map(l) {
        return env_sample_map(l, u);
    }
    return EnvDir(uniform_sphere(u.y, u.z), 0.25 / PI);
}

// The environment as a light kind (twin of src/lights/environment/kind.rs): p0 the scene's
// bounding sphere (centre, radius), p1 = (radiance scale, start of its distribution in
// light_cdf), p2 = (power / (pi R^2), its map or NO_TEXTURE).
fn environment_emit(l: Light, u0: vec3<f32>, u3: f32, u4: f32) -> Emission {
    // From the disc two radii out towards w; an image's photon carries
    // L pi R^2 / (pdf power) = L / (pdf mean).
    let s = env_emit_dir(l, vec3<f32>(u0.x, u3, u4));
    let r = bitcast<f32>(l.p0.w);
    var e = Emission(light_vec(l.p0) + 2.0 * r * s.dir + light_disc(r, -s.dir, u0.y, u0.z), -s.dir, vec3<f32>(0.0), vec3<f32>(1.0));
    if env_is_map(l) {
        let tm = light_vec(l.p2) * s.pdf;
        e.scale = select(vec3<f32>(0.0), env_radiance(l, s.dir) / tm, tm > vec3<f32>(0.0));
    }
    return e;
}

// ns: the shading normal at x (the constant environment samples a cosine about it).
fn environment_sample(l: Light, x: vec3<f32>, ns: vec3<f32>, u: vec3<f32>) -> LightSample {
    let s = env_sample(l, ns, u);
    if s.pdf <= 0.0 {
        return LightSample(x + s.dir, vec3<f32>(0.0), true, 0.0);
    }
    return LightSample(x + s.dir, env_radiance(l, s.dir) / s.pdf, true, s.pdf);
}

fn environment_anchor(l: Light, u: vec3<f32>) -> Anchor {
    return Anchor(vec3<f32>(0.0), false);
}

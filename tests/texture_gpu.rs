//! Oracle test of `src/textures/texture.wgsl` against `texture::SceneTexture::eval`: a
//! probe kernel of this test's own (the library, the two bindings it expects, one entry
//! point) evaluates colour and alpha at a few thousand uv per texture: 8-bit sRGB and raw,
//! float RGB and RGBA, grey+alpha, every wrap mode, both filters, uv transforms, a
//! checkerboard; and the luminance gradient (`texture_grad`, `SceneTexture::eval_grad`) at
//! the same points. On lavapipe every lookup must be bit for bit equal (it is: same LUT words,
//! same operations in the same order). Other drivers may fuse a multiply and an add or
//! reorder a sum (Vulkan allows both): there a single fetch (nearest, checkerboard) must
//! still be bit for bit equal except within rounding of a texel boundary, and a bilinear
//! lookup within the texture's contrast times the pixel coordinate's rounding plus 8 ulp of
//! its largest texel. Counts and worst ulp are printed. Without a Vulkan adapter the device
//! test is skipped (CI=true makes that a failure).

mod common;

use glam::{Vec2, Vec3};
use gpu_photon::integrators::gpu::buffers::{empty_buffer, read_back, storage_buffer};
use gpu_photon::integrators::gpu::shaders::validate;
use gpu_photon::integrators::gpu::texture_buffers::layout_entries;
use gpu_photon::integrators::gpu::textures::{wgsl_library, GpuTexture, PackedTextures};
use gpu_photon::textures::{
    Checkerboard, Encoding, Filter, Sampler, SceneTexture, Texture, UvTransform, Wrap,
};
use std::path::Path;

const PROBE: &str = "
@group(0) @binding(0) var<storage, read> tex_table: array<TextureRecord>;
@group(0) @binding(1) var<storage, read> tex_words: array<u32>;
@group(0) @binding(2) var<storage, read> probe_in: array<vec4<f32>>;
@group(0) @binding(3) var<storage, read_write> probe_out: array<vec4<f32>>;

@compute @workgroup_size(64)
fn probe_texture(@builtin(global_invocation_id) g: vec3<u32>) {
    let i = g.x;
    if i >= arrayLength(&probe_in) {
        return;
    }
    let q = probe_in[i];
    let id = bitcast<u32>(q.z);
    if q.w != 0.0 {
        probe_out[i] = vec4<f32>(texture_grad(id, q.xy), 0.0, 0.0);
    } else {
        probe_out[i] = vec4<f32>(texture_eval(id, q.xy), texture_alpha(id, q.xy));
    }
}
";

fn source() -> String {
    format!("{}\n{PROBE}", wgsl_library())
}

fn data(name: &str) -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/textures")
        .join(name)
}

/// The textures under test, and whether each is looked up by single fetches.
fn textures() -> Vec<(SceneTexture, bool)> {
    use Filter::*;
    use Wrap::*;
    let id = UvTransform::IDENTITY;
    let gltf = UvTransform::from_gltf([0.25, -0.5], 0.7, [1.5, -2.0]);
    let mitsuba = UvTransform::from_mitsuba([[0.5, 1.25, 0.1], [-0.75, 0.3, 0.2], [0.0, 0.0, 1.0]]);
    let mut rng = common::TestRng(11);
    let raw8: Vec<u32> = (0..37 * 23)
        .map(|_| (rng.f32() * 4294967295.0) as u32)
        .collect();
    let float4: Vec<f32> = (0..13 * 7 * 4).map(|_| rng.f32() * 8.0).collect();
    let random8 = |enc| Texture::from_rgba8("random 37x23", 37, 23, raw8.clone(), enc).unwrap();
    let f4 = Texture::from_float("random 13x7 rgba", 13, 7, float4, 4).unwrap();
    let (srgb, raw) = (Encoding::Srgb, Encoding::Raw);
    let file = |name, enc| Texture::load(&data(name), enc).expect("test image");
    let images = [
        (file("rgb4x3.png", srgb), Bilinear, Repeat, Repeat, id),
        (file("rgb4x3.png", raw), Nearest, Mirror, Clamp, id),
        (file("rgb4x3.png", srgb), Nearest, Repeat, Mirror, gltf),
        (file("rgba3x3.png", srgb), Bilinear, Clamp, Mirror, gltf),
        (file("ya3x2.png", srgb), Nearest, Clamp, Repeat, id),
        (file("ya3x2.png", raw), Bilinear, Mirror, Repeat, mitsuba),
        (file("float4x3.exr", raw), Bilinear, Mirror, Mirror, id),
        (file("float4x3.hdr", raw), Nearest, Clamp, Clamp, mitsuba),
        (random8(raw), Bilinear, Mirror, Repeat, id),
        (random8(srgb), Bilinear, Clamp, Clamp, mitsuba),
        (random8(raw), Nearest, Repeat, Repeat, gltf),
        (f4.clone(), Bilinear, Repeat, Clamp, gltf),
        (f4, Nearest, Mirror, Mirror, id),
    ];
    let mut out: Vec<(SceneTexture, bool)> = images
        .into_iter()
        .map(|(t, filter, wrap_u, wrap_v, to_uv)| {
            let s = Sampler {
                filter,
                wrap_u,
                wrap_v,
                to_uv,
            };
            (SceneTexture::Bitmap(t.with_sampler(s)), filter == Nearest)
        })
        .collect();
    out.push((SceneTexture::Checkerboard(Checkerboard::default()), true));
    let c = Checkerboard {
        color0: Vec3::new(0.1, 0.2, 0.3),
        color1: Vec3::new(0.9, 0.8, 0.7),
        to_uv: mitsuba,
    };
    out.push((SceneTexture::Checkerboard(c), true));
    out
}

/// The textures under test, `uvs`, and the probe's answer at every (texture, point), texture
/// after texture: `texture_grad` where `grad`, else `texture_eval` and `texture_alpha`.
#[allow(clippy::type_complexity)]
fn probe_textures(
    ctx: &gpu_photon::integrators::gpu::GpuContext,
    uvs: Vec<Vec2>,
    grad: bool,
) -> (Vec<(SceneTexture, bool)>, Vec<Vec2>, Vec<[f32; 4]>) {
    let cases = textures();
    let list: Vec<SceneTexture> = cases.iter().map(|(t, _)| t.clone()).collect();
    let packed = PackedTextures::pack(&list, ctx.max_binding).unwrap();
    let bufs = packed.upload(ctx).unwrap();
    let mode = grad as u32 as f32;
    let mut input = Vec::new();
    for id in 0..list.len() as u32 {
        input.extend(uvs.iter().map(|p| [p.x, p.y, f32::from_bits(id), mode]));
    }
    let got = run_probe(ctx, &bufs, &input);
    (cases, uvs, got)
}

/// uv points: uniform over [-3, 4]^2, then the texel-centre lattice of a 4x3 image.
fn points(n: usize, seed: u64) -> Vec<Vec2> {
    let mut r = common::TestRng(seed);
    let mut v: Vec<Vec2> = (0..n)
        .map(|_| Vec2::new(r.f32() * 7.0 - 3.0, r.f32() * 7.0 - 3.0))
        .collect();
    for i in -4..12 {
        for j in -3..9 {
            v.push(Vec2::new((i as f32 + 0.5) / 4.0, (j as f32 + 0.5) / 3.0));
        }
    }
    v
}

#[test]
fn texture_library_validates_and_matches_the_rust_record() {
    let module = validate(&source()).unwrap_or_else(|e| panic!("texture.wgsl: {e}"));
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).unwrap();
    let (handle, _) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some("TextureRecord"))
        .expect("TextureRecord");
    assert_eq!(
        layouter[handle].size as usize,
        std::mem::size_of::<GpuTexture>()
    );
    assert_eq!(std::mem::size_of::<GpuTexture>(), 96);
}

#[test]
fn wgsl_texture_eval_equals_rust() {
    let Some(ctx) = common::gpu() else { return };
    let (cases, uvs, got) = probe_textures(&ctx, points(4000, 5), false);
    // On lavapipe every operation keeps its written order (the uv transform is written in the
    // order Mesa would otherwise reorder it to): every lookup must be bit for bit equal.
    let strict = ctx.adapter.get_info().name.contains("llvmpipe");
    let mut report = Vec::new();
    for (id, (tex, exact)) in cases.iter().enumerate() {
        let (range, peak) = texel_spread(tex);
        let (mut worst, mut differ) = (0u32, 0);
        for (k, p) in uvs.iter().enumerate() {
            let g = got[id * uvs.len() + k];
            let want = tex.eval(*p).extend(tex.eval_alpha(*p));
            let (near, dpx) = slack(tex, *p);
            for c in 0..4 {
                if g[c].to_bits() == want[c].to_bits() {
                    continue;
                }
                let what = format!(
                    "texture {id} uv {p} channel {c}: gpu {} cpu {}",
                    g[c], want[c]
                );
                assert!(!strict, "{what}: lavapipe must agree bit for bit");
                differ += 1;
                worst = worst.max(ulps(g[c], want[c]));
                if *exact {
                    assert!(near, "{what}: a single fetch, not at a texel boundary");
                } else {
                    let tol = range[c] * dpx + 8.0 * f32::EPSILON * peak[c];
                    assert!(
                        (g[c] - want[c]).abs() <= tol,
                        "{what}: more than {tol} apart"
                    );
                }
            }
        }
        let kind = if *exact { "fetch" } else { "bilinear" };
        report.push(format!(
            "texture {id} ({kind}): {differ} channels not bit for bit, worst {worst} ulp"
        ));
    }
    eprintln!("{}\n{}", ctx.describe(), report.join("\n"));
}

/// `texture_grad` (a bump map's luminance gradient) equals `SceneTexture::eval_grad` on the
/// same textures and points, away from the texel-centre lines where the bilinear gradient
/// jumps: within the luminance's spread times the pixel coordinate's rounding (the weights'
/// error) plus 16 ulp of its peak, carried through the uv transform and the resolution. Zero
/// exactly for nearest lookups and checkerboards.
#[test]
fn wgsl_texture_grad_equals_rust() {
    let Some(ctx) = common::gpu() else { return };
    let (cases, uvs, got) = probe_textures(&ctx, points(2000, 9), true);
    let (mut checked, mut worst) = (0, 0f32);
    for (id, (tex, exact)) in cases.iter().enumerate() {
        let (range, peak) = texel_spread(tex);
        let (range, peak) = (
            range[..3].iter().sum::<f32>(),
            peak[..3].iter().sum::<f32>(),
        );
        for (k, p) in uvs.iter().enumerate() {
            let g = got[id * uvs.len() + k];
            let want = tex.eval_grad(*p);
            let what = format!("texture {id} uv {p}: gpu {g:?} cpu {want}");
            if *exact {
                assert_eq!(want, Vec2::ZERO, "{what}");
                assert_eq!([g[0], g[1]], [0.0, 0.0], "{what}");
                continue;
            }
            let SceneTexture::Bitmap(t) = tex else {
                unreachable!()
            };
            let (near, dpx) = slack(tex, *p);
            if near {
                continue;
            }
            let [r0, r1] = t.sampler.to_uv.rows;
            let per_texel = 4.0 * range * dpx + 16.0 * f32::EPSILON * peak;
            let tol = Vec2::new(
                t.width as f32 * (r0[0].abs() + r1[0].abs()),
                t.height as f32 * (r0[1].abs() + r1[1].abs()),
            ) * per_texel;
            let e = (Vec2::new(g[0], g[1]) - want).abs();
            assert!(e.x <= tol.x && e.y <= tol.y, "{what}: bound {tol}");
            worst = worst.max((e / tol.max(Vec2::splat(f32::MIN_POSITIVE))).max_element());
            checked += 1;
        }
    }
    assert!(checked > 10_000, "{checked}");
    eprintln!("{checked} bilinear gradients, worst at {worst:.3} of the bound");
}

/// How far apart the device's and the host's pixel coordinates may be at `uv`, summed over
/// both axes (the uv transform's 3 terms and the scale to pixels, each rounded once or
/// contracted), and whether that reaches a texel boundary (a checkerboard's square edge),
/// where a nearest lookup may take the other texel.
fn slack(tex: &SceneTexture, uv: Vec2) -> (bool, f32) {
    let (to_uv, size) = match tex {
        SceneTexture::Bitmap(t) => (t.sampler.to_uv, Vec2::new(t.width as f32, t.height as f32)),
        SceneTexture::Checkerboard(c) => (c.to_uv, Vec2::splat(2.0)),
    };
    let e = 2.0 * f32::EPSILON;
    let p = to_uv.apply(uv);
    let (mut near, mut sum) = (false, 0.0);
    for (k, row) in to_uv.rows.iter().enumerate() {
        let du = e * ((row[0] * uv.x).abs() + (row[1] * uv.y).abs() + row[2].abs());
        let px = p[k] * size[k];
        let dp = size[k] * du + e * (px.abs() + 1.0);
        let bilinear = px - 0.5;
        near |= (px - px.round()).abs() <= dp || (bilinear - bilinear.round()).abs() <= dp;
        sum += dp;
    }
    (near, sum)
}

/// Per channel (RGB, alpha): the largest difference between two texels and the largest
/// magnitude.
fn texel_spread(tex: &SceneTexture) -> ([f32; 4], [f32; 4]) {
    let SceneTexture::Bitmap(t) = tex else {
        return ([0.0; 4], [1.0; 4]);
    };
    let (mut lo, mut hi) = ([f32::MAX; 4], [f32::MIN; 4]);
    for y in 0..t.height {
        for x in 0..t.width {
            let v = t.texel(x, y);
            for c in 0..4 {
                lo[c] = lo[c].min(v[c]);
                hi[c] = hi[c].max(v[c]);
            }
        }
    }
    let range = std::array::from_fn(|c| hi[c] - lo[c]);
    let peak = std::array::from_fn(|c| hi[c].abs().max(lo[c].abs()));
    (range, peak)
}

fn ulps(a: f32, b: f32) -> u32 {
    if a == b {
        return 0;
    }
    (a.to_bits() as i64 - b.to_bits() as i64)
        .unsigned_abs()
        .min(u32::MAX as u64) as u32
}

fn run_probe(
    ctx: &gpu_photon::integrators::gpu::GpuContext,
    bufs: &gpu_photon::integrators::gpu::texture_buffers::TextureBuffers,
    input: &[[f32; 4]],
) -> Vec<[f32; 4]> {
    let dev = &ctx.device;
    let module = dev.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: Some("texture probe"),
        source: wgpu::ShaderSource::Wgsl(source().into()),
    });
    let [t, w] = layout_entries(0, 1);
    let io = |binding, read_only| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::COMPUTE,
        ty: wgpu::BindingType::Buffer {
            ty: wgpu::BufferBindingType::Storage { read_only },
            has_dynamic_offset: false,
            min_binding_size: None,
        },
        count: None,
    };
    let layout = dev.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("texture probe"),
        entries: &[t, w, io(2, true), io(3, false)],
    });
    let pl = dev.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
        label: Some("texture probe"),
        bind_group_layouts: &[Some(&layout)],
        immediate_size: 0,
    });
    let pipeline = dev.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: Some("texture probe"),
        layout: Some(&pl),
        module: &module,
        entry_point: Some("probe_texture"),
        compilation_options: Default::default(),
        cache: None,
    });
    let bytes = (input.len() * 16) as u64;
    let inb = storage_buffer(dev, "probe in", input, wgpu::BufferUsages::empty());
    let out = empty_buffer(
        dev,
        "probe out",
        bytes,
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
    );
    let [e0, e1] = bufs.entries(0, 1);
    let bind = dev.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some("texture probe"),
        layout: &layout,
        entries: &[
            e0,
            e1,
            wgpu::BindGroupEntry {
                binding: 2,
                resource: inb.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 3,
                resource: out.as_entire_binding(),
            },
        ],
    });
    let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor { label: None });
    {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: None,
            timestamp_writes: None,
        });
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups((input.len() as u32).div_ceil(64), 1, 1);
    }
    ctx.queue.submit([enc.finish()]);
    let got = read_back(ctx, &out, bytes).unwrap();
    ctx.check().unwrap();
    got
}

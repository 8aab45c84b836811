//! Unit tests of the texture lookups: the decoding tables, texel centres, wraps, glTF codes
//! and `KHR_texture_transform`, the checkerboard, and the constructors' checks.

use super::*;

fn rgba8(w: u32, h: u32, texels: &[[u8; 4]], enc: Encoding) -> Texture {
    Texture::from_rgba8(
        "test",
        w,
        h,
        texels.iter().map(|c| pack_rgba8(*c)).collect(),
        enc,
    )
    .unwrap()
}

#[test]
fn tables_decode_the_ends_exactly_and_grow() {
    for enc in [Encoding::Srgb, Encoding::Raw] {
        let lut = enc.lut();
        assert_eq!((lut[0], lut[255]), (0.0, 1.0));
        assert!(lut.windows(2).all(|w| w[0] < w[1]));
    }
    assert_eq!(Encoding::Raw.lut()[51], 0.2);
    assert!((Encoding::Srgb.lut()[128] - 0.215_860_5).abs() < 1e-6);
}

#[test]
fn texel_centres_give_the_texel_and_v_runs_down_the_rows() {
    let t: Vec<[u8; 4]> = (0..6).map(|i| [i * 40, 255 - i * 40, 7, 255 - i]).collect();
    for filter in [Filter::Nearest, Filter::Bilinear] {
        let tex = rgba8(3, 2, &t, Encoding::Raw).with_sampler(Sampler::mitsuba(
            filter,
            Wrap::Repeat,
            UvTransform::IDENTITY,
        ));
        for y in 0..2 {
            for x in 0..3 {
                let uv = Vec2::new((x as f32 + 0.5) / 3.0, (y as f32 + 0.5) / 2.0);
                assert_eq!(
                    tex.eval_rgba(uv),
                    tex.texel(x, y),
                    "{filter:?} texel {x},{y}"
                );
            }
        }
        // Row 0 (the file's first, the image's top) is at small v.
        if filter == Filter::Nearest {
            assert_eq!(tex.eval(Vec2::new(0.1, 0.2)).x, 0.0);
            assert_eq!(tex.eval(Vec2::new(0.1, 0.8)).x, Encoding::Raw.lut()[120]);
        }
    }
}

#[test]
fn bilinear_wraps_each_texel_at_the_border() {
    let t = [[0, 0, 0, 255], [255, 0, 0, 255]];
    let at = |wrap| {
        rgba8(2, 1, &t, Encoding::Raw)
            .with_sampler(Sampler::mitsuba(
                Filter::Bilinear,
                wrap,
                UvTransform::IDENTITY,
            ))
            .eval(Vec2::new(0.0, 0.5))
            .x
    };
    assert_eq!(at(Wrap::Repeat), 0.5); // halfway between the last texel and the first
    assert_eq!(at(Wrap::Clamp), 0.0);
    assert_eq!(at(Wrap::Mirror), 0.0);
}

#[test]
fn wrap_indices() {
    let idx = |w: Wrap| (-5..9).map(|i| w.index(i, 3)).collect::<Vec<_>>();
    assert_eq!(
        idx(Wrap::Repeat),
        [1, 2, 0, 1, 2, 0, 1, 2, 0, 1, 2, 0, 1, 2]
    );
    assert_eq!(idx(Wrap::Clamp), [0, 0, 0, 0, 0, 0, 1, 2, 2, 2, 2, 2, 2, 2]);
    assert_eq!(
        idx(Wrap::Mirror),
        [1, 2, 2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 1, 2]
    );
}

#[test]
fn gltf_sampler_codes() {
    let s = Sampler::gltf(Some(9728), Some(33071), Some(33648), UvTransform::IDENTITY).unwrap();
    assert_eq!(
        (s.filter, s.wrap_u, s.wrap_v),
        (Filter::Nearest, Wrap::Clamp, Wrap::Mirror)
    );
    let d = Sampler::gltf(None, None, Some(10497), UvTransform::IDENTITY).unwrap();
    assert_eq!(
        (d.filter, d.wrap_u, d.wrap_v),
        (Filter::Bilinear, Wrap::Repeat, Wrap::Repeat)
    );
    for (code, f) in [
        (9984, Filter::Nearest),
        (9985, Filter::Bilinear),
        (9986, Filter::Nearest),
        (9987, Filter::Bilinear),
    ] {
        assert_eq!(Filter::from_gltf(Some(code)).unwrap(), f);
    }
    assert!(Filter::from_gltf(Some(1)).is_err());
    assert!(Wrap::from_gltf(Some(2)).is_err());
    assert!(Wrap::from_mitsuba("tile").is_err());
}

#[test]
fn khr_texture_transform_matches_the_extension_examples() {
    // "The lower left quadrant of the image, rotated clockwise 90 degrees."
    let t = UvTransform::from_gltf([0.0, 1.0], std::f32::consts::FRAC_PI_2, [0.5, 0.5]);
    for (uv, want) in [
        ((0.0, 0.0), (0.0, 1.0)),
        ((1.0, 0.0), (0.0, 0.5)),
        ((1.0, 1.0), (0.5, 0.5)),
        ((0.0, 1.0), (0.5, 1.0)),
    ] {
        let got = t.apply(Vec2::new(uv.0, uv.1));
        assert!(
            (got - Vec2::new(want.0, want.1)).length() < 1e-6,
            "{uv:?}: {got}"
        );
    }
    // "Inverts the T axis."
    let flip = UvTransform::from_gltf([0.0, 1.0], 0.0, [1.0, -1.0]);
    assert_eq!(flip.apply(Vec2::new(0.25, 0.25)), Vec2::new(0.25, 0.75));
    // Composition: after(first) applies first, then self.
    let a = UvTransform::from_gltf([0.3, 0.1], 0.4, [2.0, 3.0]);
    let p = Vec2::new(0.7, -0.2);
    let both = t.after(&a).apply(p);
    assert!((both - t.apply(a.apply(p))).length() < 1e-5);
}

#[test]
fn checkerboard_is_mitsubas() {
    let c = Checkerboard::default();
    assert_eq!(c.eval(Vec2::new(0.25, 0.25)), Vec3::splat(0.4));
    assert_eq!(c.eval(Vec2::new(0.75, 0.25)), Vec3::splat(0.2));
    assert_eq!(c.eval(Vec2::new(0.75, 0.75)), Vec3::splat(0.4));
    assert_eq!(c.eval(Vec2::new(-0.25, 0.25)), Vec3::splat(0.2));
    assert!((c.mean() - Vec3::splat(0.3)).length() < 1e-7);
}

#[test]
fn alpha_mean_and_float_texels() {
    let tex = rgba8(2, 1, &[[255, 0, 0, 0], [0, 0, 255, 255]], Encoding::Srgb);
    assert_eq!(tex.mean(), Vec3::new(0.5, 0.0, 0.5));
    assert!(tex.has_alpha());
    let mid = tex.with_sampler(Sampler::mitsuba(
        Filter::Bilinear,
        Wrap::Clamp,
        UvTransform::IDENTITY,
    ));
    assert_eq!(mid.eval_alpha(Vec2::new(0.5, 0.5)), 0.5);
    let f = Texture::from_float("f", 1, 2, vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0], 3).unwrap();
    assert_eq!(f.texel(0, 1), Vec4::new(4.0, 5.0, 6.0, 1.0));
    assert!(!f.has_alpha());
}

#[test]
fn constructors_refuse_bad_sizes() {
    assert!(Texture::from_rgba8("x", 2, 2, vec![0; 3], Encoding::Raw).is_err());
    assert!(Texture::from_float("x", 1, 1, vec![0.0; 3], 2).is_err());
    assert!(check_size("x", 0, 5).is_err());
    assert!(check_size("x", MAX_SIDE + 1, 1).is_err());
    assert!(check_size("x", MAX_SIDE, MAX_SIDE).is_ok());
    let e = check_size("big.png", 20000, 20000).unwrap_err().to_string();
    assert!(e.contains("big.png") && e.contains("too large"), "{e}");
}

#[test]
fn far_and_non_finite_uv_stay_defined() {
    let tex = rgba8(2, 2, &[[10, 20, 30, 255]; 4], Encoding::Raw);
    for uv in [
        Vec2::new(1e30, -1e30),
        Vec2::new(f32::NAN, 0.5),
        Vec2::new(f32::INFINITY, 0.0),
    ] {
        assert_eq!(tex.eval(uv), tex.texel(0, 0).truncate(), "{uv}");
    }
}

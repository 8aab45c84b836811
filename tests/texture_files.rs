//! Texture files: every supported format decodes to the expected texels (grey expanded to
//! RGB, alpha kept, 16-bit and float images as float texels), and a missing, corrupt,
//! unknown or oversized file is an error naming it, refused before its texels are decoded.

use glam::{Vec2, Vec4};
use gpu_photon::integrators::gpu::textures::PackedTextures;
use gpu_photon::textures::{decode, srgb_to_linear, Encoding, SceneTexture, Texels, Texture};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/textures")
        .join(name)
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("gpu-photon-texture-files-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn png_grey_alpha_and_rgba() {
    let ya = Texture::load(&data("ya3x2.png"), Encoding::Raw).unwrap();
    assert_eq!((ya.width, ya.height), (3, 2));
    assert!(matches!(ya.texels, Texels::Rgba8 { .. }));
    // Texel (1, 0) is grey 90, alpha 128; (0, 1) grey 255, alpha 64.
    assert_eq!(
        ya.texel(1, 0),
        Vec4::new(90.0 / 255.0, 90.0 / 255.0, 90.0 / 255.0, 128.0 / 255.0)
    );
    assert_eq!(ya.texel(0, 1).w, 64.0 / 255.0);
    let rgba = Texture::load(&data("rgba3x3.png"), Encoding::Srgb).unwrap();
    let t = rgba.texel(2, 1); // [185, 180, 85, 165]
    assert_eq!(t.x, srgb_to_linear(185.0 / 255.0) as f32);
    assert_eq!(t.w, 165.0 / 255.0);
    assert_eq!(rgba.eval_alpha(Vec2::new(5.0 / 6.0, 0.5)), t.w);
}

#[test]
fn float_images_are_linear() {
    for name in ["float4x3.exr", "float4x3.hdr"] {
        // The encoding does not apply to float images.
        let t = Texture::load(&data(name), Encoding::Srgb).unwrap();
        assert!(
            matches!(t.texels, Texels::Float { channels: 3, .. }),
            "{name}"
        );
        assert_eq!(t.texel(1, 2), Vec4::new(1.75, 1.5, 0.75, 1.0), "{name}");
    }
}

#[test]
fn jpeg_bmp_and_16_bit_png() {
    let (w, h) = (8, 4);
    let rgb: Vec<u8> = (0..w * h).flat_map(|i| [(i * 7) as u8, 128, 200]).collect();
    let bmp = scratch("t.bmp");
    image::save_buffer(&bmp, &rgb, w, h, image::ColorType::Rgb8).unwrap();
    let t = Texture::load(&bmp, Encoding::Raw).unwrap();
    assert_eq!(
        t.texel(3, 2),
        Vec4::new(
            ((2 * 8 + 3) * 7) as f32 / 255.0,
            128.0 / 255.0,
            200.0 / 255.0,
            1.0
        )
    );
    let jpg = scratch("t.jpg");
    let flat = vec![90u8; (w * h * 3) as usize];
    image::save_buffer(&jpg, &flat, w, h, image::ColorType::Rgb8).unwrap();
    let t = Texture::load(&jpg, Encoding::Raw).unwrap();
    assert_eq!((t.width, t.height), (w, h));
    assert!((t.texel(5, 1).x - 90.0 / 255.0).abs() < 2.0 / 255.0);
    let png16 = scratch("t16.png");
    let grey: Vec<u8> = [0u16, 65535, 32768, 1000]
        .iter()
        .flat_map(|v| v.to_ne_bytes())
        .collect();
    image::save_buffer(&png16, &grey, 2, 2, image::ColorType::L16).unwrap();
    let t = Texture::load(&png16, Encoding::Srgb).unwrap();
    assert!(matches!(t.texels, Texels::Float { channels: 3, .. }));
    let want = srgb_to_linear(32768.0 / 65535.0) as f32;
    assert!((t.texel(0, 1).x - want).abs() < 1e-6 && t.texel(1, 0).y == 1.0);
}

fn assert_error_names(path: &Path, needle: &str) {
    let e = Texture::load(path, Encoding::Srgb)
        .expect_err("must fail")
        .to_string();
    assert!(
        e.contains(&path.display().to_string()),
        "error does not name the file: {e}"
    );
    assert!(e.contains(needle), "expected '{needle}' in: {e}");
}

#[test]
fn missing_corrupt_and_unknown_files_are_errors_naming_them() {
    assert_error_names(&scratch("nope.png"), "No such file");
    let corrupt = scratch("corrupt.png");
    let mut bytes = std::fs::read(data("rgb4x3.png")).unwrap();
    bytes.truncate(40);
    std::fs::write(&corrupt, &bytes).unwrap();
    assert_error_names(&corrupt, "");
    let unknown = scratch("unknown.png");
    std::fs::write(&unknown, b"not an image at all").unwrap();
    assert_error_names(&unknown, "unknown image format");
    let exr = scratch("corrupt.exr");
    let mut bytes = std::fs::read(data("float4x3.exr")).unwrap();
    bytes.truncate(bytes.len() / 2);
    std::fs::write(&exr, &bytes).unwrap();
    assert_error_names(&exr, "");
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut c = !0u32;
    for &b in bytes {
        c ^= b as u32;
        for _ in 0..8 {
            c = if c & 1 == 1 {
                0xedb8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
    }
    !c
}

/// A PNG whose header claims `w` x `h` (RGB8) and which holds no image data.
fn png_header(w: u32, h: u32) -> Vec<u8> {
    let mut out = vec![0x89, b'P', b'N', b'G', 0x0d, 0x0a, 0x1a, 0x0a];
    let mut chunk = b"IHDR".to_vec();
    chunk.extend(w.to_be_bytes());
    chunk.extend(h.to_be_bytes());
    chunk.extend([8, 2, 0, 0, 0]);
    out.extend(13u32.to_be_bytes());
    out.extend(&chunk);
    out.extend(crc32(&chunk).to_be_bytes());
    // An empty IDAT chunk: decoders read the header up to the first data chunk.
    out.extend(0u32.to_be_bytes());
    out.extend(b"IDAT");
    out.extend(crc32(b"IDAT").to_be_bytes());
    out
}

#[test]
fn oversized_images_are_refused_from_their_header() {
    for (w, h) in [(20_000, 4), (4, 16_385), (16_384, 16_384 + 1)] {
        let e = decode::decode("huge.png", &png_header(w, h), Encoding::Srgb)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("huge.png") && e.contains("too large"),
            "{w}x{h}: {e}"
        );
    }
    // The largest allowed size passes the size check (and fails only for want of data).
    let e = decode::decode("max.png", &png_header(16_384, 16_384), Encoding::Srgb)
        .unwrap_err()
        .to_string();
    assert!(!e.contains("too large"), "{e}");
}

#[test]
fn packing_checks_the_binding_size() {
    let t = Texture::load(&data("float4x3.exr"), Encoding::Raw).unwrap();
    let list = vec![SceneTexture::Bitmap(t)];
    let packed = PackedTextures::pack(&list, 1 << 20).unwrap();
    assert_eq!(packed.words.len(), 512 + 36);
    assert_eq!(packed.table[0].offset, 512);
    let e = PackedTextures::pack(&list, 1024).unwrap_err().to_string();
    assert!(e.contains("storage buffer"), "{e}");
}

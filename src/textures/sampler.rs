//! How a texture is looked up: the filter, the wrap mode of each axis and the affine uv
//! transform applied first (Mitsuba's `to_uv`, glTF's `KHR_texture_transform`), with the
//! glTF sampler codes. The integer wrap here is the one `src/textures/texture.wgsl` does.

use crate::error::{Error, Result};
use glam::Vec2;

/// How texels are combined at a lookup.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Filter {
    /// The texel containing the point (Mitsuba `nearest`, glTF 9728).
    Nearest,
    /// Bilinear interpolation between the four nearest texel centres (Mitsuba `bilinear`,
    /// the default; glTF 9729).
    #[default]
    Bilinear,
}

/// What an integer texel coordinate outside the image becomes, per axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Wrap {
    /// Tile the image (Mitsuba `repeat`, the default; glTF 10497).
    #[default]
    Repeat,
    /// Tile with every other copy reflected, edges repeated (Mitsuba `mirror`, glTF 33648).
    Mirror,
    /// The nearest edge texel (Mitsuba `clamp`, glTF 33071).
    Clamp,
}

impl Filter {
    /// The GPU code of the filter (`src/textures/texture.wgsl`).
    pub fn code(self) -> u32 {
        self as u32
    }

    /// A Mitsuba `filter_type` value.
    pub fn from_mitsuba(name: &str) -> Result<Self> {
        match name {
            "nearest" => Ok(Filter::Nearest),
            "bilinear" => Ok(Filter::Bilinear),
            _ => Err(bad("filter_type", name, "nearest or bilinear")),
        }
    }

    /// A glTF sampler `magFilter`/`minFilter` code (absent: bilinear). The mipmap minifying
    /// filters count as their base filter: 9984 and 9986 as nearest, 9985 and 9987 as linear.
    pub fn from_gltf(code: Option<u32>) -> Result<Self> {
        match code {
            None | Some(9729) | Some(9985) | Some(9987) => Ok(Filter::Bilinear),
            Some(9728) | Some(9984) | Some(9986) => Ok(Filter::Nearest),
            Some(c) => Err(bad("sampler filter", &c.to_string(), "a glTF filter code")),
        }
    }
}

impl Wrap {
    /// The GPU code of the wrap mode (`src/textures/texture.wgsl`).
    pub fn code(self) -> u32 {
        self as u32
    }

    /// A Mitsuba `wrap_mode` value.
    pub fn from_mitsuba(name: &str) -> Result<Self> {
        match name {
            "repeat" => Ok(Wrap::Repeat),
            "mirror" => Ok(Wrap::Mirror),
            "clamp" => Ok(Wrap::Clamp),
            _ => Err(bad("wrap_mode", name, "repeat, mirror or clamp")),
        }
    }

    /// A glTF sampler `wrapS`/`wrapT` code (absent: repeat).
    pub fn from_gltf(code: Option<u32>) -> Result<Self> {
        match code {
            None | Some(10497) => Ok(Wrap::Repeat),
            Some(33648) => Ok(Wrap::Mirror),
            Some(33071) => Ok(Wrap::Clamp),
            Some(c) => Err(bad("sampler wrap", &c.to_string(), "33071, 33648 or 10497")),
        }
    }

    /// The texel index in `0..n` that integer coordinate `i` reads (`n` > 0).
    pub fn index(self, i: i32, n: i32) -> i32 {
        match self {
            Wrap::Repeat => i.rem_euclid(n),
            Wrap::Clamp => i.clamp(0, n - 1),
            Wrap::Mirror => {
                let m = i.rem_euclid(2 * n);
                if m >= n {
                    2 * n - 1 - m
                } else {
                    m
                }
            }
        }
    }
}

fn bad(what: &str, value: &str, expected: &str) -> Error {
    Error::Setting {
        field: "texture",
        message: format!("{what} '{value}': expected {expected}"),
    }
}

/// An affine map of uv: `u' = a u + b v + c`, `v' = d u + e v + f` (rows `[a, b, c]` and
/// `[d, e, f]`), evaluated as `(a*u + c) + b*v` in f32, as the WGSL twin writes it (Mesa's
/// compiler reorders `(a*u + b*v) + c` into this, so lavapipe computes the same bits).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UvTransform {
    /// The two rows of the 2x3 matrix.
    pub rows: [[f32; 3]; 2],
}

impl Default for UvTransform {
    fn default() -> Self {
        UvTransform::IDENTITY
    }
}

impl UvTransform {
    /// uv unchanged.
    pub const IDENTITY: UvTransform = UvTransform {
        rows: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
    };

    /// Mitsuba's `to_uv` from its 3x3 matrix (rows; the last row, `[0, 0, 1]` for an affine
    /// map, is ignored, as Mitsuba's `ScalarAffineTransform3f` does).
    pub fn from_mitsuba(m: [[f32; 3]; 3]) -> Self {
        UvTransform { rows: [m[0], m[1]] }
    }

    /// glTF `KHR_texture_transform`: `T(offset) * R(rotation) * S(scale)`, scale first. The
    /// rotation is counter-clockwise in glTF's v-down uv space, `u' = cos u + sin v`,
    /// `v' = -sin u + cos v`: the matrix of the extension's example ("the lower left quadrant
    /// rotated clockwise 90 degrees") and of its reference implementations, whose GLSL
    /// listing has the opposite sign (KhronosGroup/glTF issue 1563).
    pub fn from_gltf(offset: [f32; 2], rotation: f32, scale: [f32; 2]) -> Self {
        let (s, c) = (rotation as f64).sin_cos();
        let (sx, sy) = (scale[0] as f64, scale[1] as f64);
        UvTransform {
            rows: [
                [(c * sx) as f32, (s * sy) as f32, offset[0]],
                [(-s * sx) as f32, (c * sy) as f32, offset[1]],
            ],
        }
    }

    /// `self` after `first`: the transform that applies `first`, then `self`.
    pub fn after(&self, first: &UvTransform) -> UvTransform {
        let (a, b) = (self.rows, first.rows);
        let mut r = [[0.0f32; 3]; 2];
        for i in 0..2 {
            for j in 0..3 {
                let t = if j == 2 { a[i][2] } else { 0.0 };
                r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + t;
            }
        }
        UvTransform { rows: r }
    }

    /// The transformed uv.
    pub fn apply(&self, uv: Vec2) -> Vec2 {
        let [r0, r1] = self.rows;
        Vec2::new(
            (r0[0] * uv.x + r0[2]) + r0[1] * uv.y,
            (r1[0] * uv.x + r1[2]) + r1[1] * uv.y,
        )
    }
}

/// A texture's lookup settings.
#[derive(Clone, Copy, Debug, PartialEq, Default)]
pub struct Sampler {
    /// Nearest or bilinear.
    pub filter: Filter,
    /// Wrap of u (image columns).
    pub wrap_u: Wrap,
    /// Wrap of v (image rows).
    pub wrap_v: Wrap,
    /// Applied to uv before the lookup.
    pub to_uv: UvTransform,
}

impl Sampler {
    /// Mitsuba's `bitmap` settings (one wrap mode for both axes).
    pub fn mitsuba(filter: Filter, wrap: Wrap, to_uv: UvTransform) -> Self {
        Sampler {
            filter,
            wrap_u: wrap,
            wrap_v: wrap,
            to_uv,
        }
    }

    /// A glTF sampler from its codes (each `None` when absent): `magFilter` decides the
    /// filter (this renderer has no mipmaps; a magnified and a minified lookup are the same).
    pub fn gltf(
        mag_filter: Option<u32>,
        wrap_s: Option<u32>,
        wrap_t: Option<u32>,
        to_uv: UvTransform,
    ) -> Result<Self> {
        Ok(Sampler {
            filter: Filter::from_gltf(mag_filter)?,
            wrap_u: Wrap::from_gltf(wrap_s)?,
            wrap_v: Wrap::from_gltf(wrap_t)?,
            to_uv,
        })
    }
}

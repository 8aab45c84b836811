//! The numbers Rust and WGSL share: surface-class, light, filter, Fresnel and bounce codes, the
//! bits of `Params.terms` and `MapParams.drop_flags`, stats indices, workgroup sizes and the
//! gather's bounds. Each is declared here once; [`wgsl_prelude`] writes them as WGSL `const`
//! declarations that `shaders.rs` puts before every kernel, so no WGSL file types one by hand
//! (tests/gpu_layout.rs checks the composed modules' constants against [`shared_constants`]).

use crate::bsdfs::SurfaceClass;
use crate::camera::pixel_filter::PixelFilter;
use crate::settings::{Filter, FresnelMode, Sampler};

/// Surface class ([`SurfaceClass`]) of a material that reflects nothing.
pub const CLASS_BLACK: u32 = 0;
/// Surface class of a material of delta lobes only (the specular chain).
pub const CLASS_DELTA: u32 = 1;
/// Surface class of a material that shades (diffuse part or non-delta lobe).
pub const CLASS_SHADED: u32 = 2;
/// Surface class of an index-matched boundary (the CPU backend only, for now).
pub const CLASS_NULL: u32 = 3;

/// `Material.alpha_mode` of an opaque surface.
pub const ALPHA_NONE: u32 = 0;
/// `Material.alpha_mode` of a mask: opaque where the opacity reaches the cutoff.
pub const ALPHA_MASK: u32 = 1;
/// `Material.alpha_mode` of a blend: opaque with probability the opacity.
pub const ALPHA_BLEND: u32 = 2;
/// Flag of `Material.alpha_mode`: the texture's luminance is the opacity (else its alpha).
pub const ALPHA_LUMINANCE: u32 = 4;

/// `Params.filter_kind` of the disc (constant) kernel.
pub const FILTER_DISC: u32 = 0;
/// `Params.filter_kind` of the cone kernel.
pub const FILTER_CONE: u32 = 1;
/// `Params.filter_kind` of the Epanechnikov kernel.
pub const FILTER_EPANECHNIKOV: u32 = 2;

/// `Params.fresnel` for the exact Fresnel equations.
pub const FRESNEL_EXACT: u32 = 0;
/// `Params.fresnel` for Schlick's approximation.
pub const FRESNEL_SCHLICK: u32 = 1;

/// `Params.sampler`: Owen-scrambled Sobol points.
pub const SAMPLER_SOBOL: u32 = 0;
/// `Params.sampler`: every number from the hash RNG.
pub const SAMPLER_INDEPENDENT: u32 = 1;

/// `Bounce.kind` (src/bsdfs/classic.wgsl): the photon is absorbed.
pub const BOUNCE_ABSORB: u32 = 0;
/// `Bounce.kind`: diffuse reflection.
pub const BOUNCE_DIFFUSE: u32 = 1;
/// `Bounce.kind`: a direction from the glossy lobe.
pub const BOUNCE_LOBE: u32 = 2;
/// `Bounce.kind`: a delta (mirror or glass) bounce; the path stays specular.
pub const BOUNCE_DELTA: u32 = 3;

/// `Params.terms` bit: shadow rays (`plan::Terms::direct`).
pub const TERM_DIRECT: u32 = 1;
/// `Params.terms` bit: the glossy lobe for delta lights
/// (`plan::Terms::point_lobe`).
pub const TERM_POINT_LOBE: u32 = 2;
/// `Params.terms` bit: a ray sampled from the glossy lobe (`plan::Terms::lobe_ray`).
pub const TERM_LOBE_RAY: u32 = 4;
/// `Params.terms` bit: a final-gather ray into the radiance cache instead of the global
/// map's estimate (`plan::Terms::final_gather`).
pub const TERM_FINAL_GATHER: u32 = 8;

/// `MapParams.drop_flags` bit: drop direct photons (`plan::StoreFilter::drop_direct`).
pub const DROP_DIRECT: u32 = 1;
/// `MapParams.drop_flags` bit: drop L S+ D photons (`plan::StoreFilter::drop_caustic`).
pub const DROP_CAUSTIC: u32 = 2;

/// `MapParams.volume_flags` bit: the map's paths store volume photons (`plan::VolumeSpec`).
pub const VOLUME_STORE: u32 = 1;
/// `MapParams.volume_flags` bit: a global map leaves the L S+ V volume photons to the caustic
/// map's paths (`plan::VolumeSpec::drop_caustic`).
pub const VOLUME_DROP_CAUSTIC: u32 = 2;

/// Index-matched boundaries a shadow ray crosses before it counts as blocked, and that a
/// photon path crosses before it is cut (twin of `cpu::media::MAX_CROSSINGS`, which
/// tests/media_gpu.rs checks it equals).
pub const MAX_CROSSINGS: u32 = 64;

/// Photons a volume-grid cell is sized to hold at the mean density (twin of
/// `cpu::volume_map::PHOTONS_PER_CELL`, which tests/media_gpu.rs checks it equals).
pub const VOLUME_PHOTONS_PER_CELL: f32 = 16.0;
/// Most volume photons a pass keeps: `size_volume`'s one workgroup reads at most 60,000 each
/// of its SCAN_BLOCK lanes (below lavapipe's loop cut).
pub const VOLUME_MAX_PHOTONS: u32 = SCAN_BLOCK * 60_000;

/// Index of the stats buffer: photons dropped because a map was full.
pub const STAT_PHOTON_OVERFLOW: u32 = 0;
/// Index of the stats buffer: invocations that exhausted their loop budget.
pub const STAT_LOOP_BUDGET: u32 = 1;
/// Index of the stats buffer: estimates cut at their cell or visit bound.
pub const STAT_GATHER_TRUNCATED: u32 = 2;
/// Length of the stats buffer in u32 counters.
pub const STATS_LEN: usize = 4;

/// Workgroup width of the one-dimensional kernels (tracing, grid build, probes) in the
/// default kernel shape (`shape::KernelShape::DEFAULT`; a render's is `GpuContext::shape`).
pub const WG_SIZE: u32 = 64;
/// Workgroup width of the grid's scan kernels: cells per scan block.
pub const SCAN_BLOCK: u32 = 256;
/// Consecutive cells each `scan_blocks` invocation sums (a scan block covers
/// SCAN_BLOCK * SCAN_ITEMS cells).
pub const SCAN_ITEMS: u32 = 16;
/// The gather's workgroups are GATHER_TILE x GATHER_TILE pixels (every kernel shape's, unless
/// forced: `shape::KernelShape::gather_tile`).
pub const GATHER_TILE: u32 = 8;

/// Invocations of a `build_cache` workgroup, which share one cache point's search, in the
/// default kernel shape: one lavapipe SIMD group, so its loops advance together (a render's
/// is the adapter's subgroup width, `shape::KernelShape::cache_lanes`).
pub const CACHE_LANES: u32 = 8;
/// Bins of `build_cache`'s distance histogram (a power of two, a multiple of CACHE_LANES).
pub const CACHE_BINS: u32 = 256;
/// Photons sharing the K-th's histogram bin that `build_cache` lists and ranks.
pub const CACHE_CANDIDATES: u32 = 128;
/// Photons before the K-th's bin that `build_cache` lists for its sum (more: it walks the
/// ring search's photons again). Its workgroup memory stays within 16 KB with CACHE_NEAR.
pub const CACHE_SELECT_LOW: u32 = 384;
/// Photons `build_cache`'s ring search lists in workgroup memory (later phases read them
/// there; when more lie in the rings, they walk the cells again).
pub const CACHE_NEAR: u32 = 1280;
/// `counters` index (a map's group) of the bits of the largest photon power channel the grid
/// holds (`count_cells`), the fixed-point scale of the fixed-radius estimates.
pub const COUNTER_MAX_POWER: u32 = 4;
/// `cache_list` index of the number of cache points (0..3: the cache values' dispatch).
pub const CACHE_LIST_COUNT: u32 = 3;
/// `cache_list` index of the first cache point.
pub const CACHE_LIST_FIRST: u32 = 4;
/// Rings of cells around a query's cell that a search visits at most (`grid::cell_size_for`
/// keeps cells at least radius / MAX_RINGS wide).
pub const MAX_RINGS: u32 = 5;

/// 16-byte words per element of the buffers the kernels read as `array<vec4<u32>>` (lavapipe
/// loads a vec4 in one per-lane loop, a struct in one per member); the WGSL accessors
/// (`load_triangle`, `map_photon`, ...) decode them. Const assertions in src/integrators/gpu/types.rs
/// tie each count to its twin's size.
pub const TRIANGLE_WORDS: u32 = 3;
/// Words per `Sphere`.
pub const SPHERE_WORDS: u32 = 2;
/// Words per `Material`.
pub const MATERIAL_WORDS: u32 = 6;
/// The word of a `Material` whose last member is its normal map (the intersection's read).
pub const MATERIAL_NORMAL_WORD: u32 = 1;
/// The word of a `Material` whose first two members are its bump map's scale and flag.
pub const MATERIAL_BUMP_WORD: u32 = 5;
/// The word of a `Material` that is its alpha test: mode, texture, factor, cutoff.
pub const MATERIAL_ALPHA_WORD: u32 = 2;
/// A `Material`'s `blend_first` when it is not a blend.
pub const NO_BLEND: u32 = u32::MAX;
/// 16-byte words of a `Medium` (`types::GpuMedium`).
pub const MEDIUM_WORDS: u32 = 2;
/// Words per `Light`.
pub const LIGHT_WORDS: u32 = 8;
/// The word of a `Light` whose last member is its emission texture (read alone by `bsdf_at`).
pub const LIGHT_EMISSION_WORD: u32 = 3;
/// Words per triangle of the `uvs` buffer: its corner uvs (`gpu::types::triangle_uvs`).
pub const UV_WORDS: u32 = 2;
/// Words per triangle of the `uvs` buffer when the scene has vertex tangents: the uvs, then
/// a tangent per corner.
pub const UV_TANGENT_WORDS: u32 = UV_WORDS + 3;
/// Words per `Photon` (every map buffer: traced, sorted, and the gather group's).
pub const PHOTON_WORDS: u32 = 3;

/// Largest K the gather kernel's heap holds.
pub const MAX_HEAP: u32 = 256;
/// Grid cells one K-nearest search may visit: rings 0..=MAX_RINGS, 11^3 (the radius fits in
/// them).
pub const MAX_CELLS: u32 = (2 * MAX_RINGS + 1).pow(3);

/// The WGSL code of a density-estimation filter.
pub fn filter_code(filter: Filter) -> u32 {
    match filter {
        Filter::Disc => FILTER_DISC,
        Filter::Cone => FILTER_CONE,
        Filter::Epanechnikov => FILTER_EPANECHNIKOV,
    }
}

/// The WGSL code of a sampler.
pub fn sampler_code(sampler: Sampler) -> u32 {
    match sampler {
        Sampler::Sobol => SAMPLER_SOBOL,
        Sampler::Independent => SAMPLER_INDEPENDENT,
    }
}

/// The WGSL code of a Fresnel mode.
pub fn fresnel_code(mode: FresnelMode) -> u32 {
    match mode {
        FresnelMode::Exact => FRESNEL_EXACT,
        FresnelMode::Schlick => FRESNEL_SCHLICK,
    }
}

/// The value of a shared constant, typed as WGSL declares it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WgslValue {
    /// A `u32`.
    U32(u32),
    /// An `f32`.
    F32(f32),
}

impl WgslValue {
    /// The WGSL type and literal: `u32 = 5u`, `f32 = 0.5f` (the shortest decimal that reads
    /// back as the same f32).
    fn declaration(self) -> String {
        match self {
            WgslValue::U32(v) => format!("u32 = {v}u"),
            WgslValue::F32(v) => format!("f32 = {v:?}f"),
        }
    }
}

/// Every constant of the WGSL prelude: (WGSL name, value).
pub fn shared_constants() -> Vec<(&'static str, WgslValue)> {
    use crate::math::rng::Stream;
    use WgslValue::{F32, U32};
    vec![
        ("CLASS_BLACK", U32(CLASS_BLACK)),
        ("CLASS_DELTA", U32(CLASS_DELTA)),
        ("CLASS_SHADED", U32(CLASS_SHADED)),
        ("CLASS_NULL", U32(CLASS_NULL)),
        (
            "ENV_HEADER_WORDS",
            U32(crate::lights::environment::sampling::ENV_HEADER_WORDS),
        ),
        ("FILTER_DISC", U32(FILTER_DISC)),
        ("FILTER_CONE", U32(FILTER_CONE)),
        ("FILTER_EPANECHNIKOV", U32(FILTER_EPANECHNIKOV)),
        ("FRESNEL_EXACT", U32(FRESNEL_EXACT)),
        ("FRESNEL_SCHLICK", U32(FRESNEL_SCHLICK)),
        ("SAMPLER_SOBOL", U32(SAMPLER_SOBOL)),
        ("SAMPLER_INDEPENDENT", U32(SAMPLER_INDEPENDENT)),
        ("BOUNCE_ABSORB", U32(BOUNCE_ABSORB)),
        ("BOUNCE_DIFFUSE", U32(BOUNCE_DIFFUSE)),
        ("BOUNCE_LOBE", U32(BOUNCE_LOBE)),
        ("BOUNCE_DELTA", U32(BOUNCE_DELTA)),
        (
            "GLASS_SPLIT_DEPTH",
            U32(crate::bsdfs::shading::GLASS_SPLIT_DEPTH),
        ),
        (
            "BRANCH_LISTS",
            U32(crate::integrators::gpu::branches::BRANCH_LISTS),
        ),
        (
            "BRANCH_SOBOL_UNUSED",
            U32(crate::integrators::gpu::branches::SOBOL_UNUSED),
        ),
        ("TERM_DIRECT", U32(TERM_DIRECT)),
        ("TERM_POINT_LOBE", U32(TERM_POINT_LOBE)),
        ("TERM_LOBE_RAY", U32(TERM_LOBE_RAY)),
        ("TERM_FINAL_GATHER", U32(TERM_FINAL_GATHER)),
        ("CACHE_STRIDE", U32(crate::integrators::plan::CACHE_STRIDE)),
        (
            "CACHE_NORMAL_COS",
            F32(crate::integrators::plan::CACHE_NORMAL_COS),
        ),
        ("DROP_DIRECT", U32(DROP_DIRECT)),
        ("DROP_CAUSTIC", U32(DROP_CAUSTIC)),
        ("VOLUME_STORE", U32(VOLUME_STORE)),
        ("VOLUME_DROP_CAUSTIC", U32(VOLUME_DROP_CAUSTIC)),
        ("NO_MEDIUM", U32(crate::media::NO_MEDIUM)),
        ("MAX_CROSSINGS", U32(MAX_CROSSINGS)),
        (
            "GATHER_MEDIUM_POINTS",
            U32(crate::media::GATHER_MEDIUM_POINTS),
        ),
        (
            "POINT_RADIUS_FACTOR",
            F32(crate::media::POINT_RADIUS_FACTOR),
        ),
        (
            "HG_ISOTROPIC_BELOW",
            F32(crate::media::phase::HG_ISOTROPIC_BELOW),
        ),
        ("STAT_PHOTON_OVERFLOW", U32(STAT_PHOTON_OVERFLOW)),
        ("STAT_LOOP_BUDGET", U32(STAT_LOOP_BUDGET)),
        ("STAT_GATHER_TRUNCATED", U32(STAT_GATHER_TRUNCATED)),
        (
            "SEARCH_VISIT_BOUND",
            U32(crate::integrators::estimate::SEARCH_VISIT_BOUND),
        ),
        ("SCAN_BLOCK", U32(SCAN_BLOCK)),
        ("SCAN_ITEMS", U32(SCAN_ITEMS)),
        ("MAX_HEAP", U32(MAX_HEAP)),
        ("CACHE_BINS", U32(CACHE_BINS)),
        ("CACHE_CANDIDATES", U32(CACHE_CANDIDATES)),
        ("CACHE_NEAR", U32(CACHE_NEAR)),
        ("CACHE_SELECT_LOW", U32(CACHE_SELECT_LOW)),
        ("CACHE_LIST_COUNT", U32(CACHE_LIST_COUNT)),
        ("COUNTER_MAX_POWER", U32(COUNTER_MAX_POWER)),
        ("CACHE_LIST_FIRST", U32(CACHE_LIST_FIRST)),
        ("MAX_RINGS", U32(MAX_RINGS)),
        ("MAX_CELLS", U32(MAX_CELLS)),
        (
            "LEAF_COUNT_SHIFT",
            U32(crate::bvh::gpu_layout::LEAF_COUNT_SHIFT),
        ),
        ("NODE_WORDS", U32(crate::bvh::gpu_layout::NODE_WORDS)),
        ("FRAME_WORDS", U32(crate::bvh::gpu_layout::FRAME_WORDS)),
        (
            "WIDE_NODE_WORDS",
            U32(crate::bvh::gpu_wide::WIDE_NODE_WORDS),
        ),
        ("WIDE_STACK", U32(crate::bvh::gpu_wide::WIDE_STACK)),
        (
            "INSTANCE_WORDS",
            U32(crate::bvh::gpu_instances::INSTANCE_WORDS),
        ),
        (
            "LEAF_PRIM_WORDS",
            U32(crate::bvh::gpu_layout::LEAF_PRIM_WORDS),
        ),
        ("TRIANGLE_WORDS", U32(TRIANGLE_WORDS)),
        ("SPHERE_WORDS", U32(SPHERE_WORDS)),
        ("MATERIAL_WORDS", U32(MATERIAL_WORDS)),
        ("MATERIAL_NORMAL_WORD", U32(MATERIAL_NORMAL_WORD)),
        ("MATERIAL_ALPHA_WORD", U32(MATERIAL_ALPHA_WORD)),
        ("MATERIAL_BUMP_WORD", U32(MATERIAL_BUMP_WORD)),
        ("MEDIUM_WORDS", U32(MEDIUM_WORDS)),
        ("F32_MIN_POSITIVE", F32(f32::MIN_POSITIVE)),
        ("F32_EPSILON", F32(f32::EPSILON)),
        ("VOLUME_PHOTONS_PER_CELL", F32(VOLUME_PHOTONS_PER_CELL)),
        ("LIGHT_WORDS", U32(LIGHT_WORDS)),
        ("LIGHT_EMISSION_WORD", U32(LIGHT_EMISSION_WORD)),
        ("PHOTON_WORDS", U32(PHOTON_WORDS)),
        ("UV_WORDS", U32(UV_WORDS)),
        ("UV_TANGENT_WORDS", U32(UV_TANGENT_WORDS)),
        ("STREAM_PHOTON", U32(Stream::Photon as u32)),
        ("STREAM_CAUSTIC", U32(Stream::Caustic as u32)),
        ("STREAM_CAMERA", U32(Stream::Camera as u32)),
        ("NO_LIGHT", U32(crate::scene::NO_LIGHT)),
        ("NO_BLEND", U32(NO_BLEND)),
        ("MAX_BLEND_DEPTH", U32(crate::bsdfs::blend::MAX_BLEND_DEPTH)),
        ("ONE_BELOW", F32(crate::bsdfs::blend::ONE_BELOW)),
        ("ALPHA_NONE", U32(ALPHA_NONE)),
        ("ALPHA_MASK", U32(ALPHA_MASK)),
        ("ALPHA_BLEND", U32(ALPHA_BLEND)),
        ("ALPHA_LUMINANCE", U32(ALPHA_LUMINANCE)),
        ("NO_TEXTURE", U32(crate::scene::NO_TEXTURE)),
        ("FLAT", U32(crate::scene::FLAT)),
        ("SPHERE_BIT", U32(crate::bvh::SPHERE_BIT)),
        ("SDF_BIT", U32(crate::bvh::SDF_BIT)),
        ("CUBIC_STEPS", U32(crate::scene::sdf_grid::CUBIC_STEPS)),
        (
            "CUBIC_TOLERANCE",
            F32(crate::scene::sdf_grid::CUBIC_TOLERANCE),
        ),
        (
            "FLAG_CAUSTIC",
            U32(crate::integrators::photon::FLAG_CAUSTIC),
        ),
        ("DEPTH_MASK", U32(crate::integrators::photon::DEPTH_MASK)),
        (
            "BEAM_ALL",
            U32(crate::integrators::photon::BeamPhotons::All as u32),
        ),
        (
            "BEAM_SKIP_DIRECT",
            U32(crate::integrators::photon::BeamPhotons::SkipDirect as u32),
        ),
        (
            "BEAM_CAUSTIC",
            U32(crate::integrators::photon::BeamPhotons::Caustic as u32),
        ),
        (
            "NEAR_GATHER_FRACTION",
            F32(crate::media::NEAR_GATHER_FRACTION),
        ),
        ("OFFSET_SCALE", F32(crate::math::geometry::OFFSET_SCALE)),
        ("OFFSET_FLOOR", F32(crate::math::geometry::OFFSET_FLOOR)),
        ("BOX_SLACK", F32(crate::math::geometry::BOX_SLACK)),
        ("FACING_COS", F32(crate::integrators::estimate::FACING_COS)),
        ("PI", F32(std::f32::consts::PI)),
        ("INV_CONE_K", F32(crate::integrators::estimate::INV_CONE_K)),
        ("CONE_NORM", F32(crate::integrators::estimate::CONE_NORM)),
        ("SQRT_2", F32(std::f32::consts::SQRT_2)),
        ("SOBOL_PAIR_JITTER", U32(crate::math::sobol::PAIR_JITTER)),
        ("SOBOL_PAIR_LIGHT", U32(crate::math::sobol::PAIR_LIGHT)),
        (
            "SOBOL_DIM_LIGHT_THIRD",
            U32(crate::math::sobol::DIM_LIGHT_THIRD),
        ),
        ("SOBOL_PAIR_GATHER", U32(crate::math::sobol::PAIR_GATHER)),
        ("SOBOL_PAIR_LENS", U32(crate::math::sobol::PAIR_LENS)),
        ("PIXEL_FILTER_BOX", U32(PixelFilter::Box.code())),
        (
            "PIXEL_FILTER_TENT",
            U32(PixelFilter::Tent { radius: 1.0 }.code()),
        ),
        (
            "PIXEL_FILTER_GAUSSIAN",
            U32(PixelFilter::Gaussian { stddev: 1.0 }.code()),
        ),
        (
            "ERF_2_SQRT_2",
            F32(crate::camera::pixel_filter::ERF_2_SQRT_2),
        ),
        (
            "ROULETTE_BELOW",
            F32(crate::media::heterogeneous::ROULETTE_BELOW),
        ),
    ]
    .into_iter()
    .chain(crate::media::gpu::WGSL_U32.map(|(name, v)| (name, U32(v))))
    .collect()
}

/// The WGSL code of a surface class (`shading::SurfaceClass`).
pub fn class_code(class: SurfaceClass) -> u32 {
    match class {
        SurfaceClass::Black => CLASS_BLACK,
        SurfaceClass::Delta => CLASS_DELTA,
        SurfaceClass::Shaded => CLASS_SHADED,
        SurfaceClass::Null => CLASS_NULL,
    }
}

/// The WGSL prelude: one `const` declaration per shared constant, the kernel shape's override
/// constants with the default shape's values (`shape::KernelShape::DEFAULT`).
pub fn wgsl_prelude() -> String {
    let mut out = String::from(
        "// Generated from src/integrators/gpu/codes.rs (shared_constants): do not declare these in WGSL.\n",
    );
    for (name, value) in shared_constants() {
        out.push_str(&format!("const {name}: {};\n", value.declaration()));
    }
    out.push_str(&format!(
        "// The kernel shape (src/integrators/gpu/shape.rs): set per adapter at pipeline creation.\n\
         override WG_SIZE: u32 = {WG_SIZE}u;\n\
         override GATHER_TILE: u32 = {GATHER_TILE}u;\n\
         override CACHE_LANES: u32 = {CACHE_LANES}u;\n\
         override LOOP_GUARD: bool = true;\n"
    ));
    out
}

//! Intel Embree 3 as the ray-throughput benchmark's anchor (cargo feature `embree`; links
//! the system's `libembree3`, Debian's `libembree-dev`): the scene's triangles as one
//! triangle mesh, its spheres as one sphere-point geometry, traced with `rtcIntersect1` and
//! `rtcOccluded1` one ray at a time. Alpha tests are not applied (Embree would need a filter
//! function): on scenes with alpha-tested surfaces its answers differ there.
//!
//! Declarations after `embree3/rtcore_*.h` of Embree 3.13.

use super::rays::Tracer;
use crate::bvh::SPHERE_BIT;
use crate::math::geometry::Ray;
use crate::scene::Scene;
use std::ffi::c_void;

type Handle = *mut c_void;

const GEOMETRY_TRIANGLE: u32 = 0;
const GEOMETRY_SPHERE_POINT: u32 = 50;
const BUFFER_INDEX: u32 = 0;
const BUFFER_VERTEX: u32 = 1;
const FORMAT_UINT3: u32 = 0x5003;
const FORMAT_FLOAT3: u32 = 0x9003;
const FORMAT_FLOAT4: u32 = 0x9004;
const INVALID_ID: u32 = u32::MAX;

#[repr(C, align(16))]
#[derive(Clone, Copy)]
struct RtcRay {
    org: [f32; 3],
    tnear: f32,
    dir: [f32; 3],
    time: f32,
    tfar: f32,
    mask: u32,
    id: u32,
    flags: u32,
}

#[repr(C, align(16))]
#[derive(Clone, Copy)]
struct RtcHit {
    ng: [f32; 3],
    u: f32,
    v: f32,
    prim_id: u32,
    geom_id: u32,
    inst_id: [u32; 1],
}

#[repr(C, align(16))]
#[derive(Clone, Copy)]
struct RtcRayHit {
    ray: RtcRay,
    hit: RtcHit,
}

#[repr(C)]
struct RtcIntersectContext {
    flags: u32,
    filter: *const c_void,
    inst_id: [u32; 1],
}

#[link(name = "embree3")]
extern "C" {
    fn rtcNewDevice(config: *const std::ffi::c_char) -> Handle;
    fn rtcReleaseDevice(device: Handle);
    fn rtcGetDeviceError(device: Handle) -> u32;
    fn rtcNewScene(device: Handle) -> Handle;
    fn rtcReleaseScene(scene: Handle);
    fn rtcSetSceneBuildQuality(scene: Handle, quality: u32);
    fn rtcNewGeometry(device: Handle, kind: u32) -> Handle;
    fn rtcSetNewGeometryBuffer(
        geometry: Handle,
        kind: u32,
        slot: u32,
        format: u32,
        stride: usize,
        count: usize,
    ) -> *mut c_void;
    fn rtcCommitGeometry(geometry: Handle);
    fn rtcAttachGeometry(scene: Handle, geometry: Handle) -> u32;
    fn rtcReleaseGeometry(geometry: Handle);
    fn rtcCommitScene(scene: Handle);
    fn rtcIntersect1(scene: Handle, context: *mut RtcIntersectContext, rayhit: *mut RtcRayHit);
    fn rtcOccluded1(scene: Handle, context: *mut RtcIntersectContext, ray: *mut RtcRay);
}

/// Embree's build quality: `rtcSetSceneBuildQuality`'s low, medium (its default) or high
/// (spatial splits).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quality {
    /// RTC_BUILD_QUALITY_LOW.
    Low = 0,
    /// RTC_BUILD_QUALITY_MEDIUM.
    Medium = 1,
    /// RTC_BUILD_QUALITY_HIGH.
    High = 2,
}

/// A committed Embree scene of one of our scenes.
pub struct EmbreeTracer {
    device: Handle,
    scene: Handle,
    /// Geometry id of the spheres (the triangles' is 0).
    spheres: u32,
    quality: Quality,
}

// SAFETY: a committed Embree scene may be traced from any thread (Embree's documentation of
// rtcIntersect1); the handles are released only in `drop`.
unsafe impl Send for EmbreeTracer {}
unsafe impl Sync for EmbreeTracer {}

impl EmbreeTracer {
    /// Builds Embree's hierarchy over `scene` with `quality`; `None` when Embree reports an
    /// error.
    pub fn new(scene: &Scene, quality: Quality) -> Option<Self> {
        // SAFETY: buffers are filled within the sizes Embree allocated for them; every
        // handle is checked and released once.
        unsafe {
            let device = rtcNewDevice(std::ptr::null());
            if device.is_null() {
                return None;
            }
            let s = rtcNewScene(device);
            rtcSetSceneBuildQuality(s, quality as u32);
            if !scene.triangles.is_empty() {
                let n = scene.triangles.len();
                let g = rtcNewGeometry(device, GEOMETRY_TRIANGLE);
                let v = rtcSetNewGeometryBuffer(g, BUFFER_VERTEX, 0, FORMAT_FLOAT3, 12, 3 * n);
                let i = rtcSetNewGeometryBuffer(g, BUFFER_INDEX, 0, FORMAT_UINT3, 12, n);
                if v.is_null() || i.is_null() {
                    rtcReleaseGeometry(g);
                    rtcReleaseScene(s);
                    rtcReleaseDevice(device);
                    return None;
                }
                let v = std::slice::from_raw_parts_mut(v as *mut [f32; 3], 3 * n);
                let i = std::slice::from_raw_parts_mut(i as *mut [u32; 3], n);
                for (k, t) in scene.triangles.iter().enumerate() {
                    v[3 * k] = t.v0.to_array();
                    v[3 * k + 1] = t.v1.to_array();
                    v[3 * k + 2] = t.v2.to_array();
                    let k = k as u32;
                    i[k as usize] = [3 * k, 3 * k + 1, 3 * k + 2];
                }
                rtcCommitGeometry(g);
                rtcAttachGeometry(s, g);
                rtcReleaseGeometry(g);
            }
            let mut spheres = INVALID_ID;
            if !scene.spheres.is_empty() {
                let n = scene.spheres.len();
                let g = rtcNewGeometry(device, GEOMETRY_SPHERE_POINT);
                let v = rtcSetNewGeometryBuffer(g, BUFFER_VERTEX, 0, FORMAT_FLOAT4, 16, n);
                if !v.is_null() {
                    let v = std::slice::from_raw_parts_mut(v as *mut [f32; 4], n);
                    for (k, sp) in scene.spheres.iter().enumerate() {
                        let c = sp.center;
                        v[k] = [c.x, c.y, c.z, sp.radius];
                    }
                }
                rtcCommitGeometry(g);
                spheres = rtcAttachGeometry(s, g);
                rtcReleaseGeometry(g);
            }
            rtcCommitScene(s);
            if rtcGetDeviceError(device) != 0 {
                rtcReleaseScene(s);
                rtcReleaseDevice(device);
                return None;
            }
            Some(EmbreeTracer {
                device,
                scene: s,
                spheres,
                quality,
            })
        }
    }
}

fn context() -> RtcIntersectContext {
    RtcIntersectContext {
        flags: 0,
        filter: std::ptr::null(),
        inst_id: [INVALID_ID],
    }
}

fn rtc_ray(ray: &Ray, t_max: f32) -> RtcRay {
    RtcRay {
        org: ray.origin.to_array(),
        tnear: 0.0,
        dir: ray.dir.to_array(),
        time: 0.0,
        tfar: t_max,
        mask: u32::MAX,
        id: 0,
        flags: 0,
    }
}

impl Tracer for EmbreeTracer {
    fn name(&self) -> String {
        format!("embree {:?}", self.quality).to_lowercase()
    }

    fn closest(&self, ray: &Ray, t_max: f32) -> Option<(u32, f32)> {
        let mut rh = RtcRayHit {
            ray: rtc_ray(ray, t_max),
            hit: RtcHit {
                ng: [0.0; 3],
                u: 0.0,
                v: 0.0,
                prim_id: INVALID_ID,
                geom_id: INVALID_ID,
                inst_id: [INVALID_ID],
            },
        };
        let mut ctx = context();
        // SAFETY: a committed scene, a valid context and ray-hit record.
        unsafe { rtcIntersect1(self.scene, &mut ctx, &mut rh) };
        match rh.hit.geom_id {
            INVALID_ID => None,
            g if g == self.spheres => Some((rh.hit.prim_id | SPHERE_BIT, rh.ray.tfar)),
            _ => Some((rh.hit.prim_id, rh.ray.tfar)),
        }
    }

    fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let mut r = rtc_ray(ray, t_max);
        let mut ctx = context();
        // SAFETY: as in `closest`.
        unsafe { rtcOccluded1(self.scene, &mut ctx, &mut r) };
        r.tfar == f32::NEG_INFINITY
    }
}

impl Drop for EmbreeTracer {
    fn drop(&mut self) {
        // SAFETY: both handles were created in `new` and are released once.
        unsafe {
            rtcReleaseScene(self.scene);
            rtcReleaseDevice(self.device);
        }
    }
}

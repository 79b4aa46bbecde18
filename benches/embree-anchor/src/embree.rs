//! Embree 3 (3.13, Debian's `libembree-dev`) through a minimal hand-written binding: the
//! dozen calls a scene of sphere points and the single-ray queries need, with the structs laid
//! out as `embree3/rtcore_*.h` lays them out for that build (`RTC_MAX_INSTANCE_LEVEL_COUNT`
//! 1, `RTC_MIN_WIDTH` 0).
//!
//! [`Spheres`] is the pbrt-style pair over it: [`Spheres::intersect`] (closest hit,
//! `rtcIntersect1`) and [`Spheres::occluded`] (any hit, `rtcOccluded1`).

use std::ffi::{c_char, c_void, CStr};
use std::ptr;
use std::sync::atomic::{AtomicIsize, Ordering};

use glam::Vec3;
use tracer::Ray;

#[allow(non_camel_case_types, reason = "the header's names")]
mod ffi {
    use std::ffi::{c_char, c_uint, c_void};

    pub type RTCDevice = *mut c_void;
    pub type RTCScene = *mut c_void;
    pub type RTCGeometry = *mut c_void;
    pub type RTCMemoryMonitorFunction = extern "C" fn(ptr: *mut c_void, bytes: isize, post: bool) -> bool;
    pub type RTCErrorFunction = extern "C" fn(user: *mut c_void, code: c_uint, msg: *const c_char);

    pub const RTC_GEOMETRY_TYPE_SPHERE_POINT: c_uint = 50;
    pub const RTC_BUFFER_TYPE_VERTEX: c_uint = 1;
    pub const RTC_FORMAT_FLOAT4: c_uint = 0x9004;
    pub const RTC_INVALID_GEOMETRY_ID: c_uint = u32::MAX;
    pub const RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT: c_uint = 0;
    pub const RTC_DEVICE_PROPERTY_VERSION: c_uint = 0;

    /// `struct RTCIntersectContext` with one instance level and no minimum width.
    #[repr(C)]
    pub struct RTCIntersectContext {
        pub flags: c_uint,
        pub filter: *const c_void,
        pub inst_id: [c_uint; 1],
    }

    /// `struct RTC_ALIGN(16) RTCRay`.
    #[repr(C, align(16))]
    #[derive(Clone, Copy, Default)]
    pub struct RTCRay {
        pub org: [f32; 3],
        pub tnear: f32,
        pub dir: [f32; 3],
        pub time: f32,
        pub tfar: f32,
        pub mask: c_uint,
        pub id: c_uint,
        pub flags: c_uint,
    }

    /// `struct RTC_ALIGN(16) RTCHit` with one instance level.
    #[repr(C, align(16))]
    #[derive(Clone, Copy, Default)]
    pub struct RTCHit {
        pub ng: [f32; 3],
        pub u: f32,
        pub v: f32,
        pub prim_id: c_uint,
        pub geom_id: c_uint,
        pub inst_id: [c_uint; 1],
    }

    /// `struct RTCRayHit`.
    #[repr(C, align(16))]
    #[derive(Clone, Copy, Default)]
    pub struct RTCRayHit {
        pub ray: RTCRay,
        pub hit: RTCHit,
    }

    const _: () = assert!(std::mem::size_of::<RTCRay>() == 48);
    const _: () = assert!(std::mem::size_of::<RTCHit>() == 32);
    const _: () = assert!(std::mem::size_of::<RTCRayHit>() == 80);
    const _: () = assert!(std::mem::size_of::<RTCIntersectContext>() == 24);

    #[link(name = "embree3")]
    extern "C" {
        pub fn rtcNewDevice(config: *const c_char) -> RTCDevice;
        pub fn rtcReleaseDevice(device: RTCDevice);
        pub fn rtcGetDeviceProperty(device: RTCDevice, prop: c_uint) -> isize;
        pub fn rtcGetDeviceError(device: RTCDevice) -> c_uint;
        pub fn rtcSetDeviceErrorFunction(device: RTCDevice, f: RTCErrorFunction, user: *mut c_void);
        pub fn rtcSetDeviceMemoryMonitorFunction(device: RTCDevice, f: RTCMemoryMonitorFunction, user: *mut c_void);
        pub fn rtcNewScene(device: RTCDevice) -> RTCScene;
        pub fn rtcReleaseScene(scene: RTCScene);
        pub fn rtcSetSceneBuildQuality(scene: RTCScene, quality: c_uint);
        pub fn rtcSetSceneFlags(scene: RTCScene, flags: c_uint);
        pub fn rtcNewGeometry(device: RTCDevice, kind: c_uint) -> RTCGeometry;
        pub fn rtcReleaseGeometry(geometry: RTCGeometry);
        pub fn rtcSetNewGeometryBuffer(
            geometry: RTCGeometry,
            kind: c_uint,
            slot: c_uint,
            format: c_uint,
            stride: usize,
            count: usize,
        ) -> *mut c_void;
        pub fn rtcCommitGeometry(geometry: RTCGeometry);
        pub fn rtcAttachGeometry(scene: RTCScene, geometry: RTCGeometry) -> c_uint;
        pub fn rtcCommitScene(scene: RTCScene);
        pub fn rtcIntersect1(scene: RTCScene, context: *mut RTCIntersectContext, rayhit: *mut RTCRayHit);
        pub fn rtcOccluded1(scene: RTCScene, context: *mut RTCIntersectContext, ray: *mut RTCRay);
    }
}

/// Bytes Embree has allocated through its device (its memory monitor's running sum).
static DEVICE_BYTES: AtomicIsize = AtomicIsize::new(0);

extern "C" fn monitor(_user: *mut c_void, bytes: isize, _post: bool) -> bool {
    DEVICE_BYTES.fetch_add(bytes, Ordering::Relaxed);
    true
}

extern "C" fn on_error(_user: *mut c_void, code: u32, msg: *const c_char) {
    let msg = if msg.is_null() { "".into() } else { unsafe { CStr::from_ptr(msg) }.to_string_lossy() };
    eprintln!("embree error {code}: {msg}");
}

/// The BVH's build quality (`RTCBuildQuality`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Quality {
    /// `RTC_BUILD_QUALITY_LOW` (Morton).
    Low = 0,
    /// `RTC_BUILD_QUALITY_MEDIUM` (binned SAH, Embree's default).
    Medium = 1,
    /// `RTC_BUILD_QUALITY_HIGH` (SAH with spatial splits where a geometry supports them).
    High = 2,
}

/// An Embree device: its own build threads, and the memory it accounts for.
pub struct Device {
    raw: ffi::RTCDevice,
}

impl Device {
    /// A device configured by `config` (e.g. `"threads=2"`).
    pub fn new(config: &str) -> Result<Self, String> {
        let config = std::ffi::CString::new(config).map_err(|e| e.to_string())?;
        let raw = unsafe { ffi::rtcNewDevice(config.as_ptr()) };
        if raw.is_null() {
            return Err(format!("rtcNewDevice failed: error {}", unsafe { ffi::rtcGetDeviceError(ptr::null_mut()) }));
        }
        unsafe {
            ffi::rtcSetDeviceErrorFunction(raw, on_error, ptr::null_mut());
            ffi::rtcSetDeviceMemoryMonitorFunction(raw, monitor, ptr::null_mut());
        }
        Ok(Self { raw })
    }

    /// Embree's version, e.g. 31305 for 3.13.5.
    #[must_use]
    pub fn version(&self) -> isize {
        unsafe { ffi::rtcGetDeviceProperty(self.raw, ffi::RTC_DEVICE_PROPERTY_VERSION) }
    }

    /// Bytes the process's Embree devices hold now (their memory monitor's sum).
    #[must_use]
    pub fn bytes() -> isize {
        DEVICE_BYTES.load(Ordering::Relaxed)
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        unsafe { ffi::rtcReleaseDevice(self.raw) }
    }
}

/// A committed Embree scene of one sphere-point geometry: sphere k is primitive k.
pub struct Spheres<'d> {
    scene: ffi::RTCScene,
    _device: &'d Device,
}

// A committed scene is read-only: Embree's ray queries on it are thread-safe.
unsafe impl Send for Spheres<'_> {}
unsafe impl Sync for Spheres<'_> {}

impl<'d> Spheres<'d> {
    /// Builds the BVH over the spheres (`centers[k]`, `radii[k]`).
    pub fn build(device: &'d Device, centers: &[Vec3], radii: &[f32], quality: Quality) -> Result<Self, String> {
        assert_eq!(centers.len(), radii.len(), "a radius per centre");
        unsafe {
            let scene = ffi::rtcNewScene(device.raw);
            ffi::rtcSetSceneBuildQuality(scene, quality as u32);
            ffi::rtcSetSceneFlags(scene, 0);
            let geometry = ffi::rtcNewGeometry(device.raw, ffi::RTC_GEOMETRY_TYPE_SPHERE_POINT);
            let buffer = ffi::rtcSetNewGeometryBuffer(
                geometry,
                ffi::RTC_BUFFER_TYPE_VERTEX,
                0,
                ffi::RTC_FORMAT_FLOAT4,
                16,
                centers.len(),
            )
            .cast::<[f32; 4]>();
            if buffer.is_null() {
                return Err(format!("rtcSetNewGeometryBuffer failed: error {}", ffi::rtcGetDeviceError(device.raw)));
            }
            let points = std::slice::from_raw_parts_mut(buffer, centers.len());
            for ((p, c), &r) in points.iter_mut().zip(centers).zip(radii) {
                *p = [c.x, c.y, c.z, r];
            }
            ffi::rtcCommitGeometry(geometry);
            ffi::rtcAttachGeometry(scene, geometry);
            ffi::rtcReleaseGeometry(geometry);
            ffi::rtcCommitScene(scene);
            match ffi::rtcGetDeviceError(device.raw) {
                0 => Ok(Self { scene, _device: device }),
                e => Err(format!("building the Embree scene failed: error {e}")),
            }
        }
    }

    fn context() -> ffi::RTCIntersectContext {
        // What the header's inline rtcInitIntersectContext does.
        ffi::RTCIntersectContext {
            flags: ffi::RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT,
            filter: ptr::null(),
            inst_id: [ffi::RTC_INVALID_GEOMETRY_ID],
        }
    }

    fn raw_ray(ray: &Ray, tnear: f32, tfar: f32) -> ffi::RTCRay {
        ffi::RTCRay {
            org: ray.origin.to_array(),
            tnear,
            dir: ray.dir.to_array(),
            time: 0.0,
            tfar,
            mask: u32::MAX,
            id: 0,
            flags: 0,
        }
    }

    /// The closest hit of `ray` in [tnear, tfar]: its parameter and sphere.
    #[inline]
    #[must_use]
    pub fn intersect(&self, ray: &Ray, tnear: f32, tfar: f32) -> Option<(f32, u32)> {
        let mut rh = ffi::RTCRayHit {
            ray: Self::raw_ray(ray, tnear, tfar),
            hit: ffi::RTCHit {
                geom_id: ffi::RTC_INVALID_GEOMETRY_ID,
                inst_id: [ffi::RTC_INVALID_GEOMETRY_ID],
                ..ffi::RTCHit::default()
            },
        };
        let mut context = Self::context();
        unsafe { ffi::rtcIntersect1(self.scene, &raw mut context, &raw mut rh) };
        (rh.hit.geom_id != ffi::RTC_INVALID_GEOMETRY_ID).then_some((rh.ray.tfar, rh.hit.prim_id))
    }

    /// Whether anything blocks `ray` in [tnear, tfar].
    #[inline]
    #[must_use]
    pub fn occluded(&self, ray: &Ray, tnear: f32, tfar: f32) -> bool {
        let mut r = Self::raw_ray(ray, tnear, tfar);
        let mut context = Self::context();
        unsafe { ffi::rtcOccluded1(self.scene, &raw mut context, &raw mut r) };
        // Embree marks an occluded ray by setting tfar to −∞.
        r.tfar == f32::NEG_INFINITY
    }
}

impl Drop for Spheres<'_> {
    fn drop(&mut self) {
        unsafe { ffi::rtcReleaseScene(self.scene) }
    }
}

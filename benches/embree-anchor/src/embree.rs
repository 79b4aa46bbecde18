//! Embree 3 (3.13, Debian's `libembree-dev`) through a minimal hand-written binding: the
//! calls a scene of spheres (sphere points, or a user geometry with our callbacks), single
//! rays and packets of 8 need, with the structs laid out as `embree3/rtcore_*.h` lays them
//! out for that build (`RTC_MAX_INSTANCE_LEVEL_COUNT` 1, `RTC_MIN_WIDTH` 0).
//!
//! [`Spheres`] is the pbrt-style pair over it: [`Spheres::intersect`] (closest hit,
//! `rtcIntersect1`) and [`Spheres::occluded`] (any hit, `rtcOccluded1`), and
//! [`Spheres::intersect8`] (eight closest hits, `rtcIntersect8`).

use std::ffi::{c_char, c_void, CStr};
use std::ptr;
use std::sync::atomic::{AtomicBool, AtomicIsize, AtomicU64, Ordering};

use glam::Vec3;
use tracer::Ray;

#[allow(non_camel_case_types, reason = "the header's names")]
mod ffi {
    use std::ffi::{c_char, c_int, c_uint, c_void};

    pub type RTCDevice = *mut c_void;
    pub type RTCScene = *mut c_void;
    pub type RTCGeometry = *mut c_void;
    pub type RTCMemoryMonitorFunction = extern "C" fn(ptr: *mut c_void, bytes: isize, post: bool) -> bool;
    pub type RTCErrorFunction = extern "C" fn(user: *mut c_void, code: c_uint, msg: *const c_char);

    pub const RTC_GEOMETRY_TYPE_SPHERE_POINT: c_uint = 50;
    pub const RTC_GEOMETRY_TYPE_USER: c_uint = 120;
    pub const RTC_BUFFER_TYPE_VERTEX: c_uint = 1;
    pub const RTC_FORMAT_FLOAT4: c_uint = 0x9004;
    pub const RTC_INVALID_GEOMETRY_ID: c_uint = u32::MAX;
    pub const RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT: c_uint = 0;
    pub const RTC_INTERSECT_CONTEXT_FLAG_COHERENT: c_uint = 1;
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

    /// `struct RTC_ALIGN(32) RTCRay8`: eight rays, field by field (SoA).
    #[repr(C, align(32))]
    #[derive(Clone, Copy, Default)]
    pub struct RTCRay8 {
        pub org_x: [f32; 8],
        pub org_y: [f32; 8],
        pub org_z: [f32; 8],
        pub tnear: [f32; 8],
        pub dir_x: [f32; 8],
        pub dir_y: [f32; 8],
        pub dir_z: [f32; 8],
        pub time: [f32; 8],
        pub tfar: [f32; 8],
        pub mask: [c_uint; 8],
        pub id: [c_uint; 8],
        pub flags: [c_uint; 8],
    }

    /// `struct RTC_ALIGN(32) RTCHit8` with one instance level.
    #[repr(C, align(32))]
    #[derive(Clone, Copy, Default)]
    pub struct RTCHit8 {
        pub ng_x: [f32; 8],
        pub ng_y: [f32; 8],
        pub ng_z: [f32; 8],
        pub u: [f32; 8],
        pub v: [f32; 8],
        pub prim_id: [c_uint; 8],
        pub geom_id: [c_uint; 8],
        pub inst_id: [[c_uint; 8]; 1],
    }

    /// `struct RTCRayHit8`.
    #[repr(C, align(32))]
    #[derive(Clone, Copy, Default)]
    pub struct RTCRayHit8 {
        pub ray: RTCRay8,
        pub hit: RTCHit8,
    }

    /// `struct RTC_ALIGN(16) RTCBounds`.
    #[repr(C, align(16))]
    pub struct RTCBounds {
        pub lower: [f32; 3],
        pub align0: f32,
        pub upper: [f32; 3],
        pub align1: f32,
    }

    /// `struct RTCBoundsFunctionArguments`.
    #[repr(C)]
    pub struct RTCBoundsFunctionArguments {
        pub geometry_user_ptr: *mut c_void,
        pub prim_id: c_uint,
        pub time_step: c_uint,
        pub bounds_o: *mut RTCBounds,
    }

    /// `struct RTCIntersectFunctionNArguments`. `rayhit` points at an `RTCRayHitN`: N rays
    /// then N hits, each field N wide (the `RTCRayN_*`/`RTCHitN_*` helpers' layout).
    #[repr(C)]
    pub struct RTCIntersectFunctionNArguments {
        pub valid: *mut c_int,
        pub geometry_user_ptr: *mut c_void,
        pub prim_id: c_uint,
        pub context: *mut RTCIntersectContext,
        pub rayhit: *mut c_void,
        pub n: c_uint,
        pub geom_id: c_uint,
    }

    /// `struct RTCOccludedFunctionNArguments`; `ray` points at an `RTCRayN`.
    #[repr(C)]
    pub struct RTCOccludedFunctionNArguments {
        pub valid: *mut c_int,
        pub geometry_user_ptr: *mut c_void,
        pub prim_id: c_uint,
        pub context: *mut RTCIntersectContext,
        pub ray: *mut c_void,
        pub n: c_uint,
        pub geom_id: c_uint,
    }

    pub type RTCBoundsFunction = unsafe extern "C" fn(args: *const RTCBoundsFunctionArguments);
    pub type RTCIntersectFunctionN = unsafe extern "C" fn(args: *const RTCIntersectFunctionNArguments);
    pub type RTCOccludedFunctionN = unsafe extern "C" fn(args: *const RTCOccludedFunctionNArguments);

    const _: () = assert!(std::mem::size_of::<RTCRay8>() == 384);
    const _: () = assert!(std::mem::size_of::<RTCHit8>() == 256);
    const _: () = assert!(std::mem::size_of::<RTCRayHit8>() == 640);
    const _: () = assert!(std::mem::size_of::<RTCBounds>() == 32);
    const _: () = assert!(std::mem::size_of::<RTCBoundsFunctionArguments>() == 24);
    const _: () = assert!(std::mem::size_of::<RTCIntersectFunctionNArguments>() == 48);
    const _: () = assert!(std::mem::offset_of!(RTCIntersectFunctionNArguments, n) == 40);
    const _: () = assert!(std::mem::size_of::<RTCOccludedFunctionNArguments>() == 48);
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
        pub fn rtcIntersect8(
            valid: *const c_int,
            scene: RTCScene,
            context: *mut RTCIntersectContext,
            rayhit: *mut RTCRayHit8,
        );
        pub fn rtcSetGeometryUserPrimitiveCount(geometry: RTCGeometry, count: c_uint);
        pub fn rtcSetGeometryUserData(geometry: RTCGeometry, ptr: *mut c_void);
        pub fn rtcSetGeometryBoundsFunction(geometry: RTCGeometry, bounds: RTCBoundsFunction, user: *mut c_void);
        pub fn rtcSetGeometryIntersectFunction(geometry: RTCGeometry, intersect: RTCIntersectFunctionN);
        pub fn rtcSetGeometryOccludedFunction(geometry: RTCGeometry, occluded: RTCOccludedFunctionN);
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

/// Which Embree geometry holds the spheres.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Geometry {
    /// `RTC_GEOMETRY_TYPE_SPHERE_POINT`: Embree's own sphere, in its curve BVH.
    Point,
    /// `RTC_GEOMETRY_TYPE_USER`: one user primitive per sphere, with our bounds, intersect
    /// and occluded callbacks (an object BVH).
    User,
}

/// The user geometry's data: centre and radius of sphere k at `spheres[k]`.
struct UserSpheres {
    spheres: Vec<[f32; 4]>,
}

/// Whether the user geometry's callbacks count their calls (off while timed frames run).
static COUNTING: AtomicBool = AtomicBool::new(false);
/// Callback calls with N = 1, calls with N > 1, and valid lanes in the latter.
static CALLS: [AtomicU64; 3] = [AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0)];

/// How Embree called the user geometry's callbacks while counting was on.
#[derive(Clone, Copy, Debug, Default)]
pub struct Callbacks {
    /// Calls with one ray (N = 1).
    pub single: u64,
    /// Calls with a packet (N > 1).
    pub packets: u64,
    /// Valid lanes over the packet calls.
    pub packet_lanes: u64,
}

/// Starts counting the user geometry's callback calls from zero.
pub fn count_callbacks() {
    for c in &CALLS {
        c.store(0, Ordering::Relaxed);
    }
    COUNTING.store(true, Ordering::Relaxed);
}

/// Stops counting, and returns the counts since [`count_callbacks`].
pub fn callbacks_counted() -> Callbacks {
    COUNTING.store(false, Ordering::Relaxed);
    let [single, packets, packet_lanes] = CALLS.each_ref().map(|c| c.load(Ordering::Relaxed));
    Callbacks { single, packets, packet_lanes }
}

/// Counts a callback call of `n` rays with mask `valid`, when counting is on.
///
/// # Safety
/// `valid` points at `n` ints.
#[inline]
unsafe fn count_call(valid: *const i32, n: usize) {
    if COUNTING.load(Ordering::Relaxed) {
        if n == 1 {
            CALLS[0].fetch_add(1, Ordering::Relaxed);
        } else {
            let lanes = (0..n).filter(|&i| unsafe { *valid.add(i) } != 0).count();
            CALLS[1].fetch_add(1, Ordering::Relaxed);
            CALLS[2].fetch_add(lanes as u64, Ordering::Relaxed);
        }
    }
}

/// The parameters where the ray o + t·d enters and leaves the sphere (c, r), nearer first:
/// the quadratic a·t² + 2b·t + c' = 0 with its discriminant taken as a·(r² − |oc − (b/a)·d|²)
/// (no cancellation of b² against a·c') and the roots as c'/q and q/a, q = −(b + sign(b)·√Δ)
/// (Haines et al., "Precision improvements for ray/sphere intersection", Ray Tracing Gems
/// ch. 7).
#[inline]
fn sphere_roots(o: Vec3, d: Vec3, c: Vec3, r: f32) -> Option<(f32, f32)> {
    let oc = o - c;
    let a = d.length_squared();
    let b = oc.dot(d);
    let l = oc - d * (b / a);
    let disc = a * (r * r - l.length_squared());
    if disc < 0.0 {
        return None;
    }
    let q = -(b + disc.sqrt().copysign(b));
    let (t0, t1) = ((oc.length_squared() - r * r) / q, q / a);
    Some((t0.min(t1), t0.max(t1)))
}

/// The user geometry's bounds callback: sphere `prim_id`'s box.
unsafe extern "C" fn user_bounds(args: *const ffi::RTCBoundsFunctionArguments) {
    let args = unsafe { &*args };
    let spheres = unsafe { &*args.geometry_user_ptr.cast::<UserSpheres>() };
    let [x, y, z, r] = spheres.spheres[args.prim_id as usize];
    unsafe {
        *args.bounds_o =
            ffi::RTCBounds { lower: [x - r, y - r, z - r], align0: 0.0, upper: [x + r, y + r, z + r], align1: 0.0 };
    }
}

/// The user geometry's intersect callback: N rays (SoA, `RTCRayHitN`) against sphere
/// `prim_id`; a valid ray whose entry (else exit) lies in [tnear, tfar] takes the hit: tfar,
/// the unnormalised normal p − c, primID, geomID and the context's instance id.
unsafe extern "C" fn user_intersect(args: *const ffi::RTCIntersectFunctionNArguments) {
    let args = unsafe { &*args };
    let n = args.n as usize;
    unsafe { count_call(args.valid, n) };
    let spheres = unsafe { &*args.geometry_user_ptr.cast::<UserSpheres>() };
    let [x, y, z, r] = spheres.spheres[args.prim_id as usize];
    let c = Vec3::new(x, y, z);
    let f = args.rayhit.cast::<f32>();
    // Field `k` of ray `i`: the k-th block of n floats (rays' 12 fields, then the hits').
    let at = |k: usize, i: usize| unsafe { f.add(k * n + i) };
    for i in 0..n {
        if unsafe { *args.valid.add(i) } == 0 {
            continue;
        }
        let (o, d) = unsafe { ray_of(f, n, i) };
        let Some(t) = (unsafe { hit_within(f, n, i, (c, r)) }) else { continue };
        let ng = o + d * t - c;
        unsafe {
            *at(8, i) = t;
            *at(12, i) = ng.x;
            *at(13, i) = ng.y;
            *at(14, i) = ng.z;
            *at(15, i) = 0.0;
            *at(16, i) = 0.0;
            *at(17, i).cast::<u32>() = args.prim_id;
            *at(18, i).cast::<u32>() = args.geom_id;
            *at(19, i).cast::<u32>() = (*args.context).inst_id[0];
        }
    }
}

/// The user geometry's occluded callback: a valid ray (SoA, `RTCRayN`) that meets sphere
/// `prim_id` in [tnear, tfar] gets tfar = −∞.
unsafe extern "C" fn user_occluded(args: *const ffi::RTCOccludedFunctionNArguments) {
    let args = unsafe { &*args };
    let n = args.n as usize;
    unsafe { count_call(args.valid, n) };
    let spheres = unsafe { &*args.geometry_user_ptr.cast::<UserSpheres>() };
    let [x, y, z, r] = spheres.spheres[args.prim_id as usize];
    let c = Vec3::new(x, y, z);
    let f = args.ray.cast::<f32>();
    for i in 0..n {
        if unsafe { *args.valid.add(i) } != 0 && unsafe { hit_within(f, n, i, (c, r)) }.is_some() {
            unsafe { *f.add(8 * n + i) = f32::NEG_INFINITY };
        }
    }
}

/// Ray `i` of `n` in SoA layout at `f` (`RTCRayN`): its origin and direction.
///
/// # Safety
///
/// `f` points at `n` rays' fields, and `i < n`.
unsafe fn ray_of(f: *const f32, n: usize, i: usize) -> (Vec3, Vec3) {
    let at = |k: usize| unsafe { *f.add(k * n + i) };
    (Vec3::new(at(0), at(1), at(2)), Vec3::new(at(4), at(5), at(6)))
}

/// Where ray `i` of `n` (SoA at `f`) meets the sphere (`c`, `r`) within its [tnear, tfar]:
/// the entry if there, else the exit.
///
/// # Safety
///
/// As [`ray_of`].
unsafe fn hit_within(f: *const f32, n: usize, i: usize, (c, r): (Vec3, f32)) -> Option<f32> {
    let (o, d) = unsafe { ray_of(f, n, i) };
    let (tnear, tfar) = unsafe { (*f.add(3 * n + i), *f.add(8 * n + i)) };
    let (t0, t1) = sphere_roots(o, d, c, r)?;
    [t0, t1].into_iter().find(|&t| tnear <= t && t <= tfar)
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

/// A committed Embree scene of one geometry of spheres (sphere points or a user geometry):
/// sphere k is primitive k.
pub struct Spheres<'d> {
    scene: ffi::RTCScene,
    /// The user geometry's spheres, which its callbacks read while the scene lives.
    _user: Option<Box<UserSpheres>>,
    _device: &'d Device,
}

// A committed scene is read-only: Embree's ray queries on it are thread-safe.
unsafe impl Send for Spheres<'_> {}
unsafe impl Sync for Spheres<'_> {}

impl<'d> Spheres<'d> {
    /// Builds the BVH over the spheres (`centers[k]`, `radii[k]`) as `geometry`.
    pub fn build(
        device: &'d Device,
        centers: &[Vec3],
        radii: &[f32],
        geometry: Geometry,
        quality: Quality,
    ) -> Result<Self, String> {
        assert_eq!(centers.len(), radii.len(), "a radius per centre");
        let spheres: Vec<[f32; 4]> = centers.iter().zip(radii).map(|(c, &r)| [c.x, c.y, c.z, r]).collect();
        unsafe {
            let scene = ffi::rtcNewScene(device.raw);
            ffi::rtcSetSceneBuildQuality(scene, quality as u32);
            ffi::rtcSetSceneFlags(scene, 0);
            let mut user = None;
            let raw = match geometry {
                Geometry::Point => {
                    let raw = ffi::rtcNewGeometry(device.raw, ffi::RTC_GEOMETRY_TYPE_SPHERE_POINT);
                    let buffer = ffi::rtcSetNewGeometryBuffer(
                        raw,
                        ffi::RTC_BUFFER_TYPE_VERTEX,
                        0,
                        ffi::RTC_FORMAT_FLOAT4,
                        16,
                        spheres.len(),
                    )
                    .cast::<[f32; 4]>();
                    if buffer.is_null() {
                        return Err(format!(
                            "rtcSetNewGeometryBuffer failed: error {}",
                            ffi::rtcGetDeviceError(device.raw)
                        ));
                    }
                    std::slice::from_raw_parts_mut(buffer, spheres.len()).copy_from_slice(&spheres);
                    raw
                }
                Geometry::User => {
                    let raw = ffi::rtcNewGeometry(device.raw, ffi::RTC_GEOMETRY_TYPE_USER);
                    let data = Box::new(UserSpheres { spheres });
                    let ptr = (&raw const *data).cast_mut().cast::<c_void>();
                    ffi::rtcSetGeometryUserPrimitiveCount(raw, data.spheres.len() as u32);
                    ffi::rtcSetGeometryUserData(raw, ptr);
                    ffi::rtcSetGeometryBoundsFunction(raw, user_bounds, ptr);
                    ffi::rtcSetGeometryIntersectFunction(raw, user_intersect);
                    ffi::rtcSetGeometryOccludedFunction(raw, user_occluded);
                    user = Some(data);
                    raw
                }
            };
            ffi::rtcCommitGeometry(raw);
            ffi::rtcAttachGeometry(scene, raw);
            ffi::rtcReleaseGeometry(raw);
            ffi::rtcCommitScene(scene);
            match ffi::rtcGetDeviceError(device.raw) {
                0 => Ok(Self { scene, _user: user, _device: device }),
                e => Err(format!("building the Embree scene failed: error {e}")),
            }
        }
    }

    fn context(flags: u32) -> ffi::RTCIntersectContext {
        // What the header's inline rtcInitIntersectContext does, with `flags`.
        ffi::RTCIntersectContext { flags, filter: ptr::null(), inst_id: [ffi::RTC_INVALID_GEOMETRY_ID] }
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
        let mut context = Self::context(ffi::RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
        unsafe { ffi::rtcIntersect1(self.scene, &raw mut context, &raw mut rh) };
        (rh.hit.geom_id != ffi::RTC_INVALID_GEOMETRY_ID).then_some((rh.ray.tfar, rh.hit.prim_id))
    }

    /// Whether anything blocks `ray` in [tnear, tfar].
    #[inline]
    #[must_use]
    pub fn occluded(&self, ray: &Ray, tnear: f32, tfar: f32) -> bool {
        let mut r = Self::raw_ray(ray, tnear, tfar);
        let mut context = Self::context(ffi::RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT);
        unsafe { ffi::rtcOccluded1(self.scene, &raw mut context, &raw mut r) };
        // Embree marks an occluded ray by setting tfar to −∞.
        r.tfar == f32::NEG_INFINITY
    }
}

impl Spheres<'_> {
    /// The closest hits in [0, ∞) of `rays[..lanes]` (`lanes` ≤ 8) as one packet
    /// (`rtcIntersect8`, the lanes past `lanes` masked off, context flag coherent: eight
    /// neighbouring primary rays): each ray's parameter and sphere.
    #[inline]
    #[must_use]
    pub fn intersect8(&self, rays: &[Ray; 8], lanes: usize) -> [Option<(f32, u32)>; 8] {
        /// The packet's valid mask: −1 on, 0 off, 32-byte aligned as `rtcIntersect8` asks.
        #[repr(C, align(32))]
        struct Valid([i32; 8]);
        let valid = Valid(std::array::from_fn(|k| if k < lanes { -1 } else { 0 }));
        let mut rh = ffi::RTCRayHit8::default();
        for (k, ray) in rays.iter().enumerate() {
            let r = &mut rh.ray;
            [r.org_x[k], r.org_y[k], r.org_z[k]] = ray.origin.to_array();
            [r.dir_x[k], r.dir_y[k], r.dir_z[k]] = ray.dir.to_array();
            r.tfar[k] = f32::INFINITY;
            r.mask[k] = u32::MAX;
        }
        rh.hit.geom_id = [ffi::RTC_INVALID_GEOMETRY_ID; 8];
        rh.hit.inst_id = [[ffi::RTC_INVALID_GEOMETRY_ID; 8]];
        let mut context = Self::context(ffi::RTC_INTERSECT_CONTEXT_FLAG_COHERENT);
        unsafe { ffi::rtcIntersect8(valid.0.as_ptr(), self.scene, &raw mut context, &raw mut rh) };
        std::array::from_fn(|k| {
            (k < lanes && rh.hit.geom_id[k] != ffi::RTC_INVALID_GEOMETRY_ID)
                .then_some((rh.ray.tfar[k], rh.hit.prim_id[k]))
        })
    }
}

impl Drop for Spheres<'_> {
    fn drop(&mut self) {
        unsafe { ffi::rtcReleaseScene(self.scene) }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Spheres on the z axis at 10 (r 1), 20 (r 2), and one off the axis at (5, 0, 10).
    fn scene(device: &Device, geometry: Geometry) -> Spheres<'_> {
        let centers = [Vec3::new(0.0, 0.0, 10.0), Vec3::new(0.0, 0.0, 20.0), Vec3::new(5.0, 0.0, 10.0)];
        Spheres::build(device, &centers, &[1.0, 2.0, 0.5], geometry, Quality::Medium).expect("an Embree scene")
    }

    #[test]
    fn both_geometries_find_the_closed_form_hits_single_and_in_packets() {
        let device = Device::new("threads=1").expect("an Embree device");
        for geometry in [Geometry::Point, Geometry::User] {
            let s = scene(&device, geometry);
            let z = Ray::new(Vec3::ZERO, Vec3::Z);
            let (t, k) = s.intersect(&z, 0.0, f32::INFINITY).expect("the first sphere");
            assert!((t - 9.0).abs() < 1e-5 && k == 0, "{geometry:?}: {t} {k}");
            // From inside sphere 0 the exit at z = 11 comes first; past it, sphere 1 at 18.
            let inside = Ray::new(Vec3::new(0.0, 0.0, 10.0), Vec3::Z);
            assert_eq!(s.intersect(&inside, 0.0, f32::INFINITY).map(|h| h.1), Some(0), "{geometry:?}");
            let (t, k) = s.intersect(&z, 11.5, f32::INFINITY).expect("the second sphere");
            assert!((t - 18.0).abs() < 1e-5 && k == 1, "{geometry:?}: {t} {k}");
            assert!(s.occluded(&z, 0.0, 9.5), "{geometry:?}");
            assert!(!s.occluded(&z, 0.0, 8.5), "{geometry:?}");
            let miss = Ray::new(Vec3::ZERO, Vec3::Y);
            assert_eq!(s.intersect(&miss, 0.0, f32::INFINITY), None, "{geometry:?}");
            // A packet of 8: lanes alternate the axis and a miss; lane 6 aims at sphere 2;
            // lane 7 is masked off.
            let mut rays = [z; 8];
            for (k, r) in rays.iter_mut().enumerate() {
                if k % 2 == 1 {
                    *r = miss;
                }
            }
            rays[6] = Ray::new(Vec3::ZERO, Vec3::new(5.0, 0.0, 10.0).normalize());
            rays[7] = z;
            let hits = s.intersect8(&rays, 7);
            for (k, hit) in hits.iter().enumerate() {
                let want = match k {
                    7 => None,
                    6 => Some(2),
                    k if k % 2 == 1 => None,
                    _ => Some(0),
                };
                assert_eq!(hit.map(|h| h.1), want, "{geometry:?}, lane {k}");
            }
            assert!((hits[0].expect("a hit").0 - 9.0).abs() < 1e-5, "{geometry:?}");
        }
    }
}

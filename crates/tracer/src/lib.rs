//! # tracer — a CPU Whitted ray tracer for spheres
//!
//! This crate owns everything about making one eye's image: the scene (plain data loaded
//! from TOML), the off-axis stereo camera, ray–sphere intersection, Whitted shading
//! (ambient + Lambert diffuse with hard shadows + Blinn–Phong highlights + mirror
//! reflection; Whitted 1980), and the parallel renderer that fills a [`Film`]. It is shaped
//! like pbrt-v4 and Embree: plain scene data, one aggregate with two queries, one render
//! call, a wavefront of SIMD lanes.
//!
//! A [`Scene`] (loaded from TOML) becomes a [`Tracer`] at one instant: a [`Snapshot`] (the
//! spheres, lights and settings as columns) and the aggregate over it (`accel/`), which
//! answers the closest-hit and any-hit queries, each for one ray or a vector of them; where
//! a ray starts (an eye, a sphere's surface, towards a light) picks the structure that
//! answers it (screen bins, direction cones, light cube maps, an 8-wide BVH), and every
//! structure answers bit-for-bit what the BVH would. A [`Camera`] gives each eye an
//! [`EyeView`]; a [`Renderer`] traces a view's [`Pixels`] (all, or these) into a [`Target`]
//! (a film with the record its caller names, or colour only), and hands a [`PixelBatch`]
//! to whoever makes an eye's chosen pixels in batches of their own: a second eye by
//! reprojection (the `stereo` crate), or what a reused frame traces again.
//!
//! Shading runs as a wavefront (pbrt-v4's wavefront integrator): a row's hits, then their
//! mirror rays' hits, each reflection depth a queue shaded in SIMD lanes (8 with AVX2, 4
//! otherwise, chosen at run time: [`lane_width`]), bit-for-bit the recursive path of
//! [`Tracer::trace_pixel`]. There is one lane layer (`fearless_simd`), one ray–sphere kernel
//! and one primary-ray kernel, which every query and the scalar forms run.
//!
//! Besides colour, the film keeps a per-pixel *visible-surface record* ([`Surface`]): hit
//! point, normal, depth, object id, per-light visibility and the view-independent part of
//! the light. The `stereo` crate reads that record to build the second eye; this crate
//! knows nothing about stereo pairs beyond the camera geometry.
//!
//! Every pixel leaves through one row sink (`sink`), whatever made it: the render's row
//! loop and each batch job write a row's columns through it, as pbrt-v4's film takes every
//! sample. Temporal reuse ([`reuse`]) is one layer on top: the swept volumes of the moving
//! spheres, the per-pixel marks of where each pixel's ray tree meets them, and the observer
//! that makes them, a marks column of the sink that watches each shaded batch. A render
//! marks only when asked ([`Target::marking`]).
//!
//! ## Modules, in dependency order
//!
//! Each uses only modules above it, so the graph has no cycle (test modules may also use
//! modules below, to build scenes and oracles):
//! - `ray`, `color`, `stats`, `error`, `surface`, `material`, `bits`, `simd`: leaves (rays
//!   and spawning, sRGB, ray counters, the scene error, the hit and visible-surface records,
//!   materials, a bit per pixel, the SIMD level with the lane kernels of rays and spheres);
//! - `sphere` (ray, simd): a sphere and the ray–sphere test one ray at a time;
//! - `camera` (ray, simd): the stereo camera, each eye's view, the disparity law;
//! - `scene`, `scene_file` (camera, material, sphere, error): the scene as described;
//! - `snapshot` (scene, material, color): the scene at one instant, as columns;
//! - `accel` (ray, simd, sphere, camera, scene, surface): the aggregate and its structures:
//!   `bvh` (and `bvh/build`), `lights` (cube maps around the lights), `cones`, `screen`
//!   (screen bins of an eye's primary rays), `flat` (every sphere in lanes), `packet`;
//! - `tracer` (snapshot, accel): the scene at one instant, ready to trace;
//! - `shade` (tracer, camera): Whitted shading, recursively, pixel by pixel: the plain path
//!   every fast one is tested against;
//! - `wavefront` (its child `lanes` has the SIMD stages; tracer, accel): the same shading
//!   as a stream of queues, whose shaded batch observers read through `Levels`;
//! - `sink` (wavefront, camera, surface): the row sink every pixel producer writes through,
//!   and the seam (`Observe`) where an observer watches each shaded batch;
//! - `reuse` (bits, scene, camera, accel's screen bound, wavefront's levels, sink's seam):
//!   the temporal reuse layer; its `observer` is the marks column, whose `tree` and `lanes`
//!   mark a shaded batch;
//! - `film` (surface): the image and its visible-surface record;
//! - `batch` (wavefront, accel, sink): batches of an eye's chosen pixels, a file per job:
//!   `trace`, `reshade`, `plan`;
//! - `render` (batch, film, sink, wavefront, reuse): the parallel renderer, and
//!   [`PixelBatch`], the batch jobs with their rows' sinks.
//! - `testing` (scene), hidden from these docs: what the workspace's tests and benches
//!   share (the bundled scenes by name, one xorshift, the SKIPPED line).
//!
//! Conventions (see the README): left-handed, +x right, +y up, +z into the scene; world
//! units are arbitrary but shared by positions and radii; light is linear inside and
//! encoded to 8-bit sRGB only when a pixel is written; pixel (i, j) has its centre at
//! (i + 0.5, j + 0.5), with j growing downwards.

mod accel;
mod batch;
pub mod bits;
mod camera;
mod color;
pub mod color_by;
mod cue;
mod error;
mod film;
mod material;
mod ray;
mod recolor;
mod render;
pub mod reuse;
mod scene;
mod scene_file;
mod shade;
mod simd;
mod sink;
mod snapshot;
mod sphere;
mod stats;
mod structure;
mod surface;
#[doc(hidden)]
pub mod testing;
mod tracer;
mod wavefront;

pub use batch::{RowPlan, KEEP, TRACE};
pub use bits::PixelBits;
pub use camera::{Camera, Disparity, Eye, EyeView};
pub use color::{linear_to_srgb8, pack_rgb, srgb8_to_linear, unpack_rgb};
pub use color_by::{parse_color_range, ColorBy, Coloring, Hide, CHAIN_COLOURS, STEPS as COLOR_STEPS, WATER_NAMES};
pub use cue::{
    bounds as scene_bounds, first_hits, outline, outline_from, sized as sized_cues, AmbientOcclusion, Cues, DepthCue,
    DepthCueMode, Outline, AO_SAMPLES_MAX, OUTLINE_JUMP, OUTLINE_MAX, STRUCTURE_AO_SAMPLES,
};
pub use error::SceneError;
pub use film::{Film, Record};
pub use material::Material;
pub use ray::{reflect, spawn_ray, Ray};
pub use render::{BatchRow, FirstHits, HitsColumns, PixelBatch, Pixels, Renderer, Target};
pub use scene::{
    AtomKind, Light, Motion, Records, RenderSettings, Scene, SceneSphere, Structure, MAX_DEPTH_LIMIT, MAX_LIGHTS,
};
pub use scene_file::{is_scene_file_name, MAX_SPHERES, MAX_TOML_BYTES};
pub use shade::Shaded;
pub use simd::{
    lane_width, level as simd_level, level_of as simd_level_of, levels as simd_levels,
    widest_level as widest_simd_level, LANES_VAR, LANE_WIDTHS,
};
pub use snapshot::Snapshot;
pub use sphere::{intersect_sphere, Sphere};
pub use stats::RayCounts;
pub use structure::{read_structure, LoadOptions, StructureOptions, ATOM_MATERIAL, DEFAULT_RADIUS_SCALE};
pub use surface::{Hit, Shading, Surface, NO_OBJECT};
pub use tracer::{Tracer, TracerMemory};

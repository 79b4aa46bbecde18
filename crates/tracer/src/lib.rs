//! # tracer — a CPU Whitted ray tracer for spheres
//!
//! This crate owns everything about making one eye's image: the scene (plain data loaded
//! from TOML), the off-axis stereo camera, ray–sphere intersection, Whitted shading
//! (ambient + Lambert diffuse with hard shadows + Blinn–Phong highlights + mirror
//! reflection; Whitted 1980), and the parallel renderer that fills a [`Film`].
//!
//! Shading runs as a wavefront (pbrt-v4's wavefront integrator): a row's hits, then their
//! mirror rays' hits, each reflection depth a queue shaded in SIMD lanes (8 with AVX2, 4
//! otherwise, chosen at run time; [`lane_width`]), bit-for-bit the recursive path of
//! [`Tracer::trace_pixel`]. Rays are answered by the cheapest structure that is exact for
//! them: primary rays by screen-space tile bins (a vector of rays per SIMD test), shadow and
//! mirror rays of small scenes by every sphere in lanes, otherwise shadow rays by a cube map
//! of sphere lists around each light, mirror rays by direction cones between spheres, and
//! anything else by an 8-wide BVH (eight child boxes per SIMD slab test) with SIMD leaves. Each
//! gives bit-for-bit the BVH's answer (tests compare them on every scene).
//!
//! Besides colour, the film keeps a per-pixel *visible-surface record*
//! ([`Surface`]): hit point, normal, depth, object id, per-light visibility and the
//! view-independent part of the light. The `stereo` crate reads that record to build the
//! second eye by reprojection, through the services of [`SecondView`]; this crate knows
//! nothing about stereo pairs beyond the camera geometry.
//!
//! The public surface: a [`Scene`] (loaded from TOML) becomes a [`Tracer`] at one instant; a
//! [`Camera`] gives each eye an [`EyeView`]; a [`Renderer`] traces a view into a [`Film`]
//! (or colour only), and hands a [`SecondView`] to whoever fills an eye pixel by pixel.
//!
//! ## Modules, in dependency order
//!
//! Each uses only modules above it, so the graph has no cycle (test modules may also use
//! modules below, to build scenes and oracles):
//! - `ray`, `color`, `stats`, `error`, `surface`, `material`, `simd`, `bits`: leaves (rays
//!   and spawning, sRGB, ray counters, the scene error, the hit and visible-surface records,
//!   materials and their highlight exponents, the SIMD level and lane helpers, a bit per
//!   pixel);
//! - `sphere` (ray): the ray–sphere test and its SIMD packets;
//! - `camera` (ray, simd): the stereo camera, each eye's view, the disparity law;
//! - `scene` (camera, material, sphere), then `scene_file` (scene, material, camera, error);
//! - `swept` (scene): where moving spheres can ever be (the washer about each orbit), the
//!   arcs of it a ray crosses, and the argument that makes temporal reuse exact; `marks`
//!   (bits, swept): per pixel, where its ray tree meets those volumes;
//! - `bvh` (its child `bvh::build` makes the tree), `cones`, `shadow` (ray, sphere, surface,
//!   scene): the acceleration structures;
//! - `tracer` (the structures, scene, camera, material, color, ray, surface): the scene at one
//!   instant and its queries, `intersect` and `occluded`;
//! - `shade` (tracer, camera, ray, color, stats, surface): Whitted shading, recursively,
//!   pixel by pixel: the plain path every fast one is tested against;
//! - `wavefront` (its child `wavefront::lanes` has the SIMD stages, `wavefront::marks` the
//!   SIMD marking of temporal reuse; tracer, material, ray, simd, stats, surface, swept,
//!   color): the same shading as a stream of queues;
//! - `primary` (tracer, camera, simd, sphere, ray, surface): screen bins for primary rays;
//! - `film` (surface, marks): the image and its visible-surface record;
//! - `second_view` (primary, wavefront, tracer, sphere, ray, stats, surface): services for a
//!   second view;
//! - `render` (film, primary, second_view, wavefront, simd, camera, ray, stats, surface,
//!   tracer, bits, marks): the parallel renderer, which also retraces only chosen pixels.
//!
//! Conventions (see the README): left-handed, +x right, +y up, +z into the scene; world
//! units are arbitrary but shared by positions and radii; light is linear inside and
//! encoded to 8-bit sRGB only when a pixel is written; pixel (i, j) has its centre at
//! (i + 0.5, j + 0.5), with j growing downwards.

pub mod bits;
mod bvh;
mod camera;
mod color;
mod cones;
mod error;
mod film;
mod marks;
mod material;
mod primary;
mod ray;
mod render;
mod scene;
mod scene_file;
mod second_view;
mod shade;
mod shadow;
mod simd;
mod sphere;
mod stats;
mod surface;
mod swept;
mod tracer;
mod wavefront;

pub use bits::PixelBits;
pub use camera::{Camera, Disparity, Eye, EyeView};
pub use color::{linear_to_srgb8, pack_rgb, srgb8_to_linear, unpack_rgb};
pub use error::SceneError;
pub use film::{Film, Record};
pub use marks::{Marks, MarksBand, MarksRow, Rewrite};
pub use material::Material;
pub use ray::{reflect, spawn_ray, Ray};
pub use render::Renderer;
pub use scene::{Light, Motion, RenderSettings, Scene, SceneSphere, MAX_DEPTH_LIMIT, MAX_LIGHTS};
pub use second_view::{RowPlan, SecondView, KEEP, TRACE};
pub use shade::Shaded;
pub use simd::{lane_width, LANES_VAR};
pub use sphere::{intersect_sphere, Sphere};
pub use stats::RayCounts;
pub use surface::{Hit, Shading, Surface, NO_OBJECT};
pub use swept::{Arc, SweptRing, Touch};
pub use tracer::Tracer;

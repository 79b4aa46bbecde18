//! A warm stereo frame allocates nothing of its own: the tracer's per-frame rebuild (BVH,
//! screen bins, shadow cube maps, cones) and every mode's passes reuse their buffers, on
//! every thread; nor does supersampling's filter (`downsample`) into a buffer it reuses.
//!
//! Allocations are counted by a global allocator that forwards to the system's, so the
//! count covers rayon's worker threads too. This file is its own test binary: nothing else
//! runs while frames are counted. One allocation is rayon's, not ours: its queue for work
//! handed in from outside the pool (crossbeam's `Injector`) takes a new 1.5 KB block every
//! 63 jobs, and a frame hands in one job per parallel pass (~5). So the test allows fewer
//! allocations than frames: anything allocated per frame, on any path, counts at least one
//! per frame and fails it.
//!
//! The frames are counted in rounds, and the round that allocated least is judged: what is
//! allocated per frame is allocated in every round, while a buffer that grows once
//! allocates in one round only. That buffer is typically a rayon worker's scratch for the
//! reprojection pass (`reproject.rs`): a worker that a busy machine kept from the warm-up
//! gets its first band later, and its scratch grows then (seen here in about one run in
//! ten, on main before this test counted in rounds).
//!
//! The same holds for frames that reuse the last one (`reuse.rs`), in every mode.

#![expect(
    unsafe_code,
    reason = "the counting allocator implements `GlobalAlloc`, an unsafe trait; it only forwards to `System` and bumps a counter"
)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicU64, Ordering};

use stereo::{Mode, Options, StereoFrame};
use tracer::{Scene, Tracer};

struct Counting;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

// SAFETY: every method forwards to `System` with the caller's arguments unchanged, so the
// caller's obligations are passed on as they are.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: as for the trait method.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: as for the trait method.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: as for the trait method.
        unsafe { System.realloc(ptr, layout, new_size) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as for the trait method.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Held while a test counts: the tests of this binary run one at a time.
static COUNTING: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Allocations made by `f`.
fn allocations(f: impl FnOnce()) -> u64 {
    let before = ALLOCATIONS.load(Ordering::SeqCst);
    f();
    ALLOCATIONS.load(Ordering::SeqCst) - before
}

#[test]
fn a_warm_frame_allocates_nothing() {
    let _alone = COUNTING.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let all = [Mode::Full, Mode::Copy, Mode::Reshade, Mode::Exact];
    for name in ["seed.toml", "many.toml"] {
        let scene =
            Scene::load(format!("{}/../../assets/scenes/{name}", env!("CARGO_MANIFEST_DIR"))).expect("scene loads");
        let (w, h) = (160, 90);
        let mut tracer = Tracer::new(&scene, 0.0);
        let mut frame = StereoFrame::new();
        // Supersampling's filter, into a buffer kept from frame to frame (as the viewer's).
        let mut filtered = Vec::new();
        let variants: Vec<Options> =
            all.iter().flat_map(|&mode| [false, true].map(|retrace_edges| Options { mode, retrace_edges })).collect();
        // Warm up: the buffers grow to the frame's size, rayon starts its threads, and every
        // worker's scratch grows (twice, as rayon may hand a band to either thread).
        for k in 0..3 {
            tracer.update(&scene, k as f32 / 30.0);
            for &opts in &variants {
                frame.render(&tracer, &scene.camera, w, h, opts);
            }
            stereo::downsample(&frame.right().rgb, (w, h), &mut filtered, (w / 2, h / 2));
            stereo::downsample_mask(frame.mask(), (w, h), &mut filtered, (w / 2, h / 2));
        }
        // The orbiting sphere moves on: the structures are rebuilt, into the same buffers.
        let frames = 3 * variants.len() as u64;
        let rounds: Vec<u64> = (1..4)
            .map(|round| {
                allocations(|| {
                    for k in 3 * round..3 * round + 3 {
                        tracer.update(&scene, k as f32 / 30.0);
                        for &opts in &variants {
                            frame.render(&tracer, &scene.camera, w, h, opts);
                        }
                        stereo::downsample(&frame.right().rgb, (w, h), &mut filtered, (w / 2, h / 2));
                        stereo::downsample_mask(frame.mask(), (w, h), &mut filtered, (w / 2, h / 2));
                    }
                })
            })
            .collect();
        let fewest = rounds.iter().copied().min().unwrap_or(0);
        assert!(fewest <= frames / 8, "{name}: rounds of {frames} warm frames allocated {rounds:?} times");
    }
}

#[test]
fn a_warm_reused_frame_allocates_nothing() {
    let _alone = COUNTING.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
    let scene =
        Scene::load(format!("{}/../../assets/scenes/seed.toml", env!("CARGO_MANIFEST_DIR"))).expect("scene loads");
    let (w, h) = (160, 90);
    let mut tracer = Tracer::new(&scene, 0.0);
    for mode in [Mode::Full, Mode::Copy, Mode::Reshade, Mode::Exact] {
        let opts = Options { mode, retrace_edges: true };
        let mut frame = StereoFrame::new();
        frame.set_reuse(Some(&scene));
        // Warm up: the first frame marks, the next ones reuse.
        for k in 0..6 {
            tracer.update(&scene, k as f32 / 60.0);
            frame.render(&tracer, &scene.camera, w, h, opts);
        }
        let frames = 24;
        let rounds: Vec<u64> = (1..4)
            .map(|round| {
                allocations(|| {
                    for k in 0..frames {
                        tracer.update(&scene, (6 + round * frames + k) as f32 / 60.0);
                        let stats = frame.render(&tracer, &scene.camera, w, h, opts);
                        assert!(stats.reuse.reused, "{mode}: every frame after the first reuses");
                    }
                })
            })
            .collect();
        let fewest = rounds.iter().copied().min().unwrap_or(0);
        assert!(fewest <= frames / 8, "{mode}: rounds of {frames} reused frames allocated {rounds:?} times");
    }
}

//! A warm stereo frame allocates nothing of its own: the tracer's per-frame rebuild (BVH,
//! screen bins, shadow cube maps, cones) and every mode's passes reuse their buffers, on
//! every thread, with depths kept or not (and then the outlines drawn from each eye's kept
//! planes); nor does supersampling's filter (`downsample`) into a buffer it reuses.
//!
//! Allocations are counted by a global allocator that forwards to the system's and counts
//! only on the threads of a rayon pool built for the purpose ([`CountingPool`]), each pool
//! into a counter of its own: this module shares its test binary with the crate's other
//! tests, which allocate on their own threads (and rayon's global pool) at the same time,
//! and none of that is counted. The frames run inside the pool (`ThreadPool::install`), so
//! every parallel pass of theirs runs on its workers, and whatever they allocate, on any of
//! the pool's threads, counts. The thread that hands the work in is not counted: its one
//! allocation is rayon's (its queue for work from outside the pool, crossbeam's `Injector`,
//! takes a new block every 63 jobs), not ours. The test allows fewer allocations than frames:
//! anything allocated per frame, on any path, counts at least one per frame and fails it.
//!
//! The frames are counted in rounds, and the round that allocated least is judged: what is
//! allocated per frame is allocated in every round, while a buffer that grows once
//! allocates in one round only. That buffer is typically a rayon worker's scratch for the
//! reprojection pass (`reproject.rs`): a worker that a busy machine kept from the warm-up
//! gets its first band later, and its scratch grows then (seen here in about one run in
//! ten, on main before this test counted in rounds).
//!
//! The same holds for frames that reuse the last one (`stereo/src/reuse/`), in every mode, and for
//! timewarp's warp (`stereo::Warp`) of one traced pair to pose after pose.

#![expect(
    unsafe_code,
    reason = "the counting allocator implements `GlobalAlloc`, an unsafe trait; it only forwards to `System` and bumps a counter"
)]

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::Vec3;
use stereo::{Mode, Options, Outlined, StereoFrame, Warp, WarpSource};
use tracer::testing::scene;
use tracer::{Camera, Eye, Film, Pixels, Record, Renderer, Target, Tracer};

thread_local! {
    /// The counter this thread's allocations go to: set on a [`CountingPool`]'s threads
    /// only. (A `const` thread-local of a type without `Drop`: reading it never allocates.)
    static COUNTER: Cell<Option<&'static AtomicU64>> = const { Cell::new(None) };
}

/// Counts an allocation if this thread counts them.
fn count() {
    // `try_with`: a thread being torn down may have no locals left; it is not counted.
    let _ = COUNTER.try_with(|counter| {
        if let Some(n) = counter.get() {
            n.fetch_add(1, Ordering::Relaxed);
        }
    });
}

struct Counting;

// SAFETY: every method forwards to `System` with the caller's arguments unchanged, so the
// caller's obligations are passed on as they are; `count` neither allocates nor unwinds.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: as for the trait method.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        // SAFETY: as for the trait method.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
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

/// A rayon pool (as many threads as the global one) whose threads count their allocations
/// into a counter of the pool's own.
struct CountingPool {
    pool: rayon::ThreadPool,
    counter: &'static AtomicU64,
}

impl CountingPool {
    fn new() -> Self {
        // Leaked: the pool's threads may outlive the test that built it.
        let counter: &'static AtomicU64 = Box::leak(Box::new(AtomicU64::new(0)));
        let pool = rayon::ThreadPoolBuilder::new()
            .start_handler(move |_| COUNTER.with(|c| c.set(Some(counter))))
            .build()
            .unwrap_or_else(|e| panic!("cannot build a thread pool: {e}"));
        Self { pool, counter }
    }

    /// Runs `f` on the pool.
    fn run<R: Send>(&self, f: impl FnOnce() -> R + Send) -> R {
        self.pool.install(f)
    }

    /// Allocations made by `f`, run on the pool, on any of the pool's threads.
    fn allocations(&self, f: impl FnOnce() + Send) -> u64 {
        let before = self.counter.load(Ordering::SeqCst);
        self.pool.install(f);
        self.counter.load(Ordering::SeqCst) - before
    }
}

#[test]
fn a_warm_frame_allocates_nothing() {
    let pool = CountingPool::new();
    let all = [Mode::Full, Mode::Copy, Mode::Reshade, Mode::Exact];
    // Without depths, and with them and the outlines drawn from each eye's kept planes.
    for (name, depths) in [("seed.toml", false), ("many.toml", false), ("seed.toml", true), ("many.toml", true)] {
        let scene = scene(name);
        let (w, h) = (160, 90);
        let mut tracer = Tracer::new(&scene, 0.0);
        let mut frame = StereoFrame::new();
        frame.set_depths(depths);
        let mut outlined = Outlined::new();
        // Supersampling's filter, into a buffer kept from frame to frame (as the viewer's).
        let mut filtered = Vec::new();
        let variants: Vec<Options> =
            all.iter().flat_map(|&mode| [false, true].map(|retrace_edges| Options { mode, retrace_edges })).collect();
        let mut frames_at = |times: std::ops::Range<u32>| {
            for k in times {
                tracer.advance(&scene, k as f32 / 30.0);
                for &opts in &variants {
                    frame.render(&tracer, &scene.camera, w, h, opts);
                    if depths {
                        outlined.eyes(&tracer, &frame, 1.0);
                    }
                }
                stereo::downsample(&frame.right().rgb, (w, h), &mut filtered, (w / 2, h / 2));
                stereo::downsample_mask(frame.mask(), (w, h), &mut filtered, (w / 2, h / 2));
            }
        };
        // Warm up: the buffers grow to the frame's size, the pool starts its threads, and
        // every worker's scratch grows (twice, as rayon may hand a band to either thread).
        pool.run(|| frames_at(0..3));
        // The orbiting sphere moves on: the structures are rebuilt, into the same buffers.
        let frames = 3 * variants.len() as u64;
        let rounds: Vec<u64> = (1..4).map(|round| pool.allocations(|| frames_at(3 * round..3 * round + 3))).collect();
        let fewest = rounds.iter().copied().min().unwrap_or(0);
        assert!(
            fewest <= frames / 8,
            "{name}, depths {depths}: rounds of {frames} warm frames allocated {rounds:?} times"
        );
    }
}

/// The progressive viewer's frames (`viewer/src/window/worker/`): while the head moves,
/// pairs at densities that change from frame to frame (one sample per k × k pixels, traced
/// with a guard band and depths) reconstructed at the eye size; at rest, refinement passes
/// (one sample of every pixel of the supersampled view, `Pixels::Only` into a colour image)
/// and the box filter of the converged samples.
#[test]
fn warm_coarse_frames_and_refinement_passes_allocate_nothing() {
    let pool = CountingPool::new();
    let scene = scene("many.toml");
    let (eye, s) = ((160u32, 90u32), 3u32);
    let mut tracer = Tracer::new(&scene, 0.0);
    let mut frame = StereoFrame::new();
    frame.set_depths(true);
    let opts = Options { mode: Mode::Exact, retrace_edges: false };
    let (mut shown, mut mask) = (Vec::new(), Vec::new());
    let views = stereo::StereoViews::new(&scene.camera, (eye.0 * s, eye.1 * s), (0, 0));
    let mut samples = [Vec::new(), Vec::new()];
    let mut renderers = [Renderer::default(), Renderer::default()];
    let mut bits = tracer::PixelBits::new(eye.0 * s, eye.1 * s);
    let mut frames_at = |times: std::ops::Range<u32>| {
        for k in times {
            tracer.advance(&scene, k as f32 / 30.0);
            for density in [4, 2, 3, 1] {
                let size = (eye.0.div_ceil(density), eye.1.div_ceil(density));
                frame.render_banded(&tracer, &scene.camera, size, (2, 2), opts);
                stereo::downsample(&frame.left().rgb[..size.0 as usize * size.1 as usize], size, &mut shown, eye);
                stereo::downsample_mask_kept_banded(frame.mask(), None, (size, (2, 2)), &mut mask, eye);
            }
            for pass in 0..s * s {
                select_pass(&mut bits, pass, s, eye);
                for ((renderer, out), view) in renderers.iter_mut().zip(&mut samples).zip(&views.eyes) {
                    renderer.render(&tracer, view, Pixels::Only(&bits), Target::colour(out));
                }
            }
            stereo::downsample(&samples[0], (eye.0 * s, eye.1 * s), &mut shown, eye);
        }
    };
    pool.run(|| frames_at(0..3));
    let frames = 3 * (4 + s * s);
    let rounds: Vec<u64> = (1..4).map(|round| pool.allocations(|| frames_at(3 * round..3 * round + 3))).collect();
    let fewest = rounds.iter().copied().min().unwrap_or(0);
    assert!(fewest <= u64::from(frames) / 8, "rounds of {frames} warm frames and passes allocated {rounds:?} times");
}

/// Selects in `bits` refinement pass `pass`'s samples of an eye of `eye` pixels at `s` × `s`
/// samples a pixel: sub-pixel (pass mod s, pass / s) of every pixel.
fn select_pass(bits: &mut tracer::PixelBits, pass: u32, s: u32, eye: (u32, u32)) {
    bits.clear();
    for j in (pass / s..eye.1 * s).step_by(s as usize) {
        for i in (pass % s..eye.0 * s).step_by(s as usize) {
            bits.set(i, j, true);
        }
    }
}

/// A resting refinement that follows orbiting spheres (`viewer/src/window/worker/refine/`):
/// its passes mark the samples they trace, each new instant selects the samples that can
/// have changed by those marks, and those are traced again, marking them anew.
#[test]
fn warm_followed_refinement_steps_allocate_nothing() {
    let pool = CountingPool::new();
    let scene = scene("many.toml");
    let (eye, s) = ((160u32, 90u32), 2u32);
    let mut tracer = Tracer::new(&scene, 0.0);
    let views = stereo::StereoViews::new(&scene.camera, (eye.0 * s, eye.1 * s), (0, 0));
    let swept = tracer::reuse::Swept::of(&scene);
    let (mut wedges, mut next) = (Vec::new(), Vec::new());
    swept.wedges(tracer.snapshot(), &mut wedges);
    let mut marks = [(); 2].map(|()| tracer::reuse::Marks::new(eye.0 * s, eye.1 * s));
    let mut samples = [Vec::new(), Vec::new()];
    let mut renderer = Renderer::default();
    let (mut bits, mut selected) = (tracer::PixelBits::new(eye.0 * s, eye.1 * s), tracer::PixelBits::default());
    for pass in 0..s * s {
        select_pass(&mut bits, pass, s, eye);
        for ((marks, out), view) in marks.iter_mut().zip(&mut samples).zip(&views.eyes) {
            renderer.render(&tracer, view, Pixels::Only(&bits), Target::colour(out).marking(marks, &swept));
        }
    }
    let mut steps = |frames: std::ops::Range<u32>| {
        let mut traced = 0;
        for k in frames {
            tracer.advance(&scene, k as f32 / 30.0);
            swept.wedges(tracer.snapshot(), &mut next);
            for ((marks, out), view) in marks.iter_mut().zip(&mut samples).zip(&views.eyes) {
                let n = marks.select([&wedges, &next], &mut selected);
                traced += n;
                if n > 0 {
                    renderer.render(&tracer, view, Pixels::Only(&selected), Target::colour(out).marking(marks, &swept));
                }
            }
            std::mem::swap(&mut wedges, &mut next);
        }
        traced
    };
    assert!(pool.run(|| steps(1..4)) > 0, "the orbits change some samples");
    let rounds: Vec<u64> = (1..4)
        .map(|round| {
            pool.allocations(|| {
                steps(3 * round + 1..3 * round + 4);
            })
        })
        .collect();
    let fewest = rounds.iter().copied().min().unwrap_or(0);
    assert!(fewest <= 1, "rounds of 3 warm steps allocated {rounds:?} times");
}

#[test]
fn a_warm_reused_frame_allocates_nothing() {
    let pool = CountingPool::new();
    let scene = scene("seed.toml");
    let (w, h) = (160, 90);
    let mut tracer = Tracer::new(&scene, 0.0);
    let modes = [Mode::Full, Mode::Copy, Mode::Reshade, Mode::Exact];
    for (mode, depths) in modes.into_iter().flat_map(|mode| [(mode, false), (mode, true)]) {
        let opts = Options { mode, retrace_edges: true };
        let mut frame = StereoFrame::new();
        frame.set_reuse(Some(&scene));
        // (With depths, the right eye's first hits kept where not made again.)
        frame.set_depths(depths);
        let mut frames_at = |times: std::ops::Range<u32>, reused: bool| {
            for k in times {
                tracer.advance(&scene, k as f32 / 60.0);
                let stats = frame.render(&tracer, &scene.camera, w, h, opts);
                assert!(stats.reuse.reused || !reused, "{mode}: every frame after the first reuses");
            }
        };
        // Warm up: the first frame marks, the next ones reuse.
        pool.run(|| frames_at(0..6, false));
        let frames = 24;
        let rounds: Vec<u64> = (1..4)
            .map(|round| {
                let first = 6 + round * frames;
                pool.allocations(|| frames_at(first..first + frames, true))
            })
            .collect();
        let fewest = rounds.iter().copied().min().unwrap_or(0);
        assert!(
            fewest <= u64::from(frames) / 8,
            "{mode}, depths {depths}: rounds of {frames} reused frames allocated {rounds:?} times"
        );
    }
}

#[test]
fn a_warm_warp_allocates_nothing() {
    let pool = CountingPool::new();
    let scene = scene("seed.toml");
    let tracer = Tracer::new(&scene, 0.0);
    let (w, h, margin) = (160, 90, (8, 6));
    let eyes = [Eye::Left, Eye::Right];
    let views = eyes.map(|eye| scene.camera.view_with_margin(eye, w, h, margin));
    let films = views.map(|view| {
        let mut film = Film::new(view.width, view.height);
        Renderer::new().render(&tracer, &view, Pixels::All, Target::film(&mut film, Record::Keys));
        film
    });
    // The head turns, tilts and steps: each pose exposes other holes and edges.
    let targets: Vec<_> = (0..6_u8)
        .map(|k| {
            let k = f32::from(k);
            let pose = Camera {
                yaw_deg: 1.5 * k - 4.0,
                pitch_deg: 2.0 - 0.7 * k,
                position: scene.camera.position + Vec3::new(0.04 * k - 0.1, 0.02 * k, -0.05 * k),
                ..scene.camera
            };
            eyes.map(|eye| pose.view(eye, w, h))
        })
        .collect();
    let mut warp = Warp::new();
    let (mut left, mut right, mut left_classes, mut right_classes) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    let mut warp_to_every_pose = || {
        for [l, r] in &targets {
            let sources = [0, 1].map(|e| WarpSource::from_film(views[e], &films[e]));
            warp.warp(sources, [l, r], [&mut left, &mut right], [&mut left_classes, &mut right_classes]);
        }
    };
    // Warm up: the images, the bounds and every thread's keys grow to their size (twice, as
    // any thread may take any band).
    pool.run(|| {
        warp_to_every_pose();
        warp_to_every_pose();
    });
    let frames = 4 * targets.len() as u64;
    let rounds: Vec<u64> = (0..3)
        .map(|_| {
            pool.allocations(|| {
                for _ in 0..4 {
                    warp_to_every_pose();
                }
            })
        })
        .collect();
    let fewest = rounds.iter().copied().min().unwrap_or(0);
    assert!(fewest <= frames / 8, "rounds of {frames} warm warps allocated {rounds:?} times");
}

//! The render worker: stereo frames are traced on their own thread so the window never waits.
//!
//! The UI thread posts the newest [`Request`] (`worker/request.rs`, with the [`FrameInfo`]
//! that answers it) into a one-slot mailbox (a `Mutex` + `Condvar`); an older request that
//! the worker has not started yet is simply replaced. The worker renders with
//! [`stereo::StereoFrame::render_banded`] (which spreads the work over rayon's global pool), copies
//! the pictures into a [`Finished`] frame (`worker/finished.rs`; the eyes to present,
//! `worker/eyes.rs`) and swaps it into a second one-slot mailbox. The UI thread swaps the
//! newest finished frame out whenever it draws. The three `Finished` buffers (the worker's,
//! the mailbox's, the UI's) rotate by swapping, so once warm nothing is allocated.
//!
//! A finished frame carries the views its pair was traced through ([`FrameInfo::views`]:
//! the pose, the sampled size and the guard band), as the stereo frame kept them: the
//! timewarp warps the pair from those views, and never derives them again from the request.
//! With the timewarp on, the frame also keeps each eye as traced, guard band and depths
//! included ([`Finished::traced`]).
//!
//! A request may ask for more samples than pixels (a render scale above 100 %): the frame is
//! traced at the sampled size and its eyes, its mask's colours and the live-PSNR reference
//! are filtered down to the eye size ([`stereo::downsample`], a box filter in linear light)
//! into the `Finished` frame's buffers. The class mask stays per sample. A sampled size
//! whose buffers would not fit in the memory that was available when the worker started
//! ([`crate::setup::viewer_frame_fits`]) is traced at the eye size instead, and the frame
//! says so ([`FrameInfo::samples`]).
//!
//! The worker owns its copy of the scene. A new one (the scene file was saved, or another
//! file opened) goes into the inbox beside the request with [`Worker::set_scene`]; the
//! worker takes both under the same lock, so the next request it starts is rendered with
//! the new scene. Nothing about this costs anything per frame: the slot is empty then.

use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::Instant;

use tracer::Scene;

use crate::setup;

mod budget;
mod eyes;
pub(crate) mod finished;
mod job;
mod progress;
mod refine;
mod request;

pub(crate) use eyes::filter_eyes;
pub use eyes::Eyes;
pub use finished::Finished;
use job::Job;
pub use request::{FrameInfo, Progressive, Request, Sampling};

#[derive(Default)]
struct Inbox {
    /// The newest request, and when it was posted.
    request: Option<(Request, Instant)>,
    /// A scene to render from the next request on.
    scene: Option<Scene>,
    quit: bool,
}

#[derive(Default)]
struct Outbox {
    frame: Finished,
    fresh: bool,
    /// The tracer being built, while it is.
    building: Option<Building>,
    /// Bytes of the resting refinement's buffers.
    refine_bytes: usize,
}

/// The worker is building its tracer for a scene (the BVH, the light maps): what a large
/// scene's first frame waits for, which the window shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Building {
    /// The scene's spheres.
    pub spheres: usize,
    /// When the build began.
    pub since: Instant,
}

#[derive(Default)]
struct Shared {
    inbox: Mutex<Inbox>,
    wake: Condvar,
    outbox: Mutex<Outbox>,
}

/// Locks a mutex, ignoring poisoning: a panic on the other side is reported through
/// [`Worker::check_alive`], and the data under these locks stays consistent (plain swaps).
fn lock<T>(m: &Mutex<T>) -> MutexGuard<'_, T> {
    m.lock().unwrap_or_else(PoisonError::into_inner)
}

/// Handle to the render thread. Dropping it stops the thread (after its current frame).
pub struct Worker {
    shared: Arc<Shared>,
    thread: Option<JoinHandle<()>>,
    front: Finished,
    last_posted: Option<Request>,
}

impl Worker {
    /// Starts the render thread for `scene`; supersampled frames must fit in the memory
    /// available now ([`setup::available_memory`]).
    pub fn spawn(scene: Scene) -> anyhow::Result<Self> {
        Self::spawn_with_memory(scene, setup::available_memory()?)
    }

    /// Starts the render thread with `memory` bytes for supersampled frames (`None`: no
    /// limit).
    fn spawn_with_memory(scene: Scene, memory: Option<u64>) -> anyhow::Result<Self> {
        let shared = Arc::new(Shared::default());
        let theirs = Arc::clone(&shared);
        let thread =
            std::thread::Builder::new().name("render".into()).spawn(move || render_loop(scene, memory, &theirs))?;
        Ok(Self { shared, thread: Some(thread), front: Finished::default(), last_posted: None })
    }

    /// Asks for a frame, replacing any request not yet started. A request equal to the last
    /// one posted is ignored, so a paused, unchanged view costs nothing.
    pub fn post(&mut self, request: Request) {
        if self.last_posted == Some(request) {
            return;
        }
        self.last_posted = Some(request);
        lock(&self.shared.inbox).request = Some((request, Instant::now()));
        self.shared.wake.notify_one();
    }

    /// Renders `scene` from the next request on (the request after this call is sent even if
    /// it equals the last one, so an unchanged view of a new scene is rendered).
    pub fn set_scene(&mut self, scene: Scene) {
        self.last_posted = None;
        lock(&self.shared.inbox).scene = Some(scene);
    }

    /// The newest finished frame (swapped in if the worker has finished one since the last
    /// call).
    pub fn latest(&mut self) -> &Finished {
        let mut out = lock(&self.shared.outbox);
        if out.fresh {
            std::mem::swap(&mut self.front, &mut out.frame);
            out.fresh = false;
        }
        drop(out);
        &self.front
    }

    /// Whether the worker has finished a frame that [`Worker::latest`] has not yet taken.
    pub fn has_fresh(&self) -> bool {
        lock(&self.shared.outbox).fresh
    }

    /// The tracer being built, while it is.
    pub fn building(&self) -> Option<Building> {
        lock(&self.shared.outbox).building
    }

    /// Bytes of the resting refinement's buffers (the progressive policy's accumulation:
    /// `worker/refine.rs`), as of the last frame finished.
    pub fn refine_bytes(&self) -> usize {
        lock(&self.shared.outbox).refine_bytes
    }

    /// The frame returned by the last [`Worker::latest`].
    pub fn current(&self) -> &Finished {
        &self.front
    }

    /// Fails if the render thread has died (it only can by panicking).
    pub fn check_alive(&self) -> anyhow::Result<()> {
        match &self.thread {
            Some(t) if !t.is_finished() => Ok(()),
            _ => anyhow::bail!("the render thread stopped unexpectedly (see the panic message above)"),
        }
    }
}

impl Drop for Worker {
    fn drop(&mut self) {
        lock(&self.shared.inbox).quit = true;
        self.shared.wake.notify_one();
        if let Some(t) = self.thread.take() {
            // A panic was already printed by the panic hook; nothing more to report here.
            let _ = t.join();
        }
    }
}

/// The tracer's threads' priority where [`lower_this_thread`] cannot make them idle-class,
/// of thread-priority's 0 (lowest) to 99 (highest): a niceness of 10 (the crate maps 0..=99
/// onto 19..=-20; the UI's threads keep 0), whose scheduler weights give a thread at 0 about
/// nine times the CPU of one at 10 when both want it.
const TRACER_PRIORITY: u8 = 22;

/// Lowers the calling thread, a tracer's, below the display's. On Linux it joins the
/// scheduler's idle class (`SCHED_IDLE`, sched(7)): it runs only on CPU time no normal thread
/// wants, so the display tick, wanting a few milliseconds of the cores at the display's rate,
/// gets them at once, and the tracer still has every cycle the tick leaves. Measured under
/// Xvfb on `thousand.toml` with D held, panel shown, three runs each: a niceness of 10 gave
/// 88.2 / 88.4 / 80.4 `pose_fps` (each redraw ~10 ms, the tracer's threads still taking
/// their tenth of the cores); the idle class 90.0 / 90.0 / 90.0 (~6 ms), at the same traced
/// rate. Elsewhere, or if that fails, it takes [`TRACER_PRIORITY`]. Failing both leaves the
/// priority as it was: the timewarp then shares the cores evenly with the tracer, which is
/// slower, not wrong.
pub fn lower_this_thread() {
    #[cfg(target_os = "linux")]
    {
        use thread_priority::{NormalThreadSchedulePolicy, ThreadPriority, ThreadSchedulePolicy};
        let idle = ThreadSchedulePolicy::Normal(NormalThreadSchedulePolicy::Idle);
        if thread_priority::set_thread_priority_and_policy(
            thread_priority::thread_native_id(),
            ThreadPriority::Min,
            idle,
        )
        .is_ok()
        {
            return;
        }
    }
    if let Ok(value) = TRACER_PRIORITY.try_into() {
        // An error leaves the thread as it was (see above).
        let _ = thread_priority::set_current_thread_priority(thread_priority::ThreadPriority::Crossplatform(value));
    }
}

/// Builds rayon's global pool, which the tracer uses, with its threads at
/// [`TRACER_PRIORITY`]; nothing if the pool was already built (its first use builds it).
pub fn lower_the_tracer_pool() {
    // An error only says that the pool exists already: it keeps its priority.
    let _ = rayon::ThreadPoolBuilder::new()
        .thread_name(|i| format!("tracer-{i}"))
        .start_handler(|_| lower_this_thread())
        .build_global();
}

/// What the worker does next.
enum Step {
    /// Trace a new request, posted at that instant.
    Trace(Request, Instant),
    /// Refine the resting request: nothing newer has come.
    Refine,
}

/// The worker thread's state: scene, tracer and all buffers, reused frame after frame. The
/// scene is a working copy whose first light the requests move; `memory` bounds the
/// supersampled frames.
fn render_loop(scene: Scene, memory: Option<u64>, shared: &Shared) {
    lower_this_thread();
    let mut job = Job::new(shared, scene, memory);
    loop {
        let step = {
            let mut inbox = lock(&shared.inbox);
            loop {
                if inbox.quit {
                    return;
                }
                if let Some((request, posted)) = inbox.request.take() {
                    if let Some(new) = inbox.scene.take() {
                        job.set_scene(new);
                    }
                    break Step::Trace(request, posted);
                }
                if job.progress.pending() {
                    break Step::Refine;
                }
                inbox = shared.wake.wait(inbox).unwrap_or_else(PoisonError::into_inner);
            }
        };
        let made = match step {
            Step::Trace(request, posted) => {
                job.trace(shared, request, posted);
                true
            }
            Step::Refine => job.refine(shared),
        };
        if !made {
            continue;
        }
        let mut out = lock(&shared.outbox);
        std::mem::swap(&mut out.frame, &mut job.back);
        out.fresh = true;
        out.refine_bytes = job.progress.refine.bytes();
    }
}

/// Runs `work`, a build of the tracer for `scene`, with the outbox saying so meanwhile.
fn build<T>(shared: &Shared, scene: &Scene, work: impl FnOnce() -> T) -> T {
    lock(&shared.outbox).building = Some(Building { spheres: scene.sphere_count(), since: Instant::now() });
    let built = work();
    lock(&shared.outbox).building = None;
    built
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::reference::Reference;
    use glam::Vec3;
    use std::time::Duration;
    use stereo::Options;
    use stereo::StereoFrame;
    use tracer::Camera;
    use tracer::Tracer;

    fn scene() -> Scene {
        Scene::from_toml(
            "[[lights]]\nposition = [0.0, 5.0, 0.0]\n[[spheres]]\ncenter = [0.0, 0.0, 12.0]\nradius = 2.0\n",
            "test.toml",
        )
        .unwrap()
    }

    fn request(width: u32, psnr: bool) -> Request {
        Request::sized(width, 24).measured(psnr)
    }

    #[test]
    fn the_test_builder_sets_what_it_names_and_nothing_else() {
        let base = Request::sized(32, 24);
        assert_eq!((base.width, base.height, base.samples, base.guard), (32, 24, (32, 24), (0, 0)));
        assert!(base.overlay && !base.psnr && !base.anaglyph && !base.timewarp && !base.reuse);
        let camera = Camera { ipd: 1.5, ..Camera::default() };
        let built = base.at(camera).sampled((64, 48)).with_timewarp((3, 2)).measured(true);
        let expect =
            Request { camera, samples: (64, 48), timewarp: true, guard: (3, 2), psnr: true, anaglyph: true, ..base };
        assert_eq!(built, expect);
    }

    fn wait_for(worker: &mut Worker, seq: u64) -> &Finished {
        let deadline = Instant::now() + Duration::from_secs(30);
        while worker.latest().info.is_none_or(|i| i.seq < seq) {
            assert!(Instant::now() < deadline, "no frame {seq}");
            std::thread::sleep(Duration::from_millis(2));
        }
        worker.current()
    }

    #[test]
    fn renders_the_requested_size_and_measures_quality_on_request() {
        let mut worker = Worker::spawn(scene()).unwrap();
        worker.post(request(32, true));
        let f = wait_for(&mut worker, 1);
        let info = f.info.unwrap();
        assert_eq!(f.size(), (32, 24));
        assert_eq!((f.eyes.left.len(), f.eyes.right.len(), f.mask.len()), (32 * 24, 32 * 24, 32 * 24));
        assert!(info.quality.is_some());
        assert_eq!(f.eyes.anaglyph.len(), 32 * 24, "asked for with the quality in these tests");
        worker.post(request(40, false));
        let f = wait_for(&mut worker, 2);
        assert_eq!(f.size(), (40, 24));
        assert!(f.info.unwrap().quality.is_none());
        assert!(f.eyes.anaglyph.is_empty());
        worker.check_alive().unwrap();
    }

    #[test]
    fn the_anaglyph_takes_red_from_the_left_eye_unless_swapped() {
        let mut worker = Worker::spawn(scene()).unwrap();
        let req = request(32, true).at(Camera { ipd: 1.5, ..Camera::default() });
        worker.post(req);
        let f = wait_for(&mut worker, 1);
        let expect: Vec<u32> =
            f.eyes.left.iter().zip(&f.eyes.right).map(|(&l, &r)| stereo::anaglyph_pixel(l, r)).collect();
        assert_eq!(f.eyes.anaglyph, expect);
        assert_ne!(f.eyes.left, f.eyes.right, "the eyes should differ for this test to mean anything");
        worker.post(Request { swap: true, ..req });
        let f = wait_for(&mut worker, 2);
        let expect: Vec<u32> =
            f.eyes.left.iter().zip(&f.eyes.right).map(|(&l, &r)| stereo::anaglyph_pixel(r, l)).collect();
        assert_eq!(f.eyes.anaglyph, expect);
        // Dubois's red row weighs the left image: a white left and black right eye give red.
        assert!(stereo::anaglyph_pixel(0x00FF_FFFF, 0) >> 16 > 0xC0);
    }

    #[test]
    fn the_request_moves_the_first_light() {
        let mut worker = Worker::spawn(scene()).unwrap();
        worker.post(request(16, false));
        let before = wait_for(&mut worker, 1).eyes.left.clone();
        // Under the sphere: its visible side falls into shadow.
        worker.post(Request { light: Some(Vec3::new(0.0, -20.0, 12.0)), ..request(16, false) });
        let moved = wait_for(&mut worker, 2).eyes.left.clone();
        assert_ne!(before, moved);
        worker.post(request(16, true));
        assert_eq!(wait_for(&mut worker, 3).eyes.left, before, "no override: the scene's light again");
    }

    /// At 200 % the frame is traced at 2 × 2 samples per pixel: the eyes are those samples
    /// filtered down, the mask stays per sample, the overlay is the mask's colours filtered.
    #[test]
    fn a_supersampled_frame_is_traced_at_the_samples_and_filtered_to_the_eye() {
        let mut worker = Worker::spawn_with_memory(scene(), None).unwrap();
        let req = request(32, true).at(Camera { ipd: 1.0, ..Camera::default() }).sampled((64, 48));
        worker.post(req);
        let f = wait_for(&mut worker, 1);
        let info = f.info.unwrap();
        assert_eq!((f.size(), f.samples(), info.samples()), ((32, 24), (64, 48), (64, 48)));
        let mut direct = StereoFrame::new();
        let mut tracer = Tracer::new(&scene(), 0.0);
        tracer.set_max_depth(2);
        direct.render(&tracer, &req.camera, 64, 48, req.opts);
        let (mut left, mut right, mut overlay) = (Vec::new(), Vec::new(), Vec::new());
        stereo::downsample(&direct.left().rgb, (64, 48), &mut left, (32, 24));
        stereo::downsample(&direct.right().rgb, (64, 48), &mut right, (32, 24));
        stereo::downsample_mask(direct.mask(), (64, 48), &mut overlay, (32, 24));
        assert_eq!((&f.eyes.left, &f.eyes.right, &f.eyes.right_overlay), (&left, &right, &overlay));
        assert_eq!(f.mask, direct.mask(), "the mask per sample");
        assert_eq!(f.eyes.anaglyph.len(), 32 * 24, "the anaglyph of the filtered eyes");
        assert_eq!(info.stats.left.rays.primary, 64 * 48, "one primary ray per sample");
        let mut reference = Reference::default();
        reference.trace(&tracer, &req.camera, 64, 48);
        assert_eq!(info.quality, Some(reference.compare_filtered(&right, (64, 48), (32, 24))), "the filtered eyes");
    }

    /// With the timewarp, the eyes are traced with a guard band and their depth: the frame
    /// keeps them for the warp, and its eyes are the shown part, the frame without the band
    /// byte for byte.
    #[test]
    fn a_timewarp_request_keeps_the_banded_eyes_and_depths() {
        let mut worker = Worker::spawn_with_memory(scene(), None).unwrap();
        let camera = Camera { ipd: 1.0, ..Camera::default() };
        let plain = Request { overlay: false, ..request(32, false).at(camera) };
        worker.post(plain);
        let (left, right) = {
            let f = wait_for(&mut worker, 1);
            assert!(f.traced.is_empty() && f.warp_sources().is_none(), "nothing kept without the timewarp");
            (f.eyes.left.clone(), f.eyes.right.clone())
        };
        worker.post(plain.with_timewarp((3, 2)));
        let f = wait_for(&mut worker, 2);
        assert_eq!((&f.eyes.left, &f.eyes.right), (&left, &right), "the shown part is the plain frame");
        let t = &f.traced;
        let n = (32 + 6) * (24 + 4);
        let views = f.info.unwrap().views;
        assert_eq!((views.camera, views.shown, views.margin), (camera, (32, 24), (3, 2)), "the views traced");
        let sources = f.warp_sources().unwrap();
        assert_eq!(sources.map(|s| (s.view.width, s.view.height, s.view.margin)), [(38, 28, (3, 2)); 2]);
        assert_eq!([t.left.len(), t.left_z.len(), t.right.len(), t.right_z.len()], [n; 4], "banded planes");
        let mut direct = StereoFrame::new();
        let mut tracer = Tracer::new(&scene(), 0.0);
        tracer.set_max_depth(2);
        direct.set_depths(true);
        direct.render_banded(&tracer, &camera, (32, 24), (3, 2), plain.opts);
        assert_eq!((&t.left, &t.left_z), (&direct.left().rgb, &direct.left().z), "the left eye as traced");
        assert_eq!((&t.right, &t.right_z[..]), (&direct.right().rgb, direct.right_depth()), "the right eye as traced");
        assert!(t.left_z.iter().any(|z| z.is_finite()), "the sphere is in view");
        // The mask asked for: the colours of the shown part's classes, which the frame
        // shows when the head is still (the frame shown as traced).
        assert!(f.eyes.right_overlay.is_empty(), "no colours unless asked for");
        worker.post(Request { overlay: true, ..plain.with_timewarp((3, 2)) });
        let f = wait_for(&mut worker, 3);
        let mut overlay = Vec::new();
        stereo::downsample_mask(&f.mask, (32, 24), &mut overlay, (32, 24));
        assert_eq!(f.mask.len(), 32 * 24, "the shown part's classes");
        assert_eq!(f.eyes.right_overlay, overlay, "their colours");
        assert!(f.mask.iter().any(|&c| c != stereo::PixelClass::Reprojected), "some pixels retraced");
    }

    #[test]
    fn the_mask_colours_are_made_only_when_asked_for() {
        let mut worker = Worker::spawn_with_memory(scene(), None).unwrap();
        worker.post(Request { overlay: false, ..request(32, false) });
        let f = wait_for(&mut worker, 1);
        assert!(f.eyes.right_overlay.is_empty() && f.mask.len() == 32 * 24, "no colours, the mask still kept");
        let (left, traced) = (f.eyes.left.clone(), f.info.unwrap().stats.left.ms);
        worker.post(request(32, false));
        let f = wait_for(&mut worker, 2);
        assert_eq!(f.eyes.right_overlay.len(), 32 * 24, "asked for: one per pixel");
        // Only the overlay was asked for: the same frame, not traced again.
        assert_eq!((&f.eyes.left, f.info.unwrap().stats.left.ms), (&left, traced));
        let mut direct = StereoFrame::new();
        let mut tracer = Tracer::new(&scene(), 0.0);
        tracer.set_max_depth(2);
        direct.render(&tracer, &Camera::default(), 32, 24, Options::default());
        let mut overlay = Vec::new();
        stereo::downsample_mask(direct.mask(), (32, 24), &mut overlay, (32, 24));
        assert_eq!(f.eyes.right_overlay, overlay, "the frame's own mask colours");
    }

    #[test]
    fn samples_that_do_not_fit_in_memory_are_traced_at_the_eye_size() {
        let eye = (32, 24);
        let need = setup::viewer_frame_bytes((64, 48), eye);
        let mut worker = Worker::spawn_with_memory(scene(), Some(need - 1)).unwrap();
        worker.post(request(32, false).sampled((64, 48)));
        let f = wait_for(&mut worker, 1);
        assert_eq!((f.size(), f.samples()), (eye, eye), "one byte short: no supersampling");
        assert_eq!(f.info.unwrap().request.samples, (64, 48), "the frame still names what was asked");
        let mut worker = Worker::spawn_with_memory(scene(), Some(need)).unwrap();
        worker.post(request(32, false).sampled((64, 48)));
        assert_eq!(wait_for(&mut worker, 1).samples(), (64, 48), "exactly enough");
    }

    #[test]
    fn a_new_scene_is_rendered_from_the_next_request_even_an_unchanged_one() {
        let mut worker = Worker::spawn(scene()).unwrap();
        worker.post(request(16, false));
        let before = wait_for(&mut worker, 1).eyes.left.clone();
        let bigger = Scene::from_toml(
            "[[lights]]\nposition = [0.0, 5.0, 0.0]\n[[spheres]]\ncenter = [0.0, 0.0, 12.0]\nradius = 4.0\n",
            "bigger.toml",
        )
        .unwrap();
        worker.set_scene(bigger.clone());
        worker.post(request(16, false));
        let after = wait_for(&mut worker, 2).eyes.left.clone();
        assert_ne!(before, after, "the bigger sphere covers more of the eye");
        let mut alone = Worker::spawn(bigger).unwrap();
        alone.post(request(16, false));
        assert_eq!(wait_for(&mut alone, 1).eyes.left, after, "exactly what a worker started on the new scene renders");
    }

    /// The tracer's threads run in the idle scheduling class on Linux, which the kernel
    /// reports as field 41 of the thread's stat line (`SCHED_IDLE`, 5), or, where a sandbox
    /// refuses that, at a niceness of 10 (field 19).
    #[cfg(target_os = "linux")]
    #[test]
    fn the_tracers_threads_run_at_a_lower_priority() {
        // (policy, niceness) of the calling thread.
        let scheduling = || {
            let stat = std::fs::read_to_string("/proc/thread-self/stat").unwrap();
            // After the command's closing parenthesis: state is field 3.
            let fields: Vec<&str> = stat[stat.rfind(')').unwrap() + 2..].split(' ').collect();
            (fields[38].parse::<i32>().unwrap(), fields[16].parse::<i32>().unwrap())
        };
        let (before, after) = std::thread::spawn(move || {
            let before = scheduling();
            lower_this_thread();
            (before, scheduling())
        })
        .join()
        .unwrap();
        assert_eq!(before, (libc_sched::OTHER, 0), "a new thread runs normally");
        let idle = after.0 == libc_sched::IDLE;
        if !idle {
            eprintln!("SCHED_IDLE was refused here: the niceness fallback is checked instead");
        }
        assert!(
            idle || after == (libc_sched::OTHER, 10),
            "lowered to the idle class, or else to niceness 10: {after:?}"
        );
    }

    /// Linux's scheduling policies, as `sched.h` numbers them.
    #[cfg(target_os = "linux")]
    mod libc_sched {
        pub const OTHER: i32 = 0;
        pub const IDLE: i32 = 5;
    }

    /// A handle whose render thread never started: what `post` sends stays in the inbox,
    /// where the test takes it out as the thread would.
    fn unstarted() -> Worker {
        Worker { shared: Arc::default(), thread: None, front: Finished::default(), last_posted: None }
    }

    /// The dedup happens where requests are sent, so it is checked there, without a thread
    /// and without waiting: the render loop renders exactly what reaches its inbox.
    #[test]
    fn an_unchanged_request_is_not_sent_again() {
        let mut worker = unstarted();
        let take = |w: &Worker| lock(&w.shared.inbox).request.take().map(|(r, _)| r);
        worker.post(request(16, false));
        assert_eq!(take(&worker), Some(request(16, false)), "the first request is sent");
        worker.post(request(16, false));
        assert_eq!(take(&worker), None, "the same request again is not");
        worker.post(request(17, false));
        assert_eq!(take(&worker), Some(request(17, false)), "a changed one is");
        worker.post(request(16, false));
        worker.post(request(18, false));
        assert_eq!(take(&worker), Some(request(18, false)), "a request not yet started is replaced");
        worker.post(request(18, true));
        assert_eq!(take(&worker), Some(request(18, true)), "any field counts as a change");
        worker.set_scene(scene());
        assert!(lock(&worker.shared.inbox).scene.is_some(), "the new scene waits beside the request");
        worker.post(request(18, true));
        assert_eq!(take(&worker), Some(request(18, true)), "after a new scene the same request is sent again");
    }
}

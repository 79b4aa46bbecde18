//! The progressive policy (`Request::progressive`): young, coarse pairs while the head
//! moves, then the resting pose in full and refined pass by pass.
//!
//! - A request posted while the head moves is traced at the density the time budget picks
//!   (`budget.rs`): one sample per k × k pixels, reconstructed at the eye size
//!   ([`stereo::upsample`]) and warped by depth like a full pair.
//! - A request the head rests on (posted with the head still, or the last one of a move,
//!   when nothing newer comes) is traced in full, then refined to S × S samples a pixel
//!   (`refine.rs`), converging to `render --supersample S` byte for byte.
//! - Any new request (the head, a slider, the mode, a reload) restarts: the refinement
//!   stops and the new request is traced from scratch. A new instant of orbiting spheres
//!   alone does not: the samples that can have changed become stale and are traced again
//!   ([`Refine::advance`]), and the rest keep accumulating.
//!
//! Without the policy (`--no-progressive`, `replay --policy fixed`), every request is traced
//! at its samples, as before it existed.

use std::time::Instant;

use tracer::{Scene, Tracer};

use super::budget::{self, Budget};
use super::refine::{self, Refine};
use super::{Eyes, Request, Sampling};

/// The policy's state between frames.
#[derive(Debug, Default)]
pub struct Progress {
    /// What pairs cost, by density.
    budget: Budget,
    /// The resting pose's refinement.
    pub refine: Refine,
    /// The request the worker rests on while no newer one comes, with when it was posted.
    pub resting: Option<(Request, Instant)>,
    /// The resting request was last traced coarse: its full pair comes next.
    pub coarse: bool,
}

impl Progress {
    /// Whether there is work for the resting request.
    #[must_use]
    pub fn pending(&self) -> bool {
        self.resting.is_some() && (self.coarse || self.refine.pending())
    }

    /// Forgets the measured costs and the resting request (another scene).
    pub fn forget(&mut self) {
        self.budget.forget();
        self.refine.stop();
        (self.resting, self.coarse) = (None, false);
    }

    /// The density to trace `request` at: the budget's while the head moves (a pose not
    /// only a scene time away from the last), else every sample. A new trace stops the
    /// refinement of the last pose, unless the refinement can follow it to its instant
    /// ([`Progress::advance`]).
    pub fn density(&mut self, request: &Request, only_time: bool) -> u32 {
        if !(only_time && self.follows(request)) {
            self.refine.stop();
        }
        match request.progressive {
            Some(p) if request.moving && !only_time && refinable(request) => {
                self.budget.choose((request.width, request.height), f64::from(p.target_age_ms))
            }
            _ => 1,
        }
    }

    /// Whether `request` is the resting request at another instant of the scene, and the
    /// refinement can follow it there.
    fn follows(&self, request: &Request) -> bool {
        let resting = self.resting.is_some_and(|(r, _)| Request { time: request.time, ..r } == *request);
        resting && !self.coarse && self.refine.follows()
    }

    /// `request`, posted at `posted`, is the resting request at a new instant of its scene,
    /// which `tracer` is at: the refinement moves its samples there and rests on it
    /// ([`Refine::advance`]). Returns false, changing nothing, when it cannot.
    pub fn advance(&mut self, (request, posted): (Request, Instant), tracer: &Tracer) -> bool {
        if !self.follows(&request) || !self.refine.advance(tracer) {
            return false;
        }
        self.resting = Some((request, posted));
        true
    }

    /// Remembers that `request`'s pair at `density` took `ms`.
    pub fn measured(&mut self, request: &Request, density: u32, ms: f64) {
        if request.progressive.is_some() && refinable(request) {
            self.budget.record((request.width, request.height), density, ms);
        }
    }

    /// `request`, posted at `posted`, was traced at `density` in `ms`: what comes next for
    /// it if no newer request comes. The refinement's buffers fit in `memory` (`None`: no
    /// limit). With `follow` (the scene with its orbiting spheres, when the request reuses,
    /// and the tracer at its instant), the refinement follows the scene's time.
    pub fn traced(
        &mut self,
        (request, posted): (Request, Instant),
        (density, outline): (u32, u32),
        ms: f64,
        memory: Option<u64>,
        follow: Option<(&Scene, &Tracer)>,
    ) {
        self.refine.stop();
        (self.resting, self.coarse) = (None, false);
        let Some(p) = request.progressive.filter(|_| refinable(&request)) else { return };
        // A moving head's request is not rested on: the window's next request (the key let
        // go) says the head stopped. Traced in full now, it would hold the worker for a full
        // pair while the head moves on.
        if request.moving {
            return;
        }
        (self.resting, self.coarse) = (Some((request, posted)), density > 1);
        if density == 1 {
            let eye = (request.width, request.height);
            let pixels = u64::from(eye.0) * u64::from(eye.1);
            let following = follow.is_some() && outline == 0;
            let fits = |s: u32| memory.is_none_or(|m| refine::bytes_per_pixel(s, following) * pixels <= m);
            let s = (1..=p.max_supersample).rev().find(|&s| fits(s)).unwrap_or(1);
            if s > 1 {
                self.refine.start(&request.camera, eye, (s, outline), ms, follow);
            }
        }
    }

    /// How the frame made now is sampled: at `density` for a new trace, or the
    /// refinement's samples so far.
    #[must_use]
    pub fn sampling(&self, request: &Request, density: u32) -> Sampling {
        if density > 1 {
            return Sampling { density, spp: 0, converged: false };
        }
        let spp = self.refine.spp();
        if spp > 0 {
            return Sampling { density: 1, spp, converged: self.refine.converged() };
        }
        let converged = request.progressive.is_some_and(|p| p.max_supersample <= 1);
        Sampling { density: 1, spp: 1, converged }
    }

    /// Over `eyes`, the refined pair, when a pass is done (and the anaglyph made again).
    pub fn paint(&mut self, tracer: &Tracer, eyes: &mut Eyes, (anaglyph, swap): (bool, bool)) {
        if self.refine.spp() > 0 {
            self.refine.eyes(tracer, [&mut eyes.left, &mut eyes.right]);
            eyes.finish_anaglyph(anaglyph, swap);
        }
    }
}

/// Whether the policy applies to `request`: traced at the eye size (a render scale of
/// 100 %; other scales keep their own sampling).
fn refinable(request: &Request) -> bool {
    request.samples == (request.width, request.height)
}

/// The density's sample size, re-exported for the worker.
pub use budget::samples_at;

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use stereo::{Mode, StereoFrame};
    use tracer::testing::scene;
    use tracer::{Scene, Tracer};

    use super::super::{Finished, Progressive, Request, Worker};
    use super::*;
    use crate::window::settings::Settings;

    const EYE: (u32, u32) = (40, 30);

    /// The viewer's request for `scene` at `EYE` in `mode`, refined to `s` × `s`.
    fn request(scene: &Scene, mode: Mode, s: u32, timewarp: bool) -> Request {
        let mut settings = Settings::from_scene(scene);
        (settings.mode, settings.timewarp, settings.depth) = (mode, timewarp, 2);
        settings.ipd = settings.ipd.max(0.3);
        settings.progressive = Some(Progressive { target_age_ms: 33.0, max_supersample: s });
        settings.request(scene, 0.0, EYE.0, EYE.1)
    }

    /// Waits for the first frame after `seq` that `done` accepts.
    fn wait(worker: &mut Worker, seq: u64, done: impl Fn(&Finished) -> bool) -> &Finished {
        let deadline = Instant::now() + Duration::from_secs(60);
        loop {
            let f = worker.latest();
            if f.info.is_some_and(|i| i.seq > seq) && done(f) {
                return worker.current();
            }
            assert!(Instant::now() < deadline, "no such frame");
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    /// `request`'s pair as `render --supersample s` makes it: traced at s × s samples a
    /// pixel in its mode, the scene's outlines drawn on the samples, each eye filtered down.
    fn supersampled(scene: &Scene, request: &Request, s: u32) -> [Vec<u32>; 2] {
        let mut tracer = Tracer::new(scene, request.time);
        tracer.set_max_depth(request.depth);
        let mut frame = StereoFrame::new();
        frame.render(&tracer, &request.camera, EYE.0 * s, EYE.1 * s, request.opts);
        let size = (EYE.0 * s, EYE.1 * s);
        let mut outlined = stereo::Outlined::new();
        let [l, r] = outlined.eyes(&tracer, &frame, (scene.render.cues.outline * s) as f32);
        let (mut left, mut right) = (Vec::new(), Vec::new());
        stereo::downsample(l, size, &mut left, EYE);
        stereo::downsample(r, size, &mut right, EYE);
        [left, right]
    }

    fn eyes(f: &Finished) -> [Vec<u32>; 2] {
        [f.eyes.left.clone(), f.eyes.right.clone()]
    }

    #[test]
    fn a_resting_view_converges_to_the_supersampled_render_byte_for_byte() {
        let scene = scene("seed.toml");
        for (mode, timewarp) in [(Mode::Full, false), (Mode::Exact, false), (Mode::Exact, true)] {
            let mut worker = Worker::spawn_with_memory(scene.clone(), None).unwrap();
            let request = request(&scene, mode, 3, timewarp);
            worker.post(request);
            let f = wait(&mut worker, 0, |f| f.info.is_some_and(|i| i.sampling.converged));
            let info = f.info.unwrap();
            assert_eq!(info.sampling, Sampling { density: 1, spp: 9, converged: true }, "{mode}");
            assert_eq!(f.size(), EYE);
            let want = supersampled(&scene, &request, 3);
            assert_eq!(eyes(f), want, "{mode}, timewarp {timewarp}: render --supersample 3's pair");
            assert_ne!(want[0], want[1], "the eyes differ, so a swap would show");
            assert_eq!(info.views.camera, request.camera, "shown as traced at the resting pose");
        }
    }

    /// While the seed scene's spheres orbit, a resting head's new instants do not restart
    /// the refinement: it keeps its passes, traces again what the orbits changed, and
    /// converges to `render --supersample 2` at each new instant.
    #[test]
    fn orbiting_spheres_keep_the_refinement_and_it_converges_at_each_instant() {
        let scene = scene("seed.toml");
        let mut worker = Worker::spawn_with_memory(scene.clone(), None).unwrap();
        let first = request(&scene, Mode::Exact, 2, true);
        assert!(first.reuse && scene.is_animated());
        worker.post(first);
        let mut seq = wait(&mut worker, 0, |f| f.info.is_some_and(|i| i.sampling.converged)).info.unwrap().seq;
        for time in [0.3, 0.7] {
            let next = Request { time, ..first };
            worker.post(next);
            let f = wait(&mut worker, seq, |f| f.info.is_some_and(|i| i.request.time == time && i.sampling.converged));
            assert_eq!(eyes(f), supersampled(&scene, &next, 2), "t = {time}: render --supersample 2's pair there");
            // A restart would take five frames: the pair at one sample a pixel, then four
            // passes. Following, the pair and at most three more repairs of what changed.
            let frames = f.info.unwrap().seq - seq;
            assert!(frames <= 4, "t = {time}: {frames} frames to converge again");
            seq += frames;
        }
    }

    /// With outlines (1 pixel), the converged pair has them as `render` draws them: on the
    /// samples, S samples wide, before the filter.
    #[test]
    fn a_resting_view_with_outlines_converges_to_the_render_with_them() {
        let mut scene = scene("seed.toml");
        scene.render.cues.outline = 1;
        let mut worker = Worker::spawn_with_memory(scene.clone(), None).unwrap();
        let request = request(&scene, Mode::Exact, 2, true);
        worker.post(request);
        let f = wait(&mut worker, 0, |f| f.info.is_some_and(|i| i.sampling.converged));
        let want = supersampled(&scene, &request, 2);
        assert_eq!(eyes(f), want, "render --supersample 2 --outline 1's pair");
        let mut plain = scene.clone();
        plain.render.cues.outline = 0;
        assert_ne!(want, supersampled(&plain, &request, 2), "the outlines show");
    }

    #[test]
    fn the_refined_frames_count_their_samples_and_a_change_restarts() {
        let scene = scene("seed.toml");
        let mut worker = Worker::spawn_with_memory(scene.clone(), None).unwrap();
        let first = request(&scene, Mode::Full, 2, true);
        worker.post(first);
        // Frame 1 is the pose in full, frames 2 to 5 its four passes (the mailbox keeps
        // only the newest, so the frames between may go unseen).
        let f = wait(&mut worker, 0, |f| f.info.is_some_and(|i| i.sampling.converged));
        assert_eq!(
            (f.info.unwrap().seq, f.info.unwrap().sampling.spp),
            (5, 4),
            "one full frame, then a pass at a time"
        );
        let seq = f.info.unwrap().seq;
        // A slider moved: the new request starts again from a full frame of its own.
        let mut moved = first;
        moved.camera.ipd *= 1.5;
        worker.post(moved);
        let f = wait(&mut worker, seq, |f| f.info.is_some_and(|i| i.request == moved && i.sampling.converged));
        assert_eq!(f.info.unwrap().seq, seq + 5, "from scratch: a full frame and four passes");
        assert_eq!(eyes(f), supersampled(&scene, &moved, 2), "converged again, to the new request");
    }

    #[test]
    fn a_moving_head_gets_coarse_pairs_at_the_eye_size_and_a_still_one_the_full_pair() {
        let scene = scene("seed.toml");
        let mut worker = Worker::spawn_with_memory(scene.clone(), None).unwrap();
        let mut moving = Request { moving: true, ..request(&scene, Mode::Exact, 2, true) };
        // A budget nothing fits: every moving pair at the coarsest density.
        moving.progressive = Some(Progressive { target_age_ms: 1e-6, max_supersample: 2 });
        // The head turns a little at every post, as while a key is held: each request is
        // new, so the worker never rests on one.
        let deadline = Instant::now() + Duration::from_secs(60);
        let info = loop {
            moving.camera.yaw_deg += 0.01;
            worker.post(moving);
            // (A worker done before the next post has time for the full pair too.)
            if let Some(info) = worker.latest().info.filter(|i| i.request.moving && i.sampling.density > 1) {
                break info;
            }
            assert!(Instant::now() < deadline, "no coarse frame");
            std::thread::sleep(Duration::from_micros(200));
        };
        let f = worker.current();
        let k = info.sampling.density;
        // The first pair at the first guess (4), the later ones at the coarsest (16).
        assert!([4, 16].contains(&k) && info.sampling.spp == 0, "a coarse pair: {:?}", info.sampling);
        assert_eq!((info.samples(), f.size()), (samples_at(EYE, k), EYE), "traced coarse, shown at the eye size");
        let n = |(w, h): (u32, u32)| w as usize * h as usize;
        assert_eq!((f.eyes.left.len(), f.mask.len()), (n(EYE), n(info.samples())), "the mask per sample");
        let sources = f.warp_sources().expect("a coarse pair is warped like a full one");
        let guard = info.request.guard;
        let banded = (info.samples().0 + 2 * guard.0.div_ceil(k), info.samples().1 + 2 * guard.1.div_ceil(k));
        assert_eq!((sources[0].view.width, sources[0].view.height), banded, "its guard band scaled too");
        // Nothing newer, the head still moving: the worker waits rather than trace the pose
        // in full.
        let seq = wait(&mut worker, 0, |f| f.info.is_some_and(|i| i.request == moving)).info.unwrap().seq;
        std::thread::sleep(Duration::from_millis(50));
        let last = worker.latest().info.unwrap();
        assert_eq!((last.seq, last.sampling.density), (seq, 16), "no full pair for a moving head: {last:?}");
        // The key let go: the same pose, still, is traced in full, then refined.
        let still = Request { moving: false, ..moving };
        worker.post(still);
        let f = wait(&mut worker, seq, |f| f.info.is_some_and(|i| i.request == still && i.sampling.converged));
        assert_eq!(f.info.unwrap().samples(), EYE);
        assert_eq!(eyes(f), supersampled(&scene, &still, 2), "the still pose converges");
    }
}

//! `replay`'s scoring, after the run and untimed: each kept frame, both eyes, against the
//! picture a resting head converges to at its pose — a trace in the same mode at S × S
//! samples a pixel, filtered down to the eye, as `render --supersample S` makes it
//! (`cli/render.rs`) — with the metrics `timewarp` scores its warps with
//! ([`stereo::Quality`], both eyes as one image); and `converge_s`.
//!
//! In `full` mode each eye is a trace of its own, so the reference is traced eye by eye,
//! colour only, into one buffer of (W·S) × (H·S) reused for both eyes and every pose
//! (31 MB at 800 × 600 and S = 4). The other modes make the right eye from the left, so
//! their reference is a whole stereo frame at S, one reused for every pose (`run` checks
//! that it fits in memory). A reference is traced again only when the pose changes: a
//! resting head's frames share one.
//!
//! Each scored frame's pose is also traced fresh at one sample a pixel, in the same mode,
//! and scored against the same reference: the score of a frame of no age with nothing
//! guessed, the best any policy that shows one sample a pixel can do at that pose
//! (`fresh` in the reports). Only samples beyond one a pixel, and only at rest the
//! refinement's, score above it.

use std::sync::atomic::{AtomicU32, Ordering};

use anyhow::Result;
use stereo::{downsample, Mode, Options, Quality, StereoFrame};
use tracer::{Camera, Eye, Pixels, Renderer, Target, Tracer};

use super::record::{hash_eyes, Recording};
use crate::args::ReplayArgs;
use crate::cli::timewarp::both_eyes;
use crate::setup::FrameSetup;

/// The converged picture at a pose, and what makes it.
pub struct Reference {
    tracer: Tracer,
    opts: Options,
    eye: (u32, u32),
    samples: (u32, u32),
    renderer: Renderer,
    traced: Vec<u32>,
    frame: StereoFrame,
    /// Each eye at the eye size.
    eyes: [Vec<u32>; 2],
    /// Each eye traced at one sample a pixel.
    fresh: [Vec<u32>; 2],
    /// The pose `eyes` are of.
    at: Option<Camera>,
}

impl Reference {
    /// The reference of `setup`'s scene at scene time `time` (as the requests have it),
    /// reflection depth `depth`, in `opts`, for eyes of `eye` at `s` × `s` samples a pixel.
    pub fn new(setup: &FrameSetup, (time, depth): (f32, u32), opts: Options, eye: (u32, u32), s: u32) -> Self {
        let mut tracer = Tracer::new(&setup.scene, time);
        tracer.set_max_depth(depth);
        Self {
            tracer,
            opts,
            eye,
            samples: (eye.0 * s, eye.1 * s),
            renderer: Renderer::default(),
            traced: Vec::new(),
            frame: StereoFrame::new(),
            eyes: Default::default(),
            fresh: Default::default(),
            at: None,
        }
    }

    /// The scores of both eyes traced at `pose` at one sample a pixel, in the reference's
    /// mode, against the converged picture there.
    pub fn fresh(&mut self, pose: &Camera) -> Quality {
        self.at(pose);
        let ((w, h), [left, right]) = (self.eye, &mut self.fresh);
        if self.opts.mode == Mode::Full {
            for (eye, out) in [(Eye::Left, left), (Eye::Right, right)] {
                let view = pose.view(eye, w, h);
                self.renderer.render(&self.tracer, &view, Pixels::All, Target::colour(out));
            }
        } else {
            self.frame.render(&self.tracer, pose, w, h, self.opts);
            left.clone_from(&self.frame.left().rgb);
            right.clone_from(&self.frame.right().rgb);
        }
        let (fresh, eyes) = (&self.fresh, &self.eyes);
        both_eyes(Quality::compare(&fresh[0], &eyes[0]), Quality::compare(&fresh[1], &eyes[1]))
    }

    /// Both eyes of the converged picture at `pose`, at the eye size.
    pub fn at(&mut self, pose: &Camera) -> [&[u32]; 2] {
        if self.at != Some(*pose) {
            let ((w, h), [left, right]) = (self.samples, &mut self.eyes);
            if self.opts.mode == Mode::Full {
                for (eye, out) in [(Eye::Left, left), (Eye::Right, right)] {
                    let view = pose.view(eye, w, h);
                    self.renderer.render(&self.tracer, &view, Pixels::All, Target::colour(&mut self.traced));
                    downsample(&self.traced, self.samples, out, self.eye);
                }
            } else {
                self.frame.render(&self.tracer, pose, w, h, self.opts);
                downsample(&self.frame.left().rgb, self.samples, left, self.eye);
                downsample(&self.frame.right().rgb, self.samples, right, self.eye);
            }
            self.at = Some(*pose);
        }
        [&self.eyes[0], &self.eyes[1]]
    }
}

/// What scoring found.
#[derive(Debug, Default)]
pub struct Scored {
    /// Per presented frame, its scores when it was scored.
    pub quality: Vec<Option<Quality>>,
    /// Per scored frame, the scores of a fresh trace at one sample a pixel at its pose.
    pub fresh: Vec<Option<Quality>>,
    /// Seconds from the head's stop to the first presented pair equal to the converged
    /// picture at the rest pose; `None` if none was.
    pub converge_s: Option<f64>,
    /// A second Ctrl-C stopped the scoring.
    pub interrupted: bool,
}

/// Scores `recording`'s kept frames and finds `converge_s`; stops early on a second Ctrl-C
/// (`presses`).
///
/// # Errors
///
/// A kept frame whose eyes are not the eye size: the worker delivers every pair at the eye
/// size, and the replay does not scale them.
pub fn score(setup: &FrameSetup, args: &ReplayArgs, recording: &Recording, presses: &AtomicU32) -> Result<Scored> {
    let eye = (args.frame.width, args.frame.height);
    let time = if setup.scene.is_animated() { args.frame.time } else { 0.0 };
    let opts = Options { mode: args.mode, retrace_edges: false };
    let mut reference = Reference::new(setup, (time, setup.scene.render.max_depth), opts, eye, args.max_supersample);
    let n = recording.frames.len();
    let mut scored = Scored { quality: vec![None; n], fresh: vec![None; n], ..Scored::default() };
    let todo = recording.frames.iter().filter(|f| f.kept.is_some()).count();
    let bar = indicatif::ProgressBar::new(todo as u64).with_style(
        indicatif::ProgressStyle::with_template("{spinner} [{elapsed_precise}] {wide_bar} {pos}/{len} frames scored")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    let mut done = 0;
    for (k, frame) in recording.frames.iter().enumerate() {
        let Some(index) = frame.kept else { continue };
        if presses.load(Ordering::SeqCst) > 1 {
            scored.interrupted = true;
            break;
        }
        if frame.size != eye {
            anyhow::bail!(
                "frame {k} (at {:.3} s) was presented at {}×{}, not at the eye size {}×{}: the replay scores eyes as presented, unscaled",
                frame.tick.t,
                frame.size.0,
                frame.size.1,
                eye.0,
                eye.1
            );
        }
        let kept = &recording.kept[index];
        let pose = &frame.tick.pose;
        scored.fresh[k] = Some(reference.fresh(pose));
        let [left, right] = reference.at(pose);
        scored.quality[k] = Some(both_eyes(Quality::compare(&kept.left, left), Quality::compare(&kept.right, right)));
        done += 1;
        bar.inc(1);
        if bar.is_hidden() && (done % 50 == 0 || done == todo) {
            eprintln!("replay: {done}/{todo} frames scored");
        }
    }
    bar.finish_and_clear();
    if !recording.rest.is_empty() && !scored.interrupted {
        let [left, right] = reference.at(&recording.rest_pose);
        let converged = hash_eyes(left, right);
        scored.converge_s =
            recording.rest.iter().find(|&&(_, hash)| hash == converged).map(|&(t, _)| (t - recording.stop_s).max(0.0));
    }
    Ok(scored)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn setup() -> FrameSetup {
        let scene = tracer::Scene::from_toml(
            "[camera]\nipd = 1.0\n[[lights]]\nposition = [0.0, 5.0, 0.0]\n\
             [[spheres]]\ncenter = [0.0, 0.0, 12.0]\nradius = 2.0\n\
             [[spheres]]\ncenter = [1.5, 0.5, 9.0]\nradius = 0.7\nreflectivity = 0.5\n",
            "t.toml",
        )
        .unwrap();
        FrameSetup { camera: scene.camera, scene, path: "t.toml".into() }
    }

    /// The eye-by-eye reference of `full` is `render --mode full --supersample S`'s eyes
    /// byte for byte, and another mode's is that mode's frame at S.
    #[test]
    fn the_reference_is_renders_supersampled_frame() {
        let setup = setup();
        let (eye, s, depth) = ((24, 16), 3, 2);
        let pose = Camera { yaw_deg: 4.0, ..setup.camera };
        for mode in [Mode::Full, Mode::Exact, Mode::Copy] {
            let opts = Options { mode, retrace_edges: false };
            let mut reference = Reference::new(&setup, (0.0, depth), opts, eye, s);
            let [left, right] = reference.at(&pose);
            let mut tracer = Tracer::new(&setup.scene, 0.0);
            tracer.set_max_depth(depth);
            let mut frame = StereoFrame::new();
            frame.render(&tracer, &pose, eye.0 * s, eye.1 * s, opts);
            let (mut l, mut r) = (Vec::new(), Vec::new());
            downsample(&frame.left().rgb, (eye.0 * s, eye.1 * s), &mut l, eye);
            downsample(&frame.right().rgb, (eye.0 * s, eye.1 * s), &mut r, eye);
            assert_eq!((left, right), (&l[..], &r[..]), "{mode}");
        }
    }
}

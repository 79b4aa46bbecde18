//! What `replay` records of each presented stereo frame while it runs, kept cheap so that
//! the display's thread takes little from the tracer: the tick's time and pose, the traced
//! pair's age and sampling, the share the warp guessed; every `--score-every`-th frame's eyes
//! (a frame at rest that shows the same pair as the last one kept shares its copy); and at
//! rest, a hash of each distinct pair shown, with the time it was first shown, which
//! `converge_s` is found from.

use std::hash::Hasher as _;
use std::time::Instant;

use tracer::Camera;

use crate::setup::BadInput;
use crate::window::display::Shown;
use crate::window::worker::{Eyes, Sampling};

/// The tick a frame is presented at.
#[derive(Clone, Copy, Debug)]
pub struct TickAt {
    /// Seconds since the head started.
    pub t: f64,
    /// The head was moving.
    pub moving: bool,
    /// The head's pose: what the frame is scored against.
    pub pose: Camera,
}

/// A presented stereo frame.
#[derive(Clone, Copy, Debug)]
pub struct Frame {
    /// The tick.
    pub tick: TickAt,
    /// The traced pair's sequence number.
    pub seq: u64,
    /// Its age when presented (since its request was posted), ms.
    pub age_ms: f64,
    /// Both eyes' share of pixels the warp guessed (holes filled; 0 when shown as traced).
    pub guessed_share: f64,
    /// Warped to the tick's pose (else shown as traced).
    pub warped: bool,
    /// How the pair was sampled.
    pub sampling: Sampling,
    /// The eyes' size.
    pub size: (u32, u32),
    /// Its eyes among [`Recording::kept`], when it is scored.
    pub kept: Option<usize>,
}

/// A kept pair of eyes.
#[derive(Debug)]
pub struct Kept {
    pub left: Vec<u32>,
    pub right: Vec<u32>,
}

/// What identifies a presented pair: the traced pair, and the pose it was warped to.
type Key = (u64, Option<Camera>);

/// The run's record.
#[derive(Debug)]
pub struct Recording {
    /// Every presented stereo frame, in order.
    pub frames: Vec<Frame>,
    /// The eyes kept for scoring.
    pub kept: Vec<Kept>,
    /// At rest: each distinct pair presented, (seconds since the start, its hash).
    pub rest: Vec<(f64, u64)>,
    /// Display ticks, presenting or not.
    pub ticks: u64,
    /// When the head stopped, seconds since the start (`--seconds`).
    pub stop_s: f64,
    /// Where the head rests.
    pub rest_pose: Camera,
    /// Ctrl-C ended the run.
    pub interrupted: bool,
    /// The most the worker's resting refinement held at once, bytes
    /// ([`crate::window::worker::Worker::refine_bytes`]).
    pub accumulation_bytes: usize,
    score_every: u32,
    last_kept: Option<(Key, usize)>,
    last_rest: Option<Key>,
}

impl Recording {
    /// Nothing recorded yet; every `score_every`-th frame will be kept, the head stops at
    /// `stop_s`.
    pub fn new(score_every: u32, stop_s: f64) -> Self {
        Self {
            frames: Vec::new(),
            kept: Vec::new(),
            rest: Vec::new(),
            ticks: 0,
            stop_s,
            rest_pose: Camera::default(),
            accumulation_bytes: 0,
            interrupted: false,
            score_every: score_every.max(1),
            last_kept: None,
            last_rest: None,
        }
    }

    /// Records `shown`, presented at `tick`, at `now` (nothing before the first frame).
    pub fn record(&mut self, shown: &Shown, tick: TickAt, now: Instant) {
        let Some(info) = shown.info else { return };
        let age = shown.age(now).unwrap_or_default();
        let key: Key = (info.seq, shown.warped.map(|_| tick.pose));
        let scored = self.frames.len().is_multiple_of(self.score_every as usize);
        let kept = scored.then(|| match self.last_kept {
            Some((k, index)) if k == key => index,
            _ => {
                let eyes = shown.eyes;
                self.kept.push(Kept { left: eyes.left.clone(), right: eyes.right.clone() });
                self.last_kept = Some((key, self.kept.len() - 1));
                self.kept.len() - 1
            }
        });
        if !tick.moving && self.last_rest != Some(key) {
            self.last_rest = Some(key);
            self.rest.push((tick.t, hash_pair(shown.eyes)));
        }
        self.frames.push(Frame {
            tick,
            seq: info.seq,
            age_ms: age.as_secs_f64() * 1e3,
            guessed_share: shown.hole_share(),
            warped: shown.warped.is_some(),
            sampling: info.sampling,
            size: shown.eyes.size,
            kept,
        });
    }

    /// The frames presented while the head moved, and at rest.
    /// Seconds from the head's stop to the first presented frame traced at its resting
    /// pose at every pixel (shown as traced, at density 1), if one came.
    #[must_use]
    pub fn first_full_s(&self) -> Option<f64> {
        self.frames
            .iter()
            .find(|f| !f.tick.moving && !f.warped && f.sampling.density == 1 && f.seq > 0)
            .map(|f| f.tick.t - self.stop_s)
    }

    pub fn phases(&self) -> [(&'static str, Vec<usize>); 2] {
        let of = |moving: bool| (0..self.frames.len()).filter(|&k| self.frames[k].tick.moving == moving).collect();
        [("moving", of(true)), ("resting", of(false))]
    }
}

/// A hash of both eyes' pixels (`std`'s SipHash, the same in every run of a binary).
pub fn hash_pair(eyes: &Eyes) -> u64 {
    hash_eyes(&eyes.left, &eyes.right)
}

/// A hash of a left and a right image.
pub fn hash_eyes(left: &[u32], right: &[u32]) -> u64 {
    let mut h = std::hash::DefaultHasher::new();
    h.write(bytemuck::cast_slice(left));
    h.write(bytemuck::cast_slice(right));
    h.finish()
}

/// Refuses a run whose kept eyes would not fit in `available` bytes: at most `ticks`
/// presented frames, every `score_every`-th kept, two eyes of `eye` at 4 bytes a pixel.
pub fn check_memory(ticks: u64, score_every: u32, eye: (u32, u32), available: Option<u64>) -> Result<(), BadInput> {
    let kept = ticks.div_ceil(u64::from(score_every.max(1)));
    let need = kept.saturating_mul(8 * u64::from(eye.0) * u64::from(eye.1));
    match available {
        Some(a) if need > a / 2 => Err(BadInput(format!(
            "--score-every {score_every}: up to {kept} frames of {}×{} kept for scoring need {:.1} GiB, more than half the {:.1} GiB available; score fewer (a larger --score-every) or replay for less time",
            eye.0,
            eye.1,
            need as f64 / f64::from(1u32 << 30),
            a as f64 / f64::from(1u32 << 30)
        ))),
        _ => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_kept_eyes_must_fit_in_half_the_memory() {
        // 91 ticks, every 10th kept: 10 pairs of 8 × 4 at 4 bytes an eye pixel, 2560 bytes.
        assert!(check_memory(91, 10, (8, 4), Some(2 * 2560)).is_ok(), "exactly half");
        assert!(check_memory(91, 10, (8, 4), None).is_ok(), "no limit known");
        let e = check_memory(91, 10, (8, 4), Some(2 * 2560 - 1)).unwrap_err().0;
        assert!(e.starts_with("--score-every 10: up to 10 frames of 8×4 kept"), "{e}");
    }

    #[test]
    fn the_pair_hash_sees_every_pixel_of_both_eyes() {
        let (a, b) = (vec![1, 2, 3], vec![4, 5, 6]);
        assert_eq!(hash_eyes(&a, &b), hash_eyes(&a.clone(), &b.clone()));
        assert_ne!(hash_eyes(&a, &b), hash_eyes(&b, &a), "the eyes in order");
        assert_ne!(hash_eyes(&a, &b), hash_eyes(&a, &[4, 5, 7]));
    }
}

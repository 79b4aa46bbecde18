//! What a moving head sees of the viewer: how many presented frames a second show a new
//! head pose (`pose_fps`: a frame repeating the pose of the one before does not count), how
//! long an input takes to show (`latency_ms`: from the event that moved the head to the
//! present of the first frame whose pose was taken after it), and how old the traced frame
//! is at present (`age_ms`: since the moment of the pose it was traced for). Latency and
//! age are medians over the rate meter's window; `STEREOTRACE_LOG_FPS=1` logs all three,
//! and the panel shows them.
//!
//! A frame's pose is taken when the pose is read from the settings: at present with the
//! timewarp (the warp's target), when its render request was posted without it.

use std::collections::VecDeque;
use std::time::Instant;

use tracer::Camera;

use crate::window::timing::RateMeter;

/// Inputs awaiting the frame that shows them, at most: a burst beyond it (hundreds of
/// events between two frames) drops its oldest, which a frame would resolve at once anyway.
const PENDING: usize = 64;

/// Latency and age samples kept per window, at most (a window is half a second, so 240
/// presents at the most).
const SAMPLES: usize = 512;

/// The medians of one window, `None` when it had no sample.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Medians {
    /// Input to present, milliseconds.
    pub latency_ms: Option<f64>,
    /// The traced frame's age at present, milliseconds.
    pub age_ms: Option<f64>,
}

/// The pose rate, the latency and the age, measured over the presents.
#[derive(Debug)]
pub struct PoseMeter {
    last_pose: Option<Camera>,
    new_poses: u64,
    rate: RateMeter,
    pending: VecDeque<Instant>,
    latencies: Vec<f64>,
    ages: Vec<f64>,
    medians: Medians,
}

impl PoseMeter {
    /// Nothing measured yet, the window starting at `now`.
    #[must_use]
    pub fn new(now: Instant) -> Self {
        Self {
            last_pose: None,
            new_poses: 0,
            rate: RateMeter::new(now, 0),
            pending: VecDeque::with_capacity(PENDING),
            latencies: Vec::with_capacity(SAMPLES),
            ages: Vec::with_capacity(SAMPLES),
            medians: Medians::default(),
        }
    }

    /// An input that moves the head arrived at `at` (a movement key pressed or repeated, a
    /// drag turning the head).
    pub fn input(&mut self, at: Instant) {
        if self.pending.len() == PENDING {
            self.pending.pop_front();
        }
        self.pending.push_back(at);
    }

    /// A frame showing `pose`, taken at `pose_at`, traced for a pose taken at `traced_at`,
    /// was presented at `now`.
    pub fn presented(&mut self, pose: &Camera, pose_at: Instant, traced_at: Instant, now: Instant) {
        if self.last_pose.is_some_and(|p| p != *pose) {
            self.new_poses += 1;
        }
        self.last_pose = Some(*pose);
        while let Some(&input) = self.pending.front().filter(|&&t| t <= pose_at) {
            self.pending.pop_front();
            push(&mut self.latencies, ms(now, input));
        }
        push(&mut self.ages, ms(now, traced_at));
    }

    /// Closes the window when it is due at `now` (as [`RateMeter::update`]): the rate and
    /// the medians are then those of the window just closed. Returns whether it closed.
    pub fn update(&mut self, now: Instant) -> bool {
        if !self.rate.update(now, self.new_poses) {
            return false;
        }
        self.medians = Medians { latency_ms: median(&mut self.latencies), age_ms: median(&mut self.ages) };
        self.latencies.clear();
        self.ages.clear();
        true
    }

    /// Presented frames a second that showed a new pose, over the last window.
    #[must_use]
    pub fn rate(&self) -> f64 {
        self.rate.rate()
    }

    /// The last window's medians.
    #[must_use]
    pub fn medians(&self) -> Medians {
        self.medians
    }
}

fn ms(now: Instant, then: Instant) -> f64 {
    now.saturating_duration_since(then).as_secs_f64() * 1e3
}

/// Keeps a sample while there is room (a window never fills it; see [`SAMPLES`]).
fn push(samples: &mut Vec<f64>, value: f64) {
    if samples.len() < SAMPLES {
        samples.push(value);
    }
}

/// The median (the mean of the middle two of an even count), `None` of nothing.
fn median(samples: &mut [f64]) -> Option<f64> {
    let n = samples.len();
    if n == 0 {
        return None;
    }
    samples.sort_unstable_by(f64::total_cmp);
    Some(if n % 2 == 1 { samples[n / 2] } else { f64::midpoint(samples[n / 2 - 1], samples[n / 2]) })
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use glam::Vec3;

    use super::*;

    fn at(t0: Instant, ms: u64) -> Instant {
        t0 + Duration::from_millis(ms)
    }

    #[test]
    fn a_repeated_pose_is_not_a_new_one() {
        let t0 = Instant::now();
        let mut m = PoseMeter::new(t0);
        let still = Camera::default();
        let moved = Camera { position: Vec3::X, ..still };
        for (k, pose) in [still, still, moved, moved, still, moved].iter().enumerate() {
            m.presented(pose, at(t0, 10 * k as u64), t0, at(t0, 10 * k as u64));
        }
        assert!(m.update(at(t0, 1000)));
        assert!((m.rate() - 3.0).abs() < 1e-9, "three changes in a second: {}", m.rate());
    }

    /// Two inputs: the first frame whose pose was taken after an input shows it; a frame
    /// whose pose was taken before does not, however late it is presented.
    #[test]
    fn latency_runs_from_the_input_to_the_first_frame_posed_after_it() {
        let t0 = Instant::now();
        let mut m = PoseMeter::new(t0);
        let pose = Camera::default();
        m.input(at(t0, 10));
        // Posed at 5 (before the input), presented at 40: does not show it.
        m.presented(&pose, at(t0, 5), at(t0, 5), at(t0, 40));
        // Posed at 50, presented at 60: shows it, 50 ms after.
        m.presented(&pose, at(t0, 50), at(t0, 20), at(t0, 60));
        m.input(at(t0, 70));
        m.presented(&pose, at(t0, 71), at(t0, 20), at(t0, 80));
        assert!(m.update(at(t0, 600)));
        let Medians { latency_ms, age_ms } = m.medians();
        assert_eq!(latency_ms, Some(30.0), "median of 50 and 10");
        assert_eq!(age_ms, Some(40.0), "median of 35, 40, 60");
        assert!(m.update(at(t0, 1200)));
        assert_eq!(m.medians(), Medians::default(), "a window without presents has no medians");
    }

    #[test]
    fn the_median_of_odd_and_even_counts() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), Some(2.5));
        assert_eq!(median(&mut []), None);
    }
}

//! Timing: frame-rate meters for the statistics panel, and the scene clock that Space pauses
//! and the orbit-speed slider speeds up or slows down.

use std::time::{Duration, Instant};

/// Measures how fast a monotonic counter (frames presented, frames rendered) grows, averaged
/// over windows of about half a second so the readout is steady.
#[derive(Clone, Copy, Debug)]
pub struct RateMeter {
    window_start: Instant,
    count_at_start: u64,
    rate: f64,
}

impl RateMeter {
    /// Length of one averaging window.
    pub const WINDOW: Duration = Duration::from_millis(500);

    /// A meter whose first window starts now at count `count`.
    #[must_use]
    pub fn new(now: Instant, count: u64) -> Self {
        Self { window_start: now, count_at_start: count, rate: 0.0 }
    }

    /// Feeds the counter's current value; returns true when a window closed and
    /// [`RateMeter::rate`] changed.
    pub fn update(&mut self, now: Instant, count: u64) -> bool {
        let elapsed = now.saturating_duration_since(self.window_start);
        if elapsed < Self::WINDOW {
            return false;
        }
        self.rate = count.saturating_sub(self.count_at_start) as f64 / elapsed.as_secs_f64();
        self.window_start = now;
        self.count_at_start = count;
        true
    }

    /// Events per second over the last closed window.
    #[must_use]
    pub fn rate(&self) -> f64 {
        self.rate
    }
}

/// Scene time: wall time since start times a speed factor, which can be paused and resumed.
#[derive(Clone, Copy, Debug)]
pub struct SceneClock {
    /// Scene time when the clock last (re)started, paused or changed speed.
    base: f32,
    /// When the clock last (re)started or changed speed; `None` while paused.
    running_since: Option<Instant>,
    /// Scene seconds per wall second (≥ 0; 0 stands still without being paused).
    speed: f32,
}

impl SceneClock {
    /// A running clock that reads 0 now.
    #[must_use]
    pub fn running(now: Instant) -> Self {
        Self { base: 0.0, running_since: Some(now), speed: 1.0 }
    }

    /// A clock paused at `t` seconds.
    #[must_use]
    pub fn paused_at(t: f32) -> Self {
        Self { base: t, running_since: None, speed: 1.0 }
    }

    /// Scene time at `now`, seconds.
    #[must_use]
    pub fn time(&self, now: Instant) -> f32 {
        match self.running_since {
            Some(since) => self.base + self.speed * now.saturating_duration_since(since).as_secs_f32(),
            None => self.base,
        }
    }

    /// Whether time stands still.
    #[must_use]
    pub fn is_paused(&self) -> bool {
        self.running_since.is_none()
    }

    /// Pauses or resumes; the scene time carries on from where it stopped.
    pub fn set_paused(&mut self, paused: bool, now: Instant) {
        if paused == self.is_paused() {
            return;
        }
        if paused {
            self.base = self.time(now);
            self.running_since = None;
        } else {
            self.running_since = Some(now);
        }
    }

    /// Sets how many scene seconds pass per wall second from `now` on (negative counts as 0);
    /// the scene time carries on from where it is.
    pub fn set_speed(&mut self, speed: f32, now: Instant) {
        let speed = speed.max(0.0);
        if speed == self.speed {
            return;
        }
        if self.running_since.is_some() {
            self.base = self.time(now);
            self.running_since = Some(now);
        }
        self.speed = speed;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rate_is_count_over_elapsed_time() {
        let t0 = Instant::now();
        let mut m = RateMeter::new(t0, 10);
        assert!(!m.update(t0 + Duration::from_millis(100), 15));
        assert!(m.update(t0 + Duration::from_secs(1), 40));
        assert!((m.rate() - 30.0).abs() < 1e-9);
    }

    #[test]
    fn paused_clock_stands_still_and_resumes_where_it_stopped() {
        let t0 = Instant::now();
        let mut c = SceneClock::running(t0);
        assert!((c.time(t0 + Duration::from_secs(2)) - 2.0).abs() < 1e-6);
        c.set_paused(true, t0 + Duration::from_secs(2));
        assert_eq!(c.time(t0 + Duration::from_secs(9)), c.time(t0 + Duration::from_secs(3)));
        c.set_paused(false, t0 + Duration::from_secs(10));
        assert!((c.time(t0 + Duration::from_secs(11)) - 3.0).abs() < 1e-5);
        let p = SceneClock::paused_at(1.0);
        assert!(p.is_paused());
        assert_eq!(p.time(t0 + Duration::from_secs(5)), 1.0);
    }

    #[test]
    fn speed_scales_the_advance_from_the_change_on() {
        let t0 = Instant::now();
        let mut c = SceneClock::running(t0);
        c.set_speed(2.0, t0 + Duration::from_secs(1));
        assert!((c.time(t0 + Duration::from_secs(3)) - 5.0).abs() < 1e-5);
        c.set_speed(0.0, t0 + Duration::from_secs(3));
        assert!((c.time(t0 + Duration::from_secs(9)) - 5.0).abs() < 1e-5);
        assert!(!c.is_paused(), "speed 0 stands still without pausing");
        c.set_paused(true, t0 + Duration::from_secs(9));
        c.set_speed(4.0, t0 + Duration::from_secs(9));
        c.set_paused(false, t0 + Duration::from_secs(10));
        assert!((c.time(t0 + Duration::from_secs(11)) - 9.0).abs() < 1e-5);
    }
}

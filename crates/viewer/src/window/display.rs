//! A display tick's decisions, the window's (`app/frame.rs`) and `stereotrace replay`'s
//! alike, so that what the replay scores is what the window shows: whether a tick redraws
//! ([`due`]), when the next one comes ([`next_tick`]), the request it posts for the tick's
//! head pose ([`post`]) and the picture it presents ([`show`]): the newest finished frame
//! warped to that pose by the timewarp (`timewarp.rs`), or as traced when it is fresh
//! (traced at that very pose) or the timewarp is off.

use std::time::{Duration, Instant};

use tracer::{Camera, Scene};

use crate::window::present::Look;
use crate::window::settings::Settings;
use crate::window::timewarp::{Timewarp, Warped};
use crate::window::worker::{Eyes, Finished, FrameInfo, Request, Worker};

/// Longest time between redraws of an otherwise unchanged picture (the window's clocks and
/// rates keep moving).
pub const IDLE_REDRAW: Duration = Duration::from_millis(250);

/// What a tick knows when it decides whether to redraw.
#[derive(Clone, Copy, Debug)]
#[expect(clippy::struct_excessive_bools, reason = "independent reasons to redraw")]
pub struct Tick {
    /// Input arrived, or the panel asked for a repaint, since the last redraw.
    pub dirty: bool,
    /// The worker has finished a frame not yet taken ([`Worker::has_fresh`]).
    pub fresh: bool,
    /// Time since the last redraw.
    pub since_redraw: Duration,
    /// The timewarp is on.
    pub timewarp: bool,
    /// The head is moving.
    pub moving: bool,
}

/// Whether a tick redraws. A moving head alone is not a reason without the timewarp: until
/// the worker has a frame of the new pose there is nothing new to show, and repainting at
/// every tick would take the cores from the tracer. With the timewarp it is: every display
/// tick shows the head's pose of that moment.
#[must_use]
pub fn due(t: Tick) -> bool {
    t.dirty || t.fresh || t.since_redraw >= IDLE_REDRAW || (t.timewarp && t.moving)
}

/// When the tick after one due at `next` comes, `interval` later, met at `now`: the cadence
/// is kept, but missed ticks are never caught up on.
#[must_use]
pub fn next_tick(next: Instant, now: Instant, interval: Duration) -> Instant {
    (next + interval).max(now + interval / 2)
}

/// Posts the request `settings` make for `scene` at scene time `time` and an eye of `eye`
/// on screen, with the head `moving` or not (the progressive policy spends its time budget
/// on a moving head's requests), and returns it (none for an eye without pixels). The
/// worker ignores a request equal to the last one.
pub fn post(
    worker: &mut Worker,
    settings: &Settings,
    (scene, time): (&Scene, f32),
    eye: (u32, u32),
    moving: bool,
) -> Option<Request> {
    (eye.0 > 0 && eye.1 > 0).then(|| {
        let request = Request { moving, ..settings.request(scene, time, eye.0, eye.1) };
        worker.post(request);
        request
    })
}

/// What a tick presents.
#[derive(Clone, Copy, Debug)]
pub struct Shown<'a> {
    /// The eyes: the timewarp's, or the traced frame's own.
    pub eyes: &'a Eyes,
    /// The traced frame they come from (`None` before the first).
    pub info: Option<FrameInfo>,
    /// The head pose of the picture and the moment it was the head's: the tick's, when
    /// warped; else the one the frame was traced at, when its request was posted.
    pub pose: Option<(Camera, Instant)>,
    /// What the warp did, when the frame was warped.
    pub warped: Option<Warped>,
}

impl Shown<'_> {
    /// How old the traced frame shown is at `now`: since its request was posted.
    #[must_use]
    pub fn age(&self, now: Instant) -> Option<Duration> {
        self.info.map(|i| now.saturating_duration_since(i.posted))
    }

    /// The share of both eyes' pixels the warp filled as holes (0 when not warped).
    #[must_use]
    pub fn hole_share(&self) -> f64 {
        self.warped.map_or(0.0, |w| w.hole_share())
    }
}

/// The picture for `traced`, the newest finished frame: warped to `pose`, the tick's head
/// pose, by `timewarp` (`None`: the timewarp is off), or as traced when it was traced at
/// that pose or without what the warp needs.
pub fn show<'a>(traced: &'a Finished, timewarp: &'a mut Timewarp, pose: Option<Camera>, look: Look) -> Shown<'a> {
    let pose_at = Instant::now();
    let warped_to = pose.filter(|pose| timewarp.show(traced, pose, look).is_some());
    let timewarp: &'a Timewarp = timewarp;
    match warped_to {
        Some(pose) => Shown {
            eyes: timewarp.eyes(),
            info: traced.info,
            pose: Some((pose, pose_at)),
            warped: Some(timewarp.last()),
        },
        None => Shown {
            eyes: &traced.eyes,
            info: traced.info,
            pose: traced.info.map(|i| (i.views.camera, i.posted)),
            warped: None,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tick_redraws_for_news_a_quiet_quarter_second_or_a_warped_moving_head() {
        let quiet =
            Tick { dirty: false, fresh: false, since_redraw: Duration::from_millis(10), timewarp: true, moving: false };
        assert!(!due(quiet), "nothing new");
        assert!(due(Tick { fresh: true, ..quiet }) && due(Tick { dirty: true, ..quiet }));
        assert!(due(Tick { since_redraw: IDLE_REDRAW, ..quiet }), "a quarter second gone by");
        assert!(due(Tick { moving: true, ..quiet }), "the timewarp shows every pose");
        assert!(!due(Tick { moving: true, timewarp: false, ..quiet }), "without it, only a new frame does");
    }

    #[test]
    fn the_cadence_is_kept_but_never_caught_up() {
        let (t0, tick) = (Instant::now(), Duration::from_millis(10));
        assert_eq!(next_tick(t0, t0 + Duration::from_millis(2), tick), t0 + tick, "on time: the next in the cadence");
        let late = t0 + Duration::from_millis(35);
        assert_eq!(next_tick(t0, late, tick), late + tick / 2, "late: half a tick on, no burst");
    }
}

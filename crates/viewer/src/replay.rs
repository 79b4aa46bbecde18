//! `stereotrace replay`: what the eye sees in the viewer, scored. The viewer's own pipeline
//! runs headless and in real time: the window's render worker (`window/worker.rs`, its
//! tracer threads lowered below the display's), its timewarp on a pool of its own
//! (`window/timewarp.rs`) and its display ticks (`window/display.rs`: redraw or not, the
//! request posted for the tick's head pose, the newest frame warped to that pose or shown as
//! traced when fresh). Only the window is missing.
//!
//! A scripted head follows `--motion` (`motion.rs`, `timewarp`'s syntax) for `--seconds`,
//! then rests there for `--still`; ticks come at `--display-hz`. The head starts once the
//! worker has its first frame (a large scene's tracer is built first), and its stop counts
//! as input, as a released key does in the window: the tick after it redraws. The scene
//! time stands at `--time`. Every presented stereo frame is recorded (`replay/record.rs`)
//! with its tick's time and pose, the age of the traced pair it shows, the share the warp
//! guessed (holes filled) and how the pair was sampled; every `--score-every`-th keeps its
//! eyes.
//!
//! After the run, untimed, those are scored against a trace at their pose in the same mode,
//! supersampled at `--max-supersample` (`replay/score.rs`): the picture a resting head
//! converges to, as `render --supersample S` makes it. `converge_s` is the time from the
//! head's stop to the first presented pair equal to that picture at the rest pose.
//! Reports: `replay/report.rs` (JSON, CSV, summary), `replay/figure.rs` (the plot).
//!
//! Ctrl-C stops the run, and the frames recorded are still scored; a second one stops the
//! scoring. Either way what was done is written and the exit code is 1.

mod figure;
mod record;
mod report;
mod score;

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::Result;
use stereo::Mode;
use tracer::{Camera, Scene};

use self::record::{Recording, TickAt};
use crate::args::{Policy, ReplayArgs};
use crate::cli::plot;
use crate::setup::{self, BadInput, FrameSetup};
use crate::window::display::{self, Tick};
use crate::window::settings::Settings;
use crate::window::timewarp::Timewarp;
use crate::window::worker::{self, Progressive, Worker};
use viewer::write_bytes;

/// Longest `--seconds` accepted.
pub const MAX_SECONDS: f64 = 60.0;

/// Longest `--still` accepted.
pub const MAX_STILL: f64 = 600.0;

/// Largest `--target-age-ms` accepted.
pub const MAX_TARGET_AGE_MS: f32 = 1000.0;

/// Checks what clap cannot: the durations and the target age.
fn check(args: &ReplayArgs) -> Result<(), BadInput> {
    let s = args.seconds;
    if !(s.is_finite() && s > 0.0 && s <= MAX_SECONDS) {
        return Err(BadInput(format!("--seconds {s}: must be more than 0 and at most {MAX_SECONDS}")));
    }
    let still = args.still;
    if !(still.is_finite() && (0.0..=MAX_STILL).contains(&still)) {
        return Err(BadInput(format!("--still {still}: must be 0 to {MAX_STILL} seconds")));
    }
    let age = args.target_age_ms;
    if !(age.is_finite() && age > 0.0 && age <= MAX_TARGET_AGE_MS) {
        return Err(BadInput(format!("--target-age-ms {age}: must be more than 0 and at most {MAX_TARGET_AGE_MS}")));
    }
    Ok(())
}

/// What the requests carry for `--policy`.
fn progressive(args: &ReplayArgs) -> Option<Progressive> {
    (args.policy == Policy::Progressive)
        .then_some(Progressive { target_age_ms: args.target_age_ms, max_supersample: args.max_supersample })
}

/// Runs the command.
pub fn run(args: &ReplayArgs) -> Result<()> {
    check(args)?;
    plot::check_outputs(args.csv.as_deref(), args.plot.as_deref())?;
    // Before anything uses rayon's global pool: the tracer's threads below the display's.
    worker::lower_the_tracer_pool();
    // The reference of a mode other than full is a stereo frame at S × S samples a pixel.
    let supersample = if args.mode == Mode::Full { 1 } else { args.max_supersample };
    let setup = FrameSetup::load_supersampled(&args.frame, 1, supersample)?;
    let eye = (args.frame.width, args.frame.height);
    let ticks = ((args.seconds + args.still) * f64::from(args.display_hz)).ceil() as u64 + 1;
    record::check_memory(ticks, args.score_every, eye, setup::available_memory()?)?;
    let presses = Arc::new(AtomicU32::new(0));
    {
        let presses = Arc::clone(&presses);
        // If a handler is already installed (only in tests), Ctrl-C keeps its default.
        let _ = ctrlc::set_handler(move || {
            presses.fetch_add(1, Ordering::SeqCst);
        });
    }
    let mut session = Session::new(&setup, args)?;
    let recording = session.replay(&presses)?;
    drop(session);
    let scored = score::score(&setup, args, &recording, &presses)?;
    let summary = report::Summary::new(args, &setup, &recording, &scored);
    if let Some(path) = &args.csv {
        write_bytes(path, report::csv(&recording, &scored).as_bytes())?;
    }
    if let Some(path) = &args.plot {
        plot::write(path, &figure::Figure::new(&summary, &recording, &scored))?;
    }
    if args.json {
        crate::cli::print_out(&(serde_json::to_string_pretty(&summary.json())? + "\n"))?;
    } else {
        crate::cli::print_out(&summary.text())?;
    }
    eprintln!("{}", summary.done_line());
    if recording.interrupted || scored.interrupted {
        anyhow::bail!("interrupted; what was recorded and scored was written");
    }
    Ok(())
}

/// The viewer's pipeline without its window: the worker, the timewarp and the settings the
/// requests come from, along the scripted head.
struct Session<'a> {
    args: &'a ReplayArgs,
    scene: &'a Scene,
    /// The head's pose at the start.
    start: Camera,
    settings: Settings,
    worker: Worker,
    timewarp: Timewarp,
    eye: (u32, u32),
}

impl<'a> Session<'a> {
    /// The viewer's settings for the scene (its camera with the command line's overrides,
    /// exactly), in `--mode`, with `--guard-band` and the policy; the worker started.
    fn new(setup: &'a FrameSetup, args: &'a ReplayArgs) -> Result<Self> {
        let scene = &setup.scene;
        let mut settings = Settings::from_scene(scene);
        (settings.ipd, settings.distance) = (setup.camera.ipd, setup.camera.distance);
        settings.depth = scene.render.max_depth;
        settings.mode = args.mode;
        settings.guard_band = args.guard_band as f32 / 100.0;
        settings.paused = true;
        settings.progressive = progressive(args);
        Ok(Self {
            args,
            scene,
            start: setup.camera,
            settings,
            worker: Worker::spawn(scene.clone())?,
            timewarp: Timewarp::new()?,
            eye: (args.frame.width, args.frame.height),
        })
    }

    /// Puts the head where the script has it `t` seconds after the start, and returns the
    /// pose the requests ask for.
    fn walk(&mut self, t: f64) -> Camera {
        let pose = self.args.motion.pose(&self.start, t.min(self.args.seconds));
        let s = &mut self.settings;
        (s.position, s.yaw_deg, s.pitch_deg) = (pose.position, pose.yaw_deg, pose.pitch_deg);
        s.camera(&self.scene.camera)
    }

    /// Posts the tick's request, as the window does on every tick, with the head `moving`
    /// or resting.
    fn post(&mut self, moving: bool) -> Option<tracer::Camera> {
        let s = &self.settings;
        display::post(&mut self.worker, s, (self.scene, self.args.frame.time), self.eye, moving).map(|r| r.camera)
    }

    /// The run: the first frame awaited at the start pose, then the ticks, in real time.
    fn replay(&mut self, presses: &AtomicU32) -> Result<Recording> {
        let stopped = || presses.load(Ordering::SeqCst) > 0;
        let mut recording = Recording::new(self.args.score_every, self.args.seconds);
        self.walk(0.0);
        self.post(false);
        eprintln!("replay: waiting for the first frame");
        while self.worker.latest().info.is_none() {
            self.worker.check_alive()?;
            if stopped() {
                recording.interrupted = true;
                return Ok(recording);
            }
            std::thread::sleep(Duration::from_millis(1));
        }
        let (seconds, end) = (self.args.seconds, self.args.seconds + self.args.still);
        eprintln!("replay: the head moves for {seconds} s, then rests for {} s", self.args.still);
        let interval = Duration::from_secs(1) / self.args.display_hz;
        let t0 = Instant::now();
        let (mut next, mut last_redraw) = (t0, t0);
        // The motion starting and stopping are input, as a key pressed or released.
        let (mut dirty, mut was_moving) = (true, true);
        loop {
            std::thread::sleep(next.saturating_duration_since(Instant::now()));
            if stopped() {
                recording.interrupted = true;
                break;
            }
            self.worker.check_alive()?;
            let now = Instant::now();
            let t = (now - t0).as_secs_f64();
            if t > end {
                break;
            }
            recording.ticks += 1;
            let moving = t < seconds;
            dirty |= was_moving && !moving;
            was_moving = moving;
            self.walk(t);
            let due = display::due(Tick {
                dirty,
                fresh: self.worker.has_fresh(),
                since_redraw: now - last_redraw,
                timewarp: self.settings.timewarp,
                moving,
            });
            if due {
                (dirty, last_redraw) = (false, now);
                // The window's redraw: the newest frame taken, the request posted, the
                // newest frame presented at the request's pose.
                self.worker.latest();
                let pose = self.post(moving).filter(|_| self.settings.timewarp);
                let look = self.settings.look();
                let shown = display::show(self.worker.current(), &mut self.timewarp, pose, look);
                let camera = self.settings.camera(&self.scene.camera);
                recording.record(&shown, TickAt { t, moving, pose: camera }, Instant::now());
                recording.accumulation_bytes = recording.accumulation_bytes.max(self.worker.refine_bytes());
            } else {
                self.post(moving);
            }
            next = display::next_tick(next, now, interval);
        }
        recording.rest_pose = self.walk(end);
        Ok(recording)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser as _;

    fn args(extra: &[&str]) -> ReplayArgs {
        let cli = crate::args::Cli::try_parse_from([&["stereotrace", "replay", "--motion", "yaw=1"], extra].concat())
            .unwrap();
        match cli.command {
            Some(crate::args::Command::Replay(a)) => a,
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn durations_and_the_target_age_are_checked_naming_the_flag() {
        assert!(check(&args(&[])).is_ok());
        assert!(check(&args(&["--still", "0"])).is_ok(), "no rest is allowed");
        let err = |extra: &[&str]| check(&args(extra)).unwrap_err().0;
        assert_eq!(err(&["--seconds", "0"]), "--seconds 0: must be more than 0 and at most 60");
        assert_eq!(err(&["--seconds", "-2"]), "--seconds -2: must be more than 0 and at most 60");
        assert_eq!(err(&["--still", "-1"]), "--still -1: must be 0 to 600 seconds");
        assert_eq!(err(&["--still", "NaN"]), "--still NaN: must be 0 to 600 seconds");
        assert!(err(&["--target-age-ms", "0"]).starts_with("--target-age-ms 0: must be more than 0"));
    }

    #[test]
    fn the_policy_rides_on_the_requests() {
        let p = progressive(&args(&["--target-age-ms", "20", "--max-supersample", "2"]));
        assert_eq!(p, Some(Progressive { target_age_ms: 20.0, max_supersample: 2 }));
        assert_eq!(progressive(&args(&["--policy", "fixed"])), None);
    }
}

//! What the viewer draws over the eyes besides the panel's contents: Tab hides the panel,
//! the hint and every other UI pixel, so both eyes are clean for stereo viewing; the hint
//! that Tab does so shows for a while at start; ? or F1 opens the key overlay (shown even
//! with the UI hidden, since it was asked for), which Esc closes before it quits. While a
//! scene file is read, or the tracer is built for a large scene, a progress note says so
//! in the middle of the window (also with the UI hidden: the eyes wait for it).

use std::path::Path;
use std::time::{Duration, Instant};

use crate::window::worker::Building;

/// How long a read or a build goes before the progress note shows (a small scene's never
/// does: it would only flash).
const PROGRESS_AFTER: Duration = Duration::from_millis(250);

/// The progress note at `now`, while a scene file is being read (its path, since when) or
/// the tracer is being built, and has been for [`PROGRESS_AFTER`].
pub(super) fn progress(reading: Option<(&Path, Instant)>, building: Option<Building>, now: Instant) -> Option<String> {
    let seconds = |since: Instant| now.saturating_duration_since(since).as_secs_f64();
    let due = |since: Instant| now.saturating_duration_since(since) >= PROGRESS_AFTER;
    if let Some((path, since)) = reading.filter(|&(_, since)| due(since)) {
        let name = path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned());
        return Some(format!("reading {name}… {:.1} s", seconds(since)));
    }
    building.filter(|b| due(b.since)).map(|b| {
        format!("building the BVH and light maps of {} spheres… {:.1} s", thousands(b.spheres), seconds(b.since))
    })
}

/// `n` with thousands separated by commas.
fn thousands(n: usize) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// How long the hint that Tab hides the UI is shown, unless Tab is pressed first.
const HINT_SHOWN: Duration = Duration::from_secs(12);

/// What is drawn over the eyes besides the panel's contents.
#[derive(Clone, Copy, Debug)]
pub(super) struct Chrome {
    /// Tab: nothing of the UI is drawn.
    pub(super) hidden: bool,
    /// The hint that Tab hides the UI shows until this time (or the first Tab).
    hint_until: Option<Instant>,
    /// ? or F1: the key overlay is open.
    pub(super) keys_open: bool,
}

impl Chrome {
    pub(super) fn new(now: Instant) -> Self {
        Self { hidden: false, hint_until: Some(now + HINT_SHOWN), keys_open: false }
    }

    /// Tab: hides or shows the UI; the hint has done its job.
    pub(super) fn toggle_hidden(&mut self) {
        self.hidden ^= true;
        self.hint_until = None;
    }

    /// Whether the hint shows at `now`.
    pub(super) fn hint(&self, now: Instant) -> bool {
        !self.hidden && self.hint_until.is_some_and(|t| now < t)
    }

    /// Esc: closes the key overlay if it is open; otherwise it means quit (returns true).
    pub(super) fn escape_quits(&mut self) -> bool {
        !std::mem::take(&mut self.keys_open)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn progress_shows_a_read_then_a_build_once_they_take_a_while() {
        let t0 = Instant::now();
        let path = Path::new("/data/2btv.pdb.gz");
        let building = Some(Building { spheres: 2_943_660, since: t0 });
        assert_eq!(progress(Some((path, t0)), building, t0 + PROGRESS_AFTER / 2), None, "not yet");
        assert_eq!(
            progress(Some((path, t0)), building, t0 + Duration::from_millis(1500)).as_deref(),
            Some("reading 2btv.pdb.gz… 1.5 s"),
            "the read first"
        );
        assert_eq!(
            progress(None, building, t0 + Duration::from_secs(2)).as_deref(),
            Some("building the BVH and light maps of 2,943,660 spheres… 2.0 s")
        );
        assert_eq!(progress(None, None, t0 + Duration::from_secs(2)), None, "nothing under way");
        assert_eq!((thousands(0), thousands(999), thousands(1000)), ("0".into(), "999".into(), "1,000".into()));
    }

    #[test]
    fn tab_hides_the_ui_and_ends_the_hint_and_esc_closes_the_overlay_first() {
        let t0 = Instant::now();
        let mut chrome = Chrome::new(t0);
        assert!(!chrome.hidden && chrome.hint(t0), "the UI and the hint show at first");
        assert!(!chrome.hint(t0 + HINT_SHOWN), "the hint goes by itself after a while");
        chrome.toggle_hidden();
        assert!(chrome.hidden && !chrome.hint(t0), "Tab hides everything");
        chrome.toggle_hidden();
        assert!(!chrome.hidden && !chrome.hint(t0), "Tab again shows the UI; the hint has done its job");
        chrome.keys_open = true;
        assert!(!chrome.escape_quits(), "Esc closes the key overlay first");
        assert!(!chrome.keys_open, "closed");
        assert!(chrome.escape_quits(), "then Esc quits");
    }
}

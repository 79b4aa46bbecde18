//! What the viewer draws over the eyes besides the panel's contents: Tab hides the panel,
//! the hint and every other UI pixel, so both eyes are clean for stereo viewing; the hint
//! that Tab does so shows for a while at start; ? or F1 opens the key overlay (shown even
//! with the UI hidden, since it was asked for), which Esc closes before it quits.

use std::time::{Duration, Instant};

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

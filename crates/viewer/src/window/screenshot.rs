//! Screenshots (F12 or P): the frame on screen as PNGs named
//! `stereotrace-YYYYmmdd-HHMMSS-<left|right|pair|mask>.png` (UTC) in a folder created if
//! missing, and the note the panel shows about the last save. A supersampled frame's mask
//! is saved per sample, at the size traced, as `render --mask` writes it.

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant, SystemTime, UNIX_EPOCH};

use crate::window::present::Look;
use crate::window::worker::Finished;
use anyhow::Context as _;

/// The default folder, relative to the current directory.
pub const DEFAULT_FOLDER: &str = "./screenshots";

/// How long the panel shows where the last screenshot went.
const NOTE_SHOWN: Duration = Duration::from_secs(6);

/// The screenshot folder and what the last save did.
#[derive(Clone, Debug)]
pub struct Screenshots {
    /// The folder, as typed in the panel.
    pub folder: String,
    /// What the last save wrote, or why it failed.
    pub note: Note,
}

/// What the last save wrote (or why it failed), and when.
#[derive(Clone, Debug, Default)]
pub struct Note(Option<(String, Instant)>);

impl Note {
    /// The note while it is recent at `now`.
    #[must_use]
    pub fn recent(&self, now: Instant) -> Option<&str> {
        self.0.as_ref().filter(|(_, at)| now.saturating_duration_since(*at) < NOTE_SHOWN).map(|(note, _)| &**note)
    }
}

impl Default for Screenshots {
    fn default() -> Self {
        Self { folder: DEFAULT_FOLDER.to_owned(), note: Note::default() }
    }
}

impl Screenshots {
    /// Writes `frame` as `look` shows it into the folder ([`save`]); the note says where (or
    /// why not), and so does stderr. The viewer carries on either way.
    pub fn save(&mut self, frame: &Finished, look: Look) {
        let folder = PathBuf::from(if self.folder.trim().is_empty() { "." } else { self.folder.trim() });
        let note = match save(&folder, frame, look, SystemTime::now()) {
            Ok(paths) => {
                for p in &paths {
                    eprintln!("stereotrace: saved {}", p.display());
                }
                let names: Vec<String> =
                    paths.iter().filter_map(|p| p.file_name()).map(|n| n.to_string_lossy().into_owned()).collect();
                format!("saved in {}:\n{}", folder.display(), names.join("\n"))
            }
            Err(e) => {
                eprintln!("stereotrace: {e:#}");
                format!("not saved: {e:#}")
            }
        };
        self.note = Note(Some((note, Instant::now())));
    }
}

/// `YYYYmmdd-HHMMSS` in UTC for a time (times before 1970 count as 1970-01-01 00:00:00).
#[must_use]
pub fn stamp(time: SystemTime) -> String {
    let secs = time.duration_since(UNIX_EPOCH).map_or(0, |d| d.as_secs());
    let (days, rem) = (secs / 86_400, secs % 86_400);
    let (y, m, d) = civil_from_days(days as i64);
    format!("{y:04}{m:02}{d:02}-{:02}{:02}{:02}", rem / 3600, rem % 3600 / 60, rem % 60)
}

/// Year, month (1..=12) and day (1..=31) of a day count since 1970-01-01 in the proleptic
/// Gregorian calendar (Howard Hinnant's `civil_from_days`).
fn civil_from_days(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097); // [0, 146096]
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365; // [0, 399]
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100); // [0, 365]
    let mp = (5 * doy + 2) / 153; // [0, 11], March first
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    let y = yoe + era * 400 + i64::from(m <= 2);
    (y, m, d)
}

/// Writes the left and right eyes, the pair in the look's layout (eyes exchanged first when
/// it swaps them) and, when it shows the mask, the right eye's class mask into `folder`,
/// creating it if missing. Returns the files written.
pub fn save(folder: &Path, frame: &Finished, look: Look, time: SystemTime) -> anyhow::Result<Vec<PathBuf>> {
    let Look { layout, swap, show_mask } = look;
    let (w, h) = frame.size();
    let n = w as usize * h as usize;
    let (sw, sh) = frame.samples();
    let (left, right) = (&frame.eyes.left, &frame.eyes.right);
    if frame.info.is_none() || left.len() != n || right.len() != n || frame.mask.len() != sw as usize * sh as usize {
        anyhow::bail!("nothing to save yet: no frame has been rendered");
    }
    std::fs::create_dir_all(folder).with_context(|| format!("cannot create the folder {}", folder.display()))?;
    let base = format!("stereotrace-{}", stamp(time));
    let mut pair = Vec::new();
    stereo::compose(layout, swap, left, right, w, h, &mut pair);
    let (pw, ph) = layout.size(w, h);
    let mut mask = Vec::new();
    if show_mask {
        stereo::mask_image(&frame.mask, &mut mask);
    }
    let mut written = Vec::new();
    for (name, pixels, (iw, ih)) in
        [("left", left, (w, h)), ("right", right, (w, h)), ("pair", &pair, (pw, ph)), ("mask", &mask, (sw, sh))]
    {
        if pixels.is_empty() {
            continue;
        }
        let path = folder.join(format!("{base}-{name}.png"));
        viewer::write_png(&path, iw, ih, pixels)?;
        written.push(path);
    }
    Ok(written)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::Duration;

    #[test]
    fn stamps_are_utc_civil_dates() {
        assert_eq!(stamp(UNIX_EPOCH), "19700101-000000");
        // 2000-02-29 12:34:56 UTC (a leap day in a century leap year).
        assert_eq!(stamp(UNIX_EPOCH + Duration::from_secs(951_827_696)), "20000229-123456");
        // 2026-11-22 03:46:45 UTC.
        assert_eq!(stamp(UNIX_EPOCH + Duration::from_secs(1_795_319_205)), "20261122-034645");
        // 2100-03-01 00:00:00 UTC (2100 is not a leap year).
        assert_eq!(stamp(UNIX_EPOCH + Duration::from_secs(4_107_542_400)), "21000301-000000");
        assert_eq!(stamp(UNIX_EPOCH - Duration::from_secs(5)), "19700101-000000");
    }

    /// A supersampled frame: the eyes at their size, the mask per sample.
    #[test]
    fn a_supersampled_mask_is_saved_per_sample() {
        use crate::window::worker::{Eyes, FrameInfo, Request};
        let dir = std::env::temp_dir().join(format!("stereotrace-shot-ss-test-{}", std::process::id()));
        let request = Request::sized(2, 1).sampled((4, 2));
        let info = FrameInfo::answering(1, request);
        let eyes = Eyes {
            size: (2, 1),
            left: vec![0; 2],
            right: vec![0x00FF_FFFF; 2],
            right_overlay: vec![0; 2],
            ..Eyes::default()
        };
        let frame =
            Finished { info: Some(info), eyes, mask: vec![stereo::PixelClass::Reprojected; 8], ..Finished::default() };
        let look = Look { layout: stereo::Layout::SideBySide, swap: false, show_mask: true };
        let paths = save(&dir, &frame, look, UNIX_EPOCH).unwrap();
        let size = |p: &Path| {
            let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(p).unwrap()));
            let info = decoder.read_info().unwrap();
            (info.info().width, info.info().height)
        };
        let sizes: Vec<(u32, u32)> = paths.iter().map(|p| size(p)).collect();
        assert_eq!(sizes, [(2, 1), (2, 1), (4, 1), (4, 2)], "left, right, pair, mask");
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn saving_before_the_first_frame_fails_cleanly() {
        let dir = std::env::temp_dir().join(format!("stereotrace-shot-test-{}", std::process::id()));
        let look = Look { layout: stereo::Layout::SideBySide, swap: false, show_mask: true };
        let e = save(&dir, &Finished::default(), look, SystemTime::now()).unwrap_err();
        assert!(e.to_string().contains("nothing to save"), "{e}");
        assert!(!dir.exists(), "no folder is made for nothing");
        let mut shots = Screenshots { folder: dir.display().to_string(), note: Note::default() };
        let before = Instant::now();
        assert_eq!(shots.note.recent(before), None, "no note before a save");
        shots.save(&Finished::default(), look);
        let note = shots.note.recent(before).unwrap_or_default();
        assert!(note.starts_with("not saved: nothing to save"), "the panel says why: {note}");
        assert_eq!(shots.note.recent(Instant::now() + NOTE_SHOWN), None, "the note goes after a while");
    }
}

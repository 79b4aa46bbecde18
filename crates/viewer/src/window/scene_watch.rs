//! Live scene editing: the viewer's scene file is watched and reloaded on save, another
//! scene file (`.toml`, or a structure file) can be opened (dropped on the window, or picked
//! from the panel's list of the scene's folder), and a broken file never replaces the last
//! good scene.
//!
//! A file is read on a thread of its own, so that a large structure never stalls the
//! window: [`SceneWatch::loading`] says what is being read meanwhile, and the poll that
//! finds it done adopts it (or its error). Reading runs with the options the viewer was
//! started with (`--assembly`, `--radius-scale`).
//!
//! Watching is a modification-time poll on the UI thread, twice a second ([`POLL_INTERVAL`]):
//! one `stat` of the file (its modification time and length; an editor that saves by
//! renaming a new file over the old one changes both) and one of its folder, whose own
//! modification time says when the list of scenes must be read again. Between polls a tick
//! costs one comparison of instants, and nothing is allocated. A save that fails to load
//! (unreadable, not TOML, a bad value) leaves the last good scene rendering and keeps the
//! error — worded exactly as the command line prints it, `file:line: field = value: why`
//! ([`tracer::SceneError`]) — until a good save arrives.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{self, Receiver, TryRecvError};
use std::time::{Duration, Instant, SystemTime};

use tracer::{LoadOptions, Scene};

/// How often the scene file and its folder are looked at.
pub const POLL_INTERVAL: Duration = Duration::from_millis(500);

/// What a file looked like at the last look: its modification time and length, or `None`
/// when it could not be looked at (missing, unreadable).
type Stamp = Option<(SystemTime, u64)>;

/// The stamp of `path` now.
fn stamp(path: &Path) -> Stamp {
    let meta = std::fs::metadata(path).ok()?;
    Some((meta.modified().ok()?, meta.len()))
}

/// A new scene became current.
#[derive(Debug)]
pub struct Change {
    /// The scene it replaced.
    pub previous: Scene,
    /// Whether it came from the same file (a reload): the viewer keeps the head pose then.
    pub same_file: bool,
}

/// A file being read on its own thread.
#[derive(Debug)]
struct Loading {
    path: PathBuf,
    /// Whether it is the file shown (a reload).
    same_file: bool,
    /// Its stamp when the read began.
    stamp: Stamp,
    started: Instant,
    /// The read's result, when it is done: the scene, or the error's message.
    result: Receiver<Result<Scene, String>>,
}

/// The scene file being shown, the last good scene, and the scene files beside it.
#[derive(Debug)]
pub struct SceneWatch {
    /// The file shown (as given or resolved, not canonicalised, so messages name it so).
    path: PathBuf,
    /// Its file name, for the title and the panel.
    name: String,
    /// The last scene that loaded.
    scene: Scene,
    /// The file's stamp when it was last loaded (or failed to load).
    stamp: Stamp,
    /// Why the last load failed, until one succeeds.
    error: Option<String>,
    /// How many loads have failed so far.
    failures: u64,
    /// When the next poll is due.
    next_poll: Instant,
    /// The folder listed, its stamp at the last listing, and the `.toml` files in it (sorted).
    folder: PathBuf,
    folder_stamp: Stamp,
    files: Vec<PathBuf>,
    /// Why the folder could not be listed, if it could not.
    folder_error: Option<String>,
    /// How structure files are read.
    options: LoadOptions,
    /// The file being read, if one is.
    loading: Option<Loading>,
}

impl SceneWatch {
    /// Watches `path`, from which `scene` was just loaded with `options` (which later reads
    /// use too); the first poll is due at `now`.
    #[must_use]
    pub fn new(path: PathBuf, scene: Scene, options: LoadOptions, now: Instant) -> Self {
        let mut watch = Self {
            options,
            loading: None,
            stamp: stamp(&path),
            name: file_name(&path),
            path,
            scene,
            error: None,
            failures: 0,
            next_poll: now,
            folder: PathBuf::new(),
            folder_stamp: None,
            files: Vec::new(),
            folder_error: None,
        };
        watch.list_folder();
        watch
    }

    /// The last good scene.
    #[must_use]
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The scene file shown.
    #[cfg(test)]
    #[must_use]
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The scene file's name, for the title and the panel.
    #[must_use]
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Why the last load failed (the command line's wording), until a load succeeds.
    #[must_use]
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    /// The file being read, and since when, while one is.
    #[must_use]
    pub fn loading(&self) -> Option<(&Path, Instant)> {
        self.loading.as_ref().map(|l| (&*l.path, l.started))
    }

    /// How many loads (reloads, drops, picks) have failed so far.
    #[must_use]
    pub fn failures(&self) -> u64 {
        self.failures
    }

    /// The scene files in the scene's folder, sorted by name.
    #[must_use]
    pub fn files(&self) -> &[PathBuf] {
        &self.files
    }

    /// Why the scene's folder could not be listed, if it could not.
    #[must_use]
    pub fn folder_error(&self) -> Option<&str> {
        self.folder_error.as_deref()
    }

    /// The folder whose scenes [`SceneWatch::files`] lists.
    #[cfg(test)]
    #[must_use]
    pub fn folder(&self) -> &Path {
        &self.folder
    }

    /// Adopts a file whose read has finished: returns the change when it loaded. Otherwise,
    /// unless a read is under way, looks at the file when a poll is due at `now`: starts
    /// reading it again when its stamp changed since the last load, and lists the folder
    /// again when it changed.
    pub fn poll(&mut self, now: Instant) -> Option<Change> {
        if let Some(loading) = &self.loading {
            let result = match loading.result.try_recv() {
                Ok(result) => result,
                Err(TryRecvError::Empty) => return None,
                Err(TryRecvError::Disconnected) => Err(stopped(&loading.path)),
            };
            let loading = self.loading.take()?;
            return self.finish(loading, result);
        }
        if now < self.next_poll {
            return None;
        }
        self.next_poll = now + POLL_INTERVAL;
        if stamp(&self.folder) != self.folder_stamp {
            self.list_folder();
        }
        let current = stamp(&self.path);
        if current != self.stamp {
            self.stamp = current;
            self.start(self.path.clone(), true);
        }
        None
    }

    /// Waits up to `timeout` for the read under way, if any, and adopts it as [`poll`] does:
    /// tests wait for the reading thread's answer, not for time to pass.
    ///
    /// [`poll`]: SceneWatch::poll
    #[cfg(test)]
    pub fn wait_for_read(&mut self, timeout: Duration) -> Option<Change> {
        let loading = self.loading.take()?;
        let result = match loading.result.recv_timeout(timeout) {
            Ok(result) => result,
            Err(mpsc::RecvTimeoutError::Timeout) => panic!("{}: not read in {timeout:?}", loading.path.display()),
            Err(mpsc::RecvTimeoutError::Disconnected) => Err(stopped(&loading.path)),
        };
        self.finish(loading, result)
    }

    /// Opens another scene file (dropped on the window or picked in the panel): starts
    /// reading it, in place of any read under way. One that does not load keeps the current
    /// scene and sets the error. Opening the file already shown is a reload of it.
    pub fn open(&mut self, path: &Path) {
        let same_file = same_file(path, &self.path);
        self.start(path.to_path_buf(), same_file);
    }

    /// Starts reading `path` on a thread of its own.
    fn start(&mut self, path: PathBuf, same_file: bool) {
        let (send, result) = mpsc::channel();
        let options = self.options;
        let reading = path.clone();
        let spawned = std::thread::Builder::new().name("scene-read".into()).spawn(move || {
            // The viewer may have moved on (another file opened): then nobody listens.
            let _ = send.send(Scene::load_with(&reading, options).map_err(|e| e.to_string()));
        });
        let stamp = stamp(&path);
        match spawned {
            Ok(_) => self.loading = Some(Loading { path, same_file, stamp, started: Instant::now(), result }),
            Err(e) => self.fail(format!("{}: cannot start reading it: {e}", path.display())),
        }
    }

    /// Adopts a finished read: on success its file and scene become current.
    fn finish(&mut self, loading: Loading, result: Result<Scene, String>) -> Option<Change> {
        let Loading { path, same_file, stamp, .. } = loading;
        match result {
            Ok(scene) => {
                self.error = None;
                self.stamp = stamp;
                self.name = file_name(&path);
                self.path = path;
                eprintln!("stereotrace: loaded {}", self.path.display());
                if !same_file {
                    self.list_folder();
                }
                Some(Change { previous: std::mem::replace(&mut self.scene, scene), same_file })
            }
            Err(message) => {
                self.fail(message);
                None
            }
        }
    }

    /// A load failed: says why, on stderr and in the panel.
    fn fail(&mut self, message: String) {
        eprintln!("stereotrace: error: {message}");
        self.error = Some(message);
        self.failures += 1;
    }

    /// Lists the scene files of the current scene's folder.
    fn list_folder(&mut self) {
        self.folder = match self.path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        self.folder_stamp = stamp(&self.folder);
        self.files.clear();
        match std::fs::read_dir(&self.folder) {
            Ok(entries) => {
                self.folder_error = None;
                let scenes = entries
                    .filter_map(Result::ok)
                    .map(|e| e.path())
                    .filter(|p| p.is_file() && tracer::is_scene_file_name(p));
                self.files.extend(scenes);
                self.files.sort();
            }
            Err(e) => self.folder_error = Some(format!("{}: cannot list the folder: {e}", self.folder.display())),
        }
    }
}

/// Why a read of `path` gave no answer.
fn stopped(path: &Path) -> String {
    format!("{}: the reading thread stopped", path.display())
}

/// The file name of `path` (the whole path when it has none).
fn file_name(path: &Path) -> String {
    path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned())
}

/// Whether two paths name the same file (the same path, or the same file once resolved).
fn same_file(a: &Path, b: &Path) -> bool {
    a == b || matches!((std::fs::canonicalize(a), std::fs::canonicalize(b)), (Ok(x), Ok(y)) if x == y)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    use crate::window::settings::Settings;

    const GOOD: &str = "[camera]\nposition = [0.0, 0.0, -1.0]\n[[spheres]]\ncenter = [0.0, 0.0, 10.0]\nradius = 1.0\n";
    const BROKEN: &str =
        "[camera]\nposition = [0.0, 0.0, -1.0]\n[[spheres]]\ncenter = [0.0, 0.0, 10.0]\nradius = -2.0\n";
    const FIXED: &str = "[camera]\nposition = [0.0, 0.0, -1.0]\n[[spheres]]\ncenter = [0.0, 0.0, 10.0]\nradius = 3.0\n";

    /// A fresh folder under the system's temporary one, removed when dropped.
    struct TempDir(PathBuf);

    impl TempDir {
        fn new(name: &str) -> Self {
            let dir = std::env::temp_dir().join(format!("stereotrace-watch-{name}-{}", std::process::id()));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir).unwrap();
            Self(dir)
        }

        /// Writes `text` to `name` in the folder so that its stamp surely changes (the
        /// length differs, or the modification time is set a second later).
        fn write(&self, name: &str, text: &str) -> PathBuf {
            let path = self.0.join(name);
            let before = stamp(&path);
            std::fs::write(&path, text).unwrap();
            if let Some((time, _)) = before.filter(|_| stamp(&path) == before) {
                let later = time + Duration::from_secs(1);
                std::fs::File::options().write(true).open(&path).unwrap().set_modified(later).unwrap();
            }
            path
        }
    }

    impl Drop for TempDir {
        fn drop(&mut self) {
            let _ = std::fs::remove_dir_all(&self.0);
        }
    }

    fn radius(watch: &SceneWatch) -> f32 {
        watch.scene().spheres[0].radius
    }

    /// Polls at `now` and waits for the read that starts, if one does (reads run on their
    /// own thread), returning the change found.
    fn settle(watch: &mut SceneWatch, now: Instant) -> Option<Change> {
        let change = watch.poll(now);
        if change.is_some() {
            return change;
        }
        watch.wait_for_read(Duration::from_secs(30))
    }

    /// Opens `path` and waits for its read.
    fn open(watch: &mut SceneWatch, path: &Path) -> Option<Change> {
        watch.open(path);
        assert!(watch.loading().is_some_and(|(p, _)| p == path), "the read is under way");
        settle(watch, Instant::now())
    }

    #[test]
    fn a_broken_save_keeps_the_scene_and_reports_the_error_until_a_good_one_reloads() {
        let dir = TempDir::new("reload");
        let path = dir.write("scene.toml", GOOD);
        let scene = Scene::load(&path).unwrap();
        let t0 = Instant::now();
        let mut settings = Settings::from_scene(&scene);
        let mut watch = SceneWatch::new(path.clone(), scene, LoadOptions::default(), t0);
        assert!(settle(&mut watch, t0).is_none(), "nothing changed");

        // The user walks; then saves a broken file.
        settings.move_head(2.0, 0.5);
        let walked = settings.position;
        dir.write("scene.toml", BROKEN);
        assert!(watch.poll(t0 + POLL_INTERVAL / 2).is_none(), "no poll before the interval");
        assert!(watch.loading().is_none(), "nothing read before the interval");
        assert!(settle(&mut watch, t0 + POLL_INTERVAL).is_none(), "the broken save is not taken");
        assert_eq!(radius(&watch), 1.0, "the last good scene stays");
        let expected = format!("{}:3: spheres[0].radius = -2: must be > 0", path.display());
        assert_eq!(watch.error(), Some(&*expected), "file, line of the table, field, value, why");
        assert_eq!(Scene::load(&path).unwrap_err().to_string(), expected, "the command line's wording");
        assert_eq!(watch.failures(), 1, "one failed load");
        assert!(settle(&mut watch, t0 + 2 * POLL_INTERVAL).is_none(), "an unchanged broken file is not read again");
        assert_eq!(watch.failures(), 1, "not read again");
        assert!(watch.error().is_some(), "the error stays until a good save");

        // Fixed: it reloads, and the head stays where the user walked to.
        dir.write("scene.toml", FIXED);
        assert!(watch.poll(t0 + 3 * POLL_INTERVAL).is_none(), "the read starts");
        assert!(watch.loading().is_some(), "and is under way");
        let change = settle(&mut watch, t0 + 3 * POLL_INTERVAL).expect("the fixed file reloads");
        assert!(change.same_file, "a reload of the same file");
        assert_eq!(radius(&watch), 3.0, "the new scene");
        assert_eq!(change.previous.spheres[0].radius, 1.0, "it replaced the last good one");
        assert_eq!(watch.error(), None, "the error is gone");
        settings.follow_reload(&change.previous, watch.scene());
        assert_eq!(settings.position, walked, "the head pose is kept");
    }

    #[test]
    fn dropping_a_file_opens_it_or_reports_why_not() {
        let dir = TempDir::new("drop");
        let first = dir.write("a.toml", GOOD);
        let other = dir.write("b.toml", &GOOD.replace("-1.0", "-4.0"));
        let broken = dir.write("c.toml", BROKEN);
        let picture = dir.write("d.png", "not a scene");
        let t0 = Instant::now();
        let mut watch = SceneWatch::new(first.clone(), Scene::load(&first).unwrap(), LoadOptions::default(), t0);
        assert_eq!(watch.files(), [first.clone(), other.clone(), broken.clone()], "the folder's .toml files, sorted");
        assert_eq!(watch.folder(), dir.0, "the scene's own folder");

        assert!(open(&mut watch, &picture).is_none(), "a PNG is no scene");
        let error = watch.error().unwrap_or_default();
        assert!(error.starts_with(&format!("{}: not a scene file:", picture.display())), "{error}");
        assert_eq!(watch.path(), first, "the scene stays");
        assert!(open(&mut watch, &broken).is_none(), "a broken scene is not taken");
        let expected = format!("{}:3: spheres[0].radius = -2: must be > 0", broken.display());
        assert_eq!(watch.error(), Some(&*expected), "the load error");
        assert_eq!(watch.path(), first, "the scene still stays");

        // Another file: it starts at its own head pose.
        let mut settings = Settings::from_scene(watch.scene());
        settings.move_head(1.0, 0.0);
        let change = open(&mut watch, &other).expect("b.toml opens");
        assert!(!change.same_file, "another file");
        assert_eq!((watch.path(), watch.error(), watch.name()), (&*other, None, "b.toml"));
        settings.reset_camera(watch.scene());
        assert_eq!(settings.position, Vec3::new(0.0, 0.0, -4.0), "the new file's head pose");
        // Dropping the file shown is a reload of it.
        assert!(open(&mut watch, &dir.0.join(".").join("b.toml")).expect("reopens").same_file, "the same file");
    }

    /// A structure file beside the scene is listed, and opens as a scene of its atoms.
    #[test]
    fn a_structure_file_is_listed_and_opens() {
        let dir = TempDir::new("structure");
        let first = dir.write("a.toml", GOOD);
        let water = dir.write("water.xyz", "3\nwater\nO 0.0 0.0 0.0\nH 0.76 0.59 0.0\nH -0.76 0.59 0.0\n");
        let mut watch =
            SceneWatch::new(first.clone(), Scene::load(&first).unwrap(), LoadOptions::default(), Instant::now());
        assert_eq!(watch.files(), [first, water.clone()], "scenes and structures, sorted");
        let change = open(&mut watch, &water).expect("the structure opens");
        assert!(!change.same_file);
        assert_eq!((watch.name(), watch.scene().sphere_count()), ("water.xyz", 3), "its three atoms");
    }

    #[test]
    fn the_folder_list_follows_the_folder_and_a_missing_one_is_reported() {
        let dir = TempDir::new("list");
        let first = dir.write("a.toml", GOOD);
        let t0 = Instant::now();
        let mut watch = SceneWatch::new(first.clone(), Scene::load(&first).unwrap(), LoadOptions::default(), t0);
        assert_eq!(watch.files().len(), 1);
        let before = stamp(&dir.0).expect("the folder's stamp");
        let second = dir.write("z.toml", GOOD);
        // A folder's time can be coarse, so a new file may leave it as it was: move it on.
        std::fs::File::open(&dir.0).unwrap().set_modified(before.0 + Duration::from_secs(2)).unwrap();
        assert_ne!(stamp(&dir.0), Some(before), "the folder changed");
        settle(&mut watch, t0 + POLL_INTERVAL);
        assert_eq!(watch.files(), [first.clone(), second], "the new file is listed");

        // The folder goes away: the scene stays, the list is empty and says why.
        drop(dir);
        assert!(settle(&mut watch, t0 + 2 * POLL_INTERVAL).is_none(), "nothing to reload");
        assert!(watch.files().is_empty(), "no files");
        assert!(
            watch.folder_error().unwrap_or_default().contains("cannot list the folder"),
            "{:?}",
            watch.folder_error()
        );
        assert!(
            watch.error().unwrap_or_default().contains("cannot read scene file"),
            "the file is gone too: {:?}",
            watch.error()
        );
        assert_eq!(radius(&watch), 1.0, "the last good scene stays");
    }
}

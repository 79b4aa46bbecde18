//! A virtual X display for the window tests, and waits on what happens there.
//!
//! [`XSession::start`] runs `xvfb-run` around a placeholder command that prints the display
//! it was given and then waits on its standard input: the X server lives until the session
//! is dropped, and the test runs the viewer and `xdotool` against it itself. Every wait is
//! for a condition — a line on the viewer's stderr, a window mapped, a process exiting —
//! with [`TIMEOUT`] as its limit, and a failure says what did not happen and shows what the
//! viewer wrote so far. Nothing waits a fixed time.

use std::ffi::OsStr;
use std::io::{BufRead, BufReader, Read};
use std::os::unix::process::CommandExt;
use std::path::Path;
use std::process::{Child, ChildStdin, Command, ExitStatus, Stdio};
use std::sync::mpsc::{self, Receiver, RecvTimeoutError};
use std::time::{Duration, Instant};

/// The longest any one wait may take: far more than the slowest machine needs (a first
/// frame at these sizes comes in well under a second when the machine is idle).
pub const TIMEOUT: Duration = Duration::from_secs(90);

/// The lines a child writes to one of its pipes, read on a thread of their own, and those
/// taken so far.
struct Lines {
    rx: Receiver<String>,
    seen: Vec<String>,
}

/// Why no more lines came.
enum Stop {
    /// The deadline passed.
    Timeout,
    /// The pipe closed: the process has exited (or closed it).
    Closed,
}

impl Lines {
    fn of(pipe: impl Read + Send + 'static) -> Self {
        let (tx, rx) = mpsc::channel();
        std::thread::spawn(move || {
            let mut reader = BufReader::new(pipe);
            let mut line = Vec::new();
            while reader.read_until(b'\n', &mut line).is_ok_and(|n| n > 0) {
                let text = String::from_utf8_lossy(&line).trim_end_matches(['\n', '\r']).to_owned();
                if tx.send(text).is_err() {
                    break;
                }
                line.clear();
            }
        });
        Self { rx, seen: Vec::new() }
    }

    /// The next line, if one comes before `deadline`.
    fn next(&mut self, deadline: Instant) -> Result<&str, Stop> {
        let left = deadline.saturating_duration_since(Instant::now());
        match self.rx.recv_timeout(left) {
            Ok(line) => {
                self.seen.push(line);
                Ok(self.seen.last().map_or("", String::as_str))
            }
            Err(RecvTimeoutError::Timeout) => Err(Stop::Timeout),
            Err(RecvTimeoutError::Disconnected) => Err(Stop::Closed),
        }
    }

    /// Every line, once the pipe has closed (within `deadline`): false if it had not.
    fn drain(&mut self, deadline: Instant) -> bool {
        loop {
            match self.next(deadline) {
                Ok(_) => {}
                Err(Stop::Closed) => return true,
                Err(Stop::Timeout) => return false,
            }
        }
    }

    fn text(&self) -> String {
        self.seen.join("\n")
    }
}

/// Kills `child` and every process in its process group (it must lead one), and reaps it.
fn kill_group(child: &mut Child) {
    let _ = Command::new("kill").args(["-KILL", "--", &format!("-{}", child.id())]).status();
    let _ = child.kill();
    let _ = child.wait();
}

/// A virtual X server (Xvfb at 1920 × 1080 × 24, by `xvfb-run -a`), up until dropped.
pub struct XSession {
    /// `xvfb-run`, in a process group of its own, running the placeholder.
    xvfb_run: Child,
    /// The placeholder's standard input: closing it ends the session.
    stdin: Option<ChildStdin>,
    /// `xvfb-run`'s and Xvfb's complaints, if any.
    stderr: Lines,
    /// `DISPLAY` and `XAUTHORITY` for the programs run on it.
    env: [(&'static str, String); 2],
}

impl XSession {
    /// Starts the server and waits until it accepts connections (`xvfb-run` starts its
    /// command only then).
    pub fn start() -> Self {
        let mut child = Command::new("xvfb-run")
            .args(["-a", "-s", "-screen 0 1920x1080x24"])
            .args(["sh", "-c", r#"echo "$DISPLAY"; echo "$XAUTHORITY"; exec cat >/dev/null"#])
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            // Its own process group, so that a session that does not end is killed whole.
            .process_group(0)
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start xvfb-run: {e}"));
        let stdin = child.stdin.take();
        let mut stdout = Lines::of(child.stdout.take().unwrap_or_else(|| unreachable!("stdout is piped")));
        let mut stderr = Lines::of(child.stderr.take().unwrap_or_else(|| unreachable!("stderr is piped")));
        // The placeholder's two lines: DISPLAY, then XAUTHORITY.
        let deadline = Instant::now() + TIMEOUT;
        let mut value = || stdout.next(deadline).map(str::to_owned).ok();
        let (Some(display), Some(xauthority)) = (value(), value()) else {
            kill_group(&mut child);
            stderr.drain(Instant::now() + Duration::from_secs(5));
            panic!("xvfb-run did not start an X server within {TIMEOUT:?}:\n{}", stderr.text());
        };
        Self { xvfb_run: child, stdin, stderr, env: [("DISPLAY", display), ("XAUTHORITY", xauthority)] }
    }

    /// `program` set up to run on this display, with no standard input.
    pub fn command(&self, program: impl AsRef<OsStr>) -> Command {
        let mut command = Command::new(program);
        command.envs(self.env.iter().map(|(k, v)| (k, v))).stdin(Stdio::null());
        command
    }

    /// Starts `stereotrace` with `args` and `env` in `dir`, its stderr read line by line.
    pub fn viewer(&self, dir: &Path, args: &[&OsStr], env: &[(&str, &str)]) -> Viewer {
        let mut child = self
            .command(env!("CARGO_BIN_EXE_stereotrace"))
            .args(args)
            .envs(env.iter().copied())
            .current_dir(dir)
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot start stereotrace: {e}"));
        let stderr = Lines::of(child.stderr.take().unwrap_or_else(|| unreachable!("stderr is piped")));
        Viewer { child, stderr }
    }

    /// Runs `xdotool` with `args` to its end (within [`TIMEOUT`]) and returns its output;
    /// a failure names the `step` and shows what `viewer` wrote so far.
    pub fn xdotool(&self, viewer: &Viewer, step: &str, args: &[&str]) -> String {
        let mut child = self
            .command("xdotool")
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap_or_else(|e| panic!("cannot run xdotool: {e}"));
        let mut out = Lines::of(child.stdout.take().unwrap_or_else(|| unreachable!("stdout is piped")));
        let mut err = Lines::of(child.stderr.take().unwrap_or_else(|| unreachable!("stderr is piped")));
        let deadline = Instant::now() + TIMEOUT;
        if !(out.drain(deadline) && err.drain(deadline)) {
            let _ = child.kill();
            let _ = child.wait();
            panic!(
                "{step}: `xdotool {}` did not finish within {TIMEOUT:?}; the viewer's stderr:\n{}",
                args.join(" "),
                viewer.stderr.text()
            );
        }
        let status = child.wait().unwrap_or_else(|e| panic!("xdotool: {e}"));
        assert!(
            status.success(),
            "{step}: `xdotool {}` failed ({status}): {}\nthe viewer's stderr:\n{}",
            args.join(" "),
            err.text(),
            viewer.stderr.text()
        );
        out.text()
    }

    /// Waits until the viewer's window is mapped (`xdotool search --sync --onlyvisible`) and
    /// gives it the keyboard focus; returns its id.
    pub fn focus_window(&self, viewer: &Viewer) -> String {
        let found = self.xdotool(
            viewer,
            "the window to appear",
            &["search", "--sync", "--onlyvisible", "--name", "stereotrace"],
        );
        let id = found.lines().next().unwrap_or_default().to_owned();
        self.xdotool(viewer, "the window to take the focus", &["windowfocus", "--sync", &id]);
        id
    }
}

impl Drop for XSession {
    fn drop(&mut self) {
        // The placeholder's input closes: it exits, and `xvfb-run` stops the server.
        drop(self.stdin.take());
        if !self.stderr.drain(Instant::now() + Duration::from_secs(10)) {
            kill_group(&mut self.xvfb_run);
        }
        let _ = self.xvfb_run.wait();
    }
}

/// The viewer running on an [`XSession`], killed if dropped while it runs.
pub struct Viewer {
    child: Child,
    stderr: Lines,
}

impl Viewer {
    /// Waits for a line on the viewer's stderr that `matches` (`what` says what it shows,
    /// for a failure), and returns it.
    pub fn wait_for_line(&mut self, what: &str, matches: impl Fn(&str) -> bool) -> String {
        let deadline = Instant::now() + TIMEOUT;
        loop {
            match self.stderr.next(deadline) {
                Ok(line) if matches(line) => return line.to_owned(),
                Ok(_) => {}
                Err(Stop::Timeout) => {
                    panic!("waited {TIMEOUT:?} for {what}; the viewer's stderr:\n{}", self.stderr.text())
                }
                Err(Stop::Closed) => {
                    let status = self.child.wait().map_or_else(|e| e.to_string(), |s| s.to_string());
                    panic!("the viewer exited ({status}) before {what}; its stderr:\n{}", self.stderr.text())
                }
            }
        }
    }

    /// Waits for the viewer to exit, asserts that it succeeded, and returns its stderr.
    pub fn wait_exit(mut self) -> String {
        assert!(
            self.stderr.drain(Instant::now() + TIMEOUT),
            "the viewer did not exit within {TIMEOUT:?}; its stderr:\n{}",
            self.stderr.text()
        );
        let status: ExitStatus = self.child.wait().unwrap_or_else(|e| panic!("stereotrace: {e}"));
        let stderr = self.stderr.text();
        assert!(status.success(), "the viewer failed ({status}); its stderr:\n{stderr}");
        stderr
    }
}

impl Drop for Viewer {
    fn drop(&mut self) {
        if self.child.try_wait().ok().flatten().is_none() {
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

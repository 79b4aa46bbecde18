//! Start-up checks before a window is opened: is there a display, and are the shared
//! libraries winit and softbuffer load at run time installed?
//!
//! winit opens libX11, libxcb, libXcursor, libXi and libxkbcommon with `dlopen`, so a missing
//! one is not a link error but a panic deep inside the event loop (xkbcommon-dl panics when
//! libxkbcommon-x11 is missing). We look for each library first — in `ldconfig -p`'s cache and
//! in the usual library directories, never by loading it (`unsafe_code` is denied) — and fail
//! with a message that names the Debian package to install.

use std::path::{Path, PathBuf};

/// The windowing system the event loop will use.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// X11 (also under `XWayland` and Xvfb). Chosen whenever `DISPLAY` is set: it is the most
    /// robust choice, and a broken `WAYLAND_DISPLAY` cannot stop the viewer.
    X11,
    /// Wayland, used only when `DISPLAY` is unset and `WAYLAND_DISPLAY` is set.
    Wayland,
}

/// A shared library the viewer needs at run time and the Debian package that provides it.
#[derive(Clone, Copy, Debug)]
pub struct RuntimeLib {
    /// The soname winit or softbuffer opens.
    pub soname: &'static str,
    /// Debian/Ubuntu package providing it.
    pub package: &'static str,
}

const fn lib(soname: &'static str, package: &'static str) -> RuntimeLib {
    RuntimeLib { soname, package }
}

/// Libraries opened on X11.
pub const X11_LIBS: [RuntimeLib; 7] = [
    lib("libX11.so.6", "libx11-6"),
    lib("libX11-xcb.so.1", "libx11-xcb1"),
    lib("libxcb.so.1", "libxcb1"),
    lib("libXcursor.so.1", "libxcursor1"),
    lib("libXi.so.6", "libxi6"),
    lib("libxkbcommon.so.0", "libxkbcommon0"),
    lib("libxkbcommon-x11.so.0", "libxkbcommon-x11-0"),
];

/// Libraries opened on Wayland.
pub const WAYLAND_LIBS: [RuntimeLib; 2] =
    [lib("libwayland-client.so.0", "libwayland-client0"), lib("libxkbcommon.so.0", "libxkbcommon0")];

/// Directories searched besides `LD_LIBRARY_PATH` and the `ldconfig` cache.
const LIB_DIRS: [&str; 10] = [
    "/lib",
    "/usr/lib",
    "/lib64",
    "/usr/lib64",
    "/usr/local/lib",
    "/usr/lib/x86_64-linux-gnu",
    "/lib/x86_64-linux-gnu",
    "/usr/lib/aarch64-linux-gnu",
    "/lib/aarch64-linux-gnu",
    "/usr/lib/arm-linux-gnueabihf",
];

/// Picks the windowing backend from the environment, or explains why there is no display.
pub fn choose_backend(display: Option<&str>, wayland_display: Option<&str>) -> anyhow::Result<Backend> {
    let set = |v: Option<&str>| v.is_some_and(|s| !s.trim().is_empty());
    if set(display) {
        Ok(Backend::X11)
    } else if set(wayland_display) {
        Ok(Backend::Wayland)
    } else {
        anyhow::bail!(
            "no display: neither DISPLAY nor WAYLAND_DISPLAY is set. The viewer window needs a desktop \
             session; headless, run it under Xvfb (`xvfb-run -a stereotrace`, Debian packages xvfb xauth) \
             or use `stereotrace render` / `stereotrace bench`, which need no display"
        )
    }
}

/// The backend for this process's environment.
pub fn backend_from_env() -> anyhow::Result<Backend> {
    let display = std::env::var("DISPLAY").ok();
    let wayland = std::env::var("WAYLAND_DISPLAY").ok();
    choose_backend(display.as_deref(), wayland.as_deref())
}

/// Fails with an install hint if a library `backend` needs is not installed.
pub fn check_runtime_libraries(backend: Backend) -> anyhow::Result<()> {
    if !cfg!(target_os = "linux") {
        return Ok(());
    }
    let needed: &[RuntimeLib] = match backend {
        Backend::X11 => &X11_LIBS,
        Backend::Wayland => &WAYLAND_LIBS,
    };
    let cache = ldconfig_cache();
    let mut dirs: Vec<PathBuf> = std::env::var_os("LD_LIBRARY_PATH")
        .map(|p| std::env::split_paths(&p).filter(|d| !d.as_os_str().is_empty()).collect())
        .unwrap_or_default();
    dirs.extend(LIB_DIRS.iter().map(PathBuf::from));
    let missing = missing_libraries(needed, &cache, &dirs, Path::exists);
    if missing.is_empty() {
        return Ok(());
    }
    let names: Vec<&str> = missing.iter().map(|l| l.soname).collect();
    let mut packages: Vec<&str> = missing.iter().map(|l| l.package).collect();
    packages.dedup();
    anyhow::bail!(
        "cannot open the window: missing runtime librar{} {} (needed by winit/softbuffer on {}). \
         On Debian/Ubuntu install them with: sudo apt-get install {}",
        if names.len() == 1 { "y" } else { "ies" },
        names.join(", "),
        match backend {
            Backend::X11 => "X11",
            Backend::Wayland => "Wayland",
        },
        packages.join(" ")
    )
}

/// The libraries of `needed` found neither in the `ldconfig -p` listing `cache` nor as a file
/// in one of `dirs` (checked with `exists`).
pub fn missing_libraries(
    needed: &[RuntimeLib],
    cache: &str,
    dirs: &[PathBuf],
    exists: impl Fn(&Path) -> bool,
) -> Vec<RuntimeLib> {
    needed
        .iter()
        .filter(|lib| {
            !cached_paths(cache, lib.soname).any(&exists) && !dirs.iter().any(|d| exists(&d.join(lib.soname)))
        })
        .copied()
        .collect()
}

/// The paths an `ldconfig -p` listing gives for `soname` (lines look like
/// `\tlibX11.so.6 (libc6,x86-64) => /lib/x86_64-linux-gnu/libX11.so.6`). The caller checks
/// that they still exist: the cache can be stale.
fn cached_paths<'a>(cache: &'a str, soname: &'a str) -> impl Iterator<Item = &'a Path> + 'a {
    cache.lines().filter(move |line| line.split_whitespace().next() == Some(soname)).filter_map(|line| {
        let (_, path) = line.split_once("=>")?;
        Some(Path::new(path.trim()))
    })
}

/// `ldconfig -p`'s output, or an empty string if it cannot be run (the directory search still
/// applies).
fn ldconfig_cache() -> String {
    for exe in ["ldconfig", "/sbin/ldconfig", "/usr/sbin/ldconfig"] {
        if let Ok(out) = std::process::Command::new(exe).arg("-p").output() {
            if out.status.success() {
                return String::from_utf8_lossy(&out.stdout).into_owned();
            }
        }
    }
    String::new()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_decides_the_backend() {
        assert_eq!(choose_backend(Some(":0"), None).unwrap(), Backend::X11);
        assert_eq!(choose_backend(Some(":0"), Some("wayland-0")).unwrap(), Backend::X11);
        assert_eq!(choose_backend(None, Some("wayland-0")).unwrap(), Backend::Wayland);
        assert_eq!(choose_backend(Some(""), Some("wayland-0")).unwrap(), Backend::Wayland);
        let err = choose_backend(None, Some(" ")).unwrap_err().to_string();
        assert!(err.contains("DISPLAY") && err.contains("xvfb-run"), "{err}");
    }

    #[test]
    fn libraries_are_found_in_the_cache_or_a_directory() {
        let cache = "1234 libs found in cache `/etc/ld.so.cache'\n\
                     \tlibX11.so.6 (libc6,x86-64) => /usr/lib/x86_64-linux-gnu/libX11.so.6\n\
                     \tlibX11-xcb.so.1 (libc6,x86-64) => /usr/lib/x86_64-linux-gnu/libX11-xcb.so.1\n";
        let dirs = [PathBuf::from("/opt/x")];
        let exists = |p: &Path| {
            p == Path::new("/opt/x/libxcb.so.1") || p.to_string_lossy().starts_with("/usr/lib/x86_64-linux-gnu/libX11")
        };
        let missing = missing_libraries(&X11_LIBS, cache, &dirs, exists);
        let names: Vec<_> = missing.iter().map(|l| l.soname).collect();
        assert_eq!(
            names,
            ["libXcursor.so.1", "libXi.so.6", "libxkbcommon.so.0", "libxkbcommon-x11.so.0"],
            "a prefix such as libX11.so.6 must not satisfy libX11-xcb.so.1 and vice versa"
        );
        // A stale cache entry whose file is gone does not count.
        let gone = missing_libraries(&X11_LIBS[..1], cache, &[], |_| false);
        assert_eq!(gone.len(), 1);
    }

    /// Whether a file `soname` is in a library folder or one level below it (the multiarch
    /// folders): a search that shares no code with the check's.
    fn on_disk(soname: &str) -> bool {
        ["/lib", "/usr/lib", "/lib64", "/usr/lib64", "/usr/local/lib"].iter().any(|root| {
            let below = std::fs::read_dir(root).into_iter().flatten().flatten().map(|e| e.path());
            std::iter::once(PathBuf::from(root)).chain(below).any(|dir| dir.join(soname).is_file())
        })
    }

    /// On a host that has every X11 library (CI installs them) the check passes. Elsewhere,
    /// a library it reports missing must truly be absent, and its package named.
    #[test]
    fn this_machine_passes_or_names_the_packages() {
        let absent: Vec<&str> = X11_LIBS.iter().map(|l| l.soname).filter(|s| !on_disk(s)).collect();
        let result = check_runtime_libraries(Backend::X11);
        if absent.is_empty() {
            assert!(result.is_ok(), "every X11 library is on disk, yet the check fails: {result:?}");
            return;
        }
        assert!(std::env::var_os("CI").is_none(), "CI installs the X11 libraries, yet {absent:?} are missing");
        if let Err(e) = result {
            let e = e.to_string();
            for lib in X11_LIBS.iter().filter(|l| e.contains(l.soname)) {
                assert!(absent.contains(&lib.soname), "{} is on disk, yet reported missing: {e}", lib.soname);
                assert!(e.contains(&format!(" {}", lib.package)), "names the package {}: {e}", lib.package);
            }
        }
        tracer::testing::skipped(&format!("the X11 libraries {absent:?} are not on this host"));
    }
}

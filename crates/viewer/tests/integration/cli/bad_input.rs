//! The headless commands refuse bad input before any work: exit code 2 (1 for a failure
//! that is not the input's) and a message that names the argument, the file or the
//! variable, and the value; nothing is written.

use crate::common::{stereotrace, stereotrace_with, tmp};

#[test]
fn a_bad_scene_file_names_file_line_and_field_and_exits_2() {
    let bad = tmp("bad.toml");
    std::fs::write(&bad, "[[spheres]]\ncenter = [0.0, 0.0, 15.0]\nradius = -2.0\n").unwrap();
    let out = stereotrace(&["render", "--scene", bad.to_str().unwrap(), "--json"]);
    assert_eq!(out.status.code(), Some(2), "bad input");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("bad.toml:1: spheres[0].radius = -2: must be > 0"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn bad_arguments_exit_2_without_writing() {
    let out = stereotrace(&["render", "--width", "0", "--json"]);
    assert_eq!(out.status.code(), Some(2), "--width 0");
    let out = stereotrace(&["render", "--ipd", "-1", "--json"]);
    assert_eq!(out.status.code(), Some(2), "--ipd -1");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--ipd -1"), "{err}");
    let missing = tmp("no/such/dir/l.png");
    let out = stereotrace(&["render", "--width", "8", "--height", "8", "--left", missing.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "an output in a missing directory");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("does not exist"), "{err}");
    assert!(!missing.exists(), "nothing written");
}

/// `STEREOTRACE_LANES` accepts the lane widths this CPU has (4 everywhere: the report names
/// the width that ran) and refuses the rest, naming the widths there are.
#[test]
fn the_lanes_variable_picks_a_width_and_refuses_other_values() {
    let args = ["render", "--width", "16", "--height", "8", "--json"];
    for lanes in tracer::LANE_WIDTHS {
        let out = stereotrace_with(&[("STEREOTRACE_LANES", &lanes.to_string())], &args);
        if tracer::simd_level_of(lanes).is_none() {
            assert_eq!(out.status.code(), Some(2), "{lanes} lanes on a CPU without them");
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(err.contains(&format!("STEREOTRACE_LANES={lanes}: this CPU has no")), "{err}");
            continue;
        }
        assert!(out.status.success(), "{lanes}: {}", String::from_utf8_lossy(&out.stderr));
        let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("the JSON report");
        assert_eq!(report["lanes"], lanes, "{lanes} lanes ran");
    }
    for bad in ["12", "wide"] {
        let out = stereotrace_with(&[("STEREOTRACE_LANES", bad)], &args);
        assert_eq!(out.status.code(), Some(2), "a width the tracer does not have is bad input");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(&format!("STEREOTRACE_LANES={bad}: must be a lane width this CPU has (4")), "{err}");
    }
}

/// The memory check, with the limit injected (`STEREOTRACE_MEMORY_AVAILABLE`) so the answer
/// does not depend on this machine's free memory.
#[test]
fn a_frame_too_large_for_the_memory_is_refused_before_any_work() {
    let limit = |bytes: &str| [("STEREOTRACE_MEMORY_AVAILABLE", bytes.to_owned())];
    let run = |env: &[(&str, String)], args: &[&str]| {
        let env: Vec<(&str, &str)> = env.iter().map(|(k, v)| (*k, v.as_str())).collect();
        stereotrace_with(&env, args)
    };
    let out = run(&limit("17179869184"), &["render", "--width", "16384", "--height", "16384", "--json"]);
    assert_eq!(out.status.code(), Some(2), "refused as bad input");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("--width 16384 --height 16384: the frame needs 52.0 GiB but only 16.0 GiB of memory is available"),
        "{err}"
    );
    // 208 bytes per eye pixel (three films, the source map and the mask, and what temporal
    // reuse keeps): 64 × 64 needs 851968.
    let small = ["render", "--width", "64", "--height", "64", "--json"];
    assert!(run(&limit("851968"), &small).status.success(), "exactly enough memory");
    let out = run(&limit("851967"), &small);
    assert_eq!(out.status.code(), Some(2), "one byte short: {}", String::from_utf8_lossy(&out.stderr));
    let out = run(&limit("lots"), &small);
    assert_eq!(out.status.code(), Some(2), "a limit that is no number");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("STEREOTRACE_MEMORY_AVAILABLE=lots: must be a whole number of bytes"), "{err}");
}

#[test]
fn limits_are_refused_before_any_work() {
    let out = stereotrace(&["render", "--width", "20000", "--json"]);
    assert_eq!(out.status.code(), Some(2), "over the documented maximum side");
    let out = stereotrace(&["render", "--mode", "fast", "--json"]);
    assert_eq!(out.status.code(), Some(2), "an unknown mode");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("expected one of full, copy, reshade, exact"), "{err}");
    let out = stereotrace(&["render", "--layout", "over-under", "--out", "x.png"]);
    assert_eq!(out.status.code(), Some(2), "an unknown layout");
    let dir = tmp("anim-bad-fps");
    let out = stereotrace(&["render", "--frames", "2", "--fps", "0", "--out-dir", dir.to_str().unwrap()]);
    assert_eq!(out.status.code(), Some(2), "--fps 0");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("--fps 0"), "{err}");
    let out = stereotrace(&["render", "--scene", "no/such/scene.toml", "--json"]);
    assert_eq!(out.status.code(), Some(2), "a missing scene");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("no/such/scene.toml: cannot read scene file"), "{err}");
}

#[test]
fn an_unwritable_output_fails_cleanly_and_leaves_no_partial_file() {
    // /proc accepts no new files, even for root.
    let out = stereotrace(&["render", "--width", "8", "--height", "8", "--left", "/proc/stereotrace-left.png"]);
    assert_eq!(out.status.code(), Some(1), "not bad input, a failure");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("cannot write /proc/stereotrace-left.png"), "{err}");
    let leftovers: Vec<_> = std::fs::read_dir("/proc")
        .unwrap()
        .filter_map(Result::ok)
        .filter(|e| e.file_name().to_string_lossy().contains("stereotrace-left"))
        .collect();
    assert!(leftovers.is_empty(), "no partial file: {leftovers:?}");
}

#[test]
fn a_supersample_factor_outside_1_to_4_exits_2() {
    for bad in ["0", "5", "1.5", "two"] {
        let out = stereotrace(&["render", "--supersample", bad, "--json"]);
        assert_eq!(out.status.code(), Some(2), "--supersample {bad}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(&format!("invalid value '{bad}' for '--supersample <S>'")), "{err}");
        assert!(out.stdout.is_empty(), "nothing rendered for --supersample {bad}");
    }
    let out = stereotrace(&["render", "--width", "16384", "--height", "16384", "--supersample", "4", "--json"]);
    assert_eq!(out.status.code(), Some(2), "2³² samples per eye");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("65536 × 65536 samples per eye; an eye must have fewer than 4294967295 samples"), "{err}");
}

/// What is not a scene file, and structure files that lie, each a clear message and exit 2,
/// nothing read past what it takes to say so (a FIFO would block, /dev/zero never ends).
#[test]
fn scene_paths_that_are_not_scene_files_and_broken_structures_exit_2() {
    let run = |scene: &str, extra: &[&str]| {
        let mut args = vec!["render", "--scene", scene, "--width", "8", "--height", "8", "--json"];
        args.extend_from_slice(extra);
        let out = stereotrace(&args);
        (out.status.code(), String::from_utf8_lossy(&out.stderr).into_owned())
    };
    let expect = |(code, err): (Option<i32>, String), what: &str| {
        assert_eq!(code, Some(2), "{what}: {err}");
        assert!(err.contains(what), "{what}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    };
    expect(run("/dev/zero", &[]), "/dev/zero: not a regular file (character device)");
    let dir = tmp("scene-dir");
    std::fs::create_dir_all(&dir).unwrap();
    expect(run(dir.to_str().unwrap(), &[]), "not a regular file (directory)");
    let fifo = tmp("scene.pdb");
    let _ = std::fs::remove_file(&fifo);
    if std::process::Command::new("mkfifo").arg(&fifo).status().is_ok_and(|s| s.success()) {
        expect(run(fifo.to_str().unwrap(), &[]), "not a regular file (FIFO)");
    }
    let huge = tmp("huge.toml");
    std::fs::File::create(&huge).unwrap().set_len(64 << 20 | 1).unwrap();
    expect(run(huge.to_str().unwrap(), &[]), "above the limit of 67108864 for a TOML scene");
    let write = |name: &str, text: &str| {
        let path = tmp(name);
        std::fs::write(&path, text).unwrap();
        path.to_str().unwrap().to_owned()
    };
    let atom = |x: &str| format!("ATOM      1  N   ALA A   1    {x:>8}  16.250  -3.000  1.00 20.00           N\n");
    expect(run(&write("bad-x.pdb", &atom("12.3a4")), &[]), "bad-x.pdb:1: ATOM x = \"12.3a4\"");
    expect(run(&write("short.pdb", "ATOM      1  N   ALA A   1      11.104\n"), &[]), "short.pdb:1:");
    expect(run(&write("empty.pdb", ""), &[]), "empty.pdb: no atoms");
    expect(
        run(&write("lying.gro", "water\n    5\n    1SOL     OW    1   0.126   1.624   1.679\n 1.0 1.0 1.0\n"), &[]),
        "lying.gro:",
    );
    expect(run(&write("x.xyz", "2\nc\nC 0 0 0\n"), &[]), "x.xyz:");
    expect(
        run(&write("ok.xyz", "1\nc\nC 0 0 20\n"), &["--radius-scale", "0"]),
        "--radius-scale 0: must be a finite number > 0",
    );
}

/// An unknown colour scheme, a bad `--color-range` and an unknown `--hide` item exit 2 and
/// name the value.
#[test]
fn a_bad_colour_scheme_range_or_hide_item_exits_2_naming_it() {
    let tii = "/usr/share/pymol/data/demo/1tii.pdb";
    for (flag, value, says) in [
        ("--color", "chian", "unknown colour scheme `chian`"),
        ("--color-range", "5,1", "`5,1`: expected two finite numbers A,B with A < B"),
        ("--color-range", "x", "`x`: expected two finite numbers"),
        ("--hide", "water,ions", "unknown item `ions` in `water,ions`"),
    ] {
        for command in ["render", "bench"] {
            let out = stereotrace(&[command, "--scene", tii, "--width", "8", "--height", "8", flag, value, "--json"]);
            assert_eq!(out.status.code(), Some(2), "{command} {flag} {value}");
            let err = String::from_utf8_lossy(&out.stderr);
            assert!(err.contains(flag) && err.contains(says), "{command} {flag} {value}: {err}");
            assert!(!err.contains("panicked"), "{err}");
        }
    }
    // The window's flags too (refused before any window opens).
    let out = stereotrace(&["--scene", tii, "--color", "chian"]);
    assert_eq!(out.status.code(), Some(2), "the window's --color chian");
}

#[test]
fn cue_flags_out_of_range_exit_2() {
    for (args, flag, value) in [
        (["--ao-samples", "2000"], "--ao-samples", "2000"),
        (["--outline", "9"], "--outline", "9"),
        (["--outline=-1", "--ao-samples=4"], "--outline", "-1"),
        (["--depth-cue", "fog"], "--depth-cue", "fog"),
    ] {
        let out = stereotrace(&["render", "--width", "8", "--height", "8", "--json", args[0], args[1]]);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(err.contains(flag) && err.contains(value), "{args:?}: {err}");
    }
}

/// A report whose reader has gone (`stereotrace render --json | head -c 0`) ends the command
/// quietly with success: no panic from the broken pipe.
#[test]
fn a_closed_pipe_on_standard_output_is_not_a_panic() {
    use std::io::Read;
    use std::process::{Command, Stdio};
    for args in [
        &["render", "--width", "64", "--height", "48", "--json"][..],
        &["bench", "--width", "32", "--height", "16", "--frames", "1"],
    ] {
        let mut child = Command::new(env!("CARGO_BIN_EXE_stereotrace"))
            .args(args)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("stereotrace starts");
        drop(child.stdout.take()); // the reader goes before a byte is written
        let mut err = String::new();
        child.stderr.take().expect("stderr").read_to_string(&mut err).expect("stderr reads");
        let status = child.wait().expect("stereotrace ends");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(status.success(), "{args:?}: {status}: {err}");
    }
}

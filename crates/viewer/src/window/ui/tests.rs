//! Tests of `ui.rs`.
use egui::accesskit::Role;
use egui_kittest::kittest::Queryable as _;
use egui_kittest::Harness;
use tracer::Scene;

use super::*;
use crate::window::settings::{LIGHT_RANGE, MAX_IPD};

fn scene() -> Scene {
    let src = "[camera]\nipd = 0.5\ndistance = 9.0\n[render]\nmax_depth = 12\n\
               [[spheres]]\ncenter = [0.0, 0.0, 10.0]\nradius = 1.0\n";
    Scene::from_toml(src, "s.toml").unwrap()
}

/// A scene with a light and a revolving sphere, so the light section's controls are on.
fn lit_scene() -> Scene {
    let src = "[[lights]]\nposition = [0.0, 5.0, 0.0]\n[[spheres]]\ncenter = [0.0, 0.0, 10.0]\nradius = 1.0\n\
               [[spheres]]\nradius = 0.5\norbit = { center = [0.0, 0.0, 10.0], radius = 3.0, period_s = 8.0 }\n";
    Scene::from_toml(src, "lit.toml").unwrap()
}

/// What the panel shows before the first frame arrives.
fn idle_readout(history: &FrameTimes) -> Readout<'_> {
    Readout {
        ui_fps: 60.0,
        render_fps: 30.0,
        frame: None,
        time: 0.0,
        animated: true,
        history,
        saved: None,
        scene: SceneReadout { name: "s.toml", ..SceneReadout::default() },
        fullscreen: false,
        motion: Motion::default(),
    }
}

/// What the harness keeps between frames: the panel's model and every action reported.
struct State {
    settings: Settings,
    folder: String,
    actions: Actions,
    /// When set, the readout's last warp from then on.
    warp: Option<Warped>,
}

/// The panel for `scene` in a kittest harness, the way the app runs it.
fn harness<'a>(scene: &Scene, readout: Readout<'a>) -> Harness<'a, State> {
    harness_sized(scene, readout, egui::vec2(1600.0, 900.0))
}

/// [`harness`] in a window of `size` points.
fn harness_sized<'a>(scene: &Scene, readout: Readout<'a>, size: egui::Vec2) -> Harness<'a, State> {
    let state = State {
        settings: Settings::from_scene(scene),
        folder: "./screenshots".into(),
        actions: Actions::default(),
        warp: None,
    };
    let mut readout = readout;
    let mut harness = Harness::builder().with_size(size).build_ui_state(
        move |ui, st: &mut State| {
            setup_style(ui.ctx());
            if st.warp.is_some() {
                readout.motion.warp = st.warp;
            }
            let actions = panel(ui.ctx(), &mut st.settings, &readout, &mut st.folder);
            st.actions.reset |= actions.reset;
            st.actions.save |= actions.save;
            st.actions.reset_light |= actions.reset_light;
            st.actions.toggle_fullscreen |= actions.toggle_fullscreen;
            st.actions.open_scene = st.actions.open_scene.or(actions.open_scene);
        },
        state,
    );
    harness.run();
    harness
}

/// Focuses the slider labelled `label` and presses `key` once.
fn nudge(harness: &mut Harness<'_, State>, label: &str, key: egui::Key) {
    harness.get_by_role_and_label(Role::Slider, label).focus();
    harness.run();
    harness.key_press(key);
    harness.run();
}

#[test]
fn panel_wraps_its_contents_and_scrolls_only_when_short() {
    let ctx = egui::Context::default();
    setup_style(&ctx);
    let mut s = Settings::from_scene(&scene());
    s.live_psnr = true;
    let history = FrameTimes::default();
    let readout = idle_readout(&history);
    let mut folder = "./screenshots".to_owned();
    let mut panel_rect = |s: &mut Settings, height: f32| {
        for _ in 0..3 {
            let input = egui::RawInput {
                screen_rect: Some(egui::Rect::from_min_size(egui::Pos2::ZERO, egui::vec2(1600.0, height))),
                ..Default::default()
            };
            let _ = ctx.run_ui(input, |ui| {
                let _ = panel(ui.ctx(), s, &readout, &mut folder);
            });
        }
        ctx.globally_used_rect()
    };
    // The window's default height is 600; with the mask legend and the sections open the
    // panel may scroll there, so it is measured in a taller one (800).
    let without = panel_rect(&mut s, 800.0);
    s.show_mask = true;
    let with = panel_rect(&mut s, 800.0);
    assert!(with.width() < 420.0, "the panel covers too much of the left eye: {with:?}");
    assert!(with.height() > without.height() + 60.0, "the legend should extend the panel: {with:?} vs {without:?}");
    assert!(with.height() < 760.0, "the panel should wrap its contents: {with:?}");
    let short = panel_rect(&mut s, 250.0);
    assert!(short.height() < 280.0, "a short window should scroll the panel: {short:?}");
    let again = panel_rect(&mut s, 800.0);
    assert_eq!(again.height(), with.height(), "the panel should grow back");
    assert_eq!(mega(1_234_567), "1.23 M", "ray counts in millions");
}

/// The panel driven as a user would, through its accessibility tree (egui_kittest):
/// widgets found by their labels, a slider moved with the keyboard, buttons clicked.
#[test]
fn panel_widgets_change_the_render_settings() {
    let history = FrameTimes::default();
    let mut harness = harness(&scene(), idle_readout(&history));

    // The IPD slider: focused and nudged up with the arrow key.
    let ipd = harness.state().settings.ipd;
    nudge(&mut harness, "IPD", egui::Key::ArrowRight);
    let after = harness.state().settings.ipd;
    assert!(after > ipd, "IPD should grow: {ipd} -> {after}");
    assert!(after <= MAX_IPD, "within the slider's range: {after}");

    // The mode buttons and the mask checkbox.
    harness.get_by_label("copy").click();
    harness.run();
    assert_eq!(harness.state().settings.mode, Mode::Copy, "the mode button picks copy");
    assert!(!harness.state().settings.show_mask, "the mask starts hidden");
    harness.get_by_label("show mask (M)").click();
    harness.run();
    assert!(harness.state().settings.show_mask, "the checkbox shows the mask");

    // Reuse starts on, and its tick turns it off in the request.
    assert!(harness.state().settings.reuse, "reuse starts on");
    harness.get_by_label("reuse").click();
    harness.run();
    assert!(!harness.state().settings.reuse, "the tick turns reuse off");
    assert!(!harness.state().settings.request(&scene(), 0.0, 64, 36).reuse, "and the request asks for none");

    // Edge retracing applies to copy: its checkbox is enabled there.
    harness.get_by_label("retrace edges").click();
    harness.run();
    assert!(harness.state().settings.options().retrace_edges, "edges are retraced");

    // The buttons report their clicks to the app.
    harness.get_by_label("save pair (F12)").click();
    harness.run();
    assert!(harness.state().actions.save, "the save click is reported");
    assert!(!harness.state().actions.reset, "and no other");

    // Without lights the light section says so.
    harness.get_by_label("light").click();
    harness.run();
    let _ = harness.get_by_label("the scene has no lights");
}

/// The light section: its position sliders move the first light, its reset button is
/// reported, and the orbit-speed slider changes the speed.
#[test]
fn the_light_controls_move_the_light_and_change_the_orbit_speed() {
    let scene = lit_scene();
    let history = FrameTimes::default();
    let mut harness = harness(&scene, idle_readout(&history));
    let home = Settings::from_scene(&scene).light.unwrap();
    harness.get_by_label("light").click();
    harness.run();

    nudge(&mut harness, "x", egui::Key::ArrowRight);
    nudge(&mut harness, "z", egui::Key::ArrowLeft);
    let moved = harness.state().settings.light.unwrap();
    assert!(moved.x > home.x, "x should grow: {home} -> {moved}");
    assert!(moved.z < home.z, "z should shrink: {home} -> {moved}");
    assert_eq!(moved.y, home.y, "y untouched");
    assert!(moved.abs().max_element() <= LIGHT_RANGE, "within the sliders' reach: {moved}");

    assert!(!harness.state().actions.reset_light, "no reset yet");
    harness.get_by_label("reset").click();
    harness.run();
    assert!(harness.state().actions.reset_light, "the light's reset click is reported");
    assert!(!harness.state().actions.reset, "the camera's reset is another button");

    let speed = harness.state().settings.orbit_speed;
    nudge(&mut harness, "orbit speed", egui::Key::ArrowLeft);
    let slower = harness.state().settings.orbit_speed;
    assert!(slower < speed && slower >= 0.0, "the orbit should slow down: {speed} -> {slower}");
    assert_eq!(harness.state().settings.light, Some(moved), "the light stays where it was moved");
}

/// The bug of issue 14: with the mask legend and every section open, the panel was taller
/// than the default 600-point window (its top cut off, the legend running off the bottom).
/// Now the whole panel stays inside the window, a margin from its edges, and scrolls.
#[test]
fn the_panel_fits_the_default_window_with_everything_open() {
    let scene = lit_scene();
    let history = FrameTimes::default();
    let mut readout = idle_readout(&history);
    readout.scene.error = Some("assets/scenes/seed.toml:12: spheres[1].radius = -1: must be > 0");
    let mut harness = harness_sized(&scene, readout, egui::vec2(1600.0, 600.0));
    harness.state_mut().settings.show_mask = true;
    harness.state_mut().settings.live_psnr = true;
    harness.run();
    harness.get_by_label("keys").click();
    harness.run();
    harness.get_by_label("light").click();
    harness.run();
    let window = harness.get_by_role_and_label(Role::Window, "stereotrace").rect();
    assert!(window.min.y >= 7.9 && window.min.x >= 7.9, "the panel's top left is in the window: {window:?}");
    assert!(window.max.y <= 592.1, "the panel ends above the window's bottom margin: {window:?}");
    assert!(window.height() > 500.0, "and uses the height it has: {window:?}");
    assert!(window.width() < 330.0, "the long error wraps: {window:?}");
    // The title is on screen and the legend can be scrolled to: the timewarp's while it
    // shows a warped frame, the stereo mask's while the frame is shown as traced or the
    // timewarp is off.
    assert!(harness.get_by_label("stereotrace").rect().min.y >= 8.0, "the title is visible");
    let _ = harness.get_by_label("timewarp mask, blended 50 % over both eyes");
    let warped = |fresh| Some(Warped { fresh, ..Warped::default() });
    harness.state_mut().warp = warped(true);
    harness.run();
    let _ = harness.get_by_label("mask, blended 50 % over the right eye");
    let _ = harness.get_by_label("fresh: shown as traced");
    harness.state_mut().warp = warped(false);
    harness.run();
    let _ = harness.get_by_label("timewarp mask, blended 50 % over both eyes");
    harness.state_mut().settings.timewarp = false;
    harness.run();
    let _ = harness.get_by_label("mask, blended 50 % over the right eye");
    assert!(harness.query_by_label("timewarp mask, blended 50 % over both eyes").is_none(), "one legend at a time");
}

/// The panel's "timewarp" tick turns the timewarp off and on; its guard band slider only
/// works while it is on; the figures of a warp are shown beside the new poses a second.
#[test]
fn the_timewarp_tick_turns_it_off_and_on() {
    let history = FrameTimes::default();
    let mut readout = idle_readout(&history);
    let mut warp = Warped { ms: 2.5, ..Warped::default() };
    (warp.counts[0].warped, warp.counts[0].other_eye) = (990, 10);
    readout.motion =
        Motion { pose_fps: 89.5, medians: Medians { latency_ms: Some(8.0), age_ms: Some(75.0) }, warp: Some(warp) };
    let mut harness = harness(&scene(), readout);
    assert!(harness.state().settings.timewarp, "on by default");
    let _ = harness.get_by_label("89.5 /s · latency 8 ms");
    let _ = harness.get_by_label("warped · 2.5 ms · holes 1.00 %");
    let _ = harness.get_by_label("75 ms");
    let guard = harness.state().settings.guard_band;
    nudge(&mut harness, "guard", egui::Key::ArrowRight);
    assert!(harness.state().settings.guard_band > guard, "the band widens while the timewarp is on");
    harness.get_by_label("timewarp (T)").click();
    harness.run();
    assert!(!harness.state().settings.timewarp, "the tick turns it off");
    assert!(harness.query_by_label("warped · 2.5 ms · holes 1.00 %").is_none(), "no warp figures without it");
    let guard = harness.state().settings.guard_band;
    nudge(&mut harness, "guard", egui::Key::ArrowRight);
    assert_eq!(harness.state().settings.guard_band, guard, "no guard band to change without it");
    harness.get_by_label("timewarp (T)").click();
    harness.run();
    assert!(harness.state().settings.timewarp, "and on again");
}

/// The scene section: the folder's scenes in a list whose pick is reported, and a scene
/// that did not load shown with the command line's message.
#[test]
fn the_scene_list_opens_a_scene_and_a_load_error_is_shown() {
    let history = FrameTimes::default();
    let files = [PathBuf::from("assets/scenes/many.toml"), PathBuf::from("assets/scenes/seed.toml")];
    let error = "assets/scenes/seed.toml:5: spheres[0].radius = -2: must be > 0";
    let mut readout = idle_readout(&history);
    readout.scene = SceneReadout { name: "seed.toml", error: Some(error), files: &files, folder_error: None };
    let mut harness = harness(&scene(), readout);
    let _ = harness.get_by_label(error);
    let _ = harness.get_by_label("not loaded (still showing the last good scene):");
    harness.get_by_role(Role::ComboBox).click();
    harness.run();
    assert_eq!(harness.state().actions.open_scene, None, "opening the list picks nothing");
    harness.get_by_label("many.toml").click();
    harness.run();
    assert_eq!(harness.state().actions.open_scene, Some(0), "many.toml is picked");
}

#[test]
fn without_an_error_or_files_the_scene_section_says_so() {
    let history = FrameTimes::default();
    let mut readout = idle_readout(&history);
    readout.scene.folder_error = Some("/gone: cannot list the folder: No such file or directory (os error 2)");
    let mut harness = harness(&scene(), readout);
    assert!(harness.query_by_label_contains("not loaded").is_none(), "no error, no error text");
    harness.get_by_role(Role::ComboBox).click();
    harness.run();
    let _ = harness.get_by_label("/gone: cannot list the folder: No such file or directory (os error 2)");
}

#[test]
fn the_fullscreen_checkbox_asks_for_fullscreen() {
    let history = FrameTimes::default();
    let mut harness = harness(&scene(), idle_readout(&history));
    assert!(!harness.state().actions.toggle_fullscreen);
    harness.get_by_label("fullscreen (F11)").click();
    harness.run();
    assert!(harness.state().actions.toggle_fullscreen, "the click is reported");
}

/// The key overlay lists every key of [`KEYS`]; its close button closes it.
#[test]
fn the_key_overlay_lists_every_key_and_closes() {
    let mut harness = Harness::builder().with_size(egui::vec2(1600.0, 600.0)).build_ui_state(
        |ui, open: &mut bool| {
            setup_style(ui.ctx());
            keys_overlay(ui.ctx(), open);
        },
        true,
    );
    harness.run();
    for (key, action) in KEYS {
        let _ = harness.get_by_label(key);
        let _ = harness.get_by_label(action);
    }
    let _ = harness.get_by_label("F12 or P");
    harness.get_by_label("Close window").click();
    harness.run();
    assert!(!*harness.state(), "closed");
    assert!(harness.query_by_label("F12 or P").is_none(), "and gone");
}

#[test]
fn the_tab_hint_says_tab_hides_the_ui() {
    let mut harness = Harness::builder().with_size(egui::vec2(800.0, 600.0)).build_ui(|ui| tab_hint(ui.ctx()));
    harness.run();
    let hint = harness.get_by_label(TAB_HINT).rect();
    assert!(hint.max.y < 600.0 && hint.min.y > 500.0, "at the bottom: {hint:?}");
    assert!((hint.center().x - 400.0).abs() < 2.0, "centred: {hint:?}");
}

/// The colour section: its combo box sets the scheme, its ticks hide atoms.
#[test]
fn the_colour_section_sets_the_scheme_and_the_hidden_atoms() {
    let history = FrameTimes::default();
    let mut harness = harness(&scene(), idle_readout(&history));
    harness.get_by_label("colour and hiding").click();
    harness.run();
    // The scene's list, then the scheme's.
    harness.get_all_by_role(Role::ComboBox).nth(1).unwrap().click();
    harness.run();
    harness.get_by_label("chain").click();
    harness.run();
    assert_eq!(harness.state().settings.atoms.scheme(), tracer::ColorBy::Chain, "by chain");
    harness.get_by_label("water").click();
    harness.run();
    assert!(harness.state().settings.atoms.hide.water, "waters hidden");
    assert!(!harness.state().settings.atoms.hide.hydrogen, "hydrogens not");
}

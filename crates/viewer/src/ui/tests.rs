//! Tests of `ui.rs`.
use egui::accesskit::Role;
use egui_kittest::kittest::Queryable as _;
use egui_kittest::Harness;
use tracer::Scene;

use super::*;

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
    Readout { ui_fps: 60.0, render_fps: 30.0, frame: None, time: 0.0, animated: true, history, saved: None }
}

/// What the harness keeps between frames: the panel's model and every action reported.
struct State {
    settings: Settings,
    folder: String,
    actions: Actions,
}

/// The panel for `scene` in a kittest harness, the way the app runs it.
fn harness<'a>(scene: &Scene, readout: Readout<'a>) -> Harness<'a, State> {
    let state =
        State { settings: Settings::from_scene(scene), folder: "./screenshots".into(), actions: Actions::default() };
    let mut harness = Harness::builder().with_size(egui::vec2(1600.0, 900.0)).build_ui_state(
        move |ui, st: &mut State| {
            setup_style(ui.ctx());
            let actions = panel(ui.ctx(), &mut st.settings, &readout, &mut st.folder);
            st.actions.reset |= actions.reset;
            st.actions.save |= actions.save;
            st.actions.reset_light |= actions.reset_light;
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
    // panel may scroll there, so it is measured in a taller one.
    let without = panel_rect(&mut s, 700.0);
    s.show_mask = true;
    let with = panel_rect(&mut s, 700.0);
    assert!(with.width() < 420.0, "the panel covers too much of the left eye: {with:?}");
    assert!(with.height() > without.height() + 60.0, "the legend should extend the panel: {with:?} vs {without:?}");
    assert!(with.height() < 660.0, "the panel should wrap its contents: {with:?}");
    let short = panel_rect(&mut s, 250.0);
    assert!(short.height() < 280.0, "a short window should scroll the panel: {short:?}");
    let again = panel_rect(&mut s, 700.0);
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

    // Edge retracing applies to copy: its checkbox is enabled there.
    harness.get_by_label("retrace edges").click();
    harness.run();
    assert!(harness.state().settings.options().retrace_edges, "edges are retraced");

    // The buttons report their clicks to the app.
    harness.get_by_label("save pair (S)").click();
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

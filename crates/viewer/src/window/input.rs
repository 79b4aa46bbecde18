//! Input handling: keys become [`Command`]s for the app, held movement keys walk the head,
//! and mouse drags turn it.
//!
//! Keys, as games and 3-D viewers have them ([`KEYS`] lists them for the panel, the key
//! overlay and the README; arrows are spelled out, egui's fonts have no arrow glyphs): W/↑
//! forward, S/↓ back, A/← and D/→ sideways, Q down and E up
//! (held: `HEAD_SPEED` units a second, forward and sideways along the head's own axes, up and
//! down straight along world y; see `settings.rs`); right-drag (or left-drag outside the
//! panel) turns the head; R resets it; 1, 2, 3 choose side-by-side, cross-eyed, anaglyph;
//! X swaps the eyes; M toggles the debug mask; T the timewarp; Space pauses the revolving spheres; F12 or P
//! saves screenshots; Tab hides and shows the whole UI; F11 toggles borderless fullscreen;
//! ? or F1 opens and closes the key overlay; a left click without drag off the panel picks
//! an atom (`picks.rs`); Esc closes the overlay, or else clears the picks, or else quits.
//!
//! Letters and arrows are ignored while egui has keyboard focus (typing a value into a
//! slider); Tab, F1, F11 and F12 are the viewer's whatever egui wants ([`Command::is_global`]),
//! and Tab never reaches egui at all (egui would move its focus with it; `app/events.rs` keeps it).

use std::time::Instant;

use stereo::Layout;
use winit::dpi::PhysicalPosition;
use winit::event::{ElementState, MouseButton};
use winit::keyboard::{Key, KeyCode, NamedKey, PhysicalKey};

/// Longest time step a held movement key advances the head by, so a stall does not jump.
const MAX_MOVE_STEP: f32 = 0.1;

/// Every key and what it does, in the order the key overlay and the README list them.
pub const KEYS: [(&str, &str); 18] = [
    ("W / Up, S / Down", "move the head forward, back"),
    ("A / Left, D / Right", "move the head left, right"),
    ("Q, E", "move the head down, up"),
    ("right drag (left drag off the panel)", "turn the head (yaw, pitch)"),
    ("R", "reset the head to the scene's camera"),
    ("1, 2, 3", "layout: side by side, cross-eyed, anaglyph"),
    ("X", "swap the eyes"),
    ("C", "next colour scheme (element, chain, residue, bfactor, plddt, rainbow, hetero)"),
    ("M", "debug mask (over both eyes with the timewarp)"),
    ("T", "timewarp on / off"),
    ("Space", "pause / resume the revolving spheres"),
    ("F12 or P", "save the stereo pair as PNGs"),
    ("Tab", "hide / show the whole UI"),
    ("F11", "borderless fullscreen on / off"),
    ("? or F1", "this list on / off"),
    ("left click (no drag) on an eye", "pick an atom: 2 show the distance, 3 the angle"),
    ("Esc", "close this list, else clear the picks, else quit"),
    ("drop a scene file", "open it (.toml or a structure)"),
];

/// What a key press asks the viewer to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    /// Esc: close the key overlay if it is open, else clear the picks, else the window.
    Quit,
    /// Space: pause or resume the revolving spheres.
    TogglePause,
    /// M: show or hide the debug mask.
    ToggleMask,
    /// T: the timewarp on or off.
    ToggleTimewarp,
    /// F12 or P: save screenshots.
    Save,
    /// X: exchange the eyes.
    SwapEyes,
    /// R: put the head back where the scene has it.
    ResetHead,
    /// C: colour the structures by the next scheme.
    CycleColor,
    /// 1, 2, 3: arrange the eyes so.
    Layout(Layout),
    /// Tab: hide or show the whole UI.
    ToggleUi,
    /// F11: borderless fullscreen on or off.
    ToggleFullscreen,
    /// ? or F1: open or close the key overlay.
    ToggleKeys,
}

impl Command {
    /// The command of a logical key (so letters follow the keyboard layout), if it has one.
    #[must_use]
    pub fn of_key(key: &Key) -> Option<Self> {
        match key {
            Key::Named(NamedKey::Escape) => Some(Self::Quit),
            Key::Named(NamedKey::Space) => Some(Self::TogglePause),
            Key::Named(NamedKey::Tab) => Some(Self::ToggleUi),
            Key::Named(NamedKey::F1) => Some(Self::ToggleKeys),
            Key::Named(NamedKey::F11) => Some(Self::ToggleFullscreen),
            Key::Named(NamedKey::F12) => Some(Self::Save),
            Key::Character(c) if c == "?" => Some(Self::ToggleKeys),
            Key::Character(c) if c.eq_ignore_ascii_case("m") => Some(Self::ToggleMask),
            Key::Character(c) if c.eq_ignore_ascii_case("t") => Some(Self::ToggleTimewarp),
            Key::Character(c) if c.eq_ignore_ascii_case("p") => Some(Self::Save),
            Key::Character(c) if c.eq_ignore_ascii_case("x") => Some(Self::SwapEyes),
            Key::Character(c) if c.eq_ignore_ascii_case("r") => Some(Self::ResetHead),
            Key::Character(c) if c.eq_ignore_ascii_case("c") => Some(Self::CycleColor),
            Key::Character(c) => {
                c.parse::<usize>().ok().and_then(|k| Layout::ALL.get(k.wrapping_sub(1))).map(|&l| Self::Layout(l))
            }
            _ => None,
        }
    }

    /// Whether a key is the viewer's even while egui has the keyboard: the keys no widget
    /// types (Tab, F1, F11, F12). Letters, digits, Space and Esc are egui's then.
    #[must_use]
    pub fn is_global(key: &Key) -> bool {
        matches!(key, Key::Named(NamedKey::Tab | NamedKey::F1 | NamedKey::F11 | NamedKey::F12))
    }
}

/// Whether egui must not see this key at all: Tab, which egui would take to move its focus
/// from widget to widget, is the viewer's.
#[must_use]
pub fn hidden_from_egui(logical: &Key) -> bool {
    matches!(logical, Key::Named(NamedKey::Tab))
}
/// Movement keys held down: forward, back, left, right, down, up.
#[derive(Clone, Copy, Debug, Default)]
struct HeldKeys([bool; 6]);

impl HeldKeys {
    /// The movement slot of a physical key (layout-independent, so W/A/D are where they are
    /// on a QWERTY keyboard: W/A/S/D and Q/E under the left hand), if it is one.
    fn slot(key: PhysicalKey) -> Option<usize> {
        match key {
            PhysicalKey::Code(KeyCode::KeyW | KeyCode::ArrowUp) => Some(0),
            PhysicalKey::Code(KeyCode::KeyS | KeyCode::ArrowDown) => Some(1),
            PhysicalKey::Code(KeyCode::KeyA | KeyCode::ArrowLeft) => Some(2),
            PhysicalKey::Code(KeyCode::KeyD | KeyCode::ArrowRight) => Some(3),
            PhysicalKey::Code(KeyCode::KeyQ) => Some(4),
            PhysicalKey::Code(KeyCode::KeyE) => Some(5),
            _ => None,
        }
    }

    /// (forward, right, up) in −1..=1.
    fn direction(self) -> (f32, f32, f32) {
        let axis = |plus: bool, minus: bool| f32::from(u8::from(plus)) - f32::from(u8::from(minus));
        (axis(self.0[0], self.0[1]), axis(self.0[3], self.0[2]), axis(self.0[5], self.0[4]))
    }
}

/// Mouse state for turning the head by dragging.
#[derive(Clone, Copy, Debug, Default)]
struct Drag {
    /// Last cursor position in the window, physical pixels.
    cursor: Option<PhysicalPosition<f64>>,
    /// A turning drag is under way.
    active: bool,
}

/// What input is under way between events: movement keys held, a drag, and when the head
/// last walked.
#[derive(Clone, Copy, Debug)]
pub struct Input {
    held: HeldKeys,
    drag: Drag,
    last_walk: Instant,
}

impl Input {
    /// No key held, no drag; the head's walking clock starts at `now`.
    #[must_use]
    pub fn new(now: Instant) -> Self {
        Self { held: HeldKeys::default(), drag: Drag::default(), last_walk: now }
    }

    /// A key went down (`pressed`) or up. A movement key's press counts only when egui does
    /// not want the keyboard, its release always (so a key never sticks). Returns the
    /// command of a first press (not a repeat) that egui does not want, or of a global key
    /// ([`Command::is_global`]) whatever egui wants.
    pub fn key(
        &mut self,
        physical: PhysicalKey,
        logical: &Key,
        pressed: bool,
        repeat: bool,
        egui_wants_keyboard: bool,
    ) -> Option<Command> {
        if let Some(slot) = HeldKeys::slot(physical) {
            if !pressed || !egui_wants_keyboard {
                self.held.0[slot] = pressed;
            }
        }
        if pressed && !repeat && (!egui_wants_keyboard || Command::is_global(logical)) {
            Command::of_key(logical)
        } else {
            None
        }
    }

    /// A mouse button: the right one always starts a turning drag, the left one only when
    /// the pointer is not on the panel (`on_panel`); releasing either ends it.
    pub fn mouse_button(&mut self, button: MouseButton, state: ElementState, on_panel: bool) {
        let starts = match button {
            MouseButton::Right => true,
            MouseButton::Left => !on_panel,
            _ => return,
        };
        match state {
            ElementState::Pressed if starts => self.drag.active = true,
            ElementState::Pressed => {}
            ElementState::Released => self.drag.active = false,
        }
    }

    /// The cursor moved: the drag's step in pixels (dx, dy) when a turning drag is under way.
    pub fn cursor_moved(&mut self, position: PhysicalPosition<f64>) -> Option<(f32, f32)> {
        let step = match (self.drag.active, self.drag.cursor) {
            (true, Some(last)) => Some(((position.x - last.x) as f32, (position.y - last.y) as f32)),
            _ => None,
        };
        self.drag.cursor = Some(position);
        step
    }

    /// The cursor left the window: the next drag step starts afresh.
    pub fn cursor_left(&mut self) {
        self.drag.cursor = None;
    }

    /// The window lost the keyboard: no key stays held, no drag goes on.
    pub fn focus_lost(&mut self) {
        self.held = HeldKeys::default();
        self.drag.active = false;
    }

    /// Whether `physical` is a movement key (its press moves the head).
    #[must_use]
    pub fn moves_head(physical: PhysicalKey) -> bool {
        HeldKeys::slot(physical).is_some()
    }

    /// Whether the head is moving or turning (a movement key is held or a drag is on).
    #[must_use]
    pub fn is_moving(&self) -> bool {
        self.held.direction() != (0.0, 0.0, 0.0) || self.drag.active
    }

    /// The held keys' direction (forward, right, up), each −1..=1, and the seconds since the
    /// last call (at most [`MAX_MOVE_STEP`]) to walk it for.
    pub fn walk(&mut self, now: Instant) -> ((f32, f32, f32), f32) {
        let dt = now.saturating_duration_since(self.last_walk).as_secs_f32().min(MAX_MOVE_STEP);
        self.last_walk = now;
        (self.held.direction(), dt)
    }
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    fn ch(c: &str) -> Key {
        Key::Character(c.into())
    }

    #[test]
    fn keys_map_to_commands() {
        let named = |k: NamedKey| Command::of_key(&Key::Named(k));
        assert_eq!(named(NamedKey::Escape), Some(Command::Quit), "Esc quits");
        assert_eq!(named(NamedKey::Space), Some(Command::TogglePause), "Space pauses");
        assert_eq!(named(NamedKey::Tab), Some(Command::ToggleUi), "Tab hides the UI");
        assert_eq!(named(NamedKey::F11), Some(Command::ToggleFullscreen), "F11 is fullscreen");
        assert_eq!(named(NamedKey::F12), Some(Command::Save), "F12 saves");
        assert_eq!(named(NamedKey::F1), Some(Command::ToggleKeys), "F1 lists the keys");
        assert_eq!(Command::of_key(&ch("?")), Some(Command::ToggleKeys), "and so does ?");
        assert_eq!(Command::of_key(&ch("M")), Some(Command::ToggleMask), "M, either case");
        assert_eq!(Command::of_key(&ch("p")), Some(Command::Save), "P saves");
        assert_eq!(Command::of_key(&ch("P")), Some(Command::Save), "either case");
        assert_eq!(Command::of_key(&ch("x")), Some(Command::SwapEyes), "X swaps");
        assert_eq!(Command::of_key(&ch("c")), Some(Command::CycleColor), "C cycles the colours");
        assert_eq!(Command::of_key(&ch("r")), Some(Command::ResetHead), "R resets");
        assert_eq!(Command::of_key(&ch("T")), Some(Command::ToggleTimewarp), "T, either case");
        for (k, layout) in Layout::ALL.into_iter().enumerate() {
            assert_eq!(Command::of_key(&ch(&(k + 1).to_string())), Some(Command::Layout(layout)), "{layout}");
        }
        // S is back now (a movement key, no command); Q and E move down and up.
        for none in ["0", "4", "s", "S", "q", "e", "w", "/"] {
            assert_eq!(Command::of_key(&ch(none)), None, "{none} is no command");
        }
        assert_eq!(named(NamedKey::F2), None, "F2 does nothing");
        assert!(hidden_from_egui(&Key::Named(NamedKey::Tab)), "egui never sees Tab");
        assert!(!hidden_from_egui(&Key::Named(NamedKey::ArrowUp)), "it sees the arrows (sliders)");
    }

    #[test]
    fn global_keys_work_while_egui_has_the_keyboard_and_letters_do_not() {
        let mut input = Input::new(Instant::now());
        let key = |input: &mut Input, code: KeyCode, logical: Key| {
            input.key(PhysicalKey::Code(code), &logical, true, false, true)
        };
        assert_eq!(key(&mut input, KeyCode::Tab, Key::Named(NamedKey::Tab)), Some(Command::ToggleUi));
        assert_eq!(key(&mut input, KeyCode::F11, Key::Named(NamedKey::F11)), Some(Command::ToggleFullscreen));
        assert_eq!(key(&mut input, KeyCode::F12, Key::Named(NamedKey::F12)), Some(Command::Save));
        assert_eq!(key(&mut input, KeyCode::F1, Key::Named(NamedKey::F1)), Some(Command::ToggleKeys));
        assert_eq!(key(&mut input, KeyCode::KeyP, ch("p")), None, "P is typed into the focused field");
        assert_eq!(key(&mut input, KeyCode::Slash, ch("?")), None, "so is ?");
        assert_eq!(key(&mut input, KeyCode::Escape, Key::Named(NamedKey::Escape)), None, "Esc leaves the field");
        assert_eq!(
            input.key(PhysicalKey::Code(KeyCode::F12), &Key::Named(NamedKey::F12), true, true, false),
            None,
            "a repeat is no command"
        );
    }

    #[test]
    fn wasd_and_q_e_walk_the_head_and_s_is_back() {
        let t0 = Instant::now();
        let mut input = Input::new(t0);
        let mut hold = |code: KeyCode, c: &str, pressed: bool| {
            assert_eq!(input.key(PhysicalKey::Code(code), &ch(c), pressed, false, false), None, "{c}: no command");
            input.walk(t0).0
        };
        assert_eq!(hold(KeyCode::KeyS, "s", true), (-1.0, 0.0, 0.0), "S walks back");
        assert_eq!(hold(KeyCode::KeyW, "w", true), (0.0, 0.0, 0.0), "W and S cancel");
        assert_eq!(hold(KeyCode::KeyS, "s", false), (1.0, 0.0, 0.0), "W alone walks forward");
        assert_eq!(hold(KeyCode::KeyW, "w", false), (0.0, 0.0, 0.0), "released");
        assert_eq!(hold(KeyCode::KeyE, "e", true), (0.0, 0.0, 1.0), "E goes up");
        assert_eq!(hold(KeyCode::KeyQ, "q", true), (0.0, 0.0, 0.0), "Q and E cancel");
        assert_eq!(hold(KeyCode::KeyE, "e", false), (0.0, 0.0, -1.0), "Q goes down");
        assert_eq!(hold(KeyCode::KeyQ, "q", false), (0.0, 0.0, 0.0), "released");
        assert_eq!(hold(KeyCode::KeyD, "d", true), (0.0, 1.0, 0.0), "D goes right");
        assert_eq!(hold(KeyCode::ArrowDown, "", true), (-1.0, 1.0, 0.0), "the arrows still work: Down is back");
    }

    #[test]
    fn the_key_table_names_every_command_key() {
        let keys: String = KEYS.iter().map(|(k, _)| *k).collect::<Vec<_>>().join(" ");
        for k in [
            "W", "S", "A", "D", "Q", "E", "R", "1, 2, 3", "X", "M", "Space", "F12", "P", "Tab", "F11", "?", "F1", "Esc",
        ] {
            assert!(keys.contains(k), "{k} is missing from the key table: {keys}");
        }
    }

    #[test]
    fn movement_keys_hold_until_released_even_when_egui_has_the_keyboard() {
        let t0 = Instant::now();
        let mut input = Input::new(t0);
        let up = PhysicalKey::Code(KeyCode::ArrowUp);
        let key = Key::Named(NamedKey::ArrowUp);
        assert_eq!(input.key(up, &key, true, false, true), None, "no command for a movement key");
        assert!(!input.is_moving(), "egui had the keyboard: the press does not count");
        input.key(up, &key, true, false, false);
        input.key(PhysicalKey::Code(KeyCode::KeyA), &ch("a"), true, false, false);
        let ((forward, right, _), dt) = input.walk(t0 + Duration::from_millis(40));
        assert_eq!((forward, right), (1.0, -1.0), "forward and to the left");
        assert!((dt - 0.04).abs() < 1e-6, "the time since the last walk: {dt}");
        assert_eq!(input.walk(t0 + Duration::from_secs(5)).1, MAX_MOVE_STEP, "a stall does not jump");
        input.key(up, &key, false, false, true);
        assert_eq!(input.walk(t0 + Duration::from_secs(5)).0, (0.0, -1.0, 0.0), "a release always counts");
        input.focus_lost();
        assert!(!input.is_moving(), "losing focus releases every key");
        assert_eq!(input.key(up, &ch("m"), true, true, false), None, "a repeat is no command");
        assert_eq!(input.key(up, &ch("m"), true, false, true), None, "nor a key egui wants");
    }

    #[test]
    fn drags_turn_with_the_right_button_anywhere_and_the_left_one_off_the_panel() {
        let mut input = Input::new(Instant::now());
        let at = |x: f64, y: f64| PhysicalPosition::new(x, y);
        assert_eq!(input.cursor_moved(at(10.0, 10.0)), None, "no drag yet");
        input.mouse_button(MouseButton::Left, ElementState::Pressed, true);
        assert_eq!(input.cursor_moved(at(12.0, 10.0)), None, "the left button on the panel is the panel's");
        input.mouse_button(MouseButton::Left, ElementState::Pressed, false);
        assert_eq!(input.cursor_moved(at(15.0, 8.0)), Some((3.0, -2.0)), "the drag's step");
        assert!(input.is_moving(), "a drag is a movement");
        input.mouse_button(MouseButton::Left, ElementState::Released, false);
        assert_eq!(input.cursor_moved(at(20.0, 8.0)), None, "released");
        input.mouse_button(MouseButton::Right, ElementState::Pressed, true);
        input.cursor_left();
        assert_eq!(input.cursor_moved(at(0.0, 0.0)), None, "re-entering starts afresh");
        assert_eq!(input.cursor_moved(at(1.0, 0.0)), Some((1.0, 0.0)), "the right button turns over the panel too");
    }
}

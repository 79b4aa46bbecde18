//! Input handling: keys become [`Command`]s for the app, held movement keys walk the head,
//! and mouse drags turn it.
//!
//! Keys (ignored while egui has keyboard focus, e.g. typing a slider value): W/Up and Down
//! move the head forward and back, A/Left and D/Right sideways (held: `HEAD_SPEED` units a
//! second along the head's own axes, see `settings.rs`); R resets the head; 1, 2, 3 choose
//! side-by-side, cross-eyed, anaglyph; X swaps the eyes; M toggles the debug mask; Space
//! pauses the revolving spheres; S saves screenshots; Esc quits. Dragging with the right
//! mouse button, or the left one outside the panel, turns the head.

use std::time::Instant;

use stereo::Layout;
use winit::dpi::PhysicalPosition;
use winit::event::{ElementState, MouseButton};
use winit::keyboard::{Key, KeyCode, NamedKey, PhysicalKey};

/// Longest time step a held movement key advances the head by, so a stall does not jump.
const MAX_MOVE_STEP: f32 = 0.1;

/// What a key press asks the viewer to do.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Command {
    /// Esc: close the window.
    Quit,
    /// Space: pause or resume the revolving spheres.
    TogglePause,
    /// M: show or hide the debug mask.
    ToggleMask,
    /// S: save screenshots.
    Save,
    /// X: exchange the eyes.
    SwapEyes,
    /// R: put the head back where the scene has it.
    ResetHead,
    /// 1, 2, 3: arrange the eyes so.
    Layout(Layout),
}

impl Command {
    /// The command of a logical key (so letters follow the keyboard layout), if it has one.
    #[must_use]
    pub fn of_key(key: &Key) -> Option<Self> {
        match key {
            Key::Named(NamedKey::Escape) => Some(Self::Quit),
            Key::Named(NamedKey::Space) => Some(Self::TogglePause),
            Key::Character(c) if c.eq_ignore_ascii_case("m") => Some(Self::ToggleMask),
            Key::Character(c) if c.eq_ignore_ascii_case("s") => Some(Self::Save),
            Key::Character(c) if c.eq_ignore_ascii_case("x") => Some(Self::SwapEyes),
            Key::Character(c) if c.eq_ignore_ascii_case("r") => Some(Self::ResetHead),
            Key::Character(c) => {
                c.parse::<usize>().ok().and_then(|k| Layout::ALL.get(k.wrapping_sub(1))).map(|&l| Self::Layout(l))
            }
            _ => None,
        }
    }
}

/// Movement keys held down: forward, back, left, right.
#[derive(Clone, Copy, Debug, Default)]
struct HeldKeys([bool; 4]);

impl HeldKeys {
    /// The movement slot of a physical key (layout-independent, so W/A/D are where they are
    /// on a QWERTY keyboard), if it is one.
    fn slot(key: PhysicalKey) -> Option<usize> {
        match key {
            PhysicalKey::Code(KeyCode::KeyW | KeyCode::ArrowUp) => Some(0),
            PhysicalKey::Code(KeyCode::ArrowDown) => Some(1),
            PhysicalKey::Code(KeyCode::KeyA | KeyCode::ArrowLeft) => Some(2),
            PhysicalKey::Code(KeyCode::KeyD | KeyCode::ArrowRight) => Some(3),
            _ => None,
        }
    }

    /// (forward, right) in −1..=1.
    fn direction(self) -> (f32, f32) {
        let axis = |plus: bool, minus: bool| f32::from(u8::from(plus)) - f32::from(u8::from(minus));
        (axis(self.0[0], self.0[1]), axis(self.0[3], self.0[2]))
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
    /// command of a first press (not a repeat) that egui does not want.
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
        if pressed && !repeat && !egui_wants_keyboard {
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

    /// Whether the head is moving or turning (a movement key is held or a drag is on).
    #[must_use]
    pub fn is_moving(&self) -> bool {
        self.held.direction() != (0.0, 0.0) || self.drag.active
    }

    /// The held keys' direction (forward, right), each −1..=1, and the seconds since the last
    /// call (at most [`MAX_MOVE_STEP`]) to walk it for.
    pub fn walk(&mut self, now: Instant) -> ((f32, f32), f32) {
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
        assert_eq!(Command::of_key(&Key::Named(NamedKey::Escape)), Some(Command::Quit), "Esc quits");
        assert_eq!(Command::of_key(&Key::Named(NamedKey::Space)), Some(Command::TogglePause), "Space pauses");
        assert_eq!(Command::of_key(&ch("M")), Some(Command::ToggleMask), "M, either case");
        assert_eq!(Command::of_key(&ch("s")), Some(Command::Save), "S saves");
        assert_eq!(Command::of_key(&ch("x")), Some(Command::SwapEyes), "X swaps");
        assert_eq!(Command::of_key(&ch("r")), Some(Command::ResetHead), "R resets");
        for (k, layout) in Layout::ALL.into_iter().enumerate() {
            assert_eq!(Command::of_key(&ch(&(k + 1).to_string())), Some(Command::Layout(layout)), "{layout}");
        }
        for none in ["0", "4", "q"] {
            assert_eq!(Command::of_key(&ch(none)), None, "{none} does nothing");
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
        let ((forward, right), dt) = input.walk(t0 + Duration::from_millis(40));
        assert_eq!((forward, right), (1.0, -1.0), "forward and to the left");
        assert!((dt - 0.04).abs() < 1e-6, "the time since the last walk: {dt}");
        assert_eq!(input.walk(t0 + Duration::from_secs(5)).1, MAX_MOVE_STEP, "a stall does not jump");
        input.key(up, &key, false, false, true);
        assert_eq!(input.walk(t0 + Duration::from_secs(5)).0, (0.0, -1.0), "a release always counts");
        input.focus_lost();
        assert!(!input.is_moving(), "losing focus releases every key");
        assert_eq!(input.key(up, &ch("s"), true, true, false), None, "a repeat is no command");
        assert_eq!(input.key(up, &ch("s"), true, false, true), None, "nor a key egui wants");
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

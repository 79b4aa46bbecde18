//! Picking in the window: a left click without drag, off the panel, on either eye picks the
//! atom under the cursor; the picks are ringed and labelled in both eyes, a second pick
//! shows the distance and a third the angle; Esc or a click on empty space clears them.
//! Each click is logged on stderr (`pick: left eye pixel (400, 300): sphere 2981 H:GLN4
//! CD`), the line the window test compares with `stereotrace pick`.
//!
//! A click's window position becomes an eye and a pixel of the eye image as `present.rs`
//! lays the eyes out ([`eye_at`]); that pixel's primary ray, through the view of the pose
//! on screen at the eye size, is the one `stereotrace pick` traces for the same pixel, and
//! its closest hit the same sphere ([`crate::pick::closest_hit`]: every sphere tested, as
//! the window has no tracer of its own on its thread).
//!
//! **The stereo labels rule.** A ring and a label are drawn in each eye at the atom's own
//! projection in that eye ([`crate::pick::label_positions`]), never at one place for both:
//! their horizontal difference is then the atom's disparity, so they float at its depth
//! instead of at the screen's. They are drawn in the UI layer, after the timewarp, projected
//! through the pose the picture on screen shows (the warp's with the timewarp on), so they
//! stay on the atom while the head moves.

use egui::{Align2, Color32, FontId, Pos2, Stroke};
use glam::{Vec2, Vec3};
use stereo::Layout;
use tracer::{Camera, Eye, Scene};

use crate::pick::{angle, atom_of, closest_hit, distance, label_positions};
use crate::window::present::{eye_size, Look};

/// Picks kept at most: the third shows the angle; a fourth starts afresh.
const MAX_PICKS: usize = 3;

/// How far (physical pixels) the cursor may move between press and release for a click.
const CLICK_SLOP: f64 = 4.0;

/// One picked sphere: where it is, and what the file says of it.
#[derive(Clone, Debug, PartialEq)]
pub struct Picked {
    /// Its object id (the scene's spheres, then each structure's atoms).
    pub object: u32,
    /// Its centre (scene space) and radius.
    pub centre: Vec3,
    /// Its radius.
    pub radius: f32,
    /// The short label drawn beside it: `H:GLN4 NE2`, or `sphere 3`.
    pub label: String,
    /// The panel's lines: residue, atom, element, B-factor, occupancy, coordinates.
    pub lines: Vec<String>,
    /// Where distances and angles are measured from: the file's coordinates of an atom, the
    /// centre of a sphere that is not one.
    pub measured_at: [f32; 3],
}

/// The picks, the label toggle, and a click under way.
#[derive(Clone, Debug)]
pub struct Picks {
    /// The picked spheres, in the order picked.
    pub picked: Vec<Picked>,
    /// Labels (and the distance on its line) are drawn; the rings always are.
    pub labels: bool,
    /// Where the left button went down off the panel, while it may still be a click.
    press: Option<(f64, f64)>,
}

impl Default for Picks {
    fn default() -> Self {
        Self { picked: Vec::new(), labels: true, press: None }
    }
}

/// The eye under window position (x, y) (physical pixels) and its pixel in the
/// `eye_size` image, as `present.rs` lays out `look` in a `window`-sized buffer; `None`
/// off the eyes. In the anaglyph both eyes are in the one centred image: the left eye's
/// pixel is taken.
#[must_use]
pub fn eye_at(window: (u32, u32), look: Look, (x, y): (f64, f64)) -> Option<(Eye, (u32, u32))> {
    let (ew, eh) = eye_size(window.0, window.1);
    if ew == 0 || x < 0.0 || y < 0.0 || y >= f64::from(eh) {
        return None;
    }
    let (col, row) = (x.floor() as u32, y.floor() as u32);
    if look.layout == Layout::Anaglyph {
        let margin = ew / 2;
        return (margin..margin + ew).contains(&col).then(|| (Eye::Left, (col - margin, row)));
    }
    let slot = (col / ew) as usize;
    let eye = *look.layout.slots(look.swap).get(slot)?;
    Some((eye, (col - slot as u32 * ew, row)))
}

/// The window column where `eye`'s image starts, as [`eye_at`] lays it out.
#[must_use]
pub fn eye_left_edge(window: (u32, u32), look: Look, eye: Eye) -> u32 {
    let (ew, _) = eye_size(window.0, window.1);
    if look.layout == Layout::Anaglyph {
        return ew / 2;
    }
    if look.layout.slots(look.swap)[0] == eye {
        0
    } else {
        ew
    }
}

/// What is shown of sphere `object` of `scene` at `time`.
#[must_use]
pub fn describe(scene: &Scene, time: f32, object: u32) -> Picked {
    let sphere = scene.sphere_at(object as usize, time);
    let atom = atom_of(scene, object as usize).and_then(|(s, k)| scene.structures[s].atom(k));
    let Some(a) = atom else {
        return Picked {
            object,
            centre: sphere.center,
            radius: sphere.radius,
            label: format!("sphere {object}"),
            lines: vec![format!("sphere {object}, radius {}", sphere.radius)],
            measured_at: sphere.center.to_array(),
        };
    };
    let number = a.residue_number.map(|n| n.to_string()).unwrap_or_default();
    let code = a.insertion_code.map(String::from).unwrap_or_default();
    let or_dash = |v: Option<f32>| v.map_or_else(|| "-".to_owned(), |v| v.to_string());
    let [x, y, z] = a.file_position;
    Picked {
        object,
        centre: sphere.center,
        radius: sphere.radius,
        label: format!("{}:{}{number}{code} {}", a.chain, a.residue_name, a.name),
        lines: vec![
            format!("chain {}  {} {number}{code}{}", a.chain, a.residue_name, if a.hetero { "  HETATM" } else { "" }),
            format!("atom {}  element {}", a.name, a.element.symbol()),
            format!("B-factor {}  occupancy {}", or_dash(a.b_factor), or_dash(a.occupancy)),
            format!("file x, y, z: {x:.3}, {y:.3}, {z:.3}"),
        ],
        measured_at: a.file_position,
    }
}

impl Picks {
    /// The left button went down (`pressed`) or up at `at`, off the panel unless
    /// `on_panel`. Returns the position of a click: a release near its press.
    pub fn button(&mut self, pressed: bool, on_panel: bool, at: Option<(f64, f64)>) -> Option<(f64, f64)> {
        if pressed {
            self.press = if on_panel { None } else { at };
            return None;
        }
        let press = self.press.take()?;
        at.filter(|&(x, y)| (x - press.0).hypot(y - press.1) <= CLICK_SLOP)
    }

    /// A click at window position `at` over a `window`-sized buffer showing `look`, the
    /// picture being of `camera` at scene time `time`: picks the sphere under it, or
    /// clears the picks on empty space. Returns the eye and pixel clicked and the sphere
    /// picked there (`None`: empty space), or `None` off the eyes.
    pub fn click(
        &mut self,
        (scene, time, camera): (&Scene, f32, &Camera),
        window: (u32, u32),
        look: Look,
        at: (f64, f64),
    ) -> Option<(Eye, (u32, u32), Option<u32>)> {
        let (eye, (i, j)) = eye_at(window, look, at)?;
        let (w, h) = eye_size(window.0, window.1);
        let ray = camera.view(eye, w, h).primary_ray(i, j);
        let object = closest_hit(scene, time, &ray).map(|(object, _)| object);
        if let Some(object) = object {
            if self.picked.len() == MAX_PICKS {
                self.picked.clear();
            }
            self.picked.push(describe(scene, time, object));
        } else {
            self.clear();
        }
        Some((eye, (i, j), object))
    }

    /// Esc or a click on empty space: forgets the picks. Returns whether there were any.
    pub fn clear(&mut self) -> bool {
        let had = !self.picked.is_empty();
        self.picked.clear();
        had
    }

    /// The distance between the first two picks (Å between atoms' file positions).
    #[must_use]
    pub fn distance(&self) -> Option<f64> {
        match self.picked.as_slice() {
            [a, b, ..] => Some(distance(a.measured_at, b.measured_at)),
            _ => None,
        }
    }

    /// The angle at the second pick between the first and the third, degrees.
    #[must_use]
    pub fn angle(&self) -> Option<f64> {
        match self.picked.as_slice() {
            [a, b, c] => Some(angle(a.measured_at, b.measured_at, c.measured_at)),
            _ => None,
        }
    }

    /// The picks' small window: each pick's fields, the distance and the angle, and the
    /// label toggle. Shown while there are picks.
    pub fn panel(&mut self, ctx: &egui::Context) {
        if self.picked.is_empty() {
            return;
        }
        egui::Window::new("picks").anchor(Align2::RIGHT_BOTTOM, [-8.0, -8.0]).resizable(false).collapsible(true).show(
            ctx,
            |ui| {
                for (k, p) in self.picked.iter().enumerate() {
                    ui.strong(format!("{} {}", k + 1, p.label));
                    for line in &p.lines {
                        ui.label(line);
                    }
                }
                if let Some(d) = self.distance() {
                    ui.strong(format!("distance 1–2: {d:.2} Å"));
                }
                if let Some(a) = self.angle() {
                    ui.strong(format!("angle 1–2–3: {a:.1}°"));
                }
                ui.horizontal(|ui| {
                    ui.checkbox(&mut self.labels, "labels");
                    if ui.button("clear (Esc)").clicked() {
                        self.picked.clear();
                    }
                });
            },
        );
    }

    /// Rings, labels and the distance line over both eyes, each at the atom's projection
    /// in that eye through `camera` (the pose on screen), for a `window`-sized buffer
    /// showing `look` at `pixels_per_point`.
    pub fn draw(&self, ctx: &egui::Context, camera: &Camera, window: (u32, u32), look: Look) {
        let size = eye_size(window.0, window.1);
        if self.picked.is_empty() || size.0 == 0 {
            return;
        }
        let painter = ctx.layer_painter(egui::LayerId::new(egui::Order::Foreground, egui::Id::new("picks")));
        let ppp = ctx.pixels_per_point();
        // Per eye: the ring colour (the anaglyph's eyes in their filters' colours).
        let anaglyph = look.layout == Layout::Anaglyph;
        let colour = |eye: Eye| match (anaglyph, eye) {
            (false, _) => Color32::from_rgb(255, 220, 60),
            (true, Eye::Left) => Color32::from_rgb(255, 40, 40),
            (true, Eye::Right) => Color32::from_rgb(40, 230, 230),
        };
        let mut at = [[None::<(Pos2, f32)>; MAX_PICKS]; 2];
        for (k, p) in self.picked.iter().enumerate() {
            let Some(pos) = label_positions(camera, size, p.centre) else { continue };
            // The ring's radius: the sphere's radius across, at its centre's depth.
            let side = camera.world_from_head() * Vec3::new(p.radius, 0.0, 0.0);
            let edge = label_positions(camera, size, p.centre + side);
            for (e, eye) in [Eye::Left, Eye::Right].into_iter().enumerate() {
                let x0 = eye_left_edge(window, look, eye) as f32;
                let to_points = |v: Vec2| Pos2::new((v.x + x0) / ppp, v.y / ppp);
                let centre = to_points(pos[e]);
                let r = edge.map_or(6.0, |edge| (edge[e] - pos[e]).length() / ppp).max(4.0);
                painter.circle_stroke(centre, r + 1.5, Stroke::new(2.0, colour(eye)));
                at[e][k] = Some((centre, r));
                if self.labels {
                    let anchor = centre + egui::vec2(r + 4.0, -r - 2.0);
                    painter.text(anchor, Align2::LEFT_BOTTOM, &p.label, FontId::proportional(14.0), colour(eye));
                }
            }
        }
        for (e, eye) in [Eye::Left, Eye::Right].into_iter().enumerate() {
            if let (Some((a, _)), Some((b, _))) = (at[e][0], at[e][1]) {
                painter.line_segment([a, b], Stroke::new(1.5, colour(eye)));
                if let (true, Some(d)) = (self.labels, self.distance()) {
                    let mid = a + (b - a) * 0.5 - egui::vec2(0.0, 3.0);
                    painter.text(
                        mid,
                        Align2::CENTER_BOTTOM,
                        format!("{d:.2} Å"),
                        FontId::proportional(14.0),
                        colour(eye),
                    );
                }
            }
            if let (Some((_, _)), Some((b, _)), Some((c, _))) = (at[e][0], at[e][1], at[e][2]) {
                painter.line_segment([b, c], Stroke::new(1.5, colour(eye)));
                if let (true, Some(a)) = (self.labels, self.angle()) {
                    painter.text(b, Align2::CENTER_TOP, format!("{a:.1}°"), FontId::proportional(14.0), colour(eye));
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use tracer::testing::XorShift;
    use tracer::Tracer;

    fn look(layout: Layout, swap: bool) -> Look {
        Look { layout, swap, show_mask: false }
    }

    #[test]
    fn a_window_position_is_an_eye_and_its_pixel_as_the_eyes_are_laid_out() {
        // 21 × 8: eyes of 10 × 8, a spare column at x = 20.
        let sbs = look(Layout::SideBySide, false);
        assert_eq!(eye_at((21, 8), sbs, (0.0, 0.0)), Some((Eye::Left, (0, 0))));
        assert_eq!(eye_at((21, 8), sbs, (9.9, 7.5)), Some((Eye::Left, (9, 7))));
        assert_eq!(eye_at((21, 8), sbs, (10.0, 3.2)), Some((Eye::Right, (0, 3))));
        assert_eq!(eye_at((21, 8), sbs, (20.5, 3.0)), None, "the spare column");
        assert_eq!(eye_at((21, 8), sbs, (5.0, 8.0)), None, "below the eyes");
        assert_eq!(eye_at((21, 8), sbs, (-0.5, 1.0)), None, "left of them");
        assert_eq!(eye_at((21, 8), look(Layout::CrossEyed, false), (1.0, 1.0)), Some((Eye::Right, (1, 1))));
        assert_eq!(eye_at((21, 8), look(Layout::SideBySide, true), (12.0, 1.0)), Some((Eye::Left, (2, 1))));
        let ana = look(Layout::Anaglyph, false);
        assert_eq!(eye_at((21, 8), ana, (4.0, 1.0)), None, "the anaglyph's margin");
        assert_eq!(eye_at((21, 8), ana, (5.0, 1.0)), Some((Eye::Left, (0, 1))), "centred at a quarter");
        assert_eq!(eye_at((1, 1), sbs, (0.0, 0.0)), None, "no eye in a 1 × 1 window");
        // The edges drawn from agree with the positions picked.
        for l in [sbs, look(Layout::CrossEyed, false), look(Layout::SideBySide, true), ana] {
            for eye in [Eye::Left, Eye::Right] {
                let x0 = eye_left_edge((21, 8), l, eye);
                let (got, pixel) = eye_at((21, 8), l, (f64::from(x0) + 3.5, 2.0)).unwrap();
                assert_eq!(pixel, (3, 2), "{l:?} {eye:?}");
                assert!(got == eye || l.layout == Layout::Anaglyph, "{l:?} {eye:?}");
            }
        }
    }

    /// The picks window, headless (egui_kittest): each pick's fields, the distance and
    /// the angle; the labels tick and the clear button.
    #[test]
    fn the_picks_window_shows_the_fields_and_the_measures() {
        use egui_kittest::kittest::Queryable as _;
        let atom = |k: u32, at: [f32; 3]| Picked {
            object: k,
            centre: Vec3::from(at),
            radius: 1.0,
            label: format!("A:GLY{k} CA"),
            lines: vec![format!("B-factor {k}.5  occupancy 1")],
            measured_at: at,
        };
        let picks = Picks {
            picked: vec![atom(1, [1.0, 0.0, 0.0]), atom(2, [0.0; 3]), atom(3, [0.0, 2.0, 0.0])],
            ..Picks::default()
        };
        let mut harness = egui_kittest::Harness::builder()
            .with_size(egui::vec2(800.0, 600.0))
            .build_ui_state(|ui, picks: &mut Picks| picks.panel(ui.ctx()), picks);
        harness.run();
        for text in
            ["1 A:GLY1 CA", "3 A:GLY3 CA", "B-factor 2.5  occupancy 1", "distance 1–2: 1.00 Å", "angle 1–2–3: 90.0°"]
        {
            let _ = harness.get_by_label(text);
        }
        harness.get_by_label("labels").click();
        harness.run();
        assert!(!harness.state().labels, "the tick hides the labels");
        harness.get_by_label("clear (Esc)").click();
        harness.run();
        assert!(harness.state().picked.is_empty(), "the button clears the picks");
    }

    #[test]
    fn a_click_is_a_release_near_its_press_off_the_panel() {
        let mut p = Picks::default();
        assert_eq!(p.button(true, false, Some((10.0, 10.0))), None, "a press is no click yet");
        assert_eq!(p.button(false, false, Some((12.0, 13.0))), Some((12.0, 13.0)), "released 3.6 px away");
        p.button(true, false, Some((10.0, 10.0)));
        assert_eq!(p.button(false, false, Some((15.0, 10.0))), None, "a drag turns the head");
        p.button(true, true, Some((10.0, 10.0)));
        assert_eq!(p.button(false, false, Some((10.0, 10.0))), None, "pressed on the panel");
        assert_eq!(p.button(false, false, Some((10.0, 10.0))), None, "a release without a press");
    }

    /// The window picks, at a pixel of either eye, the very sphere `stereotrace pick` reports
    /// there: the closest hit of the same primary ray, through the tracer there and every
    /// sphere here. Then a second and a third pick measure, and empty space clears.
    #[test]
    fn a_click_picks_what_pick_reports_at_that_pixel_and_measures() {
        let path = std::path::Path::new("/usr/share/pymol/data/demo/1tii.pdb");
        if !path.is_file() {
            tracer::testing::skipped("1tii.pdb is not installed");
            return;
        }
        let scene = Scene::load(path).unwrap();
        let tracer = Tracer::new(&scene, 0.0);
        // A wide IPD, so that the eyes' rays through a pixel part well before the molecule.
        let camera = Camera { ipd: 40.0, ..scene.camera };
        let window = (2 * 160 + 1, 120);
        let (w, h) = eye_size(window.0, window.1);
        let sbs = look(Layout::SideBySide, false);
        let mut rng = XorShift::new(7);
        let mut picked = 0;
        for k in 0..60 {
            let (x, y) = (rng.below(window.0 as usize - 1), rng.below(window.1 as usize));
            let mut picks = Picks::default();
            let clicked = picks.click((&scene, 0.0, &camera), window, sbs, (x as f64 + 0.5, y as f64 + 0.5));
            let (eye, (i, j), object) = clicked.unwrap();
            let ray = camera.view(eye, w, h).primary_ray(i, j);
            let want = tracer.intersect(&ray, f32::INFINITY).map(|hit| hit.object);
            assert_eq!(object, want, "click {k} at ({x}, {y}): {eye:?} ({i}, {j})");
            assert_eq!(picks.picked.len(), usize::from(want.is_some()));
            picked += usize::from(want.is_some());
        }
        assert!(picked > 10, "enough hits to mean something: {picked}");
        let mut picks = Picks::default();
        let centre = (f64::from(w) / 2.0, f64::from(h) / 2.0);
        for dx in [0.0, 6.0, -6.0] {
            picks.click((&scene, 0.0, &scene.camera), window, sbs, (centre.0 + dx, centre.1));
        }
        assert_eq!(picks.picked.len(), 3, "three picks");
        let [a, b, c] = [0, 1, 2].map(|k| picks.picked[k].measured_at);
        assert_eq!(picks.distance(), Some(distance(a, b)));
        assert_eq!(picks.angle(), Some(angle(a, b, c)));
        assert!(picks.picked[0].label.contains(':'), "chain:residue atom: {}", picks.picked[0].label);
        picks.click((&scene, 0.0, &scene.camera), window, sbs, (0.5, 0.5));
        assert!(picks.picked.is_empty(), "a click on empty space clears");
    }
}

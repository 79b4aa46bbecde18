//! How the window colours its structures, which atoms it hides and its cues ([`AtomLook`]:
//! `--color`, `--hide`, `--ao-samples`…, the panel's "colour" section and the C key), and
//! how the render worker takes a new look ([`Looked`]): a new colouring or new cues
//! recolour the tracer without rebuilding its BVH (`Tracer::recolor` takes the cues too);
//! hidden atoms leave the scene, which is rebuilt.

use tracer::{ColorBy, Coloring, Cues, DepthCueMode, Hide, Scene, OUTLINE_MAX, STRUCTURE_AO_SAMPLES};

use crate::args::LookArgs;

/// The colouring and the hidden atoms the window asks for.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct AtomLook {
    /// `None`: the scene's own colours (as loaded, TOML `color_by` included).
    pub coloring: Option<Coloring>,
    /// The atoms out of the scene.
    pub hide: Hide,
    /// The panel's cues; `None`: the scene's own.
    pub cues: Option<CueLook>,
}

/// The panel's cue controls: ambient occlusion on or off and its strength, depth cueing on
/// or off, the outline width.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CueLook {
    /// Ambient occlusion on (with the scene's rays a hit, or 8 where it had none).
    pub ambient_occlusion: bool,
    /// Its strength, 0 to 1.
    pub strength: f32,
    /// Depth cueing on (the scene's mode, or Exp2).
    pub depth_cue: bool,
    /// Outline width, pixels.
    pub outline: u32,
}

impl CueLook {
    /// The controls as `cues` set them.
    #[must_use]
    pub fn of(cues: &Cues) -> Self {
        Self {
            ambient_occlusion: cues.ambient_occlusion.is_on(),
            strength: cues.ambient_occlusion.strength,
            depth_cue: cues.depth_cue.mode != DepthCueMode::Off,
            outline: cues.outline,
        }
    }

    /// `cues` (a scene's, sized) as these controls set them.
    #[must_use]
    pub fn applied(&self, mut cues: Cues) -> Cues {
        let ao = &mut cues.ambient_occlusion;
        ao.samples = match (self.ambient_occlusion, ao.samples) {
            (false, _) => 0,
            (true, 0) => STRUCTURE_AO_SAMPLES,
            (true, n) => n,
        };
        ao.strength = self.strength;
        cues.depth_cue.mode = match (self.depth_cue, cues.depth_cue.mode) {
            (false, _) => DepthCueMode::Off,
            (true, DepthCueMode::Off) => DepthCueMode::Exp2,
            (true, mode) => mode,
        };
        cues.outline = self.outline;
        cues
    }
}

impl AtomLook {
    /// The look the command line asks for.
    #[must_use]
    pub fn from_args(args: &LookArgs) -> Self {
        Self { coloring: args.coloring(), hide: args.hide.unwrap_or_default(), cues: None }
    }

    /// The scheme shown (element for the scene's own).
    #[must_use]
    pub fn scheme(&self) -> ColorBy {
        self.coloring.map_or(ColorBy::Element, |c| c.by)
    }

    /// Sets the scheme, keeping the B-factor range.
    pub fn set_scheme(&mut self, by: ColorBy) {
        let range = self.coloring.and_then(|c| c.range);
        self.coloring = Some(Coloring { by, range });
    }

    /// The C key: the next scheme.
    pub fn cycle(&mut self) {
        self.set_scheme(self.scheme().next());
    }
}

/// What taking a look changed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Change {
    /// Nothing.
    None,
    /// Only colours: the tracer is recoloured ([`tracer::Tracer::recolor`]).
    Colors,
    /// Atoms left or came back: the tracer is rebuilt.
    Atoms,
}

/// The render worker's side: the look its scene has, and while atoms are hidden the whole
/// scene they were hidden from (nothing kept otherwise, so a large structure is not held
/// twice).
#[derive(Debug, Default)]
pub struct Looked {
    look: AtomLook,
    whole: Option<Scene>,
}

impl Looked {
    /// `scene` (whose look this is) given `want`; says what changed.
    pub fn apply(&mut self, scene: &mut Scene, want: AtomLook) -> Change {
        if want == self.look {
            return Change::None;
        }
        let change = if want.hide == self.look.hide {
            // New colours or cues alike: no structure changes.
            Change::Colors
        } else {
            let whole = match self.whole.take() {
                Some(whole) => whole,
                None => std::mem::take(scene),
            };
            if want.hide.is_empty() {
                *scene = whole;
            } else {
                *scene = whole.hidden(want.hide);
                self.whole = Some(whole);
            }
            Change::Atoms
        };
        // The scene's own colours back: element colours (the TOML's `color_by` is not kept).
        if want.coloring.is_some() || self.look.coloring.is_some() {
            scene.recolor(&want.coloring.unwrap_or_default());
        }
        if let Some(cues) = want.cues {
            scene.render.cues = cues.applied(scene.render.cues);
        }
        self.look = want;
        change
    }
}

/// The panel's "colour" section: the scheme's combo box and the hiding ticks. Returns
/// whether anything changed.
pub fn look_ui(ui: &mut egui::Ui, look: &mut AtomLook) -> bool {
    let before = *look;
    let mut by = look.scheme();
    egui::ComboBox::from_label("colour (C)").selected_text(by.name()).show_ui(ui, |ui| {
        for scheme in ColorBy::ALL {
            ui.selectable_value(&mut by, scheme, scheme.name());
        }
    });
    if by != look.scheme() {
        look.set_scheme(by);
    }
    ui.horizontal(|ui| {
        ui.label("hide");
        ui.checkbox(&mut look.hide.water, "water");
        ui.checkbox(&mut look.hide.hydrogen, "H");
        ui.checkbox(&mut look.hide.hetero, "hetero");
    });
    if let Some(cues) = &mut look.cues {
        ui.horizontal(|ui| {
            ui.checkbox(&mut cues.ambient_occlusion, "occlusion");
            ui.add_enabled(cues.ambient_occlusion, egui::Slider::new(&mut cues.strength, 0.0..=1.0).text("strength"));
        })
        .response
        .on_hover_text("ray-traced ambient occlusion: the ambient light a point gets from the open sky around it");
        ui.checkbox(&mut cues.depth_cue, "depth cue")
            .on_hover_text("colours fade towards the background with distance");
        ui.add(egui::Slider::new(&mut cues.outline, 0..=OUTLINE_MAX).text("outline px"));
    }
    *look != before
}

#[cfg(test)]
mod tests {
    use super::*;
    use tracer::{Tracer, WATER_NAMES};

    fn tii() -> Scene {
        Scene::load("/usr/share/pymol/data/demo/1tii.pdb").unwrap()
    }

    #[test]
    fn a_new_colouring_recolours_and_hiding_rebuilds_and_comes_back() {
        let mut scene = tii();
        let atoms = scene.sphere_count();
        let mut looked = Looked::default();
        let chain = AtomLook {
            coloring: Some(Coloring { by: ColorBy::Chain, range: None }),
            hide: Hide::default(),
            cues: None,
        };
        assert_eq!(looked.apply(&mut scene, chain), Change::Colors);
        assert_eq!(looked.apply(&mut scene, chain), Change::None);
        let hide = Hide { hydrogen: true, water: true, hetero: false };
        assert_eq!(looked.apply(&mut scene, AtomLook { hide, ..chain }), Change::Atoms);
        assert!(scene.sphere_count() < atoms, "waters hidden");
        let water = |s: &Scene| {
            let st = &s.structures[0];
            (0..st.positions.len()).any(|k| WATER_NAMES.contains(&st.atom(k).unwrap().residue_name))
        };
        assert!(!water(&scene));
        assert_eq!(looked.apply(&mut scene, chain), Change::Atoms);
        assert_eq!(scene.sphere_count(), atoms, "all back");
        assert!(water(&scene));
        // The recolour path gives what a tracer built afresh on the recoloured scene has.
        let mut tracer = Tracer::new(&scene, 0.0);
        let rainbow = AtomLook { coloring: Some(Coloring { by: ColorBy::Rainbow, range: None }), ..chain };
        assert_eq!(looked.apply(&mut scene, rainbow), Change::Colors);
        tracer.recolor(&scene);
        let fresh = Tracer::new(&scene, 0.0);
        for k in (0..atoms).step_by(7) {
            assert_eq!(tracer.snapshot().material(k), fresh.snapshot().material(k), "atom {k}");
        }
    }

    #[test]
    fn the_panels_cues_reach_the_tracer_without_a_rebuild() {
        let mut scene = tii();
        assert!(scene.render.cues.ambient_occlusion.is_on(), "a structure opens with its cues on");
        let mut looked = Looked::default();
        let mut tracer = Tracer::new(&scene, 0.0);
        let mut cues = CueLook::of(&scene.render.cues);
        assert!(cues.ambient_occlusion && cues.depth_cue && cues.outline == 1);
        cues.ambient_occlusion = false;
        cues.outline = 3;
        let look = AtomLook { cues: Some(cues), ..AtomLook::default() };
        assert_eq!(looked.apply(&mut scene, look), Change::Colors, "no atom changes");
        tracer.recolor(&scene);
        let settings = tracer.settings().cues;
        assert_eq!((settings.ambient_occlusion.samples, settings.outline), (0, 3));
        cues.ambient_occlusion = true;
        looked.apply(&mut scene, AtomLook { cues: Some(cues), ..look });
        assert_eq!(scene.render.cues.ambient_occlusion.samples, STRUCTURE_AO_SAMPLES, "back on with 8 rays");
    }
}

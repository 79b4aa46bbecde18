//! A stereo pair's outlines (`tracer`'s `cue/outline.rs`), each eye's drawn from that eye's
//! own first hits onto a copy of its colours: the frame keeps its own colours as traced (a
//! reused frame starts from them), and a right eye made by reprojection is outlined exactly
//! as a fully traced one, since both eyes' planes are their own views' whatever the mode.
//! The planes are the frame's where it kept them ([`StereoFrame::first_hits`]: the left
//! film's, and, in a frame that keeps depths, the right eye's, made by its own pass in full
//! and exact modes and by a first-hits pass in copy and reshade), else a first-hits pass of
//! their own ([`tracer::first_hits`]): the same values, bit for bit. The lines go onto the
//! copy as it is made ([`tracer::outline_from`]).

use tracer::{first_hits, outline_from, Eye, Outline, Renderer, Tracer};

use crate::frame::StereoFrame;

/// The outlined eyes of a pair, and the planes they were drawn from, kept from frame to
/// frame.
#[derive(Clone, Debug)]
pub struct Outlined {
    rgb: [Vec<u32>; 2],
    /// How much of an outlined pixel's light the lines take ([`Outline::ink`]).
    ink: f32,
    /// Traces the planes (its screen bins kept).
    renderer: Renderer,
    object: Vec<u32>,
    z: Vec<f32>,
}

impl Default for Outlined {
    fn default() -> Self {
        Self { rgb: Default::default(), ink: 1.0, renderer: Renderer::new(), object: Vec::new(), z: Vec::new() }
    }
}

impl Outlined {
    /// Empty buffers; black lines.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Lines that take `ink` of an outlined pixel's light ([`Outline::ink`]; 1, black, is
    /// the default) from the next frame drawn on.
    pub fn set_ink(&mut self, ink: f32) {
        self.ink = ink;
    }

    /// `frame`'s eyes (traced by `tracer`) with outlines `width` pixels of the traced eyes
    /// wide (for a frame supersampled S × S, the shown width times S); the frame's own
    /// colours when `width` is 0.
    pub fn eyes<'a>(&'a mut self, tracer: &Tracer, frame: &'a StereoFrame, width: f32) -> [&'a [u32]; 2] {
        if width <= 0.0 {
            return [&frame.left().rgb, &frame.right().rgb];
        }
        for eye in [Eye::Left, Eye::Right] {
            self.draw(tracer, frame, eye, width);
        }
        [&self.rgb[0], &self.rgb[1]]
    }

    /// The eyes the last [`Outlined::eyes`] drew for `frame` with `width`, without drawing
    /// them again: the frame's own colours when `width` is 0.
    #[must_use]
    pub fn drawn<'a>(&'a self, frame: &'a StereoFrame, width: f32) -> [&'a [u32]; 2] {
        if width <= 0.0 {
            return [&frame.left().rgb, &frame.right().rgb];
        }
        [&self.rgb[0], &self.rgb[1]]
    }

    /// Draws `eye`'s outlines ([`Outlined::eyes`]), into this eye's copy of its colours.
    pub fn draw(&mut self, tracer: &Tracer, frame: &StereoFrame, eye: Eye, width: f32) {
        let (k, rgb) = match eye {
            Eye::Left => (0, &frame.left().rgb),
            Eye::Right => (1, &frame.right().rgb),
        };
        let view = frame.views().eyes[k];
        // (Every pixel is written below: the copy is made with the lines.)
        self.rgb[k].resize(rgb.len(), 0);
        let (object, z) = if let Some(planes) = frame.first_hits(eye) {
            planes
        } else {
            first_hits(&mut self.renderer, tracer, &view, &mut self.object, &mut self.z);
            (&self.object[..], &self.z[..])
        };
        let size = (view.width, view.height);
        let style = Outline { ink: self.ink, ..Outline::of_view(&view, width) };
        outline_from(rgb, &mut self.rgb[k], object, z, size, style);
    }
}

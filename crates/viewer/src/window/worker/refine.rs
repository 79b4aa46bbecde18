//! The progressive policy's refinement while the head rests: the pose's pair at S × S
//! samples a pixel, traced one sample of every pixel per pass, and shown after each pass as
//! the mean of the samples so far.
//!
//! The samples are those of `render --supersample S`: the pixels of the pair's views at
//! (W·S) × (H·S) (`stereo::StereoViews`, the one place views are made), pass (sx, sy) tracing
//! the pixels (x·S + sx, y·S + sy). Each pass is a [`Renderer::render`] of those pixels
//! ([`Pixels::Only`]) into the sample image, so a sample is the very bytes a render of
//! every sample makes. Both eyes are traced in full: in `full` mode that is what the
//! render does, and `exact` mode's right eye is full's bit for bit (stereo's tests). When
//! the last pass is done, each eye is [`stereo::downsample`]d, the box filter in linear
//! light `render` uses, so the converged pair equals `render --supersample S` byte for byte.
//! Before that, a pixel shows the mean in linear light of the samples traced so far.
//!
//! The passes go in an order that spreads each prefix over the pixel (the S × S grid's
//! positions ranked as in an ordered dither's matrix, Bayer 1973, for S a power of two; a
//! spread of the rows otherwise), the jittered supersampling of interactive tracers,
//! converging to the regular grid the filter expects.
//!
//! A pass is traced in parts, bands of the eye's rows, each about [`PART_MS`] by the last
//! pass's time: the worker looks for a new request between parts, so a head that starts
//! to move waits for a part, not for a pass (a pass of 2BTV's assembly at 800 × 600 takes
//! seconds). Only a whole pass is shown.
//!
//! While spheres orbit, a new instant of the scene does not restart the refinement: only
//! the samples that can have changed are traced again, by temporal reuse's marks
//! (`follow.rs`), and the rest keep accumulating.
//!
//! Memory: the sample images, 4 · S² bytes per eye pixel and eye, the running sums, 12
//! bytes per eye pixel and eye, and one bit per sample for the pass's selection: 152 bytes
//! a pixel of both eyes at S = 4; while following orbiting spheres, also their marks,
//! 12.25 bytes a sample (392 bytes a pixel of both eyes at S = 4).

mod follow;

use std::time::Instant;

use rayon::prelude::*;
use stereo::StereoViews;
use tracer::{Camera, PixelBits, Pixels, Renderer, Scene, Tracer};

use follow::Follow;

/// Bytes a pixel of both eyes the refinement keeps at S × S samples a pixel, following
/// orbiting spheres or not (the module doc): what the memory check weighs.
#[must_use]
pub fn bytes_per_pixel(s: u32, following: bool) -> u64 {
    let samples = u64::from(s * s);
    2 * (4 * samples + 12) + if following { 2 * samples * 13 } else { 0 }
}

/// Largest S the viewer refines to (`--max-supersample`): 8 × 8 samples a pixel.
pub const MAX_SUPERSAMPLE: u32 = 8;

/// About how long a part of a pass takes (module doc): a new request waits at most about
/// this for the worker.
const PART_MS: f64 = 50.0;

/// Most parts a pass is cut into.
const MAX_PARTS: u32 = 32;

/// One resting pose's refinement, its buffers kept from pose to pose.
#[derive(Debug, Default)]
pub struct Refine {
    /// Samples per pixel along each axis.
    s: u32,
    /// The eye size.
    eye: (u32, u32),
    /// The views at the samples' size, and at the eye size.
    views: Option<StereoViews>,
    shown_views: Option<StereoViews>,
    /// Each eye's samples, (W·S) × (H·S).
    samples: [Vec<u32>; 2],
    /// The pass's selection of samples.
    bits: PixelBits,
    /// One renderer for both eyes: its screen bins are built for each pass's view anyway,
    /// and one set of them is what a 2.9-million-sphere scene can spare.
    renderer: Renderer,
    /// The sub-pixel positions in the order they are traced.
    order: Vec<(u32, u32)>,
    /// Passes done.
    done: usize,
    /// The pass being traced is in `parts` parts (bands of eye rows), `part` of them done,
    /// in `part_ms` so far; the last whole pass took `pass_ms`.
    parts: u32,
    part: u32,
    part_ms: f64,
    pass_ms: f64,
    /// Outlines this many pixels of the eye wide (0: none), and each eye's first hits at
    /// the eye size (object, depth) they are drawn from before the pair converges.
    outline: u32,
    planes: [(Vec<u32>, Vec<f32>); 2],
    /// The samples have their outlines (drawn once, when the pair converges), and the
    /// first hits at the samples' size they are drawn from, one eye at a time.
    outlined: bool,
    sample_planes: (Vec<u32>, Vec<f32>),
    /// Each eye's per-pixel sums in linear light of the samples of the first `summed`
    /// passes.
    sums: [Vec<[f32; 3]>; 2],
    summed: usize,
    /// The marks that let the samples follow the scene's time.
    follow: Follow,
    /// Each eye as last shown, but for the pixels with a stale sample, and the passes and
    /// convergence it shows (`None`: to be made again).
    picture: [Vec<u32>; 2],
    picture_of: Option<(usize, bool)>,
}

impl Refine {
    /// Starts refining the pair of `camera` at an eye of `eye` to `s` × `s` samples a pixel,
    /// with outlines `outline` pixels wide; the pair took `frame_ms` to trace at one sample a
    /// pixel, about what a pass takes. With `follow` (the scene, whose orbiting spheres the
    /// samples then follow, and the tracer at its instant), a new instant traces again only
    /// what can have changed ([`Refine::advance`]); outlines are drawn from first hits the
    /// marks do not follow, so with them the samples do not.
    pub fn start(
        &mut self,
        camera: &Camera,
        eye: (u32, u32),
        (s, outline): (u32, u32),
        frame_ms: f64,
        follow: Option<(&Scene, &Tracer)>,
    ) {
        let s = s.clamp(1, MAX_SUPERSAMPLE);
        let size = (eye.0 * s, eye.1 * s);
        self.views = Some(StereoViews::new(camera, size, (0, 0)));
        (self.s, self.eye, self.done, self.summed, self.picture_of) = (s, eye, 0, 0, None);
        (self.part, self.part_ms, self.pass_ms) = (0, 0.0, frame_ms);
        (self.outline, self.outlined) = (outline, false);
        self.shown_views = Some(StereoViews::new(camera, eye, (0, 0)));
        self.order.clear();
        self.order.extend((0..s).flat_map(|y| (0..s).map(move |x| (x, y))));
        self.order.sort_unstable_by_key(|&(x, y)| rank(x, y, s));
        let n = size.0 as usize * size.1 as usize;
        for eye in &mut self.samples {
            eye.resize(n, 0);
        }
        self.bits.resize(size.0, size.1);
        self.follow.start(follow.filter(|_| outline == 0), size, s);
    }

    /// Stops refining: nothing is left to do until the next [`Refine::start`].
    pub fn stop(&mut self) {
        (self.views, self.done, self.summed, self.picture_of) = (None, 0, 0, None);
        for (object, z) in &mut self.planes {
            object.clear();
            z.clear();
        }
    }

    /// Whether a pass is left to trace.
    #[must_use]
    pub fn pending(&self) -> bool {
        self.views.is_some() && (self.done < self.order.len() || self.follow.has_stale())
    }

    /// Samples a pixel traced so far.
    #[must_use]
    pub fn spp(&self) -> u32 {
        self.done as u32
    }

    /// Whether every pass is done: the pair is `render --supersample S`'s.
    #[must_use]
    pub fn converged(&self) -> bool {
        self.views.is_some() && self.done == self.order.len() && !self.follow.has_stale()
    }

    /// Bytes of the buffers kept: the sample images, the sums, the selection and the
    /// renderer's screen bins.
    #[must_use]
    pub fn bytes(&self) -> usize {
        let sums: usize = self.sums.iter().map(|e| e.capacity() * 12).sum();
        let samples: usize = self.samples.iter().map(|e| e.capacity() * 4).sum();
        samples + sums + self.bits.words().len() * 8 + self.renderer.memory() + self.follow.bytes()
    }

    /// Whether a new instant of the scene can move the samples to it ([`Refine::advance`]).
    #[must_use]
    pub fn follows(&self) -> bool {
        self.views.is_some() && self.follow.is_on()
    }

    /// Moves the refinement to the instant `tracer` is at (the scene's spheres orbit; the
    /// head and everything else are as at [`Refine::start`]): the samples that can have
    /// changed become stale, and the rest keep accumulating (`follow.rs`). Returns false,
    /// changing nothing, when it does not follow ([`Refine::follows`]).
    pub fn advance(&mut self, tracer: &Tracer) -> bool {
        self.views.is_some() && self.follow.advance(tracer, self.s)
    }

    /// Traces the next part of the next pass, both eyes: a band of the eye's rows, so
    /// that a new request waits for a part of a pass, not a whole one (module doc).
    /// Returns whether that completed the pass.
    pub fn step(&mut self, tracer: &Tracer) -> bool {
        let Some(views) = self.views.filter(|_| self.pending()) else { return false };
        if self.done == self.order.len() {
            return self.repair(tracer, &views);
        }
        let started = Instant::now();
        if self.part == 0 {
            // As many parts as a pass took budgets, as last measured.
            self.parts = ((self.pass_ms / PART_MS).ceil() as u32).clamp(1, MAX_PARTS.min(self.eye.1.max(1)));
        }
        let (sx, sy) = self.order[self.done];
        let s = self.s as usize;
        // The eye rows of this part, and in them sample (sx, sy) of every pixel: one row's
        // pattern, copied to the rows sy + S·y.
        let rows = self.eye.1 as usize;
        let (from, to) =
            (rows * self.part as usize / self.parts as usize, rows * (self.part as usize + 1) / self.parts as usize);
        self.bits.clear();
        let stride = self.bits.stride();
        let words = self.bits.words_mut();
        let first = (from * s + sy as usize) * stride;
        for i in (sx as usize..self.eye.0 as usize * s).step_by(s) {
            tracer::bits::set(&mut words[first..first + stride], i as u32, true);
        }
        for y in from + 1..to {
            let at = (y * s + sy as usize) * stride;
            words.copy_within(first..first + stride, at);
        }
        let Self { samples: [left, right], renderer, bits, follow, .. } = self;
        let [lv, rv] = &views.eyes;
        renderer.render(tracer, lv, Pixels::Only(bits), follow.target(0, left));
        renderer.render(tracer, rv, Pixels::Only(bits), follow.target(1, right));
        self.part_ms += started.elapsed().as_secs_f64() * 1e3;
        self.part += 1;
        if self.part < self.parts {
            return false;
        }
        (self.pass_ms, self.part_ms, self.part) = (self.part_ms, 0.0, 0);
        self.done += 1;
        true
    }

    /// With every pass done, traces the stale samples of one sub-pixel position again
    /// (`follow.rs`), and sums anew the pixels that have none left.
    fn repair(&mut self, tracer: &Tracer, views: &StereoViews) -> bool {
        let Self { follow, renderer, samples, sums, order, summed, s, picture, picture_of, .. } = self;
        // A quarter of the eye's pixels a repair, about an eighth of a pair's rays.
        let budget = u64::from(self.eye.0) * u64::from(self.eye.1) / 4;
        if !follow.repair((tracer, renderer), views, samples, (order, *s, budget.max(1))) {
            return false;
        }
        let (w, s) = (self.eye.0 as usize, *s as usize);
        for (e, sums) in sums.iter_mut().enumerate().filter(|(_, sums)| !sums.is_empty()) {
            for &(x, y) in follow.fresh_pixels(e) {
                let (x, y) = (x as usize, y as usize);
                let mut sum = [0.0f32; 3];
                for &(sx, sy) in &order[..*summed] {
                    let k = (y * s + sy as usize) * w * s + x * s + sx as usize;
                    for (c, v) in sum.iter_mut().zip(tracer::unpack_rgb(samples[e][k])) {
                        *c += tracer::srgb8_to_linear(v);
                    }
                }
                sums[y * w + x] = sum;
                if *picture_of == Some((*summed, false)) {
                    picture[e][y * w + x] = pack(sum.map(|c| c / *summed as f32));
                }
            }
        }
        true
    }

    /// Each eye as shown after the passes so far, at the eye size, into `out`: the mean in
    /// linear light of each pixel's samples traced so far (kept as running sums, which this
    /// call brings up to date), or when converged the box filter `render --supersample`
    /// applies.
    pub fn eyes(&mut self, tracer: &Tracer, out: [&mut Vec<u32>; 2]) {
        let (Some(views), Some(shown)) = (self.views, self.shown_views) else { return };
        let converged = self.converged();
        if self.outline > 0 {
            if converged {
                self.outline_samples(tracer, &views);
            } else if self.planes[0].0.is_empty() {
                for ((object, z), view) in self.planes.iter_mut().zip(&shown.eyes) {
                    tracer::first_hits(&mut self.renderer, tracer, view, object, z);
                }
            }
        }
        let (w, h, s) = (self.eye.0 as usize, self.eye.1 as usize, self.s as usize);
        let new = &self.order[self.summed..self.done];
        let (all, follow) = (&self.order[..self.done], &self.follow);
        let scale = 1.0 / self.done.max(1) as f32;
        let again = self.picture_of != Some((self.done, converged));
        let [left, right] = out;
        let eyes = self.samples.iter().zip(&mut self.sums).zip(&mut self.picture).zip([&mut *left, &mut *right]);
        for (e, (((samples, sums), picture), out)) in eyes.enumerate() {
            let stale = follow.stale_pixels(e);
            let is_stale = |x: usize, y: usize| stale.is_some_and(|stale| stale.get(x as u32, y as u32));
            if again {
                sums.resize(w * h, [0.0; 3]);
                if self.summed == 0 {
                    sums.fill([0.0; 3]);
                }
                picture.resize(w * h, 0);
                let rows = picture.par_chunks_mut(w).zip(sums.par_chunks_mut(w));
                rows.enumerate().for_each(|(y, (row, sums))| {
                    for (x, (px, sum)) in row.iter_mut().zip(sums).enumerate() {
                        for &(sx, sy) in new {
                            let k = (y * s + sy as usize) * w * s + x * s + sx as usize;
                            for (c, v) in sum.iter_mut().zip(tracer::unpack_rgb(samples[k])) {
                                *c += tracer::srgb8_to_linear(v);
                            }
                        }
                        if !is_stale(x, y) {
                            *px = pack(sum.map(|c| c * scale));
                        }
                    }
                });
                // The sums stay up to date when converged too: a new instant of orbiting
                // spheres shows them again ([`Refine::advance`]).
                if converged {
                    stereo::downsample(samples, views.shown, picture, self.eye);
                }
            }
            // The picture, but a pixel with a stale sample shows its samples that are not
            // stale, or, with none, the pixel as the pair traced at this instant shows it
            // (already in `out`).
            out.resize(w * h, 0);
            out.par_chunks_mut(w).zip(picture.par_chunks(w)).enumerate().for_each(|(y, (row, picture))| {
                if stale.is_none_or(|stale| stale.row(y as u32).iter().all(|&word| word == 0)) {
                    row.copy_from_slice(picture);
                    return;
                }
                for (x, (px, &shown)) in row.iter_mut().zip(picture).enumerate() {
                    if !is_stale(x, y) {
                        *px = shown;
                        continue;
                    }
                    let mut fresh = (0u32, [0.0f32; 3]);
                    for &(sx, sy) in all {
                        let (i, j) = (x * s + sx as usize, y * s + sy as usize);
                        if !follow.is_stale(e, (i as u32, j as u32)) {
                            fresh.0 += 1;
                            for (c, v) in fresh.1.iter_mut().zip(tracer::unpack_rgb(samples[j * w * s + i])) {
                                *c += tracer::srgb8_to_linear(v);
                            }
                        }
                    }
                    if fresh.0 > 0 {
                        *px = pack(fresh.1.map(|c| c / fresh.0 as f32));
                    }
                }
            });
        }
        self.picture_of = Some((self.done, converged));
        self.summed = self.done;
        if self.outline > 0 && !converged {
            // Before the samples have theirs, the mean gets the eye's outlines at its size.
            for ((out, (object, z)), view) in [left, right].into_iter().zip(&self.planes).zip(&shown.eyes) {
                let style = tracer::Outline::of_view(view, self.outline as f32);
                tracer::outline(out, object, z, self.eye, style);
            }
        }
    }

    /// Draws the outlines on the converged samples, once, each eye from its own first hits
    /// at the samples' size, `outline` × S samples wide: as `render --supersample S` draws
    /// them before its filter.
    fn outline_samples(&mut self, tracer: &Tracer, views: &StereoViews) {
        if self.outlined {
            return;
        }
        let (object, z) = &mut self.sample_planes;
        for (samples, view) in self.samples.iter_mut().zip(&views.eyes) {
            tracer::first_hits(&mut self.renderer, tracer, view, object, z);
            let style = tracer::Outline::of_view(view, (self.outline * self.s) as f32);
            tracer::outline(samples, object, z, views.shown, style);
        }
        self.outlined = true;
    }
}

/// A colour in linear light, packed in sRGB `0x00RRGGBB`.
fn pack(linear: [f32; 3]) -> u32 {
    let [r, g, b] = linear.map(|c| u32::from(tracer::linear_to_srgb8(c)));
    (r << 16) | (g << 8) | b
}

/// The rank of sub-pixel position (x, y) in the order the passes trace them (module doc):
/// its rank in an S × S ordered-dither matrix: Bayer's recursive matrix for
/// S a power of two, otherwise rows interleaved by bit reversal.
fn rank(x: u32, y: u32, s: u32) -> u32 {
    if s.is_power_of_two() {
        let bits = s.trailing_zeros();
        let mut r = 0;
        for b in (0..bits).rev() {
            let (xb, yb) = ((x >> b) & 1, (y >> b) & 1);
            // Bayer's 2 × 2 step: (0,0) 0, (1,1) 1, (1,0) 2, (0,1) 3.
            r = r * 4 + [[0, 3], [2, 1]][xb as usize][yb as usize];
        }
        // The finest level decides first, so that each prefix spreads over the whole pixel.
        reverse_base4(r, bits)
    } else {
        ((y * 7 + x * 3) % s) * s + x
    }
}

/// `r`'s `digits` base-4 digits in reverse order.
fn reverse_base4(mut r: u32, digits: u32) -> u32 {
    let mut out = 0;
    for _ in 0..digits {
        out = out * 4 + r % 4;
        r /= 4;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_position_is_traced_once_and_the_first_four_spread_over_the_pixel() {
        let order_of = |s: u32| {
            let mut refine = Refine::default();
            refine.start(&Camera::default(), (1, 1), (s, 0), 0.0, None);
            refine.order
        };
        for s in 1..=MAX_SUPERSAMPLE {
            let mut order = order_of(s);
            assert_eq!(order.len(), (s * s) as usize);
            order.sort_unstable();
            order.dedup();
            assert_eq!(order.len(), (s * s) as usize, "S = {s}: each position once");
        }
        let first = &order_of(4)[..4];
        let quadrants: std::collections::HashSet<_> = first.iter().map(|&(x, y)| (x / 2, y / 2)).collect();
        assert_eq!(quadrants.len(), 4, "one sample in each quarter of the pixel first: {first:?}");
    }

    /// Before it converges, a pixel shows the mean in linear light of its samples so far:
    /// after one pass, its one sample exactly (sRGB round-trips every level); after two,
    /// the mean of the two, as the box filter would weigh them.
    #[test]
    fn a_pixel_shows_the_mean_of_its_samples_so_far() {
        let scene = tracer::testing::scene("seed.toml");
        let tracer = Tracer::new(&scene, 0.0);
        let eye = (24, 18);
        let mut refine = Refine::default();
        refine.start(&scene.camera, eye, (2, 0), 0.0, None);
        let (mut left, mut right) = (Vec::new(), Vec::new());
        assert!(refine.step(&tracer), "one part: a whole pass");
        refine.eyes(&tracer, [&mut left, &mut right]);
        let (sx, sy) = refine.order[0];
        let sample = |samples: &[u32], x: usize, y: usize, (sx, sy): (u32, u32)| {
            samples[(2 * y + sy as usize) * 48 + 2 * x + sx as usize]
        };
        for (k, px) in left.iter().enumerate() {
            assert_eq!(*px, sample(&refine.samples[0], k % 24, k / 24, (sx, sy)), "pixel {k}");
        }
        assert!(refine.step(&tracer), "one part: a whole pass");
        refine.eyes(&tracer, [&mut left, &mut right]);
        let second = refine.order[1];
        for (k, px) in right.iter().enumerate() {
            let (x, y) = (k % 24, k / 24);
            let two = [sample(&refine.samples[1], x, y, (sx, sy)), sample(&refine.samples[1], x, y, second)];
            let mut mean = Vec::new();
            stereo::downsample(&two, (2, 1), &mut mean, (1, 1));
            assert_eq!(*px, mean[0], "pixel {k}");
        }
        assert!(!refine.converged() && refine.spp() == 2);
    }

    /// A pass cut into parts (here six, three eye rows each) traces the same samples: the converged pair is still `render --supersample 2`'s in
    /// `full` mode, and only every part's last completes a pass.
    #[test]
    fn a_pass_in_parts_converges_to_the_same_bytes() {
        let scene = tracer::testing::scene("seed.toml");
        let tracer = Tracer::new(&scene, 0.0);
        let (eye, camera) = ((24, 18), scene.camera);
        let mut refine = Refine::default();
        refine.start(&camera, eye, (2, 0), 1e4, None);
        let mut steps = 0;
        while !refine.converged() {
            // Every pass as slow as six parts: three eye rows a part.
            refine.pass_ms = 6.0 * PART_MS - 1.0;
            let whole = refine.step(&tracer);
            steps += 1;
            assert_eq!(whole, steps % 6 == 0, "step {steps}: a pass in 6 parts");
        }
        assert_eq!(steps, 4 * 6);
        assert_eq!(shown(&mut refine, &tracer), supersampled(&tracer, &camera, eye));
    }

    /// `render --mode full --supersample 2`'s pair of `camera` at an eye of `eye`.
    fn supersampled(tracer: &Tracer, camera: &Camera, eye: (u32, u32)) -> [Vec<u32>; 2] {
        let mut frame = stereo::StereoFrame::new();
        let opts = stereo::Options { mode: stereo::Mode::Full, retrace_edges: false };
        frame.render(tracer, camera, 2 * eye.0, 2 * eye.1, opts);
        let (mut left, mut right) = (Vec::new(), Vec::new());
        stereo::downsample(&frame.left().rgb, (2 * eye.0, 2 * eye.1), &mut left, eye);
        stereo::downsample(&frame.right().rgb, (2 * eye.0, 2 * eye.1), &mut right, eye);
        [left, right]
    }

    /// The pair `refine` shows, traced so far.
    fn shown(refine: &mut Refine, tracer: &Tracer) -> [Vec<u32>; 2] {
        let (mut left, mut right) = (Vec::new(), Vec::new());
        refine.eyes(tracer, [&mut left, &mut right]);
        [left, right]
    }

    /// While the seed scene's spheres orbit, a refinement that follows them keeps the
    /// samples no orbit can have changed: after a new instant, every pixel without a stale
    /// sample shows what a refinement started there shows after as many passes, byte for
    /// byte; and once its repairs are done, it is `render --supersample 2` at that instant.
    #[test]
    fn a_refinement_follows_orbiting_spheres_to_the_supersampled_render() {
        let scene = tracer::testing::scene("seed.toml");
        assert!(scene.is_animated());
        let (eye, camera) = ((24, 18), scene.camera);
        let mut tracer = Tracer::new(&scene, 0.0);
        let mut refine = Refine::default();
        refine.start(&camera, eye, (2, 0), 0.0, Some((&scene, &tracer)));
        assert!(refine.follows());
        for _ in 0..2 {
            assert!(refine.step(&tracer));
        }
        shown(&mut refine, &tracer);
        for time in [0.4, 0.9, 1.3] {
            tracer.advance(&scene, time);
            assert!(refine.advance(&tracer));
            let stale = refine.follow.stale_count();
            let traced = 2 * 48 * 36 * refine.spp() as u64 / 4;
            assert!(stale > 0 && stale < traced / 2, "t = {time}: {stale} of {traced} samples stale");
            let mut fresh = Refine::default();
            fresh.start(&camera, eye, (2, 0), 0.0, None);
            for _ in 0..refine.spp() {
                assert!(fresh.step(&tracer));
            }
            let (got, want) = (shown(&mut refine, &tracer), shown(&mut fresh, &tracer));
            for e in 0..2 {
                let stale = refine.follow.stale_pixels(e).unwrap();
                let kept = (0..eye.0 * eye.1).filter(|&k| !stale.get(k % eye.0, k / eye.0));
                let kept: Vec<u32> = kept.collect();
                assert!(kept.len() > (eye.0 * eye.1) as usize / 2, "t = {time}");
                for k in kept {
                    assert_eq!(got[e][k as usize], want[e][k as usize], "t = {time}, eye {e}, pixel {k}");
                }
            }
            while refine.pending() {
                assert!(refine.step(&tracer));
            }
            assert!(refine.converged() && refine.follow.stale_count() == 0);
            assert_eq!(shown(&mut refine, &tracer), supersampled(&tracer, &camera, eye), "t = {time}");
        }
    }

    /// A still scene, or outlines, and the refinement does not follow: a new instant
    /// restarts it, as any change does.
    #[test]
    fn still_scenes_and_outlines_are_not_followed() {
        let scene = tracer::testing::scene("seed.toml");
        let tracer = Tracer::new(&scene, 0.0);
        let mut refine = Refine::default();
        refine.start(&scene.camera, (8, 6), (2, 1), 0.0, Some((&scene, &tracer)));
        assert!(!refine.follows() && !refine.advance(&tracer), "outlines");
        let still = Scene::from_toml(
            "[[lights]]\nposition = [0.0, 5.0, 0.0]\n[[spheres]]\ncenter = [0.0, 0.0, 12.0]\nradius = 2.0\n",
            "still.toml",
        )
        .unwrap();
        let tracer = Tracer::new(&still, 0.0);
        refine.start(&still.camera, (8, 6), (2, 0), 0.0, Some((&still, &tracer)));
        assert!(!refine.follows() && refine.follow.bytes() == 0, "nothing orbits");
    }
}

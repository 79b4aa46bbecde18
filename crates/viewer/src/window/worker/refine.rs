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
//! Memory: the sample images, 4 · S² bytes per eye pixel and eye, the running sums, 12
//! bytes per eye pixel and eye, and one bit per sample for the pass's selection: 152 bytes
//! a pixel of both eyes at S = 4.

use rayon::prelude::*;
use stereo::StereoViews;
use tracer::{Camera, PixelBits, Pixels, RayCounts, Renderer, Target, Tracer};

/// Largest S the viewer refines to (`--max-supersample`): 8 × 8 samples a pixel.
pub const MAX_SUPERSAMPLE: u32 = 8;

/// One resting pose's refinement, its buffers kept from pose to pose.
#[derive(Debug, Default)]
pub struct Refine {
    /// Samples per pixel along each axis.
    s: u32,
    /// The eye size.
    eye: (u32, u32),
    /// The views at the samples' size.
    views: Option<StereoViews>,
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
    /// Each eye's per-pixel sums in linear light of the samples of the first `summed`
    /// passes.
    sums: [Vec<[f32; 3]>; 2],
    summed: usize,
}

impl Refine {
    /// Starts refining the pair of `camera` at an eye of `eye` to `s` × `s` samples a pixel.
    pub fn start(&mut self, camera: &Camera, eye: (u32, u32), s: u32) {
        let s = s.clamp(1, MAX_SUPERSAMPLE);
        let size = (eye.0 * s, eye.1 * s);
        self.views = Some(StereoViews::new(camera, size, (0, 0)));
        (self.s, self.eye, self.done, self.summed) = (s, eye, 0, 0);
        self.order.clear();
        self.order.extend((0..s).flat_map(|y| (0..s).map(move |x| (x, y))));
        self.order.sort_unstable_by_key(|&(x, y)| rank(x, y, s));
        let n = size.0 as usize * size.1 as usize;
        for eye in &mut self.samples {
            eye.resize(n, 0);
        }
        self.bits.resize(size.0, size.1);
    }

    /// Stops refining: nothing is left to do until the next [`Refine::start`].
    pub fn stop(&mut self) {
        self.views = None;
    }

    /// Whether a pass is left to trace.
    #[must_use]
    pub fn pending(&self) -> bool {
        self.views.is_some() && self.done < self.order.len()
    }

    /// Samples a pixel traced so far.
    #[must_use]
    pub fn spp(&self) -> u32 {
        self.done as u32
    }

    /// Whether every pass is done: the pair is `render --supersample S`'s.
    #[must_use]
    pub fn converged(&self) -> bool {
        self.views.is_some() && self.done == self.order.len()
    }

    /// Bytes of the buffers kept: the sample images, the sums, the selection and the
    /// renderer's screen bins.
    #[must_use]
    pub fn bytes(&self) -> usize {
        let sums: usize = self.sums.iter().map(|e| e.capacity() * 12).sum();
        let samples: usize = self.samples.iter().map(|e| e.capacity() * 4).sum();
        samples + sums + self.bits.words().len() * 8 + self.renderer.memory()
    }

    /// Traces the next pass, both eyes; returns the rays of each.
    pub fn pass(&mut self, tracer: &Tracer) -> [RayCounts; 2] {
        let Some(views) = self.views.filter(|_| self.pending()) else { return Default::default() };
        let (sx, sy) = self.order[self.done];
        let s = self.s;
        // Sample sx of every pixel in row sy, then that row's words copied to the rows
        // sy + S, sy + 2S, …
        self.bits.clear();
        for i in (sx..self.bits.width()).step_by(s as usize) {
            self.bits.set(i, sy, true);
        }
        let stride = self.bits.stride();
        let words = self.bits.words_mut();
        let (first, rest) = words.split_at_mut((sy as usize + 1) * stride);
        let pattern = &first[sy as usize * stride..];
        for row in rest.chunks_exact_mut(stride).skip(s as usize - 1).step_by(s as usize) {
            row.copy_from_slice(pattern);
        }
        let Self { samples: [left, right], renderer, bits, .. } = self;
        let [lv, rv] = &views.eyes;
        let counts = [
            renderer.render(tracer, lv, Pixels::Only(bits), Target::colour(left)),
            renderer.render(tracer, rv, Pixels::Only(bits), Target::colour(right)),
        ];
        self.done += 1;
        counts
    }

    /// Each eye as shown after the passes so far, at the eye size, into `out`: the mean in
    /// linear light of each pixel's samples traced so far (kept as running sums, which this
    /// call brings up to date), or when converged the box filter `render --supersample`
    /// applies.
    pub fn eyes(&mut self, out: [&mut Vec<u32>; 2]) {
        let Some(views) = self.views else { return };
        let converged = self.converged();
        let (w, h, s) = (self.eye.0 as usize, self.eye.1 as usize, self.s as usize);
        let new = &self.order[self.summed..self.done];
        let scale = 1.0 / self.done.max(1) as f32;
        for ((samples, sums), out) in self.samples.iter().zip(&mut self.sums).zip(out) {
            if converged {
                stereo::downsample(samples, views.shown, out, self.eye);
                continue;
            }
            sums.resize(w * h, [0.0; 3]);
            if self.summed == 0 {
                sums.fill([0.0; 3]);
            }
            out.resize(w * h, 0);
            out.par_chunks_mut(w).zip(sums.par_chunks_mut(w)).enumerate().for_each(|(y, (row, sums))| {
                for (x, (px, sum)) in row.iter_mut().zip(sums).enumerate() {
                    for &(sx, sy) in new {
                        let k = (y * s + sy as usize) * w * s + x * s + sx as usize;
                        for (c, v) in sum.iter_mut().zip(tracer::unpack_rgb(samples[k])) {
                            *c += tracer::srgb8_to_linear(v);
                        }
                    }
                    let [r, g, b] = sum.map(|c| u32::from(tracer::linear_to_srgb8(c * scale)));
                    *px = (r << 16) | (g << 8) | b;
                }
            });
        }
        self.summed = self.done;
    }
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
            refine.start(&Camera::default(), (1, 1), s);
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
        refine.start(&scene.camera, eye, 2);
        let (mut left, mut right) = (Vec::new(), Vec::new());
        refine.pass(&tracer);
        refine.eyes([&mut left, &mut right]);
        let (sx, sy) = refine.order[0];
        let sample = |samples: &[u32], x: usize, y: usize, (sx, sy): (u32, u32)| {
            samples[(2 * y + sy as usize) * 48 + 2 * x + sx as usize]
        };
        for (k, px) in left.iter().enumerate() {
            assert_eq!(*px, sample(&refine.samples[0], k % 24, k / 24, (sx, sy)), "pixel {k}");
        }
        refine.pass(&tracer);
        refine.eyes([&mut left, &mut right]);
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
}

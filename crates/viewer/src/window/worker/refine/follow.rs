//! A refinement that follows the scene's time: while spheres orbit and the head rests, a
//! new instant restarts only the samples that can have changed, and the rest keep
//! accumulating.
//!
//! It is temporal reuse (`stereo`'s `reuse/`, `tracer::reuse`; Adelson & Hodges 1995, made
//! exact) applied to the refinement's samples instead of a frame's pixels: each pass marks
//! where each sample's ray tree (primary, shadow and mirror rays) meets the moving spheres'
//! swept volumes, and at a new instant the marked samples whose touch meets a sphere's
//! wedge at the old or the new instant ([`Marks::select`]) become stale. The samples not
//! selected are the very bytes a trace at the new instant gives
//! (`docs/design/reuse-exactness.md`). A pixel shows the mean of its samples that are not
//! stale, or, with none, the pair traced at the new instant at one sample a pixel. Once
//! every pass is done, repairs trace the stale samples again, one sub-pixel position at a
//! time and, per eye, at most as many samples a repair as the eye has pixels over four, so
//! that the orbits keep their pace (where they keep moving, pixels hold fewer than S²
//! samples). A pair with nothing stale is `render --supersample S`'s at its instant, byte
//! for byte.
//!
//! Memory: the marks, a [`Touch`] (12 bytes) and two bits a sample, and a bit a sample for
//! staleness, per eye.

use tracer::bits::{self, PixelBits};
use tracer::reuse::{Arc, Marks, Swept, Touch};
use tracer::{Pixels, Renderer, Scene, Target, Tracer};

use stereo::StereoViews;

/// The state that lets a refinement follow the scene's time (module doc).
#[derive(Debug, Default)]
pub(super) struct Follow {
    /// The moving spheres' swept volumes; `None`: the refinement does not follow (a still
    /// scene, reuse off, or a cue the marks do not cover).
    swept: Option<Swept>,
    /// Each eye's samples' marks, at the samples' size.
    marks: [Marks; 2],
    /// The moving spheres' wedges at the scene's instant.
    wedges: Vec<Arc>,
    /// Scratch: the wedges at a new instant.
    next: Vec<Arc>,
    /// Per eye, the samples traced at an instant the scene has left that may differ now.
    stale: [PixelBits; 2],
    /// Per eye, the eye pixels with a stale sample.
    stale_pixels: [PixelBits; 2],
    /// Scratch: a selection of samples.
    selected: PixelBits,
    /// Where the next repair starts looking, an index into the positions traced.
    repair: usize,
    /// Per eye, the pixels the last repair left with no stale sample.
    fresh: [Vec<(u32, u32)>; 2],
}

impl Follow {
    /// Starts following `scene` (`None`: not following) for samples of `size`, `s` × `s` a
    /// pixel, at the instant `tracer` is at.
    pub(super) fn start(&mut self, follow: Option<(&Scene, &Tracer)>, size: (u32, u32), s: u32) {
        let swept = follow.map(|(scene, tracer)| {
            let mut swept = self.swept.take().unwrap_or_else(|| Swept::of(scene));
            swept.update(scene);
            (swept, tracer)
        });
        match swept.filter(|(swept, _)| !swept.is_empty()) {
            Some((swept, tracer)) => {
                swept.wedges(tracer.snapshot(), &mut self.wedges);
                for ((marks, stale), pixels) in self.marks.iter_mut().zip(&mut self.stale).zip(&mut self.stale_pixels) {
                    marks.resize(size.0, size.1);
                    stale.resize(size.0, size.1);
                    stale.clear();
                    pixels.resize(size.0 / s, size.1 / s);
                    pixels.clear();
                }
                self.selected.resize(size.0, size.1);
                (self.swept, self.repair) = (Some(swept), 0);
            }
            None => {
                // The marks are the refinement's largest buffers after the samples: given back.
                *self = Self::default();
            }
        }
    }

    /// Whether the samples follow the scene's time.
    pub(super) fn is_on(&self) -> bool {
        self.swept.is_some()
    }

    /// Whether some sample is stale.
    pub(super) fn has_stale(&self) -> bool {
        self.is_on() && self.stale.iter().any(|s| s.words().iter().any(|&w| w != 0))
    }

    /// How many samples are stale, both eyes.
    #[cfg(test)]
    pub(super) fn stale_count(&self) -> u64 {
        self.stale.iter().map(PixelBits::count).sum()
    }

    /// Eye `e`'s pixels with a stale sample.
    pub(super) fn stale_pixels(&self, e: usize) -> Option<&PixelBits> {
        self.is_on().then(|| &self.stale_pixels[e])
    }

    /// Whether eye `e`'s sample (i, j) is stale.
    pub(super) fn is_stale(&self, e: usize, (i, j): (u32, u32)) -> bool {
        self.stale[e].get(i, j)
    }

    /// A render target for eye `e`'s samples, marking them when following.
    pub(super) fn target<'a>(&'a mut self, e: usize, samples: &'a mut Vec<u32>) -> Target<'a> {
        let target = Target::colour(samples);
        match &self.swept {
            Some(swept) => target.marking(&mut self.marks[e], swept),
            None => target,
        }
    }

    /// Bytes of the marks and the stale samples' bits.
    pub(super) fn bytes(&self) -> usize {
        let per_sample = std::mem::size_of::<Touch>() as f64 + 0.375;
        self.marks.iter().map(|m| (f64::from(m.width()) * f64::from(m.height()) * per_sample) as usize).sum()
    }

    /// The scene moved to the instant `tracer` is at: the samples that can have changed
    /// become stale (module doc). Returns false, changing nothing, when not following.
    pub(super) fn advance(&mut self, tracer: &Tracer, s: u32) -> bool {
        let Self { swept: Some(swept), marks, wedges, next, stale, stale_pixels, selected, .. } = self else {
            return false;
        };
        swept.wedges(tracer.snapshot(), next);
        for ((marks, stale), pixels) in marks.iter_mut().zip(stale.iter_mut()).zip(stale_pixels.iter_mut()) {
            if marks.select([wedges, next], selected) == 0 {
                continue;
            }
            for (word, &add) in stale.words_mut().iter_mut().zip(selected.words()) {
                *word |= add;
            }
            for j in 0..selected.height() {
                for i in bits::ones(selected.row(j)) {
                    pixels.set(i / s, j / s, true);
                }
            }
        }
        std::mem::swap(wedges, next);
        true
    }

    /// Traces again, at the instant `tracer` is at and through `views`, the stale samples
    /// of one sub-pixel position of `positions` (the next with any, from where the last
    /// repair stopped), at most `budget` an eye, marking them. Returns whether it traced any; the pixels whose
    /// samples are all fresh again are then [`Follow::fresh_pixels`].
    pub(super) fn repair(
        &mut self,
        (tracer, renderer): (&Tracer, &mut Renderer),
        views: &StereoViews,
        samples: &mut [Vec<u32>; 2],
        (positions, s, budget): (&[(u32, u32)], u32, u64),
    ) -> bool {
        let Self { swept: Some(swept), marks, stale, stale_pixels, selected, repair, fresh, .. } = self else {
            return false;
        };
        for _ in 0..positions.len() {
            let at = *repair % positions.len();
            let (sx, sy) = positions[at];
            let (mut any, mut cut) = (false, false);
            for e in 0..2 {
                fresh[e].clear();
                selected.clear();
                let mut n = 0;
                'rows: for j in (sy..stale[e].height()).step_by(s as usize) {
                    for i in bits::ones(stale[e].row(j)).filter(|i| i % s == sx) {
                        if n == budget {
                            cut = true;
                            break 'rows;
                        }
                        selected.set(i, j, true);
                        n += 1;
                    }
                }
                if n == 0 {
                    continue;
                }
                any = true;
                for (word, &done) in stale[e].words_mut().iter_mut().zip(selected.words()) {
                    *word &= !done;
                }
                let target = Target::colour(&mut samples[e]).marking(&mut marks[e], swept);
                renderer.render(tracer, &views.eyes[e], Pixels::Only(selected), target);
                // The pixels of the samples traced that have no stale sample left.
                for j in (sy..stale[e].height()).step_by(s as usize) {
                    for i in bits::ones(selected.row(j)) {
                        let (x, y) = (i / s, j / s);
                        let clean = (0..s).all(|dy| (0..s).all(|dx| !stale[e].get(x * s + dx, y * s + dy)));
                        if clean && stale_pixels[e].get(x, y) {
                            stale_pixels[e].set(x, y, false);
                            fresh[e].push((x, y));
                        }
                    }
                }
            }
            // A position cut short by the budget is taken up again by the next repair.
            if !cut {
                *repair = (at + 1) % positions.len();
            }
            if any {
                return true;
            }
        }
        false
    }

    /// Eye `e`'s pixels the last repair left with no stale sample.
    pub(super) fn fresh_pixels(&self, e: usize) -> &[(u32, u32)] {
        &self.fresh[e]
    }
}

//! The progressive policy's time budget while the head moves: each new pose's pair is
//! traced at one sample per k × k pixels, k chosen from what the last pairs cost, so that
//! the pair is young when the display shows it (OSPRay's and Mol*'s interactive tracing
//! spend a time budget per frame in the same way; Dayal et al., "Adaptive frameless
//! rendering", EGSR 2005).
//!
//! The model: a pair's wall time at each density, as last measured. The view changes what a
//! sample costs (a mirror or a dense structure in view): a measurement that differs from
//! its density's last moves every other density's part of the way by the same factor.
//! A density not yet measured is predicted from its measured neighbours: on the line
//! through the two around it, or in proportion to its samples beyond them. The frame
//! chosen is the densest whose prediction fits the trace budget, which is half the target
//! age: a request waits on average half a frame for the worker to finish the one before,
//! then its own frame, then half a display tick to be shown.

/// The densities the policy chooses among: one sample per k × k pixels.
pub const DENSITIES: [u32; 8] = [1, 2, 3, 4, 6, 8, 12, 16];

/// The density of a first frame, before anything was measured.
const FIRST: u32 = 4;

/// How far a measurement moves the other densities' costs toward its own change.
const NEWEST: f64 = 0.5;

/// Choices without a try after a try that did not fit.
const COOL_DOWN: u32 = 30;

/// The trace's share of the target age (module doc).
const TRACE_SHARE: f64 = 0.5;

/// Samples per eye at density `k` for an eye of `eye` pixels: every side rounded up.
#[must_use]
pub fn samples_at(eye: (u32, u32), k: u32) -> (u32, u32) {
    (eye.0.div_ceil(k).max(1), eye.1.div_ceil(k).max(1))
}

/// The cost model: what a pair cost at each density, per sample of an eye.
#[derive(Clone, Copy, Debug, Default)]
pub struct Budget {
    /// Milliseconds per sample of one eye, at each of [`DENSITIES`], when measured.
    rate: [Option<f64>; DENSITIES.len()],
    /// The last choice tried a denser density than the prediction allowed (its index).
    tried: Option<usize>,
    /// Choices left before the next try.
    cool_down: u32,
    /// The last choice (its index).
    last: Option<usize>,
}

impl Budget {
    /// Remembers that a pair at density `k` for an eye of `eye` took `ms`.
    pub fn record(&mut self, eye: (u32, u32), k: u32, ms: f64) {
        let Some(i) = DENSITIES.iter().position(|&d| d == k) else { return };
        let rate = ms / samples(eye, k);
        let Some(old) = self.rate[i] else {
            self.rate[i] = Some(rate);
            return;
        };
        // The view got dearer or cheaper by this factor: every other density's cost moves
        // with it (part way), so that a density measured in another view is not trusted as
        // it was; the one measured is what it cost.
        let factor = 1.0 + NEWEST * (rate / old - 1.0);
        if !(0.5..=2.0).contains(&(rate / old)) {
            // Another view: a try that failed in the last one may fit now.
            self.cool_down = 0;
        }
        for r in self.rate.iter_mut().flatten() {
            *r *= factor;
        }
        self.rate[i] = Some(rate);
    }

    /// Forgets everything measured (another scene).
    pub fn forget(&mut self) {
        *self = Self::default();
    }

    /// The predicted wall time of a pair at density index `i` for an eye of `eye`, or
    /// `None` before anything was measured.
    #[must_use]
    pub fn predict(&self, eye: (u32, u32), i: usize) -> Option<f64> {
        let at = |j: usize| self.rate[j].map(|r| (samples(eye, DENSITIES[j]), r * samples(eye, DENSITIES[j])));
        let n = samples(eye, DENSITIES[i]);
        if let Some((_, ms)) = at(i) {
            return Some(ms);
        }
        // The nearest measured densities on either side: denser (more samples), coarser.
        let denser = (0..i).rev().find_map(at);
        let coarser = (i + 1..DENSITIES.len()).find_map(at);
        match (denser, coarser) {
            (Some((n1, ms1)), Some((n0, ms0))) => Some(ms0 + (ms1 - ms0) * (n - n0) / (n1 - n0)),
            (Some((m, ms)), None) | (None, Some((m, ms))) => Some(ms * n / m),
            (None, None) => None,
        }
    }

    /// The density for the next moving pair, for an eye of `eye` and a presented age of
    /// `target_age_ms`: the densest predicted to fit the trace budget, else the coarsest.
    /// When that one is predicted to take at most half the budget, the next denser one is
    /// tried instead (its prediction may be stale), unless a try failed in the last
    /// [`COOL_DOWN`] choices.
    pub fn choose(&mut self, eye: (u32, u32), target_age_ms: f64) -> u32 {
        let budget = target_age_ms * TRACE_SHARE;
        if self.rate.iter().all(Option::is_none) {
            self.last = DENSITIES.iter().position(|&d| d == FIRST);
            return FIRST;
        }
        let fits = (0..DENSITIES.len()).find(|&i| self.predict(eye, i).is_some_and(|ms| ms <= budget));
        let Some(i) = fits else {
            self.last = Some(DENSITIES.len() - 1);
            return DENSITIES[DENSITIES.len() - 1];
        };
        if let Some(tried) = self.tried.take() {
            // The last choice was a try: it failed if it was measured beyond the budget.
            if self.predict(eye, tried).is_some_and(|ms| ms > budget) {
                self.cool_down = COOL_DOWN;
            }
        }
        self.cool_down = self.cool_down.saturating_sub(1);
        let cheap = self.predict(eye, i).is_some_and(|ms| ms <= budget * 0.5);
        let i = if i > 0 && cheap && self.cool_down == 0 {
            self.tried = Some(i - 1);
            i - 1
        } else {
            i
        };
        // Never more than one step denser than the last choice: a prediction far from the
        // densities measured lately may be far off (one sent a half-second pair while the
        // head moved), and a step costs at most 2.25 times the samples.
        let i = self.last.map_or(i, |last| i.max(last.saturating_sub(1)));
        self.last = Some(i);
        DENSITIES[i]
    }
}

/// Samples per eye at density `k`, as a float for the model's arithmetic.
fn samples(eye: (u32, u32), k: u32) -> f64 {
    let (w, h) = samples_at(eye, k);
    f64::from(w) * f64::from(h)
}

#[cfg(test)]
mod tests {
    use super::*;

    const EYE: (u32, u32) = (800, 600);

    /// A pair's cost in a synthetic scene: a fixed part and a part per sample.
    fn model(fixed_ms: f64, us_per_sample: f64) -> impl Fn(u32) -> f64 {
        move |k| fixed_ms + us_per_sample * 1e-3 * samples(EYE, k)
    }

    /// The densest density whose true cost fits the budget of `target` ms.
    fn best(cost: &impl Fn(u32) -> f64, target: f64) -> u32 {
        DENSITIES.into_iter().find(|&k| cost(k) <= target * TRACE_SHARE).unwrap_or(16)
    }

    /// Runs the policy for `frames` moving frames against `cost`, as the worker does
    /// (choose, trace, record), and returns the densities chosen.
    fn run(budget: &mut Budget, cost: &impl Fn(u32) -> f64, target: f64, frames: usize) -> Vec<u32> {
        (0..frames)
            .map(|_| {
                let k = budget.choose(EYE, target);
                budget.record(EYE, k, cost(k));
                k
            })
            .collect()
    }

    #[test]
    fn samples_round_every_side_up() {
        assert_eq!(samples_at((800, 600), 3), (267, 200));
        assert_eq!(samples_at((1, 1), 16), (1, 1));
        assert_eq!(samples_at((800, 600), 1), (800, 600));
    }

    #[test]
    fn the_first_frame_is_coarse_and_the_choice_settles_on_the_densest_that_fits() {
        // thousand.toml-like: ~70 ms at full resolution, 33 ms target → 16.5 ms to trace.
        let cost = model(2.0, 0.1);
        let mut budget = Budget::default();
        let chosen = run(&mut budget, &cost, 33.0, 8);
        assert_eq!(chosen[0], FIRST);
        let want = best(&cost, 33.0);
        assert_eq!(want, 2, "the model's answer: 2 × 2 pixels a sample (50 ms at 1 is too slow)");
        assert!(chosen[2..].iter().all(|&k| k == want), "settles within two frames: {chosen:?}");
    }

    #[test]
    fn a_costlier_view_coarsens_and_a_cheaper_one_refines_again() {
        let (cheap, dear) = (model(1.0, 0.02), model(4.0, 0.6));
        let mut budget = Budget::default();
        run(&mut budget, &cheap, 33.0, 6);
        assert_eq!(budget.choose(EYE, 33.0), 1, "cheap: every pixel");
        let chosen = run(&mut budget, &dear, 33.0, 8);
        assert_eq!(*chosen.last().unwrap(), best(&dear, 33.0), "{chosen:?}");
        assert!(best(&dear, 33.0) > 2);
        let chosen = run(&mut budget, &cheap, 33.0, 8);
        assert_eq!(*chosen.last().unwrap(), 1, "the density rises again as soon as it may: {chosen:?}");
    }

    #[test]
    fn a_try_that_does_not_fit_is_not_repeated_at_once() {
        // Every pixel: 24 ms, beyond the 16.5 ms budget; 2 × 2: 6 ms, under half of it.
        let cost = model(0.0, 0.05);
        let mut budget = Budget::default();
        let chosen = run(&mut budget, &cost, 33.0, 40);
        let tries = chosen[1..].iter().filter(|&&k| k == 1).count();
        assert!(tries <= 2, "one try per cool-down, not every other frame: {chosen:?}");
        assert_eq!(chosen.last(), Some(&2));
    }

    /// A prediction that drifted far below the truth (here: every pixel measured cheap long
    /// ago) moves the choice one density a frame, so the error costs one step, not a jump
    /// from the coarsest to every pixel.
    #[test]
    fn the_density_rises_one_step_a_frame() {
        let cost = model(2.0, 0.5);
        let mut budget = Budget::default();
        budget.record(EYE, 16, cost(16));
        let first = budget.choose(EYE, 33.0);
        budget.record(EYE, first, cost(first));
        // A guess for every pixel far below the truth, as a drifted one can be.
        budget.record(EYE, 1, 1.0);
        let next = budget.choose(EYE, 33.0);
        let step = |k: u32| DENSITIES.iter().position(|&d| d == k).unwrap();
        assert_eq!(step(next) + 1, step(first), "one step denser than {first}, not {next}");
    }

    #[test]
    fn a_longer_target_buys_more_samples() {
        let cost = model(3.0, 0.3);
        for target in [20.0, 33.0, 100.0, 400.0] {
            let mut budget = Budget::default();
            let chosen = run(&mut budget, &cost, target, 10);
            assert_eq!(*chosen.last().unwrap(), best(&cost, target), "target {target} ms: {chosen:?}");
        }
        let mut budget = Budget::default();
        run(&mut budget, &model(500.0, 1.0), 33.0, 4);
        assert_eq!(budget.choose(EYE, 33.0), 16, "nothing fits: the coarsest");
    }

    #[test]
    fn an_unmeasured_density_is_predicted_between_its_measured_neighbours() {
        let mut budget = Budget::default();
        budget.record(EYE, 1, 100.0);
        budget.record(EYE, 4, 10.0);
        // 2: 400 × 300 samples, between 200 × 150 (10 ms) and 800 × 600 (100 ms).
        let at2 = budget.predict(EYE, 1).unwrap();
        assert!((at2 - (10.0 + 90.0 * (120_000.0 - 30_000.0) / (480_000.0 - 30_000.0))).abs() < 1e-9);
        // 8: beyond the coarsest measured, in proportion to its samples.
        assert!((budget.predict(EYE, 5).unwrap() - 10.0 * 7500.0 / 30_000.0).abs() < 1e-9);
        budget.forget();
        assert_eq!(budget.predict(EYE, 0), None);
    }
}

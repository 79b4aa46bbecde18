//! The viewer's timewarp: every presented frame is the last traced stereo pair warped to the
//! head pose of the moment it is presented ([`stereo::Warp`], a 6-DoF forward warp by each
//! eye's depth), so the picture follows the head at the display's rate while the tracer
//! traces the newest pose as fast as it can. This is what VR runtimes do between a
//! renderer and the headset (Oculus's asynchronous timewarp and spacewarp, SteamVR's motion
//! smoothing; van Waveren, "The asynchronous time warp for virtual reality on consumer
//! hardware", VRST 2016).
//!
//! The warp runs on a rayon pool of its own, whose threads keep the normal priority, while
//! the tracer's threads run at a lower one (`worker.rs`): the two cores go to the tracer
//! except for the few milliseconds a display tick asks for, which it gets at once instead of
//! queueing behind the tracer's jobs in the global pool.
//!
//! Both eyes go to one pose, from one traced pair, read with the views the pair was traced
//! through ([`Finished::warp_sources`]). The warp's output is its own [`Eyes`], finished as
//! the worker finishes a traced pair: a supersampled pair is warped at its samples and
//! filtered down to the eye size, then made into an anaglyph when shown as one. A frame at
//! the very pose it was traced for (fresh) is not warped: it is shown as traced, with the
//! stereo pair's debug mask (the seed paper's Fig. 2). A warped frame's debug mask colours
//! each pixel by where it came from: warped from its own eye, a hole filled from the other
//! eye, or a hole filled by the warp's row rule ([`TIMEWARP_LEGEND`]); it is blended over
//! both eyes.

use std::time::Instant;

use stereo::{Layout, Warp, WarpClass, WarpCounts};
use tracer::Camera;

use crate::window::present::Look;
use crate::window::worker::{filter_eyes, Eyes, Finished};

/// Mask colour of a pixel warped from its own eye's traced frame.
pub const WARPED_COLOR: u32 = 0x0040_80FF;
/// Mask colour of a hole filled by the other eye's warped pixel.
pub const OTHER_EYE_COLOR: u32 = 0x00FF_A020;
/// Mask colour of a hole neither eye covers, filled along its row.
pub const HOLE_COLOR: u32 = 0x00FF_30FF;

/// The timewarp mask's colours and names, for the panel's legend.
pub const TIMEWARP_LEGEND: [(u32, &str); 3] = [
    (WARPED_COLOR, "warped from its own eye"),
    (OTHER_EYE_COLOR, "hole, filled from the other eye"),
    (HOLE_COLOR, "hole, filled along its row"),
];

/// What the last warp did.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Warped {
    /// Each eye's pixels by where they came from (at the sampled size).
    pub counts: [WarpCounts; 2],
    /// The pose is the traced one: the frame was shown as traced, not warped.
    pub fresh: bool,
    /// Wall time of the warp and its filtering, milliseconds.
    pub ms: f64,
}

impl Warped {
    /// The share of both eyes' pixels that are holes (filled from the other eye or by the
    /// row rule).
    #[must_use]
    pub fn hole_share(&self) -> f64 {
        let [l, r] = self.counts;
        let holes = l.holes() + r.holes();
        holes as f64 / (l.total() + r.total()).max(1) as f64
    }
}

/// The warp, its own thread pool and the frame it makes, kept from tick to tick: once warm
/// nothing is allocated.
pub struct Timewarp {
    pool: rayon::ThreadPool,
    warp: Warp,
    /// The frame shown: the warped eyes and their mask colours.
    out: Eyes,
    /// Each eye's warp at the sampled size, and its pixels' classes.
    sampled: [Vec<u32>; 2],
    classes: [Vec<WarpClass>; 2],
    /// Mask colours at the sampled size, before they are filtered.
    colours: [Vec<u32>; 2],
    last: Warped,
}

impl Timewarp {
    /// A timewarp with a pool of one thread per core.
    ///
    /// # Errors
    ///
    /// If the pool's threads cannot be started.
    pub fn new() -> anyhow::Result<Self> {
        let threads = std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get);
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .thread_name(|i| format!("warp-{i}"))
            .build()
            .map_err(|e| anyhow::anyhow!("cannot start the timewarp's threads: {e}"))?;
        Ok(Self {
            pool,
            warp: Warp::new(),
            out: Eyes::default(),
            sampled: Default::default(),
            classes: Default::default(),
            colours: Default::default(),
            last: Warped::default(),
        })
    }

    /// What the last [`Timewarp::show`] did.
    #[must_use]
    pub fn last(&self) -> Warped {
        self.last
    }

    /// The eyes the last [`Timewarp::show`] that warped made (empty before the first).
    #[must_use]
    pub fn eyes(&self) -> &Eyes {
        &self.out
    }

    /// The eyes to present for `traced` at the head pose `pose` (its scene's camera with
    /// the settings' head, IPD and distance), shown as `look` asks: `traced` warped to
    /// `pose`; or `None`, to show `traced` as it is, when it was traced without what the warp
    /// needs or at `pose` itself (fresh: the warp would give it back bit for bit, and shown
    /// as traced, its debug mask is the stereo pair's, the seed paper's Fig. 2).
    pub fn show(&mut self, traced: &Finished, pose: &Camera, look: Look) -> Option<&Eyes> {
        let info = traced.info?;
        let views = info.views;
        if *pose == views.camera {
            self.last = Warped { fresh: true, ..Warped::default() };
            return None;
        }
        let sources = traced.warp_sources()?;
        let started = Instant::now();
        let (samples, eye) = (views.shown, traced.size());
        let [left_to, right_to] = views.warped_to(pose);
        let Self { pool, warp, out, sampled, classes, colours, .. } = self;
        let counts = pool.install(|| {
            out.size = eye;
            let Eyes { left, right, left_overlay, right_overlay, .. } = out;
            let [left_classes, right_classes] = classes;
            // At the eye's size the warp lands in the shown eyes themselves; supersampled, in
            // the samples, filtered down after.
            let same = samples == eye;
            let [left_sampled, right_sampled] = sampled;
            let planes = if same { [&mut *left, &mut *right] } else { [left_sampled, right_sampled] };
            let counts = warp.warp(sources, [&left_to, &right_to], planes, [left_classes, right_classes]);
            if !same {
                filter_eyes([&sampled[0], &sampled[1]], samples, [left, right], eye);
            }
            let [left_colours, right_colours] = colours;
            rayon::join(
                || mask_colours(look.show_mask, &classes[0], left_colours, samples, left_overlay, eye),
                || mask_colours(look.show_mask, &classes[1], right_colours, samples, right_overlay, eye),
            );
            out.finish_anaglyph(look.layout == Layout::Anaglyph, info.request.swap);
            counts
        });
        self.last = Warped { counts, fresh: false, ms: started.elapsed().as_secs_f64() * 1e3 };
        Some(&self.out)
    }
}

/// The mask's colours of an eye's `classes` (at `samples`), filtered down to `eye` into
/// `out` when `shown`, else `out` emptied.
fn mask_colours(
    shown: bool,
    classes: &[WarpClass],
    colours: &mut Vec<u32>,
    samples: (u32, u32),
    out: &mut Vec<u32>,
    eye: (u32, u32),
) {
    if !shown {
        out.clear();
        return;
    }
    colours.clear();
    colours.extend(classes.iter().map(|c| match c {
        WarpClass::Warped | WarpClass::Crack => WARPED_COLOR,
        WarpClass::OtherEye => OTHER_EYE_COLOR,
        WarpClass::Filled => HOLE_COLOR,
    }));
    stereo::downsample(colours, samples, out, eye);
}

#[cfg(test)]
mod tests {
    use stereo::{Options, StereoFrame};
    use tracer::{Scene, Tracer};

    use super::*;
    use crate::window::worker::finished::Traced;
    use crate::window::worker::{FrameInfo, Request};

    /// A traced frame of a sphere at `camera`, `size` with a guard band `guard`, as the
    /// worker hands it over for the timewarp.
    fn traced(camera: Camera, size: (u32, u32), guard: (u32, u32)) -> Finished {
        let scene = Scene::from_toml(
            "[[lights]]\nposition = [0.0, 5.0, 0.0]\n[[spheres]]\ncenter = [0.0, 0.0, 12.0]\nradius = 2.0\n",
            "t.toml",
        )
        .unwrap();
        let tracer = Tracer::new(&scene, 0.0);
        let mut frame = StereoFrame::new();
        frame.set_depths(true);
        frame.render_banded(&tracer, &camera, size, guard, Options::default());
        let request = Request::sized(size.0, size.1).at(camera).with_timewarp(guard);
        let info = FrameInfo::answering(1, request);
        let (w, gx, gy) = (size.0 + 2 * guard.0, guard.0 as usize, guard.1 as usize);
        let cut = |image: &[u32]| -> Vec<u32> {
            image
                .chunks_exact(w as usize)
                .skip(gy)
                .take(size.1 as usize)
                .flat_map(|r| r[gx..gx + size.0 as usize].to_vec())
                .collect()
        };
        Finished {
            info: Some(info),
            eyes: Eyes { size, left: cut(&frame.left().rgb), right: cut(&frame.right().rgb), ..Eyes::default() },
            traced: Traced {
                left: frame.left().rgb.clone(),
                left_z: frame.left().z.clone(),
                right: frame.right().rgb.clone(),
                right_z: frame.right_depth().to_vec(),
            },
            ..Finished::default()
        }
    }

    const MASK: Look = Look { layout: Layout::SideBySide, swap: false, show_mask: true };

    /// At the pose it was traced for, the frame is shown as traced (not warped, so with the
    /// stereo pair's own mask), and the warp there would give it back bit for bit; a turned
    /// head gets warped pixels and, at the edge the turn exposes beyond the band, holes.
    #[test]
    fn the_traced_pose_shows_the_frame_as_traced_and_a_turn_warps_it() {
        let camera = Camera { ipd: 1.0, ..Camera::default() };
        let frame = traced(camera, (48, 32), (2, 2));
        let mut timewarp = Timewarp::new().unwrap();
        assert!(timewarp.show(&frame, &camera, MASK).is_none(), "the traced pose: shown as traced");
        assert!(timewarp.last().fresh && timewarp.last().hole_share() == 0.0);
        // The warp to that pose would change nothing: what showing it as traced relies on.
        let nudged = Camera { yaw_deg: 1e-30, ..camera };
        assert_ne!(nudged, camera, "a pose the timewarp warps to");
        let shown = timewarp.show(&frame, &nudged, MASK).unwrap();
        assert_eq!(
            (&shown.left, &shown.right),
            (&frame.eyes.left, &frame.eyes.right),
            "warped to the traced pose: as traced"
        );
        assert!(!timewarp.last().fresh && timewarp.last().hole_share() == 0.0);
        let turned = Camera { yaw_deg: 8.0, ..camera };
        let shown = timewarp.show(&frame, &turned, MASK).unwrap();
        assert_ne!(shown.left, frame.eyes.left, "a turn moves the picture");
        let colours = |c: u32| shown.left_overlay.iter().filter(|&&p| p == c).count();
        assert!(colours(WARPED_COLOR) > 0, "warped");
        assert!(colours(OTHER_EYE_COLOR) + colours(HOLE_COLOR) > 0, "8° is beyond a 2-pixel band: an exposed edge");
        let last = timewarp.last();
        assert!(!last.fresh && last.hole_share() > 0.0, "{last:?}");
    }

    /// A coarse pair (the progressive policy's, while the head moves: traced at fewer
    /// samples than the eye has pixels) is warped at its samples and reconstructed at the
    /// eye size, its mask too: what is shown is `stereo::upsample` of the warp.
    #[test]
    fn a_coarse_pair_is_warped_at_its_samples_and_shown_at_the_eye_size() {
        let camera = Camera { ipd: 1.0, ..Camera::default() };
        let (coarse, eye) = ((12, 8), (48, 32));
        let mut frame = traced(camera, coarse, (1, 1));
        let mut info = frame.info.unwrap();
        (info.request.width, info.request.height) = eye;
        frame.info = Some(info);
        let turned = Camera { yaw_deg: 3.0, ..camera };
        let mut timewarp = Timewarp::new().unwrap();
        let shown = timewarp.show(&frame, &turned, MASK).unwrap();
        assert_eq!((shown.size, shown.left.len(), shown.left_overlay.len()), (eye, 48 * 32, 48 * 32));
        let shown = shown.left.clone();
        let counts = timewarp.last().counts;
        assert_eq!(counts[0].total(), 12 * 8, "warped at the samples");
        // The same warp at the samples, reconstructed.
        let mut warp = Warp::new();
        let [l, r] = frame.info.unwrap().views.warped_to(&turned);
        let (mut planes, mut classes) = ([Vec::new(), Vec::new()], [Vec::new(), Vec::new()]);
        let [pl, pr] = &mut planes;
        let [cl, cr] = &mut classes;
        warp.warp(frame.warp_sources().unwrap(), [&l, &r], [pl, pr], [cl, cr]);
        let mut want = Vec::new();
        stereo::upsample(&planes[0], coarse, &mut want, eye);
        assert_eq!(shown, want);
    }

    /// A frame traced without the timewarp's planes is not warped.
    #[test]
    fn a_frame_without_depths_is_not_warped() {
        let camera = Camera::default();
        let mut frame = traced(camera, (16, 8), (0, 0));
        let turned = Camera { yaw_deg: 8.0, ..camera };
        assert!(Timewarp::new().unwrap().show(&frame, &turned, MASK).is_some(), "with them, a turn is warped");
        frame.traced = Traced::default();
        assert!(Timewarp::new().unwrap().show(&frame, &turned, MASK).is_none());
    }
}

//! The sliced search's cut: how far from the eye a view bins its spheres.
//!
//! A sliced view bins the spheres nearest the eye, and sends the rays that meet none of them
//! through the BVH from the cut on (`screen.rs`). Whatever the cut, the first hits are the
//! same; only the cost moves. Binning a sphere costs its screen rectangle and a test in every
//! pixel of its tiles; a ray left open costs a BVH search. So the cut is placed where the
//! binned spheres cover the screen about [`SLICED_COVER`] times over (the sum of their
//! on-screen areas, in pixels): random spheres that cover it twice leave e⁻² ≈ 14 % of the
//! pixels open. Tightly packed spheres (a structure, the deep fields) reach that with few;
//! overlapping ones scattered through the depth (the generated fields) need more. Between
//! [`SLICED_KEPT_MIN`] and [`SLICED_KEPT_MAX`] spheres a pixel, measured on the fields of a
//! million spheres at 1280 × 720 (`benches/embree-anchor`, `docs/performance-notes.md`).
//!
//! The spheres' nearest distances go into a histogram of [`SLICES`] bins with, per bin, the
//! spheres' summed on-screen area; the cut is a bin edge. Both are sums of integers, so the
//! cut does not depend on how rayon splits the work.

use glam::Vec3;
use rayon::prelude::*;

use crate::camera::EyeView;

/// The screen's coverage the binned spheres aim for, in screens (see the module doc).
const SLICED_COVER: f64 = 2.0;

/// Fewest spheres a pixel a sliced view bins (the nearest): below this the bins cost little
/// whatever they cover.
const SLICED_KEPT_MIN: f64 = 0.2;

/// Most spheres a pixel a sliced view bins (and at most half of the spheres).
const SLICED_KEPT_MAX: f64 = 1.0;

/// Distance bins of the histogram of the spheres' nearest distances.
const SLICES: usize = 1024;

/// Spheres a rayon job takes at least.
const CHUNK: usize = 1 << 14;

/// How near the eye at `origin` the sphere (`c`, `r`) begins: no ray from there meets it
/// at a smaller `t`.
fn nearest(origin: Vec3, c: Vec3, r: f32) -> f32 {
    ((c.as_dvec3() - origin.as_dvec3()).length() - f64::from(r)) as f32
}

/// About how many of `view`'s pixels the sphere (`c`, `r`) covers: its projected disc,
/// clipped to the screen's area, 0 when it lies off screen or behind the eye.
fn screen_area(view: &EyeView, c: Vec3, r: f32) -> u64 {
    let pixels = u64::from(view.width) * u64::from(view.height);
    let p = view.head_from_world * (c - view.origin);
    if p.z <= -r {
        return 0;
    }
    if p.z <= r {
        return pixels; // around the eye: everywhere
    }
    // Pixels per unit of slope, and the centre's continuous pixel position
    // (`bound.rs`'s `screen_bound`, for the centre alone).
    let (w, h) = view.shown_size();
    let (w, h) = (w as f32, h as f32);
    let focal = view.distance * w / view.window_width;
    let disc = r * focal / p.z;
    let x = (view.eye_x + p.x / p.z * view.distance) / view.window_width * w + 0.5 * w + view.margin.0 as f32;
    let y = (0.5 - p.y / p.z * view.distance / view.window_height) * h + view.margin.1 as f32;
    let (vw, vh) = (view.width as f32, view.height as f32);
    if x + disc < 0.0 || x - disc > vw || y + disc < 0.0 || y - disc > vh || !disc.is_finite() {
        return 0;
    }
    (std::f32::consts::PI * disc * disc).min(pixels as f32).ceil() as u64
}

/// A distance from `view`'s eye within which the spheres `(centers, radii)` that begin cover
/// its pixels [`SLICED_COVER`] times over, at least [`SLICED_KEPT_MIN`] and at most
/// [`SLICED_KEPT_MAX`] of them a pixel, and at most half of them (about: a histogram's bin
/// edge); +∞ to bin them all. Each sphere's [`nearest`] distance is left in `near`, for the
/// rectangles' pass to keep the spheres before the cut by the same number.
pub(super) fn sliced_cut((centers, radii): (&[Vec3], &[f32]), view: &EyeView, near: &mut Vec<f32>) -> f32 {
    let origin = view.origin;
    near.clear();
    near.resize(centers.len(), 0.0);
    let (lo, hi) = near
        .par_chunks_mut(CHUNK)
        .zip(centers.par_chunks(CHUNK).zip(radii.par_chunks(CHUNK)))
        .map(|(near, (centers, radii))| {
            let mut range = (f32::INFINITY, f32::NEG_INFINITY);
            for (d, (&c, &r)) in near.iter_mut().zip(centers.iter().zip(radii)) {
                *d = nearest(origin, c, r);
                range = (range.0.min(*d), range.1.max(*d));
            }
            range
        })
        .reduce(|| (f32::INFINITY, f32::NEG_INFINITY), |a, b| (a.0.min(b.0), a.1.max(b.1)));
    if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) {
        return f32::INFINITY;
    }
    let scale = SLICES as f32 / (hi - lo);
    let (counts, areas) = near
        .par_chunks(CHUNK)
        .zip(centers.par_chunks(CHUNK).zip(radii.par_chunks(CHUNK)))
        .map(|(near, (centers, radii))| {
            let (mut counts, mut areas) = ([0u32; SLICES], [0u64; SLICES]);
            for (&d, (&c, &r)) in near.iter().zip(centers.iter().zip(radii)) {
                let slice = (((d - lo) * scale) as usize).min(SLICES - 1);
                counts[slice] += 1;
                areas[slice] += screen_area(view, c, r);
            }
            (counts, areas)
        })
        .reduce(
            || ([0u32; SLICES], [0u64; SLICES]),
            |(mut counts, mut areas), (c, a)| {
                counts.iter_mut().zip(c).for_each(|(n, m)| *n += m);
                areas.iter_mut().zip(a).for_each(|(n, m)| *n += m);
                (counts, areas)
            },
        );
    let rays = f64::from(view.width) * f64::from(view.height);
    let fewest = (SLICED_KEPT_MIN * rays) as usize;
    let most = ((SLICED_KEPT_MAX * rays) as usize).min(centers.len() / 2);
    let cover = (SLICED_COVER * rays) as u64;
    let (mut kept, mut area) = (0usize, 0u64);
    for (k, (&n, &a)) in counts.iter().zip(&areas).enumerate() {
        if (kept >= fewest && area >= cover) || kept + n as usize > most {
            return lo + k as f32 / scale;
        }
        kept += n as usize;
        area += a;
    }
    f32::INFINITY
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::camera::{Camera, Eye};

    /// A mono eye at the origin looking down +z through a 90° window one unit away.
    fn view(w: u32, h: u32) -> EyeView {
        Camera { ipd: 0.0, distance: 1.0, fov_deg: 90.0, ..Camera::default() }.view(Eye::Left, w, h)
    }

    #[test]
    fn screen_area_is_the_projected_disc() {
        // A unit sphere 10 ahead on a 90° window of 800 pixels: 400 pixels a unit of slope,
        // a disc of radius 40 pixels.
        let v = view(800, 800);
        let area = screen_area(&v, Vec3::new(0.0, 0.0, 10.0), 1.0) as f32;
        let disc = std::f32::consts::PI * 40.0 * 40.0;
        assert!((area - disc).abs() < 0.01 * disc, "{area} against {disc}");
        assert_eq!(screen_area(&v, Vec3::new(0.0, 0.0, -10.0), 1.0), 0, "behind the eye");
        assert_eq!(screen_area(&v, Vec3::new(30.0, 0.0, 10.0), 1.0), 0, "off screen");
        assert_eq!(screen_area(&v, Vec3::new(0.0, 0.0, 0.5), 1.0), 800 * 800, "around the eye");
    }

    /// Spheres through the view at every distance, near ones as big on screen as far ones.
    fn field(n: usize, size: f32) -> (Vec<Vec3>, Vec<f32>) {
        let mut rng = crate::testing::XorShift::new(0x9E37_79B9);
        let centers: Vec<Vec3> = (0..n)
            .map(|_| {
                let z = rng.range(5.0, 50.0);
                Vec3::new(rng.range(-1.0, 1.0) * z, rng.range(-1.0, 1.0) * z, z)
            })
            .collect();
        let radii = centers.iter().map(|c| c.z * size * rng.range(0.5, 1.5)).collect();
        (centers, radii)
    }

    /// What [`sliced_cut`] aims for, without its histogram: the spheres in order of their
    /// nearest distance, and the distance of the one with which the kept ones first cover
    /// the screen as asked (at least the fewest), or of the first beyond the most.
    fn wanted((centers, radii): (&[Vec3], &[f32]), v: &EyeView) -> (f32, bool) {
        let mut order: Vec<usize> = (0..centers.len()).collect();
        let near = |k: usize| nearest(v.origin, centers[k], radii[k]);
        order.sort_by(|&a, &b| near(a).total_cmp(&near(b)));
        let rays = f64::from(v.width) * f64::from(v.height);
        let fewest = (SLICED_KEPT_MIN * rays) as usize;
        let most = ((SLICED_KEPT_MAX * rays) as usize).min(centers.len() / 2);
        let mut area = 0;
        for (kept, &k) in order.iter().enumerate() {
            if kept + 1 > most {
                return (near(k), false);
            }
            area += screen_area(v, centers[k], radii[k]);
            if kept + 1 >= fewest && area >= (SLICED_COVER * rays) as u64 {
                return (near(k), true);
            }
        }
        (f32::INFINITY, false)
    }

    #[test]
    fn the_cut_keeps_the_nearest_spheres_until_they_cover_the_screen() {
        // Covered with more than the fewest, covered with the fewest, and never covered.
        for (n, size, covered) in [(4000, 0.06, true), (4000, 0.2, true), (4000, 0.005, false)] {
            let (w, h) = (40, 30);
            let (centers, radii) = field(n, size);
            let v = view(w, h);
            let cut = sliced_cut((&centers, &radii), &v, &mut Vec::new());
            let (want, cover) = wanted((&centers, &radii), &v);
            assert_eq!(cover, covered, "{n} spheres of {size}");
            let near: Vec<f32> = centers.iter().zip(&radii).map(|(&c, &r)| nearest(v.origin, c, r)).collect();
            let (lo, hi) = near.iter().fold((f32::INFINITY, f32::NEG_INFINITY), |(l, h), &d| (l.min(d), h.max(d)));
            let slice = (hi - lo) / SLICES as f32;
            // The first bin edge past the sphere that covers it (or before the one past
            // the most).
            if cover {
                assert!(want < cut && cut <= want + slice * 1.001, "{n}: cut {cut}, wanted just past {want}");
            } else {
                assert!(want - slice * 1.001 <= cut && cut <= want, "{n}: cut {cut}, wanted just short of {want}");
                let kept = near.iter().filter(|&&d| d < cut).count();
                assert!(kept <= n / 2, "{n}: {kept} kept");
            }
        }
    }

    #[test]
    fn the_cut_does_not_depend_on_the_threads() {
        let (centers, radii) = field(100_000, 0.01);
        let v = view(320, 240);
        let cut = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool");
            pool.install(|| sliced_cut((&centers, &radii), &v, &mut Vec::new())).to_bits()
        };
        assert_eq!(cut(1), cut(3));
    }
}

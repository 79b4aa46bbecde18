//! The parallel renderer: one eye, every pixel, rows spread over rayon's pool.

use rayon::prelude::*;

use crate::camera::EyeView;
use crate::film::Film;
use crate::stats::RayCounts;
use crate::world::Tracer;

/// Traces every pixel of `view` into `film` (resized to the view if needed) and returns the
/// rays cast.
///
/// Rows are independent work items; each row counts its own rays and the counts are summed
/// afterwards, so the result — pixels and counts — is the same for any thread count. Nothing
/// is allocated per pixel or per ray.
pub fn render_eye(tracer: &Tracer, view: &EyeView, film: &mut Film) -> RayCounts {
    film.resize(view.width, view.height);
    let w = view.width as usize;
    if w == 0 || view.height == 0 {
        return RayCounts::default();
    }
    film.rgb
        .par_chunks_mut(w)
        .zip(film.z.par_chunks_mut(w))
        .zip(film.surface.par_chunks_mut(w))
        .enumerate()
        .map(|(j, ((rgb, z), surface))| {
            let mut counts = RayCounts::default();
            for i in 0..w {
                let s = tracer.trace_pixel(view, i as u32, j as u32, &mut counts);
                rgb[i] = s.rgb;
                z[i] = s.z;
                surface[i] = s.surface;
            }
            counts
        })
        .sum()
}

/// Traces every pixel of `view` for colour only into `rgb` (resized to the view), for
/// images whose visible-surface record nobody reads. Returns the rays cast; pixels and
/// counts are those of [`render_eye`].
pub fn render_rgb(tracer: &Tracer, view: &EyeView, rgb: &mut Vec<u32>) -> RayCounts {
    let w = view.width as usize;
    rgb.resize(w * view.height as usize, 0);
    if w == 0 {
        return RayCounts::default();
    }
    rgb.par_chunks_mut(w)
        .enumerate()
        .map(|(j, row)| {
            let mut counts = RayCounts::default();
            for (i, px) in row.iter_mut().enumerate() {
                *px = tracer.trace_pixel(view, i as u32, j as u32, &mut counts).rgb;
            }
            counts
        })
        .sum()
}

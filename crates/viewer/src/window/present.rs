//! Composition of the eyes to present ([`Eyes`]: a finished stereo frame's, or the
//! timewarp's) into the window's pixel buffer (`0x00RRGGBB`, the format softbuffer presents).
//!
//! Each eye fills one half of the window: `width / 2` physical pixels wide (an odd last column
//! stays background) and the full height. If the finished frame was rendered for another
//! size — the window was just resized — it is scaled nearest-neighbour, so a resize never
//! shows stale or uninitialised memory. The layouts are [`stereo::Layout`]'s, with the eyes
//! where [`Layout::slots`] puts them: side by side, cross-eyed (eyes swapped), or the red–cyan
//! anaglyph, which the worker composes and which is shown centred at the eye size. The
//! debug mask is the worker's overlay image (the mask's colours at the eye size, filtered
//! from the samples when supersampled), blended half and half over the right eye; a
//! timewarp's mask (`timewarp.rs`) is blended over both eyes.
//!
//! This runs on the UI thread without rayon: the global pool belongs to the tracer, and
//! waiting on it would make the UI wait for the render.

use std::ops::Range;

use stereo::Layout;
use tracer::Eye;

use crate::window::worker::Eyes;

/// Colour of window areas no eye covers.
pub const BACKGROUND: u32 = 0x0018_1818;

/// The eye size for a window of `width` × `height` physical pixels: half the width, the full
/// height (zero in either when the window is too small to show an eye).
#[must_use]
pub fn eye_size(width: u32, height: u32) -> (u32, u32) {
    let (w, h) = (width / 2, height);
    if w == 0 || h == 0 {
        (0, 0)
    } else {
        (w, h)
    }
}

/// Mixes two pixels half and half (per channel, rounding down).
#[inline]
#[must_use]
pub fn blend_half(a: u32, b: u32) -> u32 {
    ((a >> 1) & 0x007F_7F7F) + ((b >> 1) & 0x007F_7F7F)
}

/// Clears the top byte of every pixel: softbuffer requires it to be zero, and the egui
/// rasteriser writes alpha there (only where it drew: see [`ui_rows`]).
pub fn clear_alpha(pixels: &mut [u32]) {
    for p in pixels {
        *p &= 0x00FF_FFFF;
    }
}

/// The rows, in physical pixels, that the UI's meshes can touch (clipped to `0..height`);
/// the eyes' pixels outside them keep a zero top byte.
#[must_use]
pub fn ui_rows(primitives: &[egui::ClippedPrimitive], pixels_per_point: f32, height: usize) -> Range<usize> {
    let mut rows = height..0;
    for p in primitives {
        if let egui::epaint::Primitive::Mesh(mesh) = &p.primitive {
            let r = mesh.calc_bounds().intersect(p.clip_rect);
            if r.is_positive() {
                let y0 = (r.min.y * pixels_per_point).floor().max(0.0) as usize;
                let y1 = (r.max.y * pixels_per_point).ceil() as usize + 1;
                rows = rows.start.min(y0)..rows.end.max(y1.min(height));
            }
        }
    }
    if rows.start < rows.end {
        rows
    } else {
        0..0
    }
}

/// How the eyes are shown: the choices that change the picture on screen but not the
/// rendered eyes (the anaglyph aside, which the worker makes with the same swap).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Look {
    /// How the eyes are arranged.
    pub layout: Layout,
    /// Exchange the eyes.
    pub swap: bool,
    /// Blend the debug mask over the right eye (or the anaglyph).
    pub show_mask: bool,
}

/// Draws stereo frames into window buffers, keeping its scratch between frames.
#[derive(Debug, Default)]
pub struct Compositor {
    /// For each destination column of an eye, the source column.
    columns: Vec<u32>,
}

impl Compositor {
    /// Fills `dst` (`width` × `height`, row-major) with `frame` as `look` asks: the eyes in
    /// the layout's slots, the right eye (or the anaglyph) blended half and half with the
    /// debug mask when it is shown.
    /// A frame without its anaglyph (the layout was just switched) is shown side by side.
    /// Returns whether the eyes were drawn (false before the first frame or when the window
    /// is too small).
    pub fn compose(&mut self, dst: &mut [u32], width: usize, height: usize, frame: &Eyes, look: Look) -> bool {
        debug_assert_eq!(dst.len(), width * height, "the buffer is width × height");
        let (ew, eh) = eye_size(width as u32, height as u32);
        let (ew, eh) = (ew as usize, eh as usize);
        let (fw, fh) = frame.size;
        let (fw, fh) = (fw as usize, fh as usize);
        let n = fw * fh;
        let complete = frame.left.len() == n && frame.right.len() == n;
        // The frame the mask was switched on in may not have its colours yet: it shows
        // without them, and the next frame has them.
        let show_mask = look.show_mask && frame.right_overlay.len() == n;
        // A timewarp's mask covers the left eye too.
        let show_left_mask = look.show_mask && frame.left_overlay.len() == n;
        if ew == 0 || fw == 0 || fh == 0 || !complete {
            dst.fill(BACKGROUND);
            return false;
        }
        self.columns.clear();
        self.columns.extend((0..ew).map(|x| (x * fw / ew) as u32));
        let columns = &self.columns;
        // Same width: whole rows are copied, not gathered column by column.
        let direct = fw == ew;
        let Look { layout, swap, .. } = look;
        let (left, right, mask, left_mask) = (&frame.left, &frame.right, &frame.right_overlay, &frame.left_overlay);
        let anaglyph = (layout == Layout::Anaglyph && frame.anaglyph.len() == fw * fh).then_some(&frame.anaglyph);
        let halves = if layout == Layout::Anaglyph { Layout::SideBySide } else { layout };
        let left_first = halves.slots(swap)[0] == Eye::Left;
        let overlay = |p: u32, s: usize| if show_mask { blend_half(p, mask[s]) } else { p };
        for (y, row) in dst.chunks_exact_mut(width).enumerate() {
            let src_row = (y * fh / eh) * fw;
            if let Some(image) = anaglyph {
                // The eye-sized image centred: a quarter of the window on each side.
                let margin = ew / 2;
                row[..margin].fill(BACKGROUND);
                fill_eye(&mut row[margin..margin + ew], columns, |c| overlay(image[src_row + c], src_row + c));
                row[margin + ew..].fill(BACKGROUND);
                continue;
            }
            let (first, rest) = row.split_at_mut(ew);
            let (second, pad) = rest.split_at_mut(ew);
            let (l, r) = if left_first { (first, second) } else { (second, first) };
            let span = src_row..src_row + fw;
            if show_left_mask {
                fill_eye(l, columns, |c| blend_half(left[src_row + c], left_mask[src_row + c]));
            } else if direct {
                l.copy_from_slice(&left[span.clone()]);
            } else {
                fill_eye(l, columns, |c| left[src_row + c]);
            }
            if direct && !show_mask {
                r.copy_from_slice(&right[span]);
            } else {
                fill_eye(r, columns, |c| overlay(right[src_row + c], src_row + c));
            }
            pad.fill(BACKGROUND);
        }
        true
    }
}

/// One eye's row: destination column x takes source column `columns[x]`.
#[inline]
fn fill_eye(dst: &mut [u32], columns: &[u32], pixel: impl Fn(usize) -> u32) {
    for (d, &c) in dst.iter_mut().zip(columns) {
        *d = pixel(c as usize);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use stereo::{mask_color, PixelClass};

    fn look(layout: Layout, swap: bool, show_mask: bool) -> Look {
        Look { layout, swap, show_mask }
    }

    fn frame(w: u32, h: u32) -> Eyes {
        let n = (w * h) as usize;
        Eyes {
            size: (w, h),
            left: (0..n as u32).collect(),
            right: (0..n as u32).map(|p| p | 0x0010_0000).collect(),
            right_overlay: vec![mask_color(PixelClass::Reprojected); n],
            ..Eyes::default()
        }
    }

    #[test]
    fn eyes_fill_the_halves_exactly_at_the_matching_size() {
        let f = frame(4, 2);
        let mut dst = vec![0xFFFF_FFFF; 9 * 2];
        assert!(Compositor::default().compose(&mut dst, 9, 2, &f, look(Layout::SideBySide, false, false)));
        assert_eq!(&dst[0..4], &f.left[0..4]);
        assert_eq!(&dst[4..8], &f.right[0..4]);
        assert_eq!(dst[8], BACKGROUND, "odd last column");
        assert_eq!(&dst[9..13], &f.left[4..8]);
        assert_eq!(&dst[13..17], &f.right[4..8]);
    }

    /// The two halves line up to the pixel in every window size: with the same picture in
    /// both eyes, every row's left half equals its right half (same width, same columns,
    /// same rows), whether the frame matches the window or is scaled; an odd width's spare
    /// column is the last one, at the right edge, so neither eye moves by it.
    #[test]
    fn the_halves_line_up_in_every_window_size() {
        let mut c = Compositor::default();
        for (fw, fh) in [(0, 0), (5, 3), (13, 7)] {
            for width in 2..=41usize {
                for height in [1usize, 3, 8] {
                    let (fw, fh) = if fw == 0 { (width as u32 / 2, height as u32) } else { (fw, fh) };
                    let mut f = frame(fw, fh);
                    f.right.clone_from(&f.left);
                    let mut dst = vec![0xFFFF_FFFF; width * height];
                    for layout in [Layout::SideBySide, Layout::CrossEyed] {
                        assert!(c.compose(&mut dst, width, height, &f, look(layout, false, false)));
                        let ew = width / 2;
                        for (y, row) in dst.chunks_exact(width).enumerate() {
                            assert_eq!(
                                row[..ew],
                                row[ew..2 * ew],
                                "{width}×{height} from {fw}×{fh}, row {y}: halves differ"
                            );
                            assert!(row[2 * ew..].iter().all(|&p| p == BACKGROUND), "{width}: the spare column");
                        }
                        let expect_top = f.left[0];
                        assert_eq!(
                            (dst[0], dst[ew]),
                            (expect_top, expect_top),
                            "both eyes start at their half's left edge"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn the_mask_blends_over_the_right_eye_once_its_colours_arrive() {
        let mut f = frame(4, 2);
        let mut dst = vec![0; 8 * 2];
        let mut c = Compositor::default();
        assert!(c.compose(&mut dst, 8, 2, &f, look(Layout::SideBySide, false, true)));
        let blended: Vec<u32> = f.right[0..4].iter().map(|&p| blend_half(p, f.right_overlay[0])).collect();
        assert_eq!(&dst[4..8], &blended[..]);
        // The frame the mask was switched on in has no colours yet: the eye shows plain.
        f.right_overlay.clear();
        assert!(c.compose(&mut dst, 8, 2, &f, look(Layout::SideBySide, false, true)));
        assert_eq!(&dst[4..8], &f.right[0..4]);
        assert_eq!(&dst[0..4], &f.left[0..4]);
    }

    #[test]
    fn a_stale_frame_is_scaled_and_small_windows_show_background() {
        let f = frame(2, 1);
        let mut dst = vec![0; 8 * 2];
        let mut c = Compositor::default();
        assert!(c.compose(&mut dst, 8, 2, &f, look(Layout::CrossEyed, false, false)));
        // Nearest neighbour: each source pixel twice across, every row the same.
        assert_eq!(&dst[0..8], &[f.right[0], f.right[0], f.right[1], f.right[1], 0, 0, 1, 1]);
        assert_eq!(&dst[0..8], &dst[8..16]);
        let mut one = [0u32; 1];
        assert!(!c.compose(&mut one, 1, 1, &f, look(Layout::SideBySide, false, false)));
        assert_eq!(one[0], BACKGROUND);
        assert!(!c.compose(&mut dst, 8, 2, &Eyes::default(), look(Layout::SideBySide, false, true)));
    }

    #[test]
    fn ui_rows_cover_the_meshes_and_nothing_else() {
        let mut mesh = egui::Mesh::default();
        let rect = egui::Rect::from_min_max(egui::pos2(5.0, 10.0), egui::pos2(50.0, 20.0));
        mesh.add_colored_rect(rect, egui::Color32::WHITE);
        let clip = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(100.0, 100.0));
        let prims = [egui::ClippedPrimitive { clip_rect: clip, primitive: egui::epaint::Primitive::Mesh(mesh) }];
        assert_eq!(ui_rows(&prims, 2.0, 300), 20..41);
        assert_eq!(ui_rows(&prims, 2.0, 30), 20..30);
        assert_eq!(ui_rows(&[], 1.0, 30), 0..0);
    }

    #[test]
    fn the_anaglyph_is_centred_and_missing_ones_fall_back_to_side_by_side() {
        let mut f = frame(2, 1);
        let mut dst = vec![0; 8];
        let mut c = Compositor::default();
        c.compose(&mut dst, 8, 1, &f, look(Layout::Anaglyph, false, false));
        assert_eq!(&dst[..4], &[f.left[0], f.left[0], f.left[1], f.left[1]], "side by side, scaled");
        f.anaglyph = vec![7, 9];
        c.compose(&mut dst, 8, 1, &f, look(Layout::Anaglyph, false, false));
        assert_eq!(dst, [BACKGROUND, BACKGROUND, 7, 7, 9, 9, BACKGROUND, BACKGROUND]);
    }

    #[test]
    fn swap_exchanges_the_eyes_and_the_mask_follows_the_right_eye() {
        let f = frame(1, 1);
        let mut dst = [0u32; 2];
        let mut c = Compositor::default();
        c.compose(&mut dst, 2, 1, &f, look(Layout::SideBySide, true, false));
        assert_eq!(dst, [f.right[0], f.left[0]]);
        c.compose(&mut dst, 2, 1, &f, look(Layout::CrossEyed, true, false));
        assert_eq!(dst, [f.left[0], f.right[0]]);
        c.compose(&mut dst, 2, 1, &f, look(Layout::SideBySide, true, true));
        assert_eq!(dst, [blend_half(f.right[0], mask_color(PixelClass::Reprojected)), f.left[0]]);
    }

    #[test]
    fn mask_blends_half_and_half() {
        let f = frame(1, 1);
        let mut dst = [0u32; 2];
        Compositor::default().compose(&mut dst, 2, 1, &f, look(Layout::SideBySide, false, true));
        assert_eq!(dst[1], blend_half(f.right[0], mask_color(PixelClass::Reprojected)));
        assert_eq!(blend_half(0x00FF_FFFF, 0x00FF_FFFF), 0x00FE_FEFE);
        assert_eq!(blend_half(0x00FF_0000, 0), 0x007F_0000);
    }
}

//! The scalar reference: one hit at a time with `glam::Vec3`, in exactly the operation order
//! of `tracer/src/shade.rs` (`to_light`, `view_independent`, `view_dependent`, `highlight`)
//! with known visibility. Every lane kernel is checked against it.

use glam::Vec3;

use crate::hits::{Hits, Scene, Shaded};
use crate::isa::{Highlight, HIGHLIGHT_FLOOR};
use crate::srgb;

/// (n·h)^e by repeated squaring (`shade.rs`'s `highlight` for `Exponent::Whole`).
#[inline]
#[must_use]
pub fn highlight(ndh: f32, mut e: u32) -> f32 {
    let (mut base, mut acc) = (ndh, 1.0f32);
    while e > 0 {
        if e & 1 == 1 {
            acc *= base;
        }
        base *= base;
        e >>= 1;
    }
    acc
}

/// [`highlight`] with every product and square below [`HIGHLIGHT_FLOOR`] taken as 0
/// ([`Highlight::Floored`]): the same products otherwise, so the same result.
#[inline]
#[must_use]
pub fn highlight_floored(ndh: f32, mut e: u32) -> f32 {
    let (mut base, mut acc) = (ndh, 1.0f32);
    while e > 0 {
        if e & 1 == 1 {
            acc *= base;
            if acc < HIGHLIGHT_FLOOR {
                return 0.0;
            }
        }
        e >>= 1;
        if e > 0 {
            base *= base;
            if base < HIGHLIGHT_FLOOR {
                // A later bit is set (e > 0), and it would multiply by 0.
                return 0.0;
            }
        }
    }
    acc
}

/// Linear radiance of hit `i`.
#[inline]
#[must_use]
pub fn shade_one<const FLOORED: bool>(scene: &Scene, h: &Hits, i: usize) -> Vec3 {
    let v3 = |a: &[Vec<f32>; 3]| Vec3::new(a[0][i], a[1][i], a[2][i]);
    let (p, n, d, c) = (v3(&h.p), v3(&h.n), v3(&h.d), v3(&h.c));
    let (kd, ks, e, kr, vis) = (h.kd[i], h.ks[i], h.e[i], h.kr[i], h.vis[i]);

    // View-independent: ambient + Lambert.
    let mut sum = Vec3::ZERO;
    let mut lit = 0u32;
    let mut dirs = [Vec3::ZERO; crate::hits::LIGHTS];
    for (k, light) in scene.lights.iter().enumerate() {
        let v = light.position - p;
        let dist = v.length();
        let l = v * dist.recip();
        dirs[k] = l;
        let ndl = n.dot(l);
        if ndl <= 0.0 {
            continue;
        }
        if vis & (1 << k) != 0 {
            lit |= 1 << k;
            sum += ndl * light.color;
        }
    }
    let diffuse = c * (scene.ambient + kd * sum);

    // View-dependent: highlights, then the mirror term.
    let mut out = Vec3::ZERO;
    if ks > 0.0 {
        for (k, light) in scene.lights.iter().enumerate() {
            if lit & (1 << k) == 0 {
                continue;
            }
            let ndh = n.dot((dirs[k] - d).normalize_or_zero());
            if ndh > 0.0 {
                let power = if FLOORED { highlight_floored(ndh, e) } else { highlight(ndh, e) };
                out += ks * power * light.color;
            }
        }
    }
    if kr > 0.0 {
        out += kr * v3(&h.mirror);
    }
    diffuse + out
}

/// Shades hits `range` into `out`.
pub fn shade_range<const FLOORED: bool>(scene: &Scene, h: &Hits, range: std::ops::Range<usize>, out: &mut Shaded) {
    for i in range {
        let c = shade_one::<FLOORED>(scene, h, i);
        out.linear[0][i] = c.x;
        out.linear[1][i] = c.y;
        out.linear[2][i] = c.z;
        out.rgb[i] = srgb::pack_rgb(c);
    }
}

/// Shades every hit.
pub fn shade(highlight: Highlight, scene: &Scene, h: &Hits, out: &mut Shaded) {
    match highlight {
        Highlight::Exact => shade_range::<false>(scene, h, 0..h.len(), out),
        Highlight::Floored => shade_range::<true>(scene, h, 0..h.len(), out),
    }
}

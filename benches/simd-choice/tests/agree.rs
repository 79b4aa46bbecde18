//! Every lane kernel against the scalar reference: with separate multiply and add they must
//! be bit-identical (linear radiance and packed sRGB), on every instruction set, with a
//! ragged tail, with exact and with floored highlights.

use simd_eval::{fearless, hits, pulp_arch, scalar, wide_mv, Highlight, Hits, Isa, Mode, Scene, Shaded};

type Kernel = fn(Mode, &Scene, &Hits, &mut Shaded);

const KERNELS: [(&str, Kernel); 8] = [
    ("wide avx2", |m, s, h, o| wide_mv::shade(Isa::Avx2, m, s, h, o)),
    ("wide fallback", |m, s, h, o| wide_mv::shade(Isa::Fallback, m, s, h, o)),
    ("pulp avx2", |m, s, h, o| pulp_arch::shade(Isa::Avx2, m, s, h, o)),
    ("pulp fallback", |m, s, h, o| pulp_arch::shade(Isa::Fallback, m, s, h, o)),
    ("pulp scalar128", pulp_arch::shade_scalar128),
    ("fearless avx2", |m, s, h, o| fearless::shade(Isa::Avx2, m, s, h, o)),
    ("fearless fallback", |m, s, h, o| fearless::shade(Isa::Fallback, m, s, h, o)),
    ("fearless sse4.2", |m, s, h, o| fearless::shade_at(fearless::sse4_2(), m, s, h, o)),
];

fn reference(highlight: Highlight, scene: &Scene, h: &Hits) -> Shaded {
    let mut out = Shaded::new(h.len());
    scalar::shade(highlight, scene, h, &mut out);
    out
}

fn assert_bit_identical(got: &Shaded, want: &Shaded, what: &str) {
    for a in 0..3 {
        for (i, (g, w)) in got.linear[a].iter().zip(&want.linear[a]).enumerate() {
            assert_eq!(g.to_bits(), w.to_bits(), "{what}: hit {i} channel {a}: {g} vs scalar {w}");
        }
    }
    assert_eq!(got.rgb, want.rgb, "{what}: packed sRGB");
}

#[test]
fn separate_multiply_add_is_bit_identical_to_scalar() {
    let scene = hits::seed_scene();
    for n in [4096, 4096 + 13] {
        let h = hits::generate(n, 7);
        for mode in [Mode::EXACT, Mode::FLOORED] {
            let want = reference(mode.highlight, &scene, &h);
            for (name, kernel) in KERNELS {
                let mut got = Shaded::new(n);
                kernel(mode, &scene, &h, &mut got);
                assert_bit_identical(&got, &want, &format!("{name}, {mode:?}, n = {n}"));
            }
        }
    }
}

/// A highlight term below 2^-63 is lost in any sum with the ambient term, so flooring
/// changes no output at all here, not even a linear value.
#[test]
fn floored_highlights_change_no_output() {
    let scene = hits::seed_scene();
    let h = hits::generate(1 << 16, 11);
    let exact = reference(Highlight::Exact, &scene, &h);
    let floored = reference(Highlight::Floored, &scene, &h);
    assert!(exact.rgb == floored.rgb, "a term below 2^-63 never changes a pixel");
    let same = (0..3).all(|a| exact.linear[a].iter().zip(&floored.linear[a]).all(|(x, y)| x.to_bits() == y.to_bits()));
    assert!(same, "nor a linear value, next to an ambient term");
}

/// For n·h in (0, 1] every partial product is at least the result, so flooring changes the
/// result exactly when it is below the floor.
#[test]
fn floored_highlight_is_exact_or_zero() {
    for e in [0, 1, 2, 3, 40, 60, 255, 256] {
        for k in 1..=10_000 {
            let ndh = k as f32 / 10_000.0;
            let (exact, floored) = (scalar::highlight(ndh, e), scalar::highlight_floored(ndh, e));
            let want = if exact < simd_eval::HIGHLIGHT_FLOOR { 0.0 } else { exact };
            assert_eq!(floored.to_bits(), want.to_bits(), "ndh = {ndh}, e = {e}: {floored} vs exact {exact}");
        }
    }
}

#[test]
fn inputs_exercise_every_branch() {
    let h = hits::generate(4096, 7);
    let scene = hits::seed_scene();
    let lit = |k: u32| h.vis.iter().filter(|&&v| v & (1 << k) != 0).count();
    assert!(lit(0) > 1000 && lit(1) > 1000, "both lights light many hits");
    assert!(h.vis.contains(&0), "some hits are in full shadow");
    assert!(h.ks.contains(&0.0) && h.kr.contains(&0.0), "matte hits");
    assert!(h.e.contains(&256) && h.e.contains(&40), "mixed exponents");
    let out = reference(Highlight::Exact, &scene, &h);
    assert!(out.rgb.contains(&0x00FF_FFFF), "some highlights saturate");
    let underflows =
        (0..h.len()).filter(|&i| h.ks[i] > 0.0 && scalar::highlight(0.1, h.e[i]) < simd_eval::HIGHLIGHT_FLOOR);
    assert!(underflows.count() > 100, "dim highlights underflow, so Highlight::Floored is exercised");
}

//! How far each kernel's fused (`mul_add`) variant is from the scalar reference, and which
//! instruction set `Isa::current()` picks (set `STEREOTRACE_LANES=4` to force the fallback).
//!
//! `cargo run --release --example diff [hits]`

use simd_eval::{fearless, hits, pulp_arch, scalar, wide_mv, Highlight, Isa, Mode, Shaded};

/// A kernel closed over its inputs.
type Run<'a> = &'a dyn Fn(Mode, &mut Shaded);

fn main() {
    println!("Isa::current() = {:?} ({} lanes)", Isa::current(), Isa::current().lanes());
    let n = std::env::args().nth(1).and_then(|a| a.parse().ok()).unwrap_or(1 << 20);
    let scene = hits::seed_scene();
    let h = hits::generate(n, 7);
    let mut want = Shaded::new(n);
    scalar::shade(Highlight::Exact, &scene, &h, &mut want);
    let runs: [(&str, Run); 7] = [
        ("wide avx2", &|f, o| wide_mv::shade(Isa::Avx2, f, &scene, &h, o)),
        ("wide fallback", &|f, o| wide_mv::shade(Isa::Fallback, f, &scene, &h, o)),
        ("pulp avx2", &|f, o| pulp_arch::shade(Isa::Avx2, f, &scene, &h, o)),
        ("pulp fallback", &|f, o| pulp_arch::shade(Isa::Fallback, f, &scene, &h, o)),
        ("fearless avx2", &|f, o| fearless::shade(Isa::Avx2, f, &scene, &h, o)),
        ("fearless fallback", &|f, o| fearless::shade(Isa::Fallback, f, &scene, &h, o)),
        ("fearless sse4.2", &|f, o| fearless::shade_at(fearless::sse4_2(), f, &scene, &h, o)),
    ];
    println!("{n} hits against the exact scalar reference; per kernel and mode: hits whose packed sRGB differs, the largest channel difference, linear channels not bit-identical");
    for (name, run) in runs {
        for mode in [Mode::EXACT, Mode::FLOORED, Mode::FUSED] {
            let mut got = Shaded::new(n);
            run(mode, &mut got);
            let mut pixels = 0;
            let mut worst = 0;
            for (&a, &b) in got.rgb.iter().zip(&want.rgb) {
                let d = (0..3).map(|s| ((a >> (8 * s)) as u8).abs_diff((b >> (8 * s)) as u8)).max().unwrap_or(0);
                pixels += usize::from(d > 0);
                worst = worst.max(d);
            }
            let (mut bits, mut ulps) = (0, 0);
            for a in 0..3 {
                for (x, y) in got.linear[a].iter().zip(&want.linear[a]) {
                    bits += usize::from(x.to_bits() != y.to_bits());
                    ulps = ulps.max(x.to_bits().abs_diff(y.to_bits()));
                }
            }
            println!(
                "{name:18} {:17} sRGB differs on {pixels:5} hits (max {worst}); linear differs on {:5.2} % of channels (max {ulps} ulp)",
                format!("{:?}/{:?}", mode.fma, mode.highlight),
                100.0 * bits as f64 / (3 * n) as f64
            );
        }
    }
}

//! Shade 4096 hits (2 lights, per-lane exponents, sRGB pack) with each crate, on the 8-lane
//! AVX2+FMA path and the forced 4-lane fallback, in each mode, against the scalar reference.
//!
//! `cargo bench --bench shade` — ns per hit is the reported time / 4096. On a shared
//! machine, `SIMD_EVAL_CPU_TIME=1` measures the bench thread's CPU time instead of wall time
//! (group `shade_4096_cpu`), which other processes' load disturbs much less.

use std::hint::black_box;
use std::time::Duration;

use criterion::measurement::{Measurement, ValueFormatter, WallTime};
use criterion::{Criterion, Throughput};
use simd_eval::{fearless, hits, pulp_arch, scalar, srgb, wide_mv, Highlight, Hits, Isa, Mode, Scene, Shaded};

const N: usize = 4096;

type Kernel = Box<dyn Fn(&Scene, &Hits, &mut Shaded)>;

/// Every kernel, named `crate/path/mode`: the 8-lane AVX2+FMA path and the 4-lane fallback
/// of each crate in each [`Mode`], plus a few paths that show where a crate's time goes.
fn kernels() -> Vec<(String, Kernel)> {
    type Shade = fn(Isa, Mode, &Scene, &Hits, &mut Shaded);
    let modes = [("exact", Mode::EXACT), ("floored", Mode::FLOORED), ("fused", Mode::FUSED)];
    let mut all: Vec<(String, Kernel)> = vec![
        ("scalar/exact".into(), Box::new(|s, h, o| scalar::shade(Highlight::Exact, s, h, o))),
        ("scalar/floored".into(), Box::new(|s, h, o| scalar::shade(Highlight::Floored, s, h, o))),
    ];
    let crates: [(&str, Shade); 3] =
        [("wide", wide_mv::shade), ("pulp", pulp_arch::shade), ("fearless", fearless::shade)];
    for (krate, shade) in crates {
        for (isa, path) in [(Isa::Avx2, "avx2"), (Isa::Fallback, "fallback")] {
            for (mode_name, mode) in modes {
                // Fused on the fallback path is only of interest for pulp (software fma).
                if mode == Mode::FUSED && isa == Isa::Fallback && krate != "pulp" {
                    continue;
                }
                all.push((format!("{krate}/{path}/{mode_name}"), Box::new(move |s, h, o| shade(isa, mode, s, h, o))));
            }
        }
    }
    all.push(("pulp/scalar128/exact".into(), Box::new(|s, h, o| pulp_arch::shade_scalar128(Mode::EXACT, s, h, o))));
    let sse4_2 = fearless::sse4_2();
    all.push((
        "fearless/sse4.2/exact".into(),
        Box::new(move |s, h, o| fearless::shade_at(sse4_2, Mode::EXACT, s, h, o)),
    ));
    let best = fearless_simd::Level::new();
    all.push(("fearless/best/exact".into(), Box::new(move |s, h, o| fearless::shade_at(best, Mode::EXACT, s, h, o))));
    // What a program runs: Isa::current(), so STEREOTRACE_LANES=4 makes this the fallback.
    let current = Isa::current();
    all.push((
        format!("current/{current:?}/exact"),
        Box::new(move |s, h, o| fearless::shade(current, Mode::EXACT, s, h, o)),
    ));
    all
}

fn shade<M: Measurement>(c: &mut Criterion<M>, group: &str) {
    let scene = hits::seed_scene();
    let h = hits::generate(N, 7);
    let mut out = Shaded::new(N);
    srgb::warm();
    let mut group = c.benchmark_group(group);
    group.throughput(Throughput::Elements(N as u64));
    group.warm_up_time(Duration::from_millis(500));
    group.measurement_time(Duration::from_secs(2));
    for (name, kernel) in kernels() {
        group.bench_function(&name, |b| b.iter(|| kernel(black_box(&scene), black_box(&h), black_box(&mut out))));
    }
    group.finish();
}

/// CPU time of the calling thread, in nanoseconds.
struct ThreadCpu;

impl Measurement for ThreadCpu {
    type Intermediate = cpu_time::ThreadTime;
    type Value = Duration;
    fn start(&self) -> Self::Intermediate {
        cpu_time::ThreadTime::now()
    }
    fn end(&self, i: Self::Intermediate) -> Self::Value {
        i.elapsed()
    }
    fn add(&self, v1: &Self::Value, v2: &Self::Value) -> Self::Value {
        *v1 + *v2
    }
    fn zero(&self) -> Self::Value {
        Duration::ZERO
    }
    fn to_f64(&self, value: &Self::Value) -> f64 {
        value.as_nanos() as f64
    }
    fn formatter(&self) -> &dyn ValueFormatter {
        &Nanoseconds
    }
}

/// Formats values as µs and throughputs as Melem/s.
struct Nanoseconds;

impl ValueFormatter for Nanoseconds {
    fn scale_values(&self, _typical: f64, values: &mut [f64]) -> &'static str {
        for v in values.iter_mut() {
            *v /= 1e3;
        }
        "µs (CPU)"
    }
    fn scale_throughputs(&self, _typical: f64, throughput: &Throughput, values: &mut [f64]) -> &'static str {
        let per = match *throughput {
            Throughput::Elements(n) | Throughput::Bytes(n) | Throughput::BytesDecimal(n) | Throughput::Bits(n) => n,
        } as f64;
        for v in values.iter_mut() {
            *v = per * 1e3 / *v;
        }
        "Melem/s (CPU)"
    }
    fn scale_for_machines(&self, _values: &mut [f64]) -> &'static str {
        "ns"
    }
}

fn main() {
    if std::env::var_os("SIMD_EVAL_CPU_TIME").is_some() {
        let mut c = Criterion::default().with_measurement(ThreadCpu).configure_from_args();
        shade(&mut c, "shade_4096_cpu");
        c.final_summary();
    } else {
        let mut c = Criterion::<WallTime>::default().configure_from_args();
        shade(&mut c, "shade_4096");
        c.final_summary();
    }
}

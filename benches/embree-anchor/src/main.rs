//! A same-machine anchor for stereotrace's trace speed: its left eye, traced fully
//! (`Renderer::render`, primary + shadow + mirror rays), against Embree 3 casting the same
//! rays over the same spheres, in the same process, alternating frame by frame: Embree's
//! sphere points or a user-geometry sphere, each with single primary rays (`rtcIntersect1`)
//! or packets of 8 (`rtcIntersect8`); shadow and mirror rays single (`rtcOccluded1` /
//! `rtcIntersect1`). Outside the product: see README.md.

mod embree;
mod field;
mod process;
mod whitted;

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Instant;

use rayon::prelude::*;
use rayon::ThreadPool;
use tracer::{Eye, Pixels, RayCounts, Renderer, Scene, Target, Tracer, NO_OBJECT};

use embree::{Callbacks, Device, Geometry, Quality, Spheres};
use whitted::Whitted;

const USAGE: &str = "\
embree-anchor [--spheres N,N,...] [--deep N,N,...] [--scene PATH ...]
              [--width W --height H] [--frames N]
              [--threads T] [--no-single] [--seed S] [--quality low|medium|high]
              [--tnear T] [--no-ftz] [--depth D] [--csv FILE] [--only ours|embree]
              [--embree point1,point8,user1,user8]

Traces the left eye of each scene with stereotrace and with Embree 3 (the same rays), and
prints markdown tables. Without --spheres or --scene: seed, many and thousand.toml and
fields of 1k, 10k and 100k spheres; --deep adds deep fields (non-overlapping spheres
filling the view frustum, src/field.rs). --depth overrides the scenes' reflection depth; --csv
appends each scene's medians to a file (to take medians over runs); --only ours|embree
times one side alone (for a profiler), skipping the other and the per-pixel comparison.
--embree picks Embree's configurations (default all four): point = RTC_GEOMETRY_TYPE_SPHERE_POINT,
user = a user geometry with our sphere callbacks; 1 = single primary rays, 8 = packets of 8.";

/// Which sides a run times.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Only {
    Both,
    Ours,
    Embree,
}

/// One of Embree's configurations: the spheres' geometry, and whether primary rays go in
/// packets of 8.
#[derive(Clone, Copy, PartialEq, Eq)]
struct Config {
    geometry: Geometry,
    packets: bool,
}

impl Config {
    const ALL: [Self; 4] = [
        Self { geometry: Geometry::Point, packets: false },
        Self { geometry: Geometry::Point, packets: true },
        Self { geometry: Geometry::User, packets: false },
        Self { geometry: Geometry::User, packets: true },
    ];

    /// The short name (`--embree`, CSV columns): point1, point8, user1, user8.
    fn name(self) -> &'static str {
        match (self.geometry, self.packets) {
            (Geometry::Point, false) => "point1",
            (Geometry::Point, true) => "point8",
            (Geometry::User, false) => "user1",
            (Geometry::User, true) => "user8",
        }
    }
}

struct Args {
    spheres: Vec<usize>,
    /// Deep fields' sizes (`field::deep`).
    deep: Vec<usize>,
    scenes: Vec<PathBuf>,
    width: u32,
    height: u32,
    frames: usize,
    threads: usize,
    single: bool,
    seed: u64,
    quality: Quality,
    tnear: f32,
    /// Embree's rows in flush-to-zero / denormals-are-zero mode (Embree's advice).
    ftz: bool,
    /// Overrides every scene's reflection depth.
    depth: Option<u32>,
    /// Appends each scene's medians here.
    csv: Option<PathBuf>,
    only: Only,
    /// Embree's configurations to time, in order.
    embree: Vec<Config>,
}

fn parse_args() -> Result<Args, String> {
    fn num<T: std::str::FromStr>(s: &str, flag: &str) -> Result<T, String> {
        s.parse().map_err(|_| format!("{flag}: not a number: {s}"))
    }
    fn sizes(list: &str, flag: &str) -> Result<Vec<usize>, String> {
        list.split(',')
            .map(|n| {
                let n = n.trim().to_lowercase();
                let (digits, scale) = match n.strip_suffix('k') {
                    Some(d) => (d, 1_000),
                    None => n.strip_suffix('m').map_or((n.as_str(), 1), |d| (d, 1_000_000)),
                };
                Ok(num::<usize>(digits, flag)? * scale)
            })
            .collect()
    }
    let mut args = Args {
        spheres: Vec::new(),
        deep: Vec::new(),
        scenes: Vec::new(),
        width: 1280,
        height: 720,
        frames: 7,
        threads: 2,
        single: true,
        seed: 2024,
        quality: Quality::Medium,
        tnear: 0.0,
        ftz: true,
        depth: None,
        csv: None,
        only: Only::Both,
        embree: Config::ALL.to_vec(),
    };
    let mut it = std::env::args().skip(1);
    let value = |it: &mut dyn Iterator<Item = String>, flag: &str| it.next().ok_or(format!("{flag} needs a value"));
    while let Some(a) = it.next() {
        match a.as_str() {
            "--spheres" => args.spheres.extend(sizes(&value(&mut it, &a)?, &a)?),
            "--deep" => args.deep.extend(sizes(&value(&mut it, &a)?, &a)?),
            "--scene" => args.scenes.push(value(&mut it, &a)?.into()),
            "--width" => args.width = num(&value(&mut it, &a)?, &a)?,
            "--height" => args.height = num(&value(&mut it, &a)?, &a)?,
            "--frames" => args.frames = num::<usize>(&value(&mut it, &a)?, &a)?.max(1),
            "--threads" => args.threads = num::<usize>(&value(&mut it, &a)?, &a)?.max(1),
            "--no-single" => args.single = false,
            "--no-ftz" => args.ftz = false,
            "--depth" => args.depth = Some(num(&value(&mut it, &a)?, &a)?),
            "--csv" => args.csv = Some(value(&mut it, &a)?.into()),
            "--seed" => args.seed = num(&value(&mut it, &a)?, &a)?,
            "--tnear" => args.tnear = num(&value(&mut it, &a)?, &a)?,
            "--quality" => {
                args.quality = match value(&mut it, &a)?.as_str() {
                    "low" => Quality::Low,
                    "medium" => Quality::Medium,
                    "high" => Quality::High,
                    q => return Err(format!("--quality: low, medium or high, not {q}")),
                }
            }
            "--only" => {
                args.only = match value(&mut it, &a)?.as_str() {
                    "ours" => Only::Ours,
                    "embree" => Only::Embree,
                    o => return Err(format!("--only: ours or embree, not {o}")),
                }
            }
            "--embree" => {
                args.embree = value(&mut it, &a)?
                    .split(',')
                    .map(|c| {
                        Config::ALL
                            .into_iter()
                            .find(|k| k.name() == c.trim())
                            .ok_or(format!("--embree: point1, point8, user1 or user8, not {c}"))
                    })
                    .collect::<Result<_, _>>()?;
            }
            "-h" | "--help" => return Err(USAGE.into()),
            _ => return Err(format!("unknown argument {a}\n\n{USAGE}")),
        }
    }
    if args.spheres.is_empty() && args.deep.is_empty() && args.scenes.is_empty() {
        let scenes = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/scenes");
        args.scenes = ["seed.toml", "many.toml", "thousand.toml"].iter().map(|s| scenes.join(s)).collect();
        args.spheres = vec![1_000, 10_000, 100_000];
    }
    Ok(args)
}

/// How the two tracers' ray trees differ over a frame, pixel by pixel.
#[derive(Clone, Copy, Default)]
struct Mismatch {
    /// Pixels whose primary rays hit different spheres (or one hit and one missed).
    first_hit: u64,
    /// Pixels whose ray counts differ in any kind.
    tree: u64,
    /// Embree's secondary rays whose first hit was the sphere they leave.
    self_hits: u64,
    /// Σ over pixels and kinds of |our count − Embree's|: rays in one tree and not the other.
    rays: u64,
    /// Our plain path's counts summed over the pixels (equal to the renderer's).
    plain: RayCounts,
}

impl std::ops::Add for Mismatch {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            first_hit: self.first_hit + o.first_hit,
            tree: self.tree + o.tree,
            self_hits: self.self_hits + o.self_hits,
            rays: self.rays + o.rays,
            plain: self.plain + o.plain,
        }
    }
}

/// One side's frame times, ms: wall and process CPU time, with all the pool's threads and
/// with one.
#[derive(Default)]
struct Times {
    wall: [Vec<f64>; 2],
    cpu: [Vec<f64>; 2],
}

/// The medians of [`Times`]: `[threads, 1 thread]`.
#[derive(Clone, Copy, Default)]
struct Medians {
    wall: [Option<f64>; 2],
    cpu: [Option<f64>; 2],
}

impl Times {
    fn medians(mut self) -> Medians {
        let [w0, w1] = &mut self.wall;
        let [c0, c1] = &mut self.cpu;
        Medians { wall: [median(w0), median(w1)], cpu: [median(c0), median(c1)] }
    }
}

/// One Embree configuration's frames in a scene.
struct EmbreeRun {
    config: Config,
    /// Rays cast per frame, by kind.
    counts: RayCounts,
    ms: Medians,
    /// With the user geometry: how Embree called its callbacks over an untimed frame.
    callbacks: Option<Callbacks>,
}

/// One geometry's Embree build: time, bytes, and how its ray trees differ from ours.
struct Build {
    geometry: Geometry,
    ms: f64,
    bytes_monitor: isize,
    bytes_rss: i64,
    mismatch: Option<Mismatch>,
}

/// One scene's row of every table.
struct Row {
    name: String,
    spheres: usize,
    ours: RayCounts,
    ours_ms: Medians,
    ours_build_ms: f64,
    ours_bytes: i64,
    embree: Vec<EmbreeRun>,
    builds: Vec<Build>,
}

impl Row {
    /// The Embree configuration `c`'s frames, if it ran.
    fn config(&self, c: Config) -> Option<&EmbreeRun> {
        self.embree.iter().find(|e| e.config == c)
    }

    /// Embree's fastest configuration here (median wall time, all the pool's threads).
    fn best(&self) -> Option<&EmbreeRun> {
        self.embree
            .iter()
            .filter(|e| e.ms.wall[0].is_some())
            .min_by(|a, b| a.ms.wall[0].unwrap_or(f64::INFINITY).total_cmp(&b.ms.wall[0].unwrap_or(f64::INFINITY)))
    }

    /// The geometry `g`'s build, if built.
    fn build(&self, g: Geometry) -> Option<&Build> {
        self.builds.iter().find(|b| b.geometry == g)
    }
}

fn median(v: &mut [f64]) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    v.sort_by(f64::total_cmp);
    let m = v.len() / 2;
    Some(if v.len() % 2 == 1 { v[m] } else { f64::midpoint(v[m - 1], v[m]) })
}

fn ms(since: Instant) -> f64 {
    since.elapsed().as_secs_f64() * 1e3
}

/// Compares the two ray trees of every pixel (untimed): our plain path
/// (`Tracer::trace_pixel`, bit for bit the renderer's) against Embree's with self-hits probed.
fn compare(tracer: &Tracer, whitted: &Whitted, view: &tracer::EyeView) -> Mismatch {
    (0..view.height)
        .into_par_iter()
        .map(|j| {
            let mut m = Mismatch::default();
            for i in 0..view.width {
                let mut ours = RayCounts::default();
                let shaded = tracer.trace_pixel(view, i, j, &mut ours);
                let theirs = whitted.probe(view, i, j);
                let first = if shaded.surface.object == NO_OBJECT { u32::MAX } else { shaded.surface.object };
                m.first_hit += u64::from(first != theirs.first);
                m.tree += u64::from(ours != theirs.counts);
                m.self_hits += theirs.self_hits;
                let (a, b) = (ours, theirs.counts);
                m.rays +=
                    a.primary.abs_diff(b.primary) + a.shadow.abs_diff(b.shadow) + a.reflection.abs_diff(b.reflection);
                m.plain += ours;
            }
            m
        })
        .reduce(Mismatch::default, |a, b| a + b)
}

/// Which side a frame times: ours, or Embree's configuration k of `Args::embree`.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    Ours,
    Embree(usize),
}

#[expect(clippy::too_many_lines, reason = "one scene's measurement, step by step")]
fn run(name: String, scene: &Scene, args: &Args, device: &Device, pools: (&ThreadPool, &ThreadPool)) -> Row {
    let (w, h) = (args.width, args.height);
    let mut depth_override;
    let scene = match args.depth {
        Some(d) => {
            depth_override = scene.clone();
            depth_override.render.max_depth = d;
            &depth_override
        }
        None => scene,
    };
    let n = scene.spheres.len();
    eprintln!("[{name}] {n} spheres, {w}×{h}");
    let view = scene.camera.view(Eye::Left, w, h);

    let rss0 = process::resident();
    let t0 = Instant::now();
    let tracer = Tracer::new(scene, 0.0);
    let ours_build_ms = ms(t0);
    let ours_bytes = process::resident() as i64 - rss0 as i64;
    eprintln!("[{name}] ours: Tracer::new {ours_build_ms:.0} ms, RSS +{:.1} MB", ours_bytes as f64 / 1e6);

    // Each geometry the configurations need, built once.
    let configs: &[Config] = if args.only == Only::Ours { &[] } else { &args.embree };
    let mut builds = Vec::new();
    let mut built = Vec::new();
    for geometry in [Geometry::Point, Geometry::User] {
        if !configs.iter().any(|c| c.geometry == geometry) {
            continue;
        }
        let (rss1, mon1) = (process::resident(), Device::bytes());
        let t1 = Instant::now();
        let s = tracer.snapshot();
        let spheres =
            Spheres::build(device, s.centers(), s.radii(), geometry, args.quality).unwrap_or_else(|e| panic!("{e}"));
        let build = Build {
            geometry,
            ms: ms(t1),
            bytes_rss: process::resident() as i64 - rss1 as i64,
            bytes_monitor: Device::bytes() - mon1,
            mismatch: None,
        };
        eprintln!(
            "[{name}] Embree {geometry:?}: build {:.0} ms, {:.1} MB (monitor), RSS +{:.1} MB",
            build.ms,
            build.bytes_monitor as f64 / 1e6,
            build.bytes_rss as f64 / 1e6
        );
        builds.push(build);
        built.push((geometry, spheres));
    }
    let spheres_of = |g: Geometry| &built.iter().find(|(b, _)| *b == g).expect("built above").1;
    let whitted: Vec<Whitted> = configs
        .iter()
        .map(|c| Whitted::new(spheres_of(c.geometry), &tracer, args.tnear, args.ftz, c.packets))
        .collect();

    // Untimed: each geometry's ray trees against ours, pixel by pixel (single rays; packets
    // change only how the primary rays are asked).
    if args.only == Only::Both {
        for b in &mut builds {
            let wh = Whitted::new(spheres_of(b.geometry), &tracer, args.tnear, args.ftz, false);
            let t = Instant::now();
            let m = pools.0.install(|| compare(&tracer, &wh, &view));
            eprintln!(
                "[{name}] {:?}: compared every pixel in {:.0} ms: first hit differs {}, ray tree differs {}, Embree self-hits {}",
                b.geometry,
                ms(t),
                m.first_hit,
                m.tree,
                m.self_hits
            );
            b.mismatch = Some(m);
        }
    }
    // Untimed: how Embree calls the user geometry's callbacks, single rays or packets.
    let callbacks: Vec<Option<Callbacks>> = configs
        .iter()
        .zip(&whitted)
        .map(|(c, wh)| {
            (c.geometry == Geometry::User).then(|| {
                embree::count_callbacks();
                std::hint::black_box(pools.0.install(|| wh.render(&view)));
                let k = embree::callbacks_counted();
                eprintln!(
                    "[{name}] {}: callbacks with N = 1: {}, with N > 1: {} ({:.2} valid lanes on average)",
                    c.name(),
                    k.single,
                    k.packets,
                    k.packet_lanes as f64 / k.packets.max(1) as f64
                );
                k
            })
        })
        .collect();

    let mut renderer = Renderer::new();
    let mut rgb = Vec::new();
    let mut ours_frame = |pool: &ThreadPool| {
        let (t, cpu) = (Instant::now(), process::cpu_ms());
        let c = pool.install(|| renderer.render(&tracer, &view, Pixels::All, Target::colour(&mut rgb)));
        (ms(t), process::cpu_ms() - cpu, c)
    };
    let embree_frame = |k: usize, pool: &ThreadPool| {
        let (t, cpu) = (Instant::now(), process::cpu_ms());
        let (c, sum) = pool.install(|| whitted[k].render(&view));
        std::hint::black_box(sum);
        (ms(t), process::cpu_ms() - cpu, c)
    };
    let mut sides = Vec::new();
    if args.only != Only::Embree {
        sides.push(Side::Ours);
    }
    sides.extend((0..configs.len()).map(Side::Embree));
    // Times and ray counts: ours, then each configuration's.
    let mut times: Vec<Times> = sides.iter().map(|_| Times::default()).collect();
    let mut seen: Vec<Option<RayCounts>> = vec![None; sides.len()];
    let who = |side: Side| match side {
        Side::Ours => "ours",
        Side::Embree(k) => configs[k].name(),
    };
    // Frame 0 warms every side up; then each frame takes the sides in turn, reversing the
    // order every other frame.
    for f in 0..=args.frames {
        let order: Vec<usize> = if f % 2 == 0 { (0..sides.len()).collect() } else { (0..sides.len()).rev().collect() };
        for s in order {
            let mut pool_list = vec![(pools.0, 0)];
            if args.single {
                pool_list.push((pools.1, 1));
            }
            for (pool, k) in pool_list {
                let (t, cpu, c) = match sides[s] {
                    Side::Ours => ours_frame(pool),
                    Side::Embree(e) => embree_frame(e, pool),
                };
                if seen[s].is_some_and(|s| s != c) {
                    eprintln!(
                        "[{name}] {}: ray counts changed between frames: {:?} then {c:?}",
                        who(sides[s]),
                        seen[s]
                    );
                }
                seen[s] = Some(c);
                if f > 0 {
                    times[s].wall[k].push(t);
                    times[s].cpu[k].push(cpu);
                }
            }
        }
        eprint!("\r[{name}] frame {f}/{}", args.frames);
    }
    eprintln!();
    let mut medians = times.into_iter().map(Times::medians);
    let ours_ms = if args.only == Only::Embree { Medians::default() } else { medians.next().unwrap_or_default() };
    let mut seen = seen.into_iter();
    let ours = if args.only == Only::Embree { RayCounts::default() } else { seen.next().flatten().unwrap_or_default() };
    let embree: Vec<EmbreeRun> = configs
        .iter()
        .zip(medians.zip(seen))
        .zip(callbacks)
        .map(|((&config, (ms, counts)), callbacks)| EmbreeRun {
            config,
            counts: counts.unwrap_or_default(),
            ms,
            callbacks,
        })
        .collect();
    for b in &builds {
        if let Some(m) = &b.mismatch {
            if m.plain != ours {
                eprintln!("[{name}] note: the plain path counted {:?}, the renderer {ours:?}", m.plain);
            }
        }
    }
    let row = Row { name, spheres: n, ours, ours_ms, ours_build_ms, ours_bytes, embree, builds };
    let show =
        |m: &Medians| format!("{} ms (CPU {}), 1 thread {}", fmt_ms(m.wall[0]), fmt_ms(m.cpu[0]), fmt_ms(m.wall[1]));
    eprintln!("[{}] ours {}", row.name, show(&row.ours_ms));
    for e in &row.embree {
        eprintln!("[{}] {} {}", row.name, e.config.name(), show(&e.ms));
    }
    if let Some(path) = &args.csv {
        if let Err(e) = append_csv(path, &row, args) {
            eprintln!("{}: {e}", path.display());
        }
    }
    row
}

fn fmt_ms(v: Option<f64>) -> String {
    v.map_or("–".into(), |v| if v < 100.0 { format!("{v:.1}") } else { format!("{v:.0}") })
}

/// Mrays per second of CPU time (per core busy).
fn rate(rays: RayCounts, cpu_ms: Option<f64>) -> String {
    cpu_ms.map_or("–".into(), |ms| format!("{:.1}", rays.total() as f64 / (ms * 1e3)))
}

fn ratio(a: Option<f64>, b: Option<f64>) -> String {
    match (a, b) {
        (Some(a), Some(b)) => format!("{:.2}", a / b),
        _ => "–".into(),
    }
}

fn count(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (k, c) in s.chars().enumerate() {
        if k > 0 && (s.len() - k).is_multiple_of(3) {
            out.push('\u{202f}');
        }
        out.push(c);
    }
    out
}

fn spheres_label(n: usize) -> String {
    match n {
        n if n >= 1_000_000 && n % 1_000_000 == 0 => format!("{}M", n / 1_000_000),
        n if n >= 1_000 && n % 1_000 == 0 => format!("{}k", n / 1_000),
        n => n.to_string(),
    }
}

fn share(part: u64, whole: u64) -> String {
    if whole == 0 {
        return "–".into();
    }
    let p = 100.0 * part as f64 / whole as f64;
    if p == 0.0 {
        "0".into()
    } else if p < 0.01 {
        format!("{p:.4} %")
    } else {
        format!("{p:.2} %")
    }
}

fn signed_share(a: u64, b: u64) -> String {
    if a == 0 {
        return "–".into();
    }
    if a == b {
        return "0".into();
    }
    let p = 100.0 * (b as f64 - a as f64) / a.max(1) as f64;
    format!("{p:+.4} %")
}

/// A ratio's cell, or "–".
fn cell(v: Option<&EmbreeRun>, f: impl Fn(&EmbreeRun) -> String) -> String {
    v.map_or("–".into(), f)
}

#[expect(clippy::too_many_lines, reason = "three tables, column by column")]
fn print_tables(rows: &[Row], args: &Args) {
    let (w, h, t) = (args.width, args.height, args.threads);
    println!("### Speed: the left eye, {t} threads over rows (medians of {} alternating frames)\n", args.frames);
    println!(
        "Ours: `Renderer::render` into a colour target (full Whitted shading). Embree: the same rays, \
         shading nothing, in four configurations: point = `RTC_GEOMETRY_TYPE_SPHERE_POINT`, user = a \
         user geometry with our ray–sphere callbacks; 1 = single primary rays (`rtcIntersect1`), \
         8 = packets of 8 primary rays (`rtcIntersect8`, 8 neighbouring pixels of a row); shadow and \
         mirror rays single in all four. ms: wall time; Embree best: its fastest configuration here \
         (wall); ratios: ours ÷ Embree's time (below 1: ours is faster), wall, and process CPU (on a \
         shared machine the CPU ratio is the steadier); Mrays/s per core: all rays ÷ CPU time.\n"
    );
    println!(
        "| scene | spheres | W×H | rays | ours ms | point1 ms | point8 ms | user1 ms | user8 ms | Embree best | \
         ours ÷ best | CPU: ours ÷ best | ours ÷ point1 | CPU: ours ÷ point1 | ours ÷ point8 | ours ÷ user1 | \
         ours ÷ user8 | ours Mrays/s/core | best Mrays/s/core | 1 thread: ours ÷ best | 1 thread: ours ÷ point1 |"
    );
    println!("|---|---:|---|---:|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for r in rows {
        let o = &r.ours_ms;
        let [p1, p8, u1, u8] = Config::ALL.map(|c| r.config(c));
        let best = r.best();
        let wall = |e: &EmbreeRun| ratio(o.wall[0], e.ms.wall[0]);
        let cpu = |e: &EmbreeRun| ratio(o.cpu[0], e.ms.cpu[0]);
        let one = |e: &EmbreeRun| ratio(o.wall[1], e.ms.wall[1]);
        println!(
            "| {} | {} | {w}×{h} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
            r.name,
            count(r.spheres as u64),
            count(if r.ours.total() > 0 { r.ours.total() } else { r.embree.first().map_or(0, |e| e.counts.total()) }),
            fmt_ms(o.wall[0]),
            cell(p1, |e| fmt_ms(e.ms.wall[0])),
            cell(p8, |e| fmt_ms(e.ms.wall[0])),
            cell(u1, |e| fmt_ms(e.ms.wall[0])),
            cell(u8, |e| fmt_ms(e.ms.wall[0])),
            cell(best, |e| e.config.name().into()),
            cell(best, wall),
            cell(best, cpu),
            cell(p1, wall),
            cell(p1, cpu),
            cell(p8, wall),
            cell(u1, wall),
            cell(u8, wall),
            rate(r.ours, o.cpu[0]),
            cell(best, |e| rate(e.counts, e.ms.cpu[0])),
            cell(best, one),
            cell(p1, one),
        );
    }
    if rows.iter().any(|r| r.embree.iter().any(|e| e.callbacks.is_some())) {
        println!("\n### How Embree called the user geometry's callbacks (one untimed frame)\n");
        println!(
            "Calls with one ray (N = 1) and with a packet (N = 8), and the valid lanes a packet call \
             carried on average. Packets of 8 primary rays reach the callbacks as N = 8 only where \
             Embree's packet traversal keeps them together; shadow and mirror rays are single.\n"
        );
        println!("| scene | configuration | calls, N = 1 | calls, N = 8 | valid lanes per N = 8 call |");
        println!("|---|---|---:|---:|---:|");
        for r in rows {
            for e in &r.embree {
                if let Some(k) = e.callbacks {
                    let lanes = if k.packets == 0 {
                        "–".into()
                    } else {
                        format!("{:.2}", k.packet_lanes as f64 / k.packets as f64)
                    };
                    println!(
                        "| {} | {} | {} | {} | {lanes} |",
                        r.name,
                        e.config.name(),
                        count(k.single),
                        count(k.packets)
                    );
                }
            }
        }
    }
    println!("\n### Rays: ours against Embree's, and where the trees differ\n");
    println!(
        "Shadow and mirror rays as each side counted them (point1; one primary ray per pixel on all \
         sides), and every configuration's rays against ours. Then pixel by pixel, our plain path \
         (`Tracer::trace_pixel`, the renderer's rays bit for bit) against Embree's single rays, \
         sphere points and the user geometry: pixels whose primary rays hit different spheres, \
         pixels whose ray counts differ, rays in one tree and not the other (Σ|Δ| over pixels and \
         kinds), and Embree secondary rays whose first hit was the sphere they leave (ours never \
         tests it).\n"
    );
    println!(
        "| scene | primary | shadow: ours | shadow: point1 | mirror: ours | mirror: point1 | all rays, each configuration vs ours | \
         point: pixels, first hit differs | point: pixels, ray tree differs | point: rays differing | point: self-hits | \
         user: pixels, first hit differs | user: pixels, ray tree differs | user: rays differing | user: self-hits |"
    );
    println!("|---|---:|---:|---:|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|");
    let px = u64::from(w) * u64::from(h);
    for r in rows {
        let p1 = r.config(Config::ALL[0]).map(|e| e.counts);
        let vs = r
            .embree
            .iter()
            .map(|e| format!("{} {}", e.config.name(), signed_share(r.ours.total(), e.counts.total())))
            .collect::<Vec<_>>();
        let diff = |g: Geometry| {
            r.build(g).and_then(|b| b.mismatch).map_or_else(
                || ["–".to_string(), "–".into(), "–".into(), "–".into()],
                |m| {
                    [
                        format!("{} ({})", m.first_hit, share(m.first_hit, px)),
                        format!("{} ({})", m.tree, share(m.tree, px)),
                        format!("{} ({})", m.rays, share(m.rays, r.ours.total())),
                        m.self_hits.to_string(),
                    ]
                },
            )
        };
        let [pf, pt, pr, ps] = diff(Geometry::Point);
        let [uf, ut, ur, us] = diff(Geometry::User);
        println!(
            "| {} | {} | {} | {} | {} | {} | {} | {pf} | {pt} | {pr} | {ps} | {uf} | {ut} | {ur} | {us} |",
            r.name,
            count(r.ours.primary),
            count(r.ours.shadow),
            p1.map_or("–".into(), |c| count(c.shadow)),
            count(r.ours.reflection),
            p1.map_or("–".into(), |c| count(c.reflection)),
            vs.join(", "),
        );
    }
    println!("\n### Build and memory\n");
    println!(
        "Ours: `Tracer::new` (snapshot and aggregate) and the resident memory's growth over it. \
         Embree, per geometry: the sphere buffer (or user data), geometry and scene commit; the \
         bytes its memory monitor counted, and the resident memory's growth.\n"
    );
    println!(
        "| scene | spheres | ours build ms | ours MB (RSS Δ) | point build ms | point MB (monitor) | point MB (RSS Δ) | \
         user build ms | user MB (monitor) | user MB (RSS Δ) |"
    );
    println!("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    for r in rows {
        let b = |g: Geometry| {
            r.build(g).map_or_else(
                || ["–".to_string(), "–".into(), "–".into()],
                |b| {
                    [
                        fmt_ms(Some(b.ms)),
                        format!("{:.2}", b.bytes_monitor as f64 / 1e6),
                        format!("{:.2}", b.bytes_rss as f64 / 1e6),
                    ]
                },
            )
        };
        let [pb, pm, pr] = b(Geometry::Point);
        let [ub, um, ur] = b(Geometry::User);
        println!(
            "| {} | {} | {} | {:.2} | {pb} | {pm} | {pr} | {ub} | {um} | {ur} |",
            r.name,
            count(r.spheres as u64),
            fmt_ms(Some(r.ours_build_ms)),
            r.ours_bytes as f64 / 1e6,
        );
    }
}

/// Appends `row`'s medians to the CSV file at `path` (a header first when it is new). Per
/// Embree configuration c (point1, point8, user1, user8): `c_ms`, `c_cpu_ms`, `c_ms_1`,
/// `c_rays`, empty where it did not run; mismatches are the sphere points'.
fn append_csv(path: &std::path::Path, row: &Row, args: &Args) -> std::io::Result<()> {
    use std::io::Write;
    let new = !path.exists();
    let mut f = std::fs::OpenOptions::new().create(true).append(true).open(path)?;
    if new {
        let configs = Config::ALL.map(Config::name).map(|c| format!("{c}_ms,{c}_cpu_ms,{c}_ms_1,{c}_rays,")).concat();
        writeln!(
            f,
            "scene,spheres,width,height,threads,ours_rays,ours_ms,ours_cpu_ms,ours_ms_1,{configs}\
             ours_build_ms,ours_mb,point_build_ms,point_mb,user_build_ms,user_mb,first_hit_differs,tree_differs,rays_differ"
        )?;
    }
    let o = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v:.3}"));
    let configs = Config::ALL
        .map(|c| match row.config(c) {
            Some(e) => format!("{},{},{},{},", o(e.ms.wall[0]), o(e.ms.cpu[0]), o(e.ms.wall[1]), e.counts.total()),
            None => ",,,,".into(),
        })
        .concat();
    let build =
        |g: Geometry| row.build(g).map_or(",".into(), |b| format!("{:.3},{:.3}", b.ms, b.bytes_monitor as f64 / 1e6));
    let m = row.build(Geometry::Point).and_then(|b| b.mismatch).unwrap_or_default();
    writeln!(
        f,
        "{},{},{},{},{},{},{},{},{},{configs}{:.3},{:.3},{},{},{},{},{}",
        row.name,
        row.spheres,
        args.width,
        args.height,
        args.threads,
        row.ours.total(),
        o(row.ours_ms.wall[0]),
        o(row.ours_ms.cpu[0]),
        o(row.ours_ms.wall[1]),
        row.ours_build_ms,
        row.ours_bytes as f64 / 1e6,
        build(Geometry::Point),
        build(Geometry::User),
        m.first_hit,
        m.tree,
        m.rays
    )
}

fn load_average() -> String {
    std::fs::read_to_string("/proc/loadavg")
        .ok()
        .and_then(|s| s.split_whitespace().next().map(String::from))
        .unwrap_or_default()
}

fn cpu_model() -> String {
    std::fs::read_to_string("/proc/cpuinfo")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("model name"))
                .and_then(|l| l.split(':').nth(1))
                .map(|m| m.trim().to_string())
        })
        .unwrap_or_default()
}

fn git_commit() -> String {
    std::process::Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .ok()
        .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
        .unwrap_or_default()
}

fn main() -> ExitCode {
    let args = match parse_args() {
        Ok(a) => a,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::from(2);
        }
    };
    let pool = |n| rayon::ThreadPoolBuilder::new().num_threads(n).build().expect("a thread pool");
    let (multi, single) = (pool(args.threads), pool(1));
    let device = match Device::new(&format!(
        "threads={}{}",
        args.threads,
        std::env::var("EMBREE_CONFIG").map(|c| format!(",{c}")).unwrap_or_default()
    )) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("{e}");
            return ExitCode::FAILURE;
        }
    };
    let load_before = load_average();
    let mut rows = Vec::new();
    for path in &args.scenes {
        let scene = match Scene::load(path) {
            Ok(s) => s,
            Err(e) => {
                eprintln!("{e}");
                return ExitCode::from(2);
            }
        };
        let name = path.file_name().map_or_else(|| path.display().to_string(), |f| f.to_string_lossy().into_owned());
        rows.push(run(name, &scene, &args, &device, (&multi, &single)));
    }
    for &n in &args.spheres {
        let t = Instant::now();
        let scene = field::field(n, args.seed);
        eprintln!("[field {}] generated in {:.0} ms", spheres_label(n), ms(t));
        rows.push(run(format!("field {}", spheres_label(n)), &scene, &args, &device, (&multi, &single)));
    }
    for &n in &args.deep {
        let t = Instant::now();
        let (scene, tries) = field::deep(n, args.seed);
        let label = format!("deep {}", spheres_label(n));
        let placed = scene.spheres.len();
        eprintln!("[{label}] generated in {:.0} ms: {placed} spheres placed from {tries} candidates", ms(t));
        if placed < n {
            eprintln!("[{label}] note: only {placed} of {n} spheres fit");
        }
        rows.push(run(label, &scene, &args, &device, (&multi, &single)));
    }
    let v = device.version();
    println!("## stereotrace against Embree {}.{}.{}, same machine, same rays\n", v / 10000, v / 100 % 100, v % 100);
    println!(
        "- commit `{}`; CPU {} ({} logical); {} rayon threads; stereotrace lanes {}; Embree configurations {}, build quality {:?}, secondary tnear {}, Embree's rows with FTZ/DAZ {}",
        git_commit(),
        cpu_model(),
        std::thread::available_parallelism().map_or(0, std::num::NonZero::get),
        args.threads,
        tracer::lane_width(),
        args.embree.iter().map(|c| c.name()).collect::<Vec<_>>().join(", "),
        args.quality,
        args.tnear,
        if args.ftz { "on" } else { "off" }
    );
    println!("- load average (1 min) {load_before} before the first scene, {} after the last", load_average());
    println!(
        "- reflection depth: {}; generated fields: seed {}, `benches/embree-anchor/src/field.rs`\n",
        args.depth.map_or("the scene's".into(), |d| d.to_string()),
        args.seed
    );
    print_tables(&rows, &args);
    ExitCode::SUCCESS
}

//! The bench that chose this crate's own PDB reader over `pdbtbx` (the crate doc has the
//! numbers): time (criterion) and peak heap (a counting allocator) to read 1TII (pymol-data)
//! and 2BTV (`shared/molecules`) from bytes already in memory and decompressed, into compact
//! positions and elements, and 2BTV's 60-operator assembly (2,943,660 atoms); then how
//! `pdbtbx` takes malformed input. A missing file is skipped with a note.
//!
//! `cargo bench -p molecule --bench readers` (add `-- --quick` for a shorter run).
#![expect(missing_docs, reason = "criterion_group! generates undocumented items")]
#![expect(unsafe_code, reason = "a counting global allocator is unsafe by nature; it only forwards to System")]
#![expect(clippy::expect_used, reason = "a bench whose input does not parse has nothing to measure")]

use std::alloc::{GlobalAlloc, Layout, System};
use std::hint::black_box;
use std::io::{BufReader, Read};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use criterion::{criterion_group, Criterion};
use glam::Vec3;
use molecule::{Element, ReadOptions};

/// Forwards to the system allocator, counting live bytes and their peak.
struct Counting;

static LIVE: AtomicUsize = AtomicUsize::new(0);
static PEAK: AtomicUsize = AtomicUsize::new(0);

// SAFETY: every call is forwarded unchanged to `System`; the counters are only statistics.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        // SAFETY: the caller's contract is passed on to System as it is.
        let p = unsafe { System.alloc(layout) };
        if !p.is_null() {
            let live = LIVE.fetch_add(layout.size(), Ordering::Relaxed) + layout.size();
            PEAK.fetch_max(live, Ordering::Relaxed);
        }
        p
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) };
        LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: as above.
        let p = unsafe { System.realloc(ptr, layout, new_size) };
        if !p.is_null() {
            LIVE.fetch_sub(layout.size(), Ordering::Relaxed);
            let live = LIVE.fetch_add(new_size, Ordering::Relaxed) + new_size;
            PEAK.fetch_max(live, Ordering::Relaxed);
        }
        p
    }
}

#[global_allocator]
static ALLOCATOR: Counting = Counting;

/// The heap `f` needs at its peak beyond what was live before it, and its result.
fn peak_heap<T>(f: impl FnOnce() -> T) -> (T, usize) {
    let before = LIVE.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let out = f();
    (out, PEAK.load(Ordering::Relaxed) - before)
}

const ONE_TII: &str = "/usr/share/pymol/data/demo/1tii.pdb";
const TWO_BTV: &str = "../../../shared/molecules/2btv.pdb.gz";

/// The file's text, decompressed when gzipped; `None` (with a note) when it is absent.
fn text_of(path: &str) -> Option<Vec<u8>> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(path);
    let Ok(bytes) = std::fs::read(&path) else {
        eprintln!("SKIPPED: {} is absent", path.display());
        return None;
    };
    if !bytes.starts_with(&[0x1f, 0x8b]) {
        return Some(bytes);
    }
    let mut text = Vec::new();
    flate2::read::MultiGzDecoder::new(&bytes[..]).read_to_end(&mut text).expect("the shared file decompresses");
    Some(text)
}

/// Ours: the compact molecule (its positions and elements are the arrays the tracer takes).
fn ours(text: &[u8], name: &str, assembly: bool) -> molecule::Molecule {
    let options = ReadOptions { format: Some(molecule::Format::Pdb), assembly, ..ReadOptions::default() };
    molecule::parse(text, name, &options).expect("our reader reads the file")
}

/// pdbtbx at its most lenient level; `atoms_only` skips every record but the coordinates
/// (and so REMARK 350). The error is the first breaking error's summary.
fn pdbtbx_try(text: &[u8], atoms_only: bool) -> Result<pdbtbx::PDB, String> {
    pdbtbx::ReadOptions::new()
        .set_format(pdbtbx::Format::Pdb)
        .set_level(pdbtbx::StrictnessLevel::Loose)
        .set_only_atomic_coords(atoms_only)
        .read_raw(BufReader::new(text))
        .map(|(pdb, _warnings)| pdb)
        .map_err(|errors| {
            let breaking = errors.iter().filter(|e| e.fails(pdbtbx::StrictnessLevel::Loose)).count();
            let first = errors
                .iter()
                .find(|e| e.fails(pdbtbx::StrictnessLevel::Loose))
                .map(ToString::to_string)
                .unwrap_or_default();
            format!("{breaking} breaking errors, the first: {}", first.replace('\n', " / "))
        })
}

fn pdbtbx_read(text: &[u8], atoms_only: bool) -> pdbtbx::PDB {
    pdbtbx_try(text, atoms_only).expect("pdbtbx reads the file")
}

/// pdbtbx (coordinates only: 1TII does not read whole), then the same compact arrays taken
/// from its hierarchy (what the tracer would do).
fn pdbtbx_compact(text: &[u8]) -> (Vec<Vec3>, Vec<Element>) {
    let pdb = pdbtbx_read(text, true);
    let positions = pdb.atoms().map(|a| Vec3::new(a.x() as f32, a.y() as f32, -a.z() as f32)).collect();
    let elements = pdb.atoms().map(element_of).collect();
    (positions, elements)
}

fn element_of(atom: &pdbtbx::Atom) -> Element {
    atom.element()
        .and_then(|e| u8::try_from(e.atomic_number()).ok())
        .and_then(Element::from_atomic_number)
        .unwrap_or_default()
}

/// pdbtbx has no assembly expansion: its REMARK 350 text is parsed here, and every BIOMT
/// operator applied to its atoms into compact arrays (all chains: 2BTV lists every chain).
fn pdbtbx_assembly(text: &[u8]) -> (Vec<Vec3>, Vec<Element>) {
    let pdb = pdbtbx_read(text, false);
    let mut rows: Vec<[f32; 4]> = Vec::new();
    for (_, remark) in pdb.remarks().filter(|(number, _)| *number == 350) {
        let tokens: Vec<&str> = remark.split_whitespace().collect();
        if tokens.first().is_some_and(|t| t.starts_with("BIOMT")) && tokens.len() == 6 {
            let n = |i: usize| tokens[i].parse::<f32>().expect("a BIOMT number");
            rows.push([n(2), n(3), n(4), n(5)]);
        }
    }
    let atoms = pdb.atoms().count();
    let mut positions = Vec::with_capacity(atoms * rows.len() / 3);
    let mut elements = Vec::with_capacity(atoms * rows.len() / 3);
    for op in rows.chunks_exact(3) {
        for atom in pdb.atoms() {
            let (x, y, z) = (atom.x() as f32, atom.y() as f32, atom.z() as f32);
            let row = |r: &[f32; 4]| r[0] * x + r[1] * y + r[2] * z + r[3];
            positions.push(Vec3::new(row(&op[0]), row(&op[1]), -row(&op[2])));
            elements.push(element_of(atom));
        }
    }
    (positions, elements)
}

fn mib(bytes: usize) -> String {
    format!("{:.1} MiB", bytes as f64 / f64::from(1 << 20))
}

/// Peak heap and one timed run of each reader, printed once (criterion then times them well).
fn memory_report() {
    for (path, name) in [(ONE_TII, "1tii.pdb"), (TWO_BTV, "2btv.pdb")] {
        let Some(text) = text_of(path) else { continue };
        if let Err(e) = pdbtbx_try(&text, false) {
            println!("pdbtbx cannot read {name} whole: {e}");
        }
        let start = Instant::now();
        let (m, own) = peak_heap(|| ours(&text, name, false));
        let own_time = start.elapsed();
        let start = Instant::now();
        let ((p, _), theirs) = peak_heap(|| pdbtbx_compact(&text));
        let their_time = start.elapsed();
        assert_eq!(m.len(), p.len(), "both read every atom");
        println!(
            "{name}: {} atoms; peak heap ours {} ({:.0} B/atom), pdbtbx {} ({:.0} B/atom); one run ours {own_time:?}, pdbtbx {their_time:?}",
            m.len(),
            mib(own),
            own as f64 / m.len() as f64,
            mib(theirs),
            theirs as f64 / m.len() as f64
        );
        if name == "2btv.pdb" {
            let start = Instant::now();
            let (m, own) = peak_heap(|| ours(&text, name, true));
            let own_time = start.elapsed();
            let start = Instant::now();
            let ((p, _), theirs) = peak_heap(|| pdbtbx_assembly(&text));
            let their_time = start.elapsed();
            assert_eq!(m.len(), p.len(), "both build every copy");
            println!(
                "{name} assembly: {} atoms; peak heap ours {} ({:.1} B/atom; {} B/atom kept), pdbtbx + expansion {} ({:.1} B/atom); one run ours {own_time:?}, pdbtbx {their_time:?}",
                m.len(),
                mib(own),
                own as f64 / m.len() as f64,
                m.heap_bytes() / m.len(),
                mib(theirs),
                theirs as f64 / m.len() as f64
            );
        }
    }
}

/// How pdbtbx takes malformed input: a panic, or the error's text.
fn malformed_report() {
    let good = "ATOM      1  N   GLY D   1      42.053  -9.336  17.867  1.00 43.86           N  \nEND\n";
    let cases: [(&str, Vec<u8>); 5] = [
        ("non-numeric x", good.replace("42.053", "42.0a3").into_bytes()),
        ("short ATOM line", good.lines().next().map(|l| format!("{}\n", &l[..40])).unwrap_or_default().into_bytes()),
        ("empty input", Vec::new()),
        ("random bytes", (0..400_u32).map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8).collect()),
        (
            "MODEL without number",
            "MODEL\nATOM      1  N   GLY D   1      42.053  -9.336  17.867  1.00 43.86           N\n".into(),
        ),
    ];
    for (what, bytes) in cases {
        let result = catch_unwind(AssertUnwindSafe(|| {
            pdbtbx::ReadOptions::new()
                .set_format(pdbtbx::Format::Pdb)
                .set_level(pdbtbx::StrictnessLevel::Loose)
                .read_raw(BufReader::new(&bytes[..]))
                .map(|(pdb, warnings)| (pdb.atom_count(), warnings.len()))
        }));
        let said = match result {
            Err(_) => "PANICKED".to_owned(),
            Ok(Ok((atoms, warnings))) => format!("accepted: {atoms} atoms, {warnings} warnings"),
            Ok(Err(errors)) => {
                errors.iter().map(|e| format!("{e}")).collect::<Vec<_>>().join(" | ").replace('\n', " / ")
            }
        };
        let ours = molecule::parse(&bytes, "case.pdb", &ReadOptions::default()).map(|m| m.len());
        println!("pdbtbx on {what}: {said}");
        println!("  ours: {}", ours.map_or_else(|e| e.to_string(), |n| format!("{n} atoms")));
    }
}

/// pdbtbx and ours on 2,000 mutations of 1TII's first 600 lines (a byte changed, a line cut
/// short, a line dropped, by a fixed-seed generator): how many panic.
fn mutation_report() {
    let Some(text) = text_of(ONE_TII) else { return };
    let lines: Vec<&[u8]> = text.split(|&b| b == b'\n').take(600).collect();
    let mut seed = 0x9e37_79b9_7f4a_7c15_u64;
    let mut next = move |n: usize| {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed % n as u64) as usize
    };
    let hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(|_| {}));
    let (mut theirs, mut own) = (0, 0);
    let mut first_panic = String::new();
    for _ in 0..2000 {
        let mut mutated: Vec<Vec<u8>> = lines.iter().map(|l| l.to_vec()).collect();
        let at = next(mutated.len());
        match next(3) {
            0 if !mutated[at].is_empty() => {
                let k = next(mutated[at].len());
                mutated[at][k] = b"0123456789.- xA-#"[next(17)];
            }
            1 => {
                let keep = next(mutated[at].len() + 1);
                mutated[at].truncate(keep);
            }
            _ => {
                mutated.remove(at);
            }
        }
        let bytes = mutated.join(&b'\n');
        let pdbtbx_ok = catch_unwind(AssertUnwindSafe(|| {
            let _ = pdbtbx::ReadOptions::new()
                .set_format(pdbtbx::Format::Pdb)
                .set_level(pdbtbx::StrictnessLevel::Loose)
                .read_raw(BufReader::new(&bytes[..]));
        }));
        if let Err(payload) = pdbtbx_ok {
            theirs += 1;
            if first_panic.is_empty() {
                let text = payload
                    .downcast_ref::<String>()
                    .cloned()
                    .or_else(|| payload.downcast_ref::<&str>().map(|s| (*s).to_owned()));
                first_panic = text.unwrap_or_default();
            }
        }
        let ours_ok = catch_unwind(AssertUnwindSafe(|| {
            molecule::parse(&bytes, "m.pdb", &ReadOptions::default()).map(|m| m.len())
        }));
        own += usize::from(ours_ok.is_err());
    }
    std::panic::set_hook(hook);
    println!("2000 mutations of 1TII's first 600 lines: pdbtbx panicked {theirs} times (the first: {first_panic:?}), ours {own}");
}

fn readers(c: &mut Criterion) {
    for (path, name) in [(ONE_TII, "1tii.pdb"), (TWO_BTV, "2btv.pdb")] {
        let Some(text) = text_of(path) else { continue };
        let mut group = c.benchmark_group(name);
        group.sample_size(10);
        group.bench_function("ours", |b| b.iter(|| ours(black_box(&text), name, false)));
        group.bench_function("pdbtbx", |b| b.iter(|| pdbtbx_compact(black_box(&text))));
        if name == "2btv.pdb" {
            group.bench_function("ours_assembly", |b| b.iter(|| ours(black_box(&text), name, true)));
            group.bench_function("pdbtbx_assembly", |b| b.iter(|| pdbtbx_assembly(black_box(&text))));
        }
        group.finish();
    }
}

criterion_group!(benches, readers);

fn main() {
    memory_report();
    malformed_report();
    mutation_report();
    benches();
    Criterion::default().configure_from_args().final_summary();
}

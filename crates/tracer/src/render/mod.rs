//! The parallel renderer: one eye, rows spread over rayon's pool, through one call.
//!
//! [`Renderer::render`] is given a pixel set ([`Pixels`]: all, or these pixels) and a target
//! ([`Target`]: a film keeping the record its caller names, colour only, colour and first
//! hits, or depth only, optionally marked for temporal reuse). It builds the screen bins of the view once (or,
//! for a scene of many spheres for the pixels traced, chooses the BVH instead: [`FirstHits`],
//! `accel/screen.rs`), then runs one parallel loop over the target's rows: each row's planes
//! become a [`RowSink`](crate::sink::RowSink) (`sink.rs`), with the row's marks as one more
//! column whose observer is temporal reuse's (`reuse/observer.rs`), and one row loop
//! (`row.rs`) fills it, as pbrt-v4's film takes every sample. A [`Renderer`] owns the buffers an eye
//! needs besides its image (the screen bins of its primary rays, `accel/screen.rs`), so a
//! warm renderer allocates nothing; [`Renderer::batch`] hands the same bins to whoever makes
//! an eye's pixels in batches of its own ([`PixelBatch`], `batch.rs` over `batch/`).

mod batch;
#[cfg(test)]
mod both_ways;
mod row;

use rayon::iter::Either;
use rayon::prelude::*;

use crate::accel::screen::{ScreenBins, Search};
use crate::batch::BinnedView;
use crate::bits::PixelBits;
use crate::camera::EyeView;
use crate::film::{Film, Record};
use crate::reuse::{with_marks, Marker, Marks, MarksColumn, MarksRow, Rewrite, Swept};
use crate::sink::{DepthRow, FilmRow, HitsRow, KeysRow, RgbRow, RowSink};
use crate::stats::RayCounts;
use crate::surface::Shading;
use crate::surface::NO_OBJECT;
use crate::tracer::Tracer;
use row::trace_row;

pub use batch::{BatchRow, HitsColumns, PixelBatch};

/// Renders one eye's views, keeping its screen bins from frame to frame.
#[derive(Clone, Debug, Default)]
pub struct Renderer {
    bins: ScreenBins,
    first_hits: FirstHits,
}

/// How a [`Renderer`] finds its primary rays' first hits. Every choice makes the same
/// pixels, records, marks and counts, bit for bit; only the time differs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum FirstHits {
    /// Per view, whichever is cheaper for its spheres and the rays traced: the screen bins
    /// while spheres are few for the pixels, the BVH when binning them all would cost more
    /// than the rays' BVH queries (`accel/screen.rs`).
    #[default]
    Cheaper,
    /// Always the screen bins.
    Bins,
    /// Always screen bins of the nearest spheres (at most half of them), the BVH for the
    /// rays that meet none of those nearer than the others begin.
    Sliced,
    /// Always the BVH, a lane vector of rays a packet.
    Bvh,
}

impl FirstHits {
    /// The search for `rays` primary rays of `tracer`'s scene.
    fn search(self, tracer: &Tracer, rays: u64) -> Search {
        match self {
            Self::Cheaper => Search::cheaper(tracer.scene.centers.len(), rays),
            Self::Bins => Search::Bins,
            Self::Sliced => Search::Sliced,
            Self::Bvh => Search::Bvh,
        }
    }
}

/// Which pixels of a view a render traces.
#[derive(Clone, Copy, Debug)]
pub enum Pixels<'a> {
    /// Every pixel.
    All,
    /// Only the pixels the bits name, in place: the target holds a render of the same view
    /// (the same record, and the marks when marking), at another instant of the same scene.
    /// Given every pixel that can differ between the two instants ([`Marks::select`]), the
    /// target ends as a render of every pixel would leave it, byte for byte.
    Only(&'a PixelBits),
}

/// Where a render's pixels go.
#[derive(Debug)]
pub struct Target<'a> {
    image: Image<'a>,
    /// The reuse layer: marks to keep, and the volumes to mark against.
    marking: Option<(&'a mut Marks, &'a Swept)>,
}

/// The image of a [`Target`].
#[derive(Debug)]
enum Image<'a> {
    Film(&'a mut Film, Record),
    Colour(&'a mut Vec<u32>),
    /// Colour, and the object and depth planes.
    ColourHits(&'a mut Vec<u32>, &'a mut Vec<u32>, &'a mut Vec<f32>),
    /// The depth plane, and the object plane if asked.
    Depth(&'a mut Vec<f32>, Option<&'a mut Vec<u32>>),
}

impl<'a> Target<'a> {
    /// `film` (resized to the view), keeping the parts of its visible-surface record that
    /// `record` names; the other planes are left as they were.
    #[must_use]
    pub fn film(film: &'a mut Film, record: Record) -> Self {
        Self { image: Image::Film(film, record), marking: None }
    }

    /// Colour only, into `rgb` (resized to the view), for images whose record nobody reads.
    #[must_use]
    pub fn colour(rgb: &'a mut Vec<u32>) -> Self {
        Self { image: Image::Colour(rgb), marking: None }
    }

    /// Colour into `rgb`, and each pixel's first hit into `object` and `z` as
    /// [`Target::first_hits`] gives them, bit for bit (all resized to the view): an eye's
    /// colours with its own object and depth planes, from the pass that shades it. With
    /// [`Pixels::Only`], the planes not traced are left as they were, as the colours are.
    #[must_use]
    pub fn colour_with_first_hits(rgb: &'a mut Vec<u32>, object: &'a mut Vec<u32>, z: &'a mut Vec<f32>) -> Self {
        Self { image: Image::ColourHits(rgb, object, z), marking: None }
    }

    /// Depth only, into `z` (resized to the view): each pixel's first hit as
    /// [`crate::EyeView::head_z`] gives it (the film's `z`, bit for bit), +∞ for a miss; no
    /// shading, so it costs the primary rays alone. What a timewarp of an eye made without a
    /// film of its own reads. Counts the primary rays; marks nothing.
    #[must_use]
    pub fn depth(z: &'a mut Vec<f32>) -> Self {
        Self { image: Image::Depth(z, None), marking: None }
    }

    /// First hits only: [`Target::depth`] into `z`, and each pixel's sphere into `object`
    /// (resized to the view; [`NO_OBJECT`] for a miss), as the screen bins or the BVH find
    /// it (of equal `t`, the lowest id). An eye's own object and depth planes at the cost of
    /// its primary rays, whatever made its colours (what outlines read).
    #[must_use]
    pub fn first_hits(object: &'a mut Vec<u32>, z: &'a mut Vec<f32>) -> Self {
        Self { image: Image::Depth(z, Some(object)), marking: None }
    }

    /// Also marks in `marks` (resized to the view) where each traced pixel's ray tree —
    /// primary, shadow and mirror rays, at any depth — meets `swept`'s volumes: what temporal
    /// reuse reads (`reuse/`).
    #[must_use]
    pub fn marking(self, marks: &'a mut Marks, swept: &'a Swept) -> Self {
        Self { marking: Some((marks, swept)), ..self }
    }
}

/// Which of a target's planes a render writes, and so which columns its rows have.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Colour,
    Hits,
    Keys,
    Full,
    Depth,
}

/// A target's planes sized to the view, or one row of them; those its [`Kind`] does not
/// write are empty.
#[derive(Debug, Default)]
struct Planes<'a> {
    rgb: &'a mut [u32],
    z: &'a mut [f32],
    t: &'a mut [f32],
    object: &'a mut [u32],
    lights: &'a mut [u32],
    shading: &'a mut [Shading],
}

impl<'a> Image<'a> {
    /// Sizes the image to `view` (a film also takes `record`), and returns which planes the
    /// render writes.
    fn planes(self, view: &EyeView, pixels: Pixels<'_>) -> (Kind, Planes<'a>) {
        let n = view.width as usize * view.height as usize;
        match self {
            Image::Colour(rgb) => {
                rgb.resize(n, 0);
                (Kind::Colour, Planes { rgb, ..Planes::default() })
            }
            Image::ColourHits(rgb, object, z) => {
                if let Pixels::Only(_) = pixels {
                    debug_assert!(rgb.len() == n && object.len() == n && z.len() == n, "planes of another size");
                }
                rgb.resize(n, 0);
                object.resize(n, NO_OBJECT);
                z.resize(n, f32::INFINITY);
                (Kind::Hits, Planes { rgb, z, object, ..Planes::default() })
            }
            Image::Depth(z, object) => {
                debug_assert!(matches!(pixels, Pixels::All), "a depth pass traces every pixel");
                z.resize(n, f32::INFINITY);
                let object = object.map_or(<&mut [u32]>::default(), |object| {
                    object.resize(n, NO_OBJECT);
                    object
                });
                (Kind::Depth, Planes { z, object, ..Planes::default() })
            }
            Image::Film(film, record) => {
                if let Pixels::Only(_) = pixels {
                    debug_assert_eq!(
                        (film.width(), film.height()),
                        (view.width, view.height),
                        "a film of another size"
                    );
                    debug_assert_eq!(film.record(), record, "a film rendered with another record");
                }
                film.resize(view.width, view.height);
                film.set_record(record);
                let Film { rgb, z, t, object, lights, shading, .. } = film;
                match record {
                    Record::Colour => (Kind::Colour, Planes { rgb, ..Planes::default() }),
                    Record::Keys => (Kind::Keys, Planes { rgb, z, t, object, lights, ..Planes::default() }),
                    Record::Full => (Kind::Full, Planes { rgb, z, t, object, lights, shading }),
                }
            }
        }
    }
}

/// The rows of a plane `w` pixels wide, or `h` empty rows for a plane not written.
fn rows_of<T: Send>(plane: &mut [T], w: usize, h: usize) -> impl IndexedParallelIterator<Item = &mut [T]> {
    if plane.is_empty() {
        Either::Right(rayon::iter::repeat_n((), h).map(|()| <&mut [T]>::default()))
    } else {
        Either::Left(plane.par_chunks_mut(w))
    }
}

/// The rows of `marks` for a pass, or none per row when the pass does not mark.
fn marks_rows(
    marks: Option<&mut Marks>,
    rows: usize,
    rewrite: Rewrite,
) -> impl IndexedParallelIterator<Item = Option<MarksRow<'_>>> {
    match marks {
        Some(marks) => Either::Left(marks.rows_mut(rewrite).map(Some)),
        None => Either::Right(rayon::iter::repeat_n((), rows).map(|()| None)),
    }
}

/// One row of a target, as a [`Kind`] of columns.
enum Row<'a> {
    Colour(RgbRow<'a>),
    Hits(HitsRow<'a>),
    Keys(KeysRow<'a>),
    Full(FilmRow<'a>),
    Depth(DepthRow<'a>),
}

impl<'a> Row<'a> {
    /// One row of each plane (empty where not written) as `kind`'s columns.
    fn of(kind: Kind, Planes { rgb, z, t, object, lights, shading }: Planes<'a>) -> Self {
        match kind {
            Kind::Colour => Self::Colour(RgbRow(rgb)),
            Kind::Hits => Self::Hits(HitsRow { rgb, z, object }),
            Kind::Keys => Self::Keys(KeysRow { rgb, z, t, object, lights }),
            Kind::Full => Self::Full(FilmRow { keys: KeysRow { rgb, z, t, object, lights }, shading }),
            Kind::Depth => Self::Depth(DepthRow { z, object }),
        }
    }

    /// Traces row `j` of `eye` into these columns, watched by `marks`, through the one row
    /// loop (`row.rs`), made for this kind of row.
    fn trace(
        self,
        eye: &BinnedView<'_>,
        j: u32,
        marks: Option<MarksColumn<'_, '_>>,
        only: Option<&[u64]>,
    ) -> RayCounts {
        let w = eye.view.width as usize;
        match self {
            Self::Colour(row) => trace_row(eye, j, w, &mut RowSink::new(row, marks), only),
            Self::Hits(row) => trace_row(eye, j, w, &mut RowSink::new(row, marks), only),
            Self::Keys(row) => trace_row(eye, j, w, &mut RowSink::new(row, marks), only),
            Self::Full(row) => trace_row(eye, j, w, &mut RowSink::new(row, marks), only),
            Self::Depth(row) => trace_row(eye, j, w, &mut RowSink::new(row, marks), only),
        }
    }
}

impl Renderer {
    /// A renderer with empty buffers; the first frame sizes them.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// This renderer, finding first hits as `first_hits` says (by default, the cheaper way
    /// per view); for tests and measurements, as every way makes the same pixels.
    #[must_use]
    pub fn with_first_hits(self, first_hits: FirstHits) -> Self {
        Self { first_hits, ..self }
    }

    /// Traces `pixels` of `view` into `target`, and returns the rays cast.
    ///
    /// First hits are found through screen-space bins, rebuilt for `view`, or through the
    /// BVH when the scene has so many spheres for the rays traced that binning them would
    /// cost more ([`FirstHits`]); the rest through the aggregate. Rows are independent work items; each row counts its own rays and the
    /// counts are summed afterwards, so the result — pixels, record, marks and counts — is
    /// the same for any thread count. Nothing is allocated per pixel or per ray, nor per
    /// frame once the target has its size.
    pub fn render(&mut self, tracer: &Tracer, view: &EyeView, pixels: Pixels<'_>, target: Target<'_>) -> RayCounts {
        let Target { image, marking } = target;
        let (w, h) = (view.width as usize, view.height as usize);
        if let Pixels::Only(bits) = pixels {
            debug_assert_eq!((bits.width(), bits.height()), (view.width, view.height), "a selection of another size");
        }
        let (kind, planes) = image.planes(view, pixels);
        let (marks, swept) = match marking {
            Some((marks, swept)) => {
                debug_assert!(kind != Kind::Depth, "a depth pass marks nothing");
                if (marks.width(), marks.height()) != (view.width, view.height) {
                    debug_assert!(matches!(pixels, Pixels::All), "marks of another size");
                    marks.resize(view.width, view.height);
                }
                (Some(marks), Some(swept))
            }
            None => (None, None),
        };
        if w == 0 || h == 0 {
            return RayCounts::default();
        }
        let rays = match pixels {
            Pixels::All => (w * h) as u64,
            Pixels::Only(bits) => bits.count(),
        };
        let search = self.first_hits.search(tracer, rays);
        self.bins.build((&tracer.scene.centers, &tracer.scene.radii), view, search);
        let eye = BinnedView { tracer, view, bins: &self.bins };
        let marker = swept.map(|swept| Marker::new(swept, view, &tracer.scene.lights));
        let rewrite = if matches!(pixels, Pixels::Only(_)) { Rewrite::Few } else { Rewrite::All };
        let Planes { rgb, z, t, object, lights, shading } = planes;
        let rows = (rows_of(rgb, w, h), rows_of(z, w, h), rows_of(t, w, h), rows_of(object, w, h));
        let rows = (rows, rows_of(lights, w, h), rows_of(shading, w, h), marks_rows(marks, h, rewrite));
        rows.into_par_iter()
            .enumerate()
            .map(|(j, ((rgb, z, t, object), lights, shading, mut marks))| {
                let only = match pixels {
                    Pixels::All => None,
                    Pixels::Only(bits) => Some(bits.row(j as u32)),
                };
                if let Some(marks) = marks.as_mut() {
                    marks.clear_only(only);
                }
                let row = Row::of(kind, Planes { rgb, z, t, object, lights, shading });
                with_marks(marks.as_mut(), marker.as_ref(), j as u32, |marks| row.trace(&eye, j as u32, marks, only))
            })
            .sum()
    }

    /// Heap bytes of the screen bins this renderer keeps.
    #[must_use]
    pub fn memory(&self) -> usize {
        self.bins.heap_bytes()
    }

    /// `view`'s pixels, to make in batches of a row's chosen pixels (`batch/`), with the
    /// screen bins rebuilt for it (or the BVH chosen, as for a render of every pixel).
    pub fn batch<'a>(&'a mut self, tracer: &'a Tracer, view: &'a EyeView) -> PixelBatch<'a> {
        let search = self.first_hits.search(tracer, u64::from(view.width) * u64::from(view.height));
        self.bins.build((&tracer.scene.centers, &tracer.scene.radii), view, search);
        PixelBatch::new(BinnedView { tracer, view, bins: &self.bins })
    }
}

#[cfg(test)]
mod tests {
    use fearless_simd::dispatch;
    use glam::Vec3;

    use super::row::trace_row_in;
    use super::*;
    use crate::camera::{Camera, Eye};
    use crate::film::Record;
    use crate::material::Material;
    use crate::reuse::Swept;
    use crate::scene::{Light, Motion, RenderSettings, Scene, SceneSphere};
    use crate::surface::Surface;
    use crate::wavefront::with_wavefront;

    fn seed() -> Scene {
        crate::testing::scene("seed.toml")
    }

    #[test]
    fn ray_counts_match_a_count_over_the_pixels_hits() {
        // One mirror sphere alone: a mirror ray leaves a convex sphere outwards and meets
        // nothing, so every hit pixel casts exactly one, and the only shadow rays are the
        // hits' own, one per light its surface faces. Those are counted here from the
        // film's records, apart from the renderer's counters.
        let material = Material { reflectivity: 0.5, specular: 0.3, ..Material::default() };
        let lights = vec![
            Light { position: Vec3::new(0.0, 0.0, 0.0), color: Vec3::ONE },
            Light { position: Vec3::new(25.0, 4.0, 12.0), color: Vec3::splat(0.5) },
        ];
        let scene = Scene {
            camera: Camera { ipd: 0.0, distance: 5.0, fov_deg: 30.0, ..Camera::default() },
            render: RenderSettings { max_depth: 3, ..RenderSettings::default() },
            spheres: vec![SceneSphere { radius: 1.5, motion: Motion::Static(Vec3::new(0.3, -0.2, 10.0)), material }],
            lights,
            structures: Vec::new(),
        };
        let tracer = Tracer::new(&scene, 0.0);
        let (w, h) = (64, 48);
        let view = scene.camera.view(Eye::Left, w, h);
        let mut film = Film::new(w, h);
        let counts = Renderer::new().render(&tracer, &view, Pixels::All, Target::film(&mut film, Record::Full));
        let hits: Vec<_> = (0..(w * h) as usize).map(|k| film.surface(k)).filter(Surface::is_hit).collect();
        let faced = hits
            .iter()
            .flat_map(|s| scene.lights.iter().map(move |l| s.normal.dot((l.position - s.point).normalize())))
            .filter(|&ndl| ndl > 0.0)
            .count();
        assert!(hits.len() > 200 && faced > hits.len(), "the sphere fills part of the view: {} hits", hits.len());
        let want = RayCounts { primary: u64::from(w * h), shadow: faced as u64, reflection: hits.len() as u64 };
        assert_eq!(counts, want, "rays counted while rendering against the count over the hits");
    }

    #[test]
    fn every_pixel_is_the_plain_paths_and_colour_only_agrees() {
        for (name, t) in [("seed.toml", 0.8), ("many.toml", 0.0)] {
            let scene = crate::testing::scene(name);
            let tracer = Tracer::new(&scene, t);
            let (w, h) = (83, 45); // not a whole number of tiles
            let view = scene.camera.view(Eye::Right, w, h);
            let mut renderer = Renderer::new();
            let mut film = Film::new(1, 1);
            let counts = renderer.render(&tracer, &view, Pixels::All, Target::film(&mut film, Record::Full));
            let mut plain = RayCounts::default();
            for j in 0..h {
                for i in 0..w {
                    let k = (j * w + i) as usize;
                    let s = tracer.trace_pixel(&view, i, j, &mut plain);
                    assert_eq!((film.rgb[k], film.z[k].to_bits()), (s.rgb, s.z.to_bits()), "{name} ({i}, {j})");
                    assert_eq!(film.surface(k), s.surface, "{name} ({i}, {j})");
                }
            }
            assert_eq!(counts, plain, "{name}");
            let mut rgb = Vec::new();
            assert_eq!(renderer.render(&tracer, &view, Pixels::All, Target::colour(&mut rgb)), counts, "{name}");
            assert_eq!(rgb, film.rgb, "{name}: colour only is the film's colour");
        }
    }

    #[test]
    fn batched_radiance_is_the_plain_paths_bit_for_bit() {
        // Before packing: a difference of a few ulps in a direction or a highlight would
        // round to the same sRGB byte and pass the test above.
        for (name, t) in [("seed.toml", 0.8), ("many.toml", 0.0), ("window.toml", 0.3)] {
            let scene = crate::testing::scene(name);
            let tracer = Tracer::new(&scene, t);
            let (w, h) = (83, 45);
            let view = scene.camera.view(Eye::Left, w, h);
            let mut bins = ScreenBins::default();
            bins.build((&tracer.scene.centers, &tracer.scene.radii), &view, Search::Bins);
            let eye = BinnedView { tracer: &tracer, view: &view, bins: &bins };
            let mut rgb = vec![0; w as usize];
            let mut hits = 0;
            for j in 0..h {
                with_wavefront(|wavefront| {
                    let mut sink = RowSink::new(RgbRow(&mut rgb), ());
                    dispatch!(crate::simd::level(), simd => trace_row_in::<_, _, _, false>(simd, wavefront, &eye, j, w as usize, &mut sink, None));
                    for e in 0..wavefront.len() {
                        let i = wavefront.tag(e);
                        let plain = tracer.pixel_radiance(&view, i, j).expect("a batched sample is a hit");
                        let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                        assert_eq!(bits(wavefront.radiance(e)), bits(plain), "{name} ({i}, {j})");
                    }
                    hits += wavefront.len();
                });
            }
            assert!(hits > (w * h) as usize / 10, "{name}: {hits} hits, too few to test");
        }
    }

    #[test]
    fn keeping_less_of_the_record_changes_nothing_that_is_kept() {
        let scene = seed();
        let tracer = Tracer::new(&scene, 0.4);
        let view = scene.camera.view(Eye::Left, 97, 55);
        let mut renderer = Renderer::new();
        let mut full = Film::new(1, 1);
        let counts = renderer.render(&tracer, &view, Pixels::All, Target::film(&mut full, Record::Full));
        assert_eq!(full.record(), Record::Full, "render keeps everything");
        for record in [Record::Colour, Record::Keys] {
            // A film last filled by another view: what is not kept stays as it was.
            let mut film = Film::new(1, 1);
            renderer.render(
                &tracer,
                &scene.camera.view(Eye::Right, 97, 55),
                Pixels::All,
                Target::film(&mut film, Record::Full),
            );
            let stale = film.z.clone();
            assert_eq!(
                renderer.render(&tracer, &view, Pixels::All, Target::film(&mut film, record)),
                counts,
                "{record:?}: the same rays"
            );
            assert_eq!((film.record(), &film.rgb), (record, &full.rgb), "{record:?}: the same colours");
            if record == Record::Keys {
                let bits = |z: &[f32]| z.iter().map(|z| z.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&film.z), bits(&full.z), "depths kept");
                assert_eq!((&film.object, &film.lights), (&full.object, &full.lights), "objects and light bits kept");
            } else {
                assert_eq!(
                    film.z.iter().map(|z| z.to_bits()).collect::<Vec<_>>(),
                    stale.iter().map(|z| z.to_bits()).collect::<Vec<_>>(),
                    "depths not written"
                );
            }
        }
    }

    #[test]
    fn a_selection_rendered_over_another_instant_is_the_full_render_there() {
        // A film (and its marks) made at one instant, then the selected pixels rendered at
        // another: those become the other instant's full render, pixel, record and mark;
        // every other pixel stays as it was. Scattered pixels, whole lane groups and a whole
        // row, in a view that is not a whole number of tiles.
        let scene = seed();
        let swept = Swept::of(&scene);
        let (t0, t1) = (Tracer::new(&scene, 0.2), Tracer::new(&scene, 1.1));
        let view = scene.camera.view(Eye::Left, 83, 45);
        let (w, h) = (view.width, view.height);
        let mut bits = PixelBits::new(w, h);
        for (i, j) in (0..h).flat_map(|j| (0..w).map(move |i| (i, j))) {
            bits.set(i, j, (i * 7 + j * 3) % 5 == 0 || (16..24).contains(&i) || j == 20);
        }
        let mut renderer = Renderer::new();
        for record in [Record::Colour, Record::Keys, Record::Full] {
            let (mut full, mut full_marks) = (Film::new(1, 1), Marks::default());
            let target = Target::film(&mut full, record).marking(&mut full_marks, &swept);
            renderer.render(&t1, &view, Pixels::All, target);
            let (mut film, mut marks) = (Film::new(1, 1), Marks::default());
            renderer.render(&t0, &view, Pixels::All, Target::film(&mut film, record).marking(&mut marks, &swept));
            let (stale, stale_marks) = (film.clone(), marks.clone());
            let target = Target::film(&mut film, record).marking(&mut marks, &swept);
            let counts = renderer.render(&t1, &view, Pixels::Only(&bits), target);
            assert_eq!(counts.primary, bits.count(), "{record:?}: a primary ray per selected pixel");
            for k in 0..(w * h) as usize {
                let (i, j) = (k as u32 % w, k as u32 / w);
                let (want, want_marks) = if bits.get(i, j) { (&full, &full_marks) } else { (&stale, &stale_marks) };
                let at = |f: &Film| {
                    let shading = (record == Record::Full).then(|| f.surface(k));
                    (f.rgb[k], f.z[k].to_bits(), f.object[k], f.lights[k], shading)
                };
                assert_eq!(at(&film), at(want), "{record:?} ({i}, {j})");
                assert_eq!(marks.touch(k), want_marks.touch(k), "{record:?} ({i}, {j}): mark");
            }
            assert!(full_marks.bits().count() > 100, "{record:?}: pixels marked");
        }
        // And the marks of background pixels are their primary rays' own, found apart.
        let (mut film, mut marks) = (Film::new(1, 1), Marks::default());
        renderer.render(&t1, &view, Pixels::All, Target::film(&mut film, Record::Keys).marking(&mut marks, &swept));
        let missed = (0..(w * h) as usize).filter(|&k| film.object[k] == crate::surface::NO_OBJECT);
        let met = missed
            .map(|k| {
                let ray = view.primary_ray(k as u32 % w, k as u32 / w);
                let touch = swept.touch(ray.origin, ray.dir, f32::INFINITY);
                assert_eq!(marks.touch(k).is_some(), touch.is_some(), "background pixel {k}");
                touch.is_some()
            })
            .filter(|&met| met)
            .count();
        assert!(met > 20, "{met} background pixels meet a volume");
    }

    #[test]
    fn same_bytes_for_one_and_two_threads() {
        let scene = seed();
        let tracer = Tracer::new(&scene, 1.5);
        let view = scene.camera.view(Eye::Right, 160, 90);
        let run = |threads| {
            let pool = rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("thread pool");
            pool.install(|| {
                let mut film = Film::new(1, 1);
                let counts = Renderer::new().render(&tracer, &view, Pixels::All, Target::film(&mut film, Record::Full));
                let z: Vec<u32> = film.z.iter().map(|z| z.to_bits()).collect();
                (film.rgb, z, film.object, film.lights, counts)
            })
        };
        assert_eq!(run(1), run(2), "pixels, depths, objects, light bits and counts");
    }

    #[test]
    fn a_guard_band_renders_the_shown_image_byte_for_byte_within_it() {
        let scene = seed();
        let tracer = Tracer::new(&scene, 0.6);
        let (w, h, margin) = (90u32, 52u32, (31u32, 16u32));
        // Turned so that the scene runs off the window's edge into the band.
        let camera = Camera { yaw_deg: 16.0, pitch_deg: -6.0, ..scene.camera };
        let mut renderer = Renderer::new();
        for eye in [Eye::Left, Eye::Right] {
            let (mut plain, mut banded) = (Film::new(1, 1), Film::new(1, 1));
            renderer.render(&tracer, &camera.view(eye, w, h), Pixels::All, Target::film(&mut plain, Record::Full));
            let view = camera.view_with_margin(eye, w, h, margin);
            renderer.render(&tracer, &view, Pixels::All, Target::film(&mut banded, Record::Full));
            let bw = view.width as usize;
            for j in 0..h as usize {
                for i in 0..w as usize {
                    let (k, kb) = (j * w as usize + i, (j + margin.1 as usize) * bw + i + margin.0 as usize);
                    assert_eq!(plain.rgb[k], banded.rgb[kb], "{eye:?} ({i}, {j}) colour");
                    assert_eq!(plain.z[k].to_bits(), banded.z[kb].to_bits(), "{eye:?} ({i}, {j}) depth");
                    assert_eq!(plain.surface(k), banded.surface(kb), "{eye:?} ({i}, {j}) record");
                }
            }
            let band_hits = (0..banded.rgb.len()).filter(|&k| {
                let (i, j) = (k % bw, k / bw);
                let inside = (margin.0 as usize..margin.0 as usize + w as usize).contains(&i)
                    && (margin.1 as usize..margin.1 as usize + h as usize).contains(&j);
                !inside && banded.object[k] != crate::surface::NO_OBJECT
            });
            assert!(band_hits.count() > 0, "{eye:?}: the band sees spheres beyond the window");
        }
    }

    #[test]
    fn colour_with_first_hits_is_the_colour_and_a_first_hits_pass_bit_for_bit() {
        // Every pixel, then a selection over another instant (the other pixels kept), marked
        // as a colour render is: the colours and marks a colour render makes, the planes a
        // first-hits pass gives.
        let bits_of = |z: &[f32]| z.iter().map(|z| z.to_bits()).collect::<Vec<_>>();
        for (name, t) in [("seed.toml", 0.8), ("many.toml", 0.0), ("window.toml", 0.3)] {
            let scene = crate::testing::scene(name);
            let swept = Swept::of(&scene);
            let (t0, t1) = (Tracer::new(&scene, t), Tracer::new(&scene, t + 0.7));
            let view = scene.camera.view_with_margin(Eye::Right, 83, 45, (9, 5));
            let (w, h) = (view.width, view.height);
            let mut selection = PixelBits::new(w, h);
            for (i, j) in (0..h).flat_map(|j| (0..w).map(move |i| (i, j))) {
                selection.set(i, j, (i * 7 + j * 3) % 5 == 0 || (16..24).contains(&i));
            }
            let mut renderer = Renderer::new();
            let (mut rgb, mut object, mut z, mut marks) = (Vec::new(), Vec::new(), Vec::new(), Marks::default());
            let target = Target::colour_with_first_hits(&mut rgb, &mut object, &mut z).marking(&mut marks, &swept);
            let counts = renderer.render(&t0, &view, Pixels::All, target);
            let target = Target::colour_with_first_hits(&mut rgb, &mut object, &mut z).marking(&mut marks, &swept);
            let only = renderer.render(&t1, &view, Pixels::Only(&selection), target);
            assert_eq!(only.primary, selection.count(), "{name}: a primary ray per selected pixel");
            let (mut want_rgb, mut want_marks) = (Vec::new(), Marks::default());
            let target = Target::colour(&mut want_rgb).marking(&mut want_marks, &swept);
            assert_eq!(renderer.render(&t0, &view, Pixels::All, target), counts, "{name}: the colour render's rays");
            let target = Target::colour(&mut want_rgb).marking(&mut want_marks, &swept);
            renderer.render(&t1, &view, Pixels::Only(&selection), target);
            let (mut want_object, mut want_z) = (Vec::new(), Vec::new());
            let mut first_hits = |tracer| {
                crate::cue::first_hits(&mut renderer, tracer, &view, &mut want_object, &mut want_z);
                (want_object.clone(), bits_of(&want_z))
            };
            let (at0, at1) = (first_hits(&t0), first_hits(&t1));
            assert_eq!(rgb, want_rgb, "{name}: colours");
            assert!((0..rgb.len()).all(|k| marks.touch(k) == want_marks.touch(k)), "{name}: marks");
            for k in 0..rgb.len() {
                let (i, j) = (k as u32 % w, k as u32 / w);
                let want = if selection.get(i, j) { &at1 } else { &at0 };
                assert_eq!((object[k], z[k].to_bits()), (want.0[k], want.1[k]), "{name} ({i}, {j})");
            }
            assert!(at1.0.contains(&NO_OBJECT) && at1.0.iter().any(|&o| o != NO_OBJECT), "{name}: hits and misses");
        }
    }

    #[test]
    fn a_depth_pass_is_the_films_depth_bit_for_bit() {
        for (name, t) in [("seed.toml", 0.8), ("many.toml", 0.0), ("window.toml", 0.3)] {
            let scene = crate::testing::scene(name);
            let tracer = Tracer::new(&scene, t);
            let mut renderer = Renderer::new();
            for view in
                [scene.camera.view(Eye::Right, 83, 45), scene.camera.view_with_margin(Eye::Left, 83, 45, (9, 5))]
            {
                let (mut film, mut z) = (Film::new(1, 1), Vec::new());
                renderer.render(&tracer, &view, Pixels::All, Target::film(&mut film, Record::Keys));
                let counts = renderer.render(&tracer, &view, Pixels::All, Target::depth(&mut z));
                let bits = |z: &[f32]| z.iter().map(|z| z.to_bits()).collect::<Vec<_>>();
                assert_eq!(bits(&z), bits(&film.z), "{name}: the film's depth");
                assert_eq!(counts.primary, u64::from(view.width * view.height), "{name}: a primary ray per pixel");
                assert!(
                    z.iter().any(|z| z.is_finite()) && z.iter().any(|z| z.is_infinite()),
                    "{name}: hits and misses"
                );
            }
        }
    }

    #[test]
    fn zero_ipd_gives_identical_eyes() {
        let mut scene = seed();
        scene.camera.ipd = 0.0;
        let tracer = Tracer::new(&scene, 0.0);
        let (mut l, mut r) = (Vec::new(), Vec::new());
        let mut renderer = Renderer::new();
        renderer.render(&tracer, &scene.camera.view(Eye::Left, 96, 54), Pixels::All, Target::colour(&mut l));
        renderer.render(&tracer, &scene.camera.view(Eye::Right, 96, 54), Pixels::All, Target::colour(&mut r));
        assert_eq!(l, r, "one eye position, one image");
        scene.camera.ipd = 0.65;
        renderer.render(&tracer, &scene.camera.view(Eye::Right, 96, 54), Pixels::All, Target::colour(&mut r));
        assert_ne!(l, r, "a real IPD changes the right eye");
    }
}

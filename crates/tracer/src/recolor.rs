//! Recolouring and hiding a structure's atoms: the kinds of atom recomputed for a colour
//! scheme (`color_by.rs`) without moving an atom, and the atoms a [`Hide`] names taken out
//! of the structure.
//!
//! A kind is an (element radius, colour) pair, so atoms keep their radii. The continuous
//! schemes are quantised to [`crate::color_by::STEPS`] colours, so a structure of 8 elements
//! has at most 256 kinds; past 256 the later pairs take the nearest colour of a kind of the
//! same radius, so the count stays a byte.

use glam::Vec3;
use molecule::AtomRecords;

use crate::color_by::{
    blue_white_red, chain_colour, plddt_band, plddt_colour, polymer_grey, rainbow, shapely_colour, shapely_slot, step,
    ColorBy, Coloring, Hide, CHAIN_COLOURS, WATER_NAMES,
};
use crate::scene::{AtomKind, Scene, Structure};
use crate::tracer::Tracer;

impl Structure {
    /// The record index (into [`Structure::records`]) of atom `k`: `k` itself unless atoms
    /// were hidden.
    #[must_use]
    pub fn record_index(&self, k: usize) -> usize {
        self.shown.as_ref().map_or(k, |ids| ids[k] as usize)
    }

    /// Recolours every atom by `coloring`, keeping its radius: the kinds and each atom's
    /// kind are recomputed; no atom moves. Atoms without records (made in code) are left as
    /// they are.
    pub fn recolor(&mut self, coloring: &Coloring) {
        let Some(records) = self.records.clone() else { return };
        let records = &*records.0;
        let scheme = Scheme::new(records, coloring);
        // Each record's colour slot, then each atom's kind from (its radius, its slot).
        let mut slots = vec![0u16; records.len()];
        scheme.slots(records, &mut slots);
        let mut radii: Vec<f32> = Vec::new();
        let class: Vec<usize> = self
            .kinds
            .iter()
            .map(|k| {
                radii.iter().position(|&r| r == k.radius).unwrap_or_else(|| {
                    radii.push(k.radius);
                    radii.len() - 1
                })
            })
            .collect();
        let material = self.kinds.first().map_or(crate::structure::ATOM_MATERIAL, |k| k.material);
        let mut kinds: Vec<AtomKind> = Vec::new();
        let mut table = vec![u16::MAX; radii.len() * SLOTS];
        for k in 0..self.kind_ids.len() {
            let r = class[usize::from(self.kind_ids[k])];
            let slot = usize::from(slots[self.record_index(k)]);
            let entry = &mut table[r * SLOTS + slot];
            if *entry == u16::MAX {
                let (radius, color) = (radii[r], scheme.colour(slot));
                *entry = if kinds.len() < 256 {
                    kinds.push(AtomKind { radius, material: crate::Material { color, ..material } });
                    (kinds.len() - 1) as u16
                } else {
                    u16::from(nearest(&kinds, radius, color))
                };
            }
            self.kind_ids[k] = *entry as u8;
        }
        self.kinds = kinds;
    }

    /// This structure without the atoms `hide` names (the records stay whole; the atoms
    /// left keep their record index, [`Structure::record_index`]).
    #[must_use]
    pub fn hidden(&self, hide: Hide) -> Structure {
        let Some(records) = self.records.as_ref().filter(|_| !hide.is_empty()) else { return self.clone() };
        let records = &*records.0;
        let (fields, elements) = (records.fields(), records.elements());
        let mut shown_record = vec![true; records.len()];
        records.for_each_file_index(|i, file| {
            let h = elements[i].atomic_number() == 1;
            let has = file < fields.len();
            let het = has && fields.is_hetero(file);
            let water = has && WATER_NAMES.contains(&fields.residue_name(file));
            shown_record[i] = !(hide.hydrogen && h || hide.hetero && het || hide.water && water);
        });
        let keep: Vec<usize> = (0..self.positions.len()).filter(|&k| shown_record[self.record_index(k)]).collect();
        Structure {
            source: self.source.clone(),
            positions: keep.iter().map(|&k| self.positions[k]).collect(),
            kind_ids: keep.iter().map(|&k| self.kind_ids[k]).collect(),
            kinds: self.kinds.clone(),
            records: self.records.clone(),
            offset: self.offset,
            shown: Some(keep.iter().map(|&k| self.record_index(k) as u32).collect()),
        }
    }
}

/// The kind of radius `radius` (one exists: the structure had it) nearest to `color`.
fn nearest(kinds: &[AtomKind], radius: f32, color: Vec3) -> u8 {
    let d = |k: &AtomKind| if k.radius == radius { k.material.color.distance_squared(color) } else { f32::INFINITY };
    let best = (0..kinds.len()).min_by(|&a, &b| d(&kinds[a]).total_cmp(&d(&kinds[b])));
    best.unwrap_or(0) as u8
}

/// Colour slots a scheme can give: an element's atomic number (0–255) or one more (256).
const SLOTS: usize = 257;
/// The slot of "no value" (a B-factor missing) and of `hetero`'s polymer.
const GREY_SLOT: u16 = 256;

/// A scheme ready to give each atom a colour slot (a small number) and each slot its colour:
/// the per-atom pass does no colour arithmetic.
struct Scheme {
    by: ColorBy,
    /// `bfactor`'s range.
    range: (f32, f32),
    /// `rainbow`'s residue-number range per chain.
    chains: Vec<(i32, i32)>,
    /// `rainbow`'s chain of each file atom.
    file_chains: Vec<u16>,
    /// Whether the file has per-atom fields (XYZ has none: element colours).
    fields: bool,
}

impl Scheme {
    fn new(records: &AtomRecords, coloring: &Coloring) -> Self {
        let fields = records.fields();
        let mut chains = Vec::new();
        let mut file_chains = Vec::new();
        if coloring.by == ColorBy::Rainbow && !fields.is_empty() {
            // Each file atom's chain (an assembly's copies keep their chain), then each
            // chain's residue-number range over the file's atoms.
            file_chains = vec![0u16; fields.len()];
            let chain_of = records.chains();
            records.for_each_file_index(|i, file| file_chains[file] = chain_of[i]);
            chains = vec![(i32::MAX, i32::MIN); records.chain_ids().len().max(1)];
            for (file, &chain) in file_chains.iter().enumerate() {
                if let Some(r) = fields.residue_number(file) {
                    let c = &mut chains[usize::from(chain)];
                    *c = (c.0.min(r), c.1.max(r));
                }
            }
        }
        let range = coloring.range.or_else(|| fields.b_factor_range()).unwrap_or((0.0, 1.0));
        Self { by: coloring.by, range, chains, file_chains, fields: !fields.is_empty() }
    }

    /// Fills each record's slot.
    fn slots(&self, records: &AtomRecords, slots: &mut [u16]) {
        let (fields, elements, chains) = (records.fields(), records.elements(), records.chains());
        let element = |i: usize| u16::from(elements[i].atomic_number());
        let mut each =
            |f: &mut dyn FnMut(usize, usize) -> u16| records.for_each_file_index(|i, file| slots[i] = f(i, file));
        match self.by {
            ColorBy::Chain => each(&mut |i, _| chains[i] % CHAIN_COLOURS as u16),
            _ if !self.fields => each(&mut |i, _| element(i)),
            ColorBy::Element => each(&mut |i, _| element(i)),
            // A slot the file's atom alone decides: once per file atom (an assembly's
            // copies share theirs).
            ColorBy::Residue | ColorBy::BFactor | ColorBy::Plddt | ColorBy::Rainbow => {
                let of_file: Vec<u16> = (0..fields.len())
                    .map(|file| match self.by {
                        ColorBy::Residue => shapely_slot(fields.residue_name(file)),
                        ColorBy::BFactor => fields.b_factor(file).map_or(GREY_SLOT, |b| u16::from(step(b, self.range))),
                        ColorBy::Rainbow => {
                            let (lo, hi) = self.chains[usize::from(self.file_chains[file])];
                            let r = fields.residue_number(file).unwrap_or(lo);
                            u16::from(step(r as f32, (lo as f32, hi as f32)))
                        }
                        _ => fields.b_factor(file).map_or(3, |b| plddt_band(b) as u16),
                    })
                    .collect();
                each(&mut |_, file| of_file[file]);
            }
            ColorBy::Hetero => each(&mut |i, file| if fields.is_hetero(file) { element(i) } else { GREY_SLOT }),
        }
    }

    /// Slot `slot`'s colour.
    fn colour(&self, slot: usize) -> Vec3 {
        let element = |slot: usize| {
            molecule::Element::from_atomic_number(slot as u8).unwrap_or(molecule::Element::UNKNOWN).linear_colour()
        };
        match self.by {
            _ if slot == usize::from(GREY_SLOT) => polymer_grey(),
            ColorBy::Chain => chain_colour(slot),
            _ if !self.fields => element(slot),
            ColorBy::Element | ColorBy::Hetero => element(slot),
            ColorBy::Residue => shapely_colour(slot),
            ColorBy::BFactor => blue_white_red(slot as u8),
            ColorBy::Plddt => plddt_colour(slot),
            ColorBy::Rainbow => rainbow(slot as u8),
        }
    }
}

impl Scene {
    /// Recolours every structure by `coloring` ([`Structure::recolor`]).
    pub fn recolor(&mut self, coloring: &Coloring) {
        for s in &mut self.structures {
            s.recolor(coloring);
        }
    }

    /// This scene without the atoms `hide` names, in every structure.
    #[must_use]
    pub fn hidden(&self, hide: Hide) -> Scene {
        Scene {
            structures: self.structures.iter().map(|s| s.hidden(hide)).collect(),
            ..self.clone_without_structures()
        }
    }

    fn clone_without_structures(&self) -> Scene {
        Scene {
            camera: self.camera,
            render: self.render,
            lights: self.lights.clone(),
            spheres: self.spheres.clone(),
            structures: Vec::new(),
        }
    }
}

impl Tracer {
    /// Takes the materials of `scene`'s spheres and atoms, which must be the scene of the
    /// last [`Tracer::update`] with only its colours changed ([`Scene::recolor`]): the
    /// palette and each sphere's material id are rewritten, the BVH and light maps kept.
    /// A new [`Tracer::generation`], so temporal reuse keeps no pixel of the old colours.
    /// The scene's cues (`render.cues`) are taken too: they change no structure either.
    pub fn recolor(&mut self, scene: &Scene) {
        self.scene.recolor(scene);
        self.scene.settings.cues = scene.render.cues;
        self.bump_generation();
    }
}

#[cfg(test)]
mod tests;

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
    blue_white_red, chain_colour, plddt_band, plddt_colour, polymer_grey, rainbow, residue_colour, step, ColorBy,
    Coloring, Hide, WATER_NAMES,
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
        let mut kind_ids = std::mem::take(&mut self.kind_ids);
        let shown = self.shown.as_deref();
        let colour_of = colour_fn(records, coloring, kind_ids.len(), move |k| shown.map_or(k, |ids| ids[k] as usize));
        let material = self.kinds.first().map_or(crate::structure::ATOM_MATERIAL, |k| k.material);
        let mut kinds: Vec<AtomKind> = Vec::new();
        // (radius, colour) pair → kind, through the pair's bits.
        let mut lookup = std::collections::HashMap::<(u32, [u32; 3]), u8>::new();
        // The colour a kind holds, per (radius kind, colour) pair seen: atoms mostly repeat
        // the last pair, so that one is checked first.
        let mut last: Option<((u32, [u32; 3]), u8)> = None;
        for (k, id) in kind_ids.iter_mut().enumerate() {
            let radius = self.kinds[usize::from(*id)].radius;
            let color = colour_of(k);
            let key = (radius.to_bits(), color.to_array().map(f32::to_bits));
            if let Some((last_key, last_id)) = last {
                if last_key == key {
                    *id = last_id;
                    continue;
                }
            }
            let new = *lookup.entry(key).or_insert_with(|| {
                if kinds.len() < 256 {
                    kinds.push(AtomKind { radius, material: crate::Material { color, ..material } });
                    (kinds.len() - 1) as u8
                } else {
                    nearest(&kinds, radius, color)
                }
            });
            last = Some((key, new));
            *id = new;
        }
        drop(colour_of);
        self.kind_ids = kind_ids;
        self.kinds = kinds;
    }

    /// This structure without the atoms `hide` names (the records stay whole; the atoms
    /// left keep their record index, [`Structure::record_index`]).
    #[must_use]
    pub fn hidden(&self, hide: Hide) -> Structure {
        let Some(records) = self.records.as_ref().filter(|_| !hide.is_empty()) else { return self.clone() };
        let records = &*records.0;
        let (fields, elements) = (records.fields(), records.elements());
        let shown_atom = |i: usize| {
            let h = elements[i].atomic_number() == 1;
            let file = records.file_index(i).unwrap_or(i);
            let has = file < fields.len();
            let het = has && fields.is_hetero(file);
            let water = has && WATER_NAMES.contains(&fields.residue_name(file));
            !(hide.hydrogen && h || hide.hetero && het || hide.water && water)
        };
        let keep: Vec<usize> = (0..self.positions.len()).filter(|&k| shown_atom(self.record_index(k))).collect();
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

/// The colour of each of `n` atoms (atom `k` being record `index(k)`) under `coloring`.
fn colour_fn<'a>(
    records: &'a AtomRecords,
    coloring: &Coloring,
    n: usize,
    index: impl Fn(usize) -> usize + 'a,
) -> Box<dyn Fn(usize) -> Vec3 + 'a> {
    let (fields, elements, chains) = (records.fields(), records.elements(), records.chains());
    // The file's atom of record i (an assembly's copies share theirs).
    let file = move |i: usize| records.file_index(i).unwrap_or(i);
    let has_fields = !fields.is_empty();
    let element = move |i: usize| elements[i].linear_colour();
    match coloring.by {
        ColorBy::Element => Box::new(move |k| element(index(k))),
        ColorBy::Chain => {
            let colours: Vec<Vec3> = (0..records.chain_ids().len().max(1)).map(chain_colour).collect();
            Box::new(move |k| colours[usize::from(chains[index(k)]) % colours.len()])
        }
        ColorBy::Residue if has_fields => Box::new(move |k| residue_colour(fields.residue_name(file(index(k))))),
        ColorBy::BFactor if has_fields => {
            let range = coloring.range.or_else(|| fields.b_factor_range()).unwrap_or((0.0, 1.0));
            Box::new(move |k| {
                fields.b_factor(file(index(k))).map_or(Vec3::splat(0.5), |b| blue_white_red(step(b, range)))
            })
        }
        ColorBy::Plddt if has_fields => {
            Box::new(move |k| fields.b_factor(file(index(k))).map_or(plddt_colour(3), |b| plddt_colour(plddt_band(b))))
        }
        ColorBy::Rainbow if has_fields => {
            // Each chain's residue-number range, over the atoms shown.
            let mut ranges = vec![(i32::MAX, i32::MIN); records.chain_ids().len().max(1)];
            for k in 0..n {
                let i = index(k);
                if let Some(r) = fields.residue_number(file(i)) {
                    let c = &mut ranges[usize::from(chains[i])];
                    *c = (c.0.min(r), c.1.max(r));
                }
            }
            Box::new(move |k| {
                let i = index(k);
                let (lo, hi) = ranges[usize::from(chains[i])];
                let r = fields.residue_number(file(i)).unwrap_or(lo);
                rainbow(step(r as f32, (lo as f32, hi as f32)))
            })
        }
        ColorBy::Hetero if has_fields => {
            let grey = polymer_grey();
            Box::new(move |k| {
                let i = index(k);
                if fields.is_hetero(file(i)) {
                    element(i)
                } else {
                    grey
                }
            })
        }
        // A file without per-atom fields (XYZ): its elements.
        _ => Box::new(move |k| element(index(k))),
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
    pub fn recolor(&mut self, scene: &Scene) {
        self.scene.recolor(scene);
        self.bump_generation();
    }
}

#[cfg(test)]
mod tests;

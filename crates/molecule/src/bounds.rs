//! Bounding volumes of a set of atoms, counting each atom's sphere (element radius × a
//! scale): what a renderer needs to frame a molecule or build a hierarchy over it.

use glam::Vec3;

use crate::element::Element;

/// An axis-aligned box, Ångström.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// The smallest corner.
    pub min: Vec3,
    /// The largest corner.
    pub max: Vec3,
}

impl Bounds {
    /// The box's centre.
    #[must_use]
    pub fn centre(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    /// The box's size along each axis.
    #[must_use]
    pub fn size(&self) -> Vec3 {
        self.max - self.min
    }
}

/// A sphere, Ångström.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Its centre.
    pub centre: Vec3,
    /// Its radius.
    pub radius: f32,
}

/// Every element's radius × `scale`, so the loops below look radii up in a flat table.
fn scaled_radii(scale: f32) -> [f32; 256] {
    let mut radii = [0.0; 256];
    for (z, r) in radii.iter_mut().enumerate() {
        let element = u8::try_from(z).ok().and_then(Element::from_atomic_number).unwrap_or(Element::UNKNOWN);
        *r = element.radius() * scale;
    }
    radii
}

/// The box around every atom's sphere, radius = element radius × `radius_scale`; `None` for
/// no atoms. `positions` and `elements` pair up to the shorter of the two.
#[must_use]
pub fn bounds(positions: &[Vec3], elements: &[Element], radius_scale: f32) -> Option<Bounds> {
    let radii = scaled_radii(radius_scale);
    sphere_bounds(positions.iter().zip(elements).map(|(&p, &e)| (p, radii[usize::from(e.atomic_number())])))
}

/// A sphere around every atom's sphere, centred on the [`bounds`] box: its radius is the
/// largest distance from that centre to an atom plus the atom's scaled radius. Not the
/// smallest enclosing sphere, but within a factor √3 of it, in two passes.
#[must_use]
pub fn bounding_sphere(positions: &[Vec3], elements: &[Element], radius_scale: f32) -> Option<Sphere> {
    let radii = scaled_radii(radius_scale);
    enclosing_sphere(positions.iter().zip(elements).map(|(&p, &e)| (p, radii[usize::from(e.atomic_number())])))
}

/// The box around spheres given as (centre, radius); `None` for none. [`bounds`] for atoms
/// whose radii are already resolved.
#[must_use]
pub fn sphere_bounds(spheres: impl IntoIterator<Item = (Vec3, f32)>) -> Option<Bounds> {
    let mut spheres = spheres.into_iter();
    let (first, r) = spheres.next()?;
    let r = Vec3::splat(r);
    let mut min = first - r;
    let mut max = first + r;
    for (p, r) in spheres {
        let r = Vec3::splat(r);
        min = min.min(p - r);
        max = max.max(p + r);
    }
    Some(Bounds { min, max })
}

/// A sphere around spheres given as (centre, radius), centred on their [`sphere_bounds`] box,
/// as [`bounding_sphere`] is for atoms; `None` for none.
#[must_use]
pub fn enclosing_sphere<I>(spheres: I) -> Option<Sphere>
where
    I: IntoIterator<Item = (Vec3, f32)>,
    I::IntoIter: Clone,
{
    let spheres = spheres.into_iter();
    let centre = sphere_bounds(spheres.clone())?.centre();
    let radius = spheres.map(|(p, r)| p.distance(centre) + r).fold(0.0_f32, f32::max);
    Some(Sphere { centre, radius })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_count_each_atom_radius_times_the_scale() {
        let positions = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(10.0, -2.0, 4.0)];
        let elements = [Element::C, Element::H];
        let b = bounds(&positions, &elements, 0.5).unwrap();
        assert_eq!(b.min, Vec3::new(-0.85, -2.6, -0.85), "C's 1.7 × 0.5 and H's 1.2 × 0.5 below");
        assert_eq!(b.max, Vec3::new(10.6, 0.85, 4.6), "and above");
        assert_eq!(bounds(&[], &[], 1.0), None, "no atoms, no box");
    }

    #[test]
    fn the_bounding_sphere_holds_every_atom_sphere() {
        let positions = [Vec3::new(-5.0, 0.0, 0.0), Vec3::new(5.0, 0.0, 0.0)];
        let elements = [Element::O, Element::O];
        let s = bounding_sphere(&positions, &elements, 1.0).unwrap();
        assert_eq!(s.centre, Vec3::ZERO, "midway");
        assert!((s.radius - (5.0 + 1.52)).abs() < 1e-6, "centre distance plus O's radius: {}", s.radius);
        assert_eq!(bounding_sphere(&[], &[], 1.0), None, "no atoms, no sphere");
    }

    #[test]
    fn spheres_given_with_their_radii_bound_as_atoms_do() {
        let positions = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(10.0, -2.0, 4.0)];
        let spheres = [(positions[0], Element::C.radius() * 0.5), (positions[1], Element::H.radius() * 0.5)];
        let atoms = [Element::C, Element::H];
        assert_eq!(sphere_bounds(spheres), bounds(&positions, &atoms, 0.5), "the same box");
        assert_eq!(enclosing_sphere(spheres), bounding_sphere(&positions, &atoms, 0.5), "the same sphere");
        assert_eq!(enclosing_sphere([]), None, "no spheres, no sphere");
    }
}

//! Biological assemblies: the rigid motions a file lists (PDB `REMARK 350` BIOMT records,
//! mmCIF `_pdbx_struct_oper_list`) and the chains each applies to
//! (`APPLY THE FOLLOWING TO CHAINS`, `_pdbx_struct_assembly_gen`).
//!
//! Operators are stored in the crate's left-handed space. A file's motion p' = R·p + t maps,
//! with S = diag(1, 1, −1) taking file space to ours, to p' = (S·R·S)·p + S·t: the signs of
//! R's entries that mix z with x or y flip, and so does t's z. Products of operators map the
//! same way, since S·S = I.

use glam::{Mat3, Vec3};

/// A rigid motion (a rotation, in principle, and a translation) in the crate's space:
/// `p' = rotation · p + translation`, Ångström.
#[derive(Clone, Debug, PartialEq)]
pub struct Operator {
    /// The file's name for it: the BIOMT serial number, or the `_pdbx_struct_oper_list.id`
    /// (`"1"`, `"P"`, or `"1x61"` for a product).
    pub id: String,
    /// The linear part.
    pub rotation: Mat3,
    /// The translation, Ångström.
    pub translation: Vec3,
}

impl Operator {
    /// The operator a file gives as three rows `[r_i1, r_i2, r_i3, t_i]` in its own
    /// (right-handed) space, mapped into the crate's space.
    #[must_use]
    pub fn from_file_rows(id: String, rows: [[f64; 4]; 3]) -> Self {
        // S·R·S negates R[i][j] when exactly one of i, j is the z row or column.
        let sign = |i: usize, j: usize| if (i == 2) == (j == 2) { 1.0 } else { -1.0 };
        let r = |i: usize, j: usize| (sign(i, j) * rows[i][j]) as f32;
        let rotation = Mat3::from_cols(
            Vec3::new(r(0, 0), r(1, 0), r(2, 0)),
            Vec3::new(r(0, 1), r(1, 1), r(2, 1)),
            Vec3::new(r(0, 2), r(1, 2), r(2, 2)),
        );
        let translation = Vec3::new(rows[0][3] as f32, rows[1][3] as f32, -rows[2][3] as f32);
        Self { id, rotation, translation }
    }

    /// The point moved by this operator.
    #[must_use]
    #[inline]
    pub fn apply(&self, point: Vec3) -> Vec3 {
        self.rotation * point + self.translation
    }

    /// `self` after `first`: the operator that applies `first`, then `self` (mmCIF's
    /// `(self)(first)` product).
    #[must_use]
    pub fn after(&self, first: &Operator) -> Operator {
        Operator {
            id: format!("{}x{}", self.id, first.id),
            rotation: self.rotation * first.rotation,
            translation: self.rotation * first.translation + self.translation,
        }
    }
}

/// Some chains and the operators applied to each of them.
#[derive(Clone, Debug, PartialEq)]
pub struct AssemblyPart {
    /// The chains, by the ids [`Molecule::chain_ids`](crate::Molecule::chain_ids) uses (PDB
    /// column 22; mmCIF `label_asym_id`). Ids without atoms are ignored.
    pub chains: Vec<String>,
    /// The operators: each gives one copy of the chains.
    pub operators: Vec<Operator>,
}

/// A biological assembly: the union of its parts' copies.
#[derive(Clone, Debug, PartialEq)]
pub struct Assembly {
    /// The file's name for it (PDB BIOMOLECULE number, mmCIF `assembly_id`).
    pub id: String,
    /// Its parts, in file order.
    pub parts: Vec<AssemblyPart>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_motion_maps_to_the_same_motion_in_our_space() {
        // A rotation about x by 90° and a translation, in file space.
        let rows = [[1.0, 0.0, 0.0, 1.0], [0.0, 0.0, -1.0, 2.0], [0.0, 1.0, 0.0, 3.0]];
        let op = Operator::from_file_rows("2".into(), rows);
        let file_point = [0.5_f64, -1.5, 2.5];
        let moved: Vec<f64> =
            rows.iter().map(|r| r[0] * file_point[0] + r[1] * file_point[1] + r[2] * file_point[2] + r[3]).collect();
        let ours = op.apply(Vec3::new(0.5, -1.5, -2.5));
        let expected = Vec3::new(moved[0] as f32, moved[1] as f32, -moved[2] as f32);
        assert!(ours.abs_diff_eq(expected, 1e-6), "S·(R·p + t) = (S·R·S)·(S·p) + S·t: {ours} vs {expected}");
    }

    #[test]
    fn after_applies_the_first_operator_first() {
        let shift = Operator { id: "a".into(), rotation: Mat3::IDENTITY, translation: Vec3::X };
        let turn = Operator {
            id: "b".into(),
            rotation: Mat3::from_rotation_z(std::f32::consts::FRAC_PI_2),
            translation: Vec3::ZERO,
        };
        let both = turn.after(&shift);
        let p = Vec3::new(1.0, 0.0, 0.0);
        assert!(both.apply(p).abs_diff_eq(turn.apply(shift.apply(p)), 1e-6), "turn(shift(p))");
        assert!(
            both.apply(p).abs_diff_eq(Vec3::new(0.0, 2.0, 0.0), 1e-6),
            "(2, 0, 0) turned a quarter: {}",
            both.apply(p)
        );
        assert_eq!(both.id, "bxa", "named as the product");
    }
}

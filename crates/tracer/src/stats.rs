//! Exact ray counters.

use std::ops::{Add, AddAssign};

/// Rays cast, by kind. Counted per worker (per row) and summed afterwards: the inner loop
/// never touches an atomic, and the sum does not depend on the thread count.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct RayCounts {
    /// Camera rays, one per traced pixel.
    pub primary: u64,
    /// Rays towards a light from a hit point (cast only where the surface faces the light).
    pub shadow: u64,
    /// Mirror-reflection rays.
    pub reflection: u64,
}

impl RayCounts {
    /// All rays: primary + shadow + reflection.
    #[must_use]
    pub fn total(&self) -> u64 {
        self.primary + self.shadow + self.reflection
    }
}

impl Add for RayCounts {
    type Output = Self;
    fn add(self, o: Self) -> Self {
        Self {
            primary: self.primary + o.primary,
            shadow: self.shadow + o.shadow,
            reflection: self.reflection + o.reflection,
        }
    }
}

impl AddAssign for RayCounts {
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl std::iter::Sum for RayCounts {
    fn sum<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.fold(Self::default(), Add::add)
    }
}

/// Heap bytes a vector holds (its capacity, not its length).
pub(crate) fn heap<T>(v: &Vec<T>) -> usize {
    v.capacity() * std::mem::size_of::<T>()
}

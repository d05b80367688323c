//! Math types: rapier's public glam types, re-exported so users need no extra import.

pub use rapier3d::math::{Pose, Real, Rotation, Vector};

/// Converts a vector to `[f32; 3]` (for errors and reports).
#[inline]
pub fn arr(v: Vector) -> [f32; 3] {
    [v.x, v.y, v.z]
}

/// Whether every component is finite.
#[inline]
pub fn finite(v: Vector) -> bool {
    v.x.is_finite() && v.y.is_finite() && v.z.is_finite()
}

/// Lower and upper corners of the points' bounding box (infinite and inverted for no point).
pub(crate) fn bounding_box(pts: &[Vector]) -> (Vector, Vector) {
    use rayon::prelude::*;
    let empty = || {
        (
            Vector::splat(f32::INFINITY),
            Vector::splat(f32::NEG_INFINITY),
        )
    };
    pts.par_iter()
        .fold(empty, |(a, b), p| (a.min(*p), b.max(*p)))
        .reduce(empty, |(a, b), (c, d)| (a.min(c), b.max(d)))
}

//! Per-slot weight vectors of the velocity constraint's operator, stored as 16-bit fixed point
//! with one scale per row: 6 bytes a slot instead of 12.
//!
//! A row's scale is its largest component over 32767, so every stored component is within
//! `1.5e-5` of the row's largest: far below the discretisation error of the weights, and four
//! orders of magnitude below the solve's stopping tolerance. The force weights are the same
//! integers as the divergence weights of the transposed pair (in that row's scale), so the
//! divergence and its adjoint, the pressure force, stay exact adjoints of each other.
//!
//! Fewer bits were measured and not kept: three 10-bit fields in one `u32` (4 bytes a slot)
//! left the tank and the dam break unchanged but moved the wedge entry at 4× its step from
//! 27.4 % to 30.5 % mean velocity deviation (11 bits 27.8 %, 12 bits 27.5 %) and let the five
//! balls at 4× their step diverge; a per-slot exponent on the 10-bit fields did not help.

use crate::math::Vector;

/// A stored weight vector (multiply by the row's scale).
pub type Packed = [i16; 3];

/// The zero vector.
pub const ZERO: Packed = [0; 3];

/// Largest stored magnitude.
const FULL: f32 = i16::MAX as f32;

/// The stored vector in units of the row's scale.
#[inline]
pub fn unpack(q: Packed) -> Vector {
    Vector::new(q[0] as f32, q[1] as f32, q[2] as f32)
}

/// `−q`, exactly (the range is symmetric: −32768 is never stored).
#[inline]
pub fn neg(q: Packed) -> Packed {
    q.map(|c| -c)
}

/// Rounds half away from zero into `−32767..=32767` (a symmetric range, so [`neg`] is exact).
/// `as` truncates (one instruction, where `f32::round` is a library call on baseline x86-64),
/// saturates and maps NaN to 0.
#[inline]
fn round(c: f32) -> i16 {
    ((c + 0.5f32.copysign(c)) as i16).max(-i16::MAX)
}

/// Largest component magnitude of `e`, NaN components ignored, 0 if it is infinite (what
/// [`row_scale`] needs of each slot).
#[inline]
pub fn magnitude(e: Vector) -> f32 {
    let m = e.abs().max_element();
    if m.is_finite() {
        m
    } else {
        0.0
    }
}

/// Scale of a row whose largest [`magnitude`] is `max`, and its inverse (both 0 for an all-zero
/// or empty row).
#[inline]
pub fn row_scale(max: f32) -> (f32, f32) {
    if max > 0.0 {
        (max / FULL, FULL / max)
    } else {
        (0.0, 0.0)
    }
}

/// `e` stored at inverse scale `inv`. A NaN component is stored as 0 and an infinite one
/// saturates (a non-finite state is caught by the step's own check and reported as
/// [`crate::FluidError::Diverged`]).
#[inline]
pub fn pack(e: Vector, inv: f32) -> Packed {
    let r = e * inv;
    [round(r.x), round(r.y), round(r.z)]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_error_is_bounded_by_the_row_maximum() {
        let v: Vec<Vector> = (0..37)
            .map(|k| {
                let t = k as f32 * 0.37;
                Vector::new(t.sin() * 3e-6, t.cos() * 1e-7, (t * 2.1).sin() * 2e-6)
            })
            .collect();
        let m = v.iter().copied().map(magnitude).fold(0.0, f32::max);
        let (s, inv) = row_scale(m);
        for e in &v {
            let q = pack(*e, inv);
            assert!(q.iter().all(|&c| c != i16::MIN));
            let err = (unpack(q) * s - *e).abs().max_element();
            assert!(err <= 0.5001 * m / FULL, "error {err} against max {m}");
            assert_eq!(unpack(neg(q)), -unpack(q));
            assert_eq!(neg(neg(q)), q);
        }
        // the largest magnitudes and the signs survive the packing of their neighbours
        assert_eq!(
            pack(Vector::new(1e30, -1e30, 0.0), 1.0),
            [i16::MAX, -i16::MAX, 0]
        );
        assert_eq!(neg([i16::MAX, -i16::MAX, 0]), [-i16::MAX, i16::MAX, 0]);
        assert_eq!(row_scale(0.0), (0.0, 0.0));
        assert_eq!(pack(Vector::new(f32::NAN, 1.0, -1.0), 0.0), ZERO);
        assert_eq!(magnitude(Vector::new(f32::NAN, 1.0, -2.0)), 2.0);
        assert_eq!(magnitude(Vector::new(f32::INFINITY, 1.0, -2.0)), 0.0);
    }
}

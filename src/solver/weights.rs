//! Per-slot weight vectors of the velocity constraint's operator, stored as three signed 10-bit
//! integers in one `u32` with one scale per row: 4 bytes a slot instead of 12.
//!
//! A row's scale is its largest component over 511, so every stored component is within
//! `1e-3` of the row's largest: below the discretisation error of the weights (the staggered
//! weights of a row are all of one order, the kernel gradient at half the pair distance), and
//! two orders of magnitude below the solve's stopping tolerance. The force weights are the same
//! integers as the divergence weights of the transposed pair (in that row's scale), so the
//! divergence and its adjoint, the pressure force, stay exact adjoints of each other.

use crate::math::Vector;

/// A stored weight vector (multiply by the row's scale): components x, y, z in bits 0–9,
/// 10–19 and 20–29, two's complement, each in `−511..=511`.
pub type Packed = u32;

/// The zero vector.
pub const ZERO: Packed = 0;

/// Bits per component.
const BITS: u32 = 10;

/// Largest stored magnitude.
const MAX: i32 = (1 << (BITS - 1)) - 1;

/// Largest stored magnitude as a float.
const FULL: f32 = MAX as f32;

/// The three components as integers.
#[inline]
fn ints(q: Packed) -> [i32; 3] {
    // shift each field to the top, then back with sign extension
    let f = |shift: u32| ((q << (32 - BITS - shift)) as i32) >> (32 - BITS);
    [f(0), f(BITS), f(2 * BITS)]
}

/// Packs three integers in `−MAX..=MAX`.
#[inline]
fn from_ints(c: [i32; 3]) -> Packed {
    let m = (1u32 << BITS) - 1;
    (c[0] as u32 & m) | (c[1] as u32 & m) << BITS | (c[2] as u32 & m) << (2 * BITS)
}

/// The stored vector in units of the row's scale.
#[inline]
pub fn unpack(q: Packed) -> Vector {
    let [x, y, z] = ints(q);
    Vector::new(x as f32, y as f32, z as f32)
}

/// `−q`, exactly (the range is symmetric).
#[inline]
pub fn neg(q: Packed) -> Packed {
    let [x, y, z] = ints(q);
    from_ints([-x, -y, -z])
}

/// Rounds half away from zero into `−MAX..=MAX`. `as` truncates (one instruction, where
/// `f32::round` is a library call on baseline x86-64), saturates and maps NaN to 0.
#[inline]
fn round(c: f32) -> i32 {
    ((c + 0.5f32.copysign(c)) as i32).clamp(-MAX, MAX)
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
    from_ints([round(r.x), round(r.y), round(r.z)])
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
            assert!(ints(q).iter().all(|c| c.abs() <= MAX));
            let err = (unpack(q) * s - *e).abs().max_element();
            assert!(err <= 0.5001 * m / FULL, "error {err} against max {m}");
            assert_eq!(unpack(neg(q)), -unpack(q));
            assert_eq!(neg(neg(q)), q);
        }
        // the largest magnitudes and the signs survive the packing of their neighbours
        let q = from_ints([-MAX, MAX, -1]);
        assert_eq!(unpack(q), Vector::new(-FULL, FULL, -1.0));
        assert_eq!(
            pack(Vector::new(1e30, -1e30, 0.0), 1.0),
            from_ints([MAX, -MAX, 0])
        );
        assert_eq!(row_scale(0.0), (0.0, 0.0));
        assert_eq!(pack(Vector::new(f32::NAN, 1.0, -1.0), 0.0), ZERO);
        assert_eq!(magnitude(Vector::new(f32::NAN, 1.0, -2.0)), 2.0);
        assert_eq!(magnitude(Vector::new(f32::INFINITY, 1.0, -2.0)), 0.0);
    }
}

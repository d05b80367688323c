//! Lattice shape matching (Rivers & James 2007 §3, after Müller et al. 2005): each region's
//! best rigid transform of its rest shape onto the predicted positions, the goal positions
//! they give every IBP, and each IBP's mean rotation (which turns the SBPs' rest offsets and
//! normals, Shao Eq. 19).

use super::lattice::Rows;
use crate::math::{Rotation, Vector};
use rapier3d::math::Matrix;
use rayon::prelude::*;

/// Most iterations of the rotation extraction per region and substep (warm-started, they
/// stop once a turn is below `ROTATION_TOLERANCE`; 6 left a body spinning 0.2 rad a substep
/// 0.025 rad behind after ten).
const ROTATION_ITERATIONS: usize = 20;
/// The turn below which the rotation extraction stops, rad.
const ROTATION_TOLERANCE: f32 = 1e-6;

/// What the regions give each IBP: its goal position and the mean rotation of the regions it
/// belongs to.
pub(crate) struct Goals {
    pub goal: Vec<Vector>,
    pub rotation: Vec<Rotation>,
}

/// The rotation of `a` (its polar part), iterated from `q` (Müller, Bender, Chentanez &
/// Macklin 2016, "A robust method to extract the rotational part of deformations"): each
/// iteration turns `q` about the axis that best aligns its columns with `a`'s. Stays a proper
/// rotation for any `a`, flat or inverted regions included.
pub(crate) fn extract_rotation(a: &Matrix, mut q: Rotation) -> Rotation {
    for _ in 0..ROTATION_ITERATIONS {
        let r = Matrix::from_quat(q);
        let num = r.x_axis.cross(a.x_axis) + r.y_axis.cross(a.y_axis) + r.z_axis.cross(a.z_axis);
        let den = (r.x_axis.dot(a.x_axis) + r.y_axis.dot(a.y_axis) + r.z_axis.dot(a.z_axis)).abs();
        let omega = num / (den + 1e-9);
        let angle = omega.length();
        if angle < 1e-9 {
            break;
        }
        q = (Rotation::from_axis_angle(omega / angle, angle) * q).normalize();
        if angle < ROTATION_TOLERANCE {
            break;
        }
    }
    q
}

/// Shape matching over `regions` for IBPs at rest positions `rest` and predicted positions
/// `x`, each of mass `m`. A point in `n` regions weighs `m / n` in each (Rivers & James'
/// mass scaling), so that the goals keep the body's linear momentum exactly:
/// `Σ m_i g_i = Σ m_i x_i`. `q` holds each region's rotation, warm start in and result out.
pub(crate) fn goals(
    regions: &Rows<u32>,
    rest: &[Vector],
    x: &[Vector],
    m: f32,
    q: &mut [Rotation],
) -> Goals {
    let n = rest.len();
    let share: Vec<f32> = (0..n).map(|i| m / regions.row(i).len() as f32).collect();
    // each region: centre now, centre at rest, rotation
    let fits: Vec<(Vector, Vector, Rotation)> = q
        .par_iter_mut()
        .enumerate()
        .map(|(r, q)| {
            let members = regions.row(r);
            let (mut mass, mut c, mut c0) = (0.0f64, [0.0f64; 3], [0.0f64; 3]);
            for &i in members {
                let (i, w) = (i as usize, share[i as usize] as f64);
                mass += w;
                for k in 0..3 {
                    c[k] += w * x[i][k] as f64;
                    c0[k] += w * rest[i][k] as f64;
                }
            }
            let c = Vector::from_array(c.map(|v| (v / mass) as f32));
            let c0 = Vector::from_array(c0.map(|v| (v / mass) as f32));
            // A = Σ m (x − c)(x⁰ − c⁰)ᵀ
            let mut a = Matrix::ZERO;
            for &i in members {
                let i = i as usize;
                let (p, p0) = (x[i] - c, rest[i] - c0);
                a += Matrix::from_cols(p * p0.x, p * p0.y, p * p0.z) * share[i];
            }
            *q = extract_rotation(&a, *q);
            (c, c0, *q)
        })
        .collect();
    let (goal, rotation) = (0..n)
        .into_par_iter()
        .map(|i| {
            let members = regions.row(i);
            let (mut g, mut qs) = (Vector::ZERO, [0.0f32; 4]);
            let first = fits[members[0] as usize].2;
            for &r in members {
                let (c, c0, q) = fits[r as usize];
                g += q * (rest[i] - c0) + c;
                // quaternions of one hemisphere, summed: their normalised mean
                let q = if q.dot(first) < 0.0 { -q } else { q };
                for (s, v) in qs.iter_mut().zip(q.to_array()) {
                    *s += v;
                }
            }
            let mean = Rotation::from_array(qs).normalize();
            (g / members.len() as f32, mean)
        })
        .unzip();
    Goals { goal, rotation }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_rotation_of_a_stretched_rotation_is_found() {
        let q = Rotation::from_axis_angle(Vector::new(1.0, 2.0, 0.5).normalize(), 1.2);
        let a = Matrix::from_quat(q) * Matrix::from_diagonal(Vector::new(1.5, 0.7, 1.1));
        let mut got = Rotation::IDENTITY;
        for _ in 0..4 {
            got = extract_rotation(&a, got);
        }
        assert!(got.dot(q).abs() > 0.9999, "{got:?} vs {q:?}");
    }
}

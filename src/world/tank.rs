//! Open-topped tanks: a floor and four walls sampled on the fluid lattice.

use super::{FluidWorld, SolidHandle, SolidKind};
use crate::error::{FluidError, Result};
use crate::math::{arr, finite, Pose, Vector};
use crate::solver::staggered::Slip;
use rapier3d::parry::shape::SharedShape;

impl FluidWorld {
    /// Adds an open-topped tank (floor and four walls) whose inner space is
    /// `[inner_min, inner_max]` (y up). Returns the handles `[floor, -x, +x, -z, +z]`.
    ///
    /// The walls are `2h + Δx` thick (h the support radius) so that every carrier fluid can reach
    /// lies nearer the inside than the outside, their carriers sit on the lattice of a fluid
    /// block filled from `inner_min`, only the shell within h of the inside (or of the rim) is
    /// sampled, and each carrier's normal points to the nearest inside point (diagonal along
    /// edges and corners, where a single box's faces would give the wrong direction).
    pub fn add_open_tank(
        &mut self,
        inner_min: Vector,
        inner_max: Vector,
        slip: Slip,
    ) -> Result<[SolidHandle; 5]> {
        let h = self.params.support_radius();
        let t = 2.0 * h + self.params.spacing;
        let (lo, hi) = (inner_min, inner_max);
        if !finite(lo) || !finite(hi) {
            return Err(FluidError::NonFinite {
                what: "tank corners".into(),
            });
        }
        if (0..3).any(|k| hi[k] <= lo[k]) {
            return Err(FluidError::DegenerateShape {
                shape: "tank".into(),
                why: format!("inner extent {:?} is not positive", arr(hi - lo)),
            });
        }
        // Boxes overlap at the edges (a later box skips carriers inside earlier ones).
        let boxes = [
            (
                "floor",
                Vector::new(lo.x - t, lo.y - t, lo.z - t),
                Vector::new(hi.x + t, lo.y, hi.z + t),
            ),
            (
                "wall -x",
                Vector::new(lo.x - t, lo.y - t, lo.z - t),
                Vector::new(lo.x, hi.y, hi.z + t),
            ),
            (
                "wall +x",
                Vector::new(hi.x, lo.y - t, lo.z - t),
                Vector::new(hi.x + t, hi.y, hi.z + t),
            ),
            (
                "wall -z",
                Vector::new(lo.x - t, lo.y - t, lo.z - t),
                Vector::new(hi.x + t, hi.y, lo.z),
            ),
            (
                "wall +z",
                Vector::new(lo.x - t, lo.y - t, hi.z),
                Vector::new(hi.x + t, hi.y, hi.z + t),
            ),
        ];
        // fluid lives in the open column above the floor, or spills over the rim
        let reach = move |p: Vector| {
            let q = Vector::new(p.x.clamp(lo.x, hi.x), p.y.max(lo.y), p.z.clamp(lo.z, hi.z));
            (p - q).length() <= h || p.y >= hi.y - h
        };
        let normal = move |p: Vector, n_box: Vector| {
            let q = p.clamp(lo, hi);
            let d = q - p;
            let l = d.length();
            if l > 1e-6 && l < hi.y - p.y {
                d / l
            } else {
                n_box
            }
        };
        let mut out = [SolidHandle(0); 5];
        for (k, (name, a, b)) in boxes.into_iter().enumerate() {
            let half = (b - a) * 0.5;
            out[k] = self.add_sampled_on(
                name.into(),
                SharedShape::cuboid(half.x, half.y, half.z),
                Pose::from_translation((a + b) * 0.5),
                slip,
                SolidKind::Static,
                Some(lo),
                &reach,
                &normal,
            )?;
        }
        Ok(out)
    }
}

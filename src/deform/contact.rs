//! A deformable body against fixed and scripted solids (a tank's walls, a rapier ground):
//! its IBPs kept half a spacing from their exact surfaces (parry's projection), so that its
//! surface, half a spacing outside its outer IBPs, rests on them.
//!
//! Frictionless and inelastic along the normal: an IBP found closer is moved out along the
//! solid's normal and loses its velocity into the solid, relative to the solid's. The solid
//! takes that momentum (fixed and scripted solids are not pushed back). Dynamic rapier bodies
//! are not in contact with deformable ones yet.

use crate::math::Vector;
use crate::world::{FluidWorld, SolidKind};

impl FluidWorld {
    /// Keeps deformable body `bi`'s IBPs half a spacing out of every fixed or scripted solid
    /// near it; returns how many were moved.
    pub(crate) fn keep_out_of_walls(&mut self, bi: usize) -> usize {
        let b = &self.deformables[bi];
        let clear = 0.5 * self.params.spacing;
        let (lo, hi) = crate::math::bounding_box(&b.x);
        let (lo, hi) = (
            lo - Vector::splat(2.0 * clear),
            hi + Vector::splat(2.0 * clear),
        );
        let walls: Vec<usize> = (0..self.solids.len())
            .filter(|&k| {
                let s = &self.solids[k];
                let fixed = matches!(s.kind, SolidKind::Static | SolidKind::Kinematic);
                let aabb = s.shape.compute_aabb(&s.pose);
                fixed
                    && !s.removed
                    && (0..3).all(|a| aabb.mins[a] <= hi[a] && aabb.maxs[a] >= lo[a])
            })
            .collect();
        if walls.is_empty() {
            return 0;
        }
        let b = &mut self.deformables[bi];
        let mut moved = 0;
        for i in 0..b.x.len() {
            if b.pinned[i] {
                continue;
            }
            for &k in &walls {
                let s = &self.solids[k];
                let local = s.pose.inverse_transform_point(b.x[i]);
                let (point, inside) = crate::sampling::project(s.shape.as_ref(), local);
                let d = point - local;
                let dist = d.length();
                if !inside && dist >= clear {
                    continue;
                }
                let Some(dir) = d.try_normalize() else {
                    continue;
                };
                // the outward normal of the wall at the IBP
                let n = s.pose.rotation * if inside { dir } else { -dir };
                b.x[i] = s.pose.transform_point(point) + n * clear;
                let u = s.linvel + s.angvel.cross(b.x[i] - s.com);
                let vn = (b.v[i] - u).dot(n);
                if vn < 0.0 {
                    b.v[i] -= n * vn;
                }
                moved += 1;
            }
        }
        moved
    }
}

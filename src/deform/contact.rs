//! A deformable body against other solids (a tank's walls, a rapier ground, a rapier body):
//! its IBPs kept half a spacing from their exact surfaces (parry's projection), so that its
//! surface, half a spacing outside its outer IBPs, rests on them.
//!
//! Frictionless and inelastic along the normal: an IBP found closer is moved out along the
//! solid's normal and loses its velocity into the solid, relative to the solid's. A fixed or
//! scripted solid takes that momentum without moving; a dynamic rapier body takes the equal
//! and opposite impulse (the two-body collision along the normal, the body's mass and
//! inertia included), kicked at once within the fluid step and handed to rapier with the
//! fluid's impulses.

use crate::math::Vector;
use crate::rigid;
use crate::world::{FluidWorld, SolidKind};

impl FluidWorld {
    /// Keeps deformable body `bi`'s IBPs half a spacing out of every other solid near it;
    /// returns how many were moved.
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
                let aabb = s.shape.compute_aabb(&s.pose);
                s.kind != SolidKind::Deformable
                    && !s.removed
                    && (0..3).all(|a| aabb.mins[a] <= hi[a] && aabb.maxs[a] >= lo[a])
            })
            .collect();
        let mut moved = 0;
        for i in 0..self.deformables[bi].x.len() {
            if self.deformables[bi].pinned[i] {
                continue;
            }
            for &k in &walls {
                let b = &self.deformables[bi];
                let s = &self.solids[k];
                let local = s.pose.inverse_transform_point(b.x[i]);
                let (point, inside) = crate::sampling::project(s.shape.as_ref(), local);
                let d = point - local;
                if !inside && d.length() >= clear {
                    continue;
                }
                let Some(dir) = d.try_normalize() else {
                    continue;
                };
                // the outward normal of the solid at the IBP
                let n = s.pose.rotation * if inside { dir } else { -dir };
                let x = s.pose.transform_point(point) + n * clear;
                let arm = x - s.com;
                let vn = (b.v[i] - (s.linvel + s.angvel.cross(arm))).dot(n);
                let (m, rigid) = (b.mass, s.rigid.filter(|_| s.kind == SolidKind::Dynamic));
                let b = &mut self.deformables[bi];
                b.x[i] = x;
                moved += 1;
                if vn >= 0.0 {
                    continue;
                }
                let Some(ri) = rigid else {
                    b.v[i] -= n * vn;
                    continue;
                };
                // the collision along n of the IBP with the rapier body
                let r = &self.rigids[ri];
                let (im, ii) = if r.moving() {
                    (r.inv_mass(), r.inv_inertia())
                } else {
                    (Vector::ZERO, Default::default())
                };
                let rn = arm.cross(n);
                let mass = 1.0 / (1.0 / m + n.dot(im * n) + rn.dot(ii * rn));
                let j = n * (-vn * mass);
                b.v[i] += j / m;
                let e = rigid::wrench(-j, arm);
                let r = &mut self.rigids[ri];
                r.linvel += im * -j;
                r.angvel += ii * arm.cross(-j);
                for (a, v) in r.impulse.iter_mut().zip(e) {
                    *a += v;
                }
                for (a, v) in self.impulses[k].iter_mut().zip(e) {
                    *a += v;
                }
            }
        }
        moved
    }
}

//! Rapier's fixed colliders inside the fluid substeps: a dynamic body resting on (or moving
//! towards) a static solid that rapier also collides it with is kept from moving into it
//! while the fluid steps, and rapier is then handed the support the wall gave.
//!
//! Without it the substeps move a body resting on the floor down under its weight less its
//! buoyancy (a 1450 kg/m³ ball of radius 6 cm at rapier's 1/60 s: half a millimetre a frame)
//! and rapier's contact lifts it back after the fluid's step: the water around it is pumped
//! every frame and carriers end up inside it.

use super::FluidWorld;
use crate::math::{Pose, Vector};
use crate::rigid::{self, Rigid};
use rapier3d::geometry::ColliderSet;
use rapier3d::parry::bounding_volume::BoundingVolume;
use rapier3d::parry::query::{ContactManifold, DefaultQueryDispatcher, PersistentQueryDispatcher};

/// Passes over a body's contacts per constraint (Gauss–Seidel).
const PASSES: usize = 4;

/// How far past a wall's surface a body may move, in spacings: as rapier's allowed linear
/// error lets resting contacts overlap a little (rapier keeps a ball resting on a floor
/// 0.04–0.08 mm in it), so that a body rapier leaves slightly in a wall is not stopped dead
/// by a microsecond step.
const SLOP: f32 = 0.01;

impl FluidWorld {
    /// Pairs each dynamic body's solids with the static solids whose rapier colliders it
    /// collides with (collision and solver groups both allow it, neither is a sensor): coupled
    /// fixed colliders, and the fluid walls of tanks made by [`Self::add_rapier_tank`] (their
    /// faces towards the water are the rapier cuboids').
    pub(crate) fn pair_with_walls(&self, rigids: &mut [Rigid], colliders: &ColliderSet) {
        let coupled = self
            .solids
            .iter()
            .enumerate()
            .filter(|(_, w)| w.kind == super::SolidKind::Static)
            .filter_map(|(k, w)| Some((k, w.collider?)));
        let tanks = self.tank_walls.iter().map(|w| w.0 as usize);
        let walls: Vec<(usize, &rapier3d::geometry::Collider)> = coupled
            .chain(tanks.zip(self.tank_colliders.iter().copied()))
            .filter(|(k, _)| !self.solids[*k].removed)
            .filter_map(|(k, ch)| Some((k, colliders.get(ch)?)))
            .filter(|(_, c)| !c.is_sensor())
            .collect();
        for (k, s) in self.solids.iter().enumerate() {
            let (Some(ri), Some(ch), false) = (s.rigid, s.collider, s.removed) else {
                continue;
            };
            let Some(co) = colliders.get(ch).filter(|c| !c.is_sensor()) else {
                continue;
            };
            for (w, cw) in &walls {
                if co.collision_groups().test(cw.collision_groups())
                    && co.solver_groups().test(cw.solver_groups())
                {
                    rigids[ri].walls.push((k as u32, *w as u32));
                }
            }
        }
    }

    /// Each moving body's contacts with its walls at the start of a substep of length `dt`:
    /// every manifold point within the distance its fastest point can travel in the substep
    /// plus half a spacing.
    pub(crate) fn find_wall_contacts(&mut self, dt: f32) {
        let margin = 0.5 * self.params.spacing;
        for r in self.rigids.iter_mut() {
            r.contacts.clear();
            if !r.moving() {
                continue;
            }
            for &(k, w) in &r.walls {
                let (s, wall) = (&self.solids[k as usize], &self.solids[w as usize]);
                if s.removed || wall.removed {
                    continue;
                }
                let sphere = s.shape.compute_bounding_sphere(&s.pose);
                let lever = (sphere.center - r.com).length() + sphere.radius;
                let reach = (r.linvel.length() + r.angvel.length() * lever) * dt + margin;
                let near = s
                    .shape
                    .compute_aabb(&s.pose)
                    .loosened(reach)
                    .intersects(&wall.shape.compute_aabb(&wall.pose));
                if !near {
                    continue;
                }
                let pos12 = s.pose.inv_mul(&wall.pose);
                let mut manifolds: Vec<ContactManifold<(), ()>> = Vec::new();
                let found = DefaultQueryDispatcher.contact_manifolds(
                    &pos12,
                    s.shape.as_ref(),
                    wall.shape.as_ref(),
                    reach,
                    &mut manifolds,
                    &mut None,
                );
                // (a pair parry has no manifold for is left to rapier, as before)
                if found.is_err() {
                    continue;
                }
                for m in &manifolds {
                    let frame = s.pose * m.subshape_pos1().copied().unwrap_or(Pose::IDENTITY);
                    let n = frame.rotation * m.local_n1;
                    for c in &m.points {
                        r.contacts
                            .push((frame.transform_point(c.local_p1), n, c.dist));
                    }
                }
            }
        }
    }

    /// Keeps each moving body from moving into its walls over a substep of length `dt`: the
    /// velocity of every contact point towards its wall is cut to what closes the gap (plus
    /// [`SLOP`]), by impulses along the contact normals; no friction here
    /// (rapier's step applies it, [`Self::apply_to_rapier`]).
    ///
    /// For the substep's predicted pose (`predicted`: after gravity, before the water's
    /// forces) the change is only provisional: the final call takes it back and keeps the
    /// final velocity off the walls, so the walls carry what gravity and the water together
    /// press on them (a heavy ball's weight less its buoyancy), summed in
    /// [`Rigid::wall_impulse`]. A body that moves with the water beside it
    /// ([`super::lumps`]) is held there with that water: the take-back and the final cut
    /// act on body and lump together ([`Self::keep_lump_off_walls`]).
    pub(crate) fn keep_off_walls(&mut self, dt: f32, predicted: bool) {
        let slop = SLOP * self.params.spacing;
        let current = !predicted && self.lumps_current();
        for ri in 0..self.rigids.len() {
            if !self.rigids[ri].moving() {
                continue;
            }
            if current && !self.rigids[ri].hung && self.has_lump(ri) {
                self.keep_lump_off_walls(ri, dt, slop);
                continue;
            }
            let r = &mut self.rigids[ri];
            if !predicted {
                let (dv, dw) = std::mem::take(&mut r.wall_kick);
                r.linvel -= dv;
                r.angvel -= dw;
                r.wall_kick_impulse = [0.0; 6];
            }
            if r.contacts.is_empty() {
                continue;
            }
            let (v0, w0) = (r.linvel, r.angvel);
            let (mut v, mut w) = (v0, w0);
            let e = cut_approach(
                &r.contacts,
                r.start.0,
                (&mut v, &mut w),
                slop,
                dt,
                |j, arm| r.response(j, arm.cross(j)),
            );
            (r.linvel, r.angvel) = (v, w);
            if predicted {
                r.wall_kick = (v - v0, w - w0);
                r.wall_kick_impulse = e;
            } else {
                for (a, b) in r.wall_impulse.iter_mut().zip(e) {
                    *a += b;
                }
            }
        }
    }

    /// The final [`Self::keep_off_walls`] of rigid `ri` moving with its lump: the predicted
    /// pose's provisional support taken back as `share_weight` gave it (to body and water
    /// beside it), then the contacts' cut with the lump's mass, whose velocity change body and
    /// lump take alike. Held by the body alone, the wall stopped the body but not the water
    /// that moved with it: a ball resting on the floor pushed its weight less its buoyancy,
    /// times the lump's share of their mass, into the water beside it every substep.
    fn keep_lump_off_walls(&mut self, ri: usize, dt: f32, slop: f32) {
        let r = &mut self.rigids[ri];
        r.wall_kick = (Vector::ZERO, Vector::ZERO);
        let mut total = std::mem::take(&mut r.wall_kick_impulse).map(|x| -x);
        let r = &self.rigids[ri];
        if r.contacts.is_empty() && total.iter().all(|&x| x == 0.0) {
            // no support to take back and no wall to cut against
            return;
        }
        if !r.contacts.is_empty() {
            let (du, dw, _) = self.rigid_response(ri, &total, true);
            let (mut v, mut w) = (r.linvel + du, r.angvel + dw);
            let e = cut_approach(
                &r.contacts,
                r.start.0,
                (&mut v, &mut w),
                slop,
                dt,
                |j, arm| {
                    let (du, dw, _) = self.rigid_response(ri, &rigid::wrench(j, arm), true);
                    (du, dw)
                },
            );
            for (a, b) in self.rigids[ri].wall_impulse.iter_mut().zip(e) {
                *a += b;
            }
            for (a, b) in total.iter_mut().zip(e) {
                *a += b;
            }
        }
        self.kick_with_lump(ri, &total, dt);
    }
}

/// Gauss–Seidel passes over `contacts` of a body whose centre of mass started the substep at
/// `com`: the velocity `(v, w)` of every contact point towards its wall cut to what closes the
/// gap (plus `slop`) over `dt`, by impulses along the contact normals, `resp` giving the body's
/// velocity change `(Δv, Δω)` for an impulse `j` at lever arm `arm`. Returns the impulses'
/// wrench `[J; L]` about `com`.
fn cut_approach(
    contacts: &[(Vector, Vector, f32)],
    com: Vector,
    (v, w): (&mut Vector, &mut Vector),
    slop: f32,
    dt: f32,
    resp: impl Fn(Vector, Vector) -> (Vector, Vector),
) -> [f64; 6] {
    let mut e = [0.0f64; 6];
    for _ in 0..PASSES {
        let mut pushed = false;
        for &(p, n, dist) in contacts {
            let arm = p - com;
            let approach = (*v + w.cross(arm)).dot(n);
            let allowed = (dist + slop).max(0.0) / dt;
            if approach <= allowed {
                continue;
            }
            let (dv, dw) = resp(n, arm);
            let k = (dv + dw.cross(arm)).dot(n);
            if k <= f32::EPSILON {
                continue;
            }
            let j = -n * ((approach - allowed) / k);
            let (dv, dw) = resp(j, arm);
            *v += dv;
            *w += dw;
            for (a, b) in e.iter_mut().zip(rigid::wrench(j, arm)) {
                *a += b;
            }
            pushed = true;
        }
        if !pushed {
            break;
        }
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::FluidParams;
    use rapier3d::prelude::*;

    /// A 1 kg ball 1 mm over a fixed floor, falling at 1 m/s: a 10 ms substep closes the gap
    /// (and the slop, 0.5 mm at Δx 5 cm) and no more; moving away, it is left alone.
    #[test]
    fn a_falling_ball_stops_at_the_floor() {
        let mut bodies = RigidBodySet::new();
        let mut colliders = ColliderSet::new();
        let floor = ColliderBuilder::cuboid(1.0, 0.1, 1.0).build();
        colliders.insert(floor);
        let ball = bodies.insert(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.0, 0.2, 0.0))
                .linvel(Vector::new(0.0, -1.0, 0.0)),
        );
        colliders.insert_with_parent(ColliderBuilder::ball(0.099).mass(1.0), ball, &mut bodies);
        let mut world = FluidWorld::new(FluidParams {
            spacing: 0.05,
            ..Default::default()
        })
        .unwrap();
        world
            .couple_all(&bodies, &colliders, crate::Slip::FreeSlip)
            .unwrap();
        world.sync_rapier(&bodies, &colliders).unwrap();
        let dt = 0.01;
        world.rigids[0].start = (world.rigids[0].com, world.rigids[0].rotation);
        world.find_wall_contacts(dt);
        assert!(!world.rigids[0].contacts.is_empty());
        world.keep_off_walls(dt, false);
        let v = world.rigids[0].linvel;
        // gap and slop 1.5 mm: 0.15 m/s closes them in 10 ms
        assert!((v.y + 0.15).abs() < 1e-3, "{v}");
        assert!((world.rigids[0].wall_impulse[1] - 0.85).abs() < 1e-3);
        world.rigids[0].linvel = Vector::new(0.0, 1.0, 0.0);
        world.keep_off_walls(dt, false);
        assert_eq!(world.rigids[0].linvel, Vector::new(0.0, 1.0, 0.0));
    }
}

//! Coupled rapier bodies inside the fluid substeps (He 2012 §5, Eq. 21): gravity and the
//! predicted pose at the start of a substep, the impulses of every stage summed per carrier and
//! per body and kicking the body, the final pose at the end.

use super::{FluidWorld, SolidKind};
use crate::math::{Pose, Rotation, Vector};
use crate::rigid;
use crate::solver::contact::PointImpulse;
use crate::solver::staggered::Share;
use crate::solver::{BodyView, Impulses};
use rapier3d::parry::shape::SharedShape;

impl FluidWorld {
    /// Dynamic bodies at the start of a substep: gravity, then the predicted pose the fluid
    /// sees (He 2012 Algorithm 1 predicts fluid and solids together).
    /// A body rapier also collides with a static solid is kept from moving into it
    /// ([`Self::keep_off_walls`]).
    pub(crate) fn predict_rigids(&mut self, gravity: Vector, dt: f32) {
        for r in self.rigids.iter_mut().filter(|r| r.moving()) {
            let free = r.inv_mass().cmpgt(Vector::ZERO);
            let g = Vector::select(free, gravity * r.gravity_scale, Vector::ZERO);
            r.linvel += g * dt;
            r.start = (r.com, r.rotation);
        }
        self.find_wall_contacts(dt);
        self.keep_off_walls(dt, true);
        self.move_rigid_solids(dt, true);
    }

    /// Dynamic bodies at the end of a substep: the pose reached with the final velocity
    /// (symplectic Euler, as rapier integrates it). The carriers stay where the substep's
    /// forces acted until the next substep (or the next sync) places them.
    pub(crate) fn finish_rigids(&mut self, dt: f32) {
        self.keep_off_walls(dt, false);
        self.move_rigid_solids(dt, false);
    }

    fn move_rigid_solids(&mut self, dt: f32, start: bool) {
        if start {
            for s in self.solids.iter_mut() {
                if s.rigid.is_some_and(|ri| self.rigids[ri].moving()) {
                    s.pose_start = s.pose;
                }
            }
        }
        self.place_rigid_solids(dt, start, None);
    }

    /// Moving rigids (those marked in `only`, or all) at the pose their velocity reaches from
    /// the substep's start; their carriers placed there too when `place`.
    fn place_rigid_solids(&mut self, dt: f32, place: bool, only: Option<&[bool]>) {
        let chosen = |ri: usize| only.is_none_or(|o| o[ri]);
        for (ri, r) in self.rigids.iter_mut().enumerate() {
            if !r.moving() || !chosen(ri) {
                continue;
            }
            let (com0, rot0) = r.start;
            r.com = com0 + r.linvel * dt;
            r.rotation = (Rotation::from_scaled_axis(r.angvel * dt) * rot0).normalize();
        }
        for k in 0..self.solids.len() {
            let Some(ri) = self.solids[k].rigid else {
                continue;
            };
            let r = &self.rigids[ri];
            if !r.moving() || !chosen(ri) {
                continue;
            }
            let s = &mut self.solids[k];
            let (com0, _) = r.start;
            let (pose, com) = rigid::advance(s.pose_start, com0, r.linvel, r.angvel, dt);
            s.pose = pose;
            s.linvel = r.linvel;
            s.angvel = r.angvel;
            if place {
                // the carriers (and the torque reference) stay where this substep's forces act
                s.com = com;
                self.place_solid(k);
            }
        }
    }

    /// Moves the carriers of moving dynamic bodies from `x0` by the displacement `Δt (ΔU + Δω ×
    /// r)` that the impulses `imp` of one density iteration would give them (their velocity is
    /// kicked only once, by [`Self::absorb`], after the last iteration).
    pub(crate) fn shift_rigids(&mut self, imp: &Impulses, x0: &[Vector], dt: f32) {
        let mut per = vec![[0.0f64; 6]; self.rigids.len()];
        for &(s, j) in imp {
            let s = s as usize;
            let b = self.solid.body[s] as usize;
            if let Some(ri) = self.solids[b].rigid {
                add6(&mut per[ri], &rigid::wrench(j, x0[s] - self.solids[b].com));
            }
        }
        for &(b, l) in imp.couples() {
            if let Some(ri) = self.solids[b as usize].rigid {
                add6(&mut per[ri], &couple(l));
            }
        }
        let dv: Vec<(Vector, Vector)> = (0..self.rigids.len())
            .map(|ri| {
                if !self.rigids[ri].moving() {
                    return (Vector::ZERO, Vector::ZERO);
                }
                let (du, dw, _) = self.rigid_response(ri, &per[ri], true);
                (du, dw)
            })
            .collect();
        for sol in &self.solids {
            let Some(ri) = sol.rigid else { continue };
            let (du, dw) = dv[ri];
            if du == Vector::ZERO && dw == Vector::ZERO {
                continue;
            }
            for i in sol.range.clone() {
                self.solid.x[i] = x0[i] + (du + dw.cross(x0[i] - sol.com)) * dt;
            }
        }
    }

    /// Adds the impulses of one stage to the per-carrier and per-solid totals (Eq. 21: torque
    /// about each solid's centre of mass) and kicks the dynamic bodies, whose carriers then move
    /// with the new velocity in the next stage. Takes them by value, so each stage's impulses
    /// are freed once absorbed. For the velocity constraint, whose solve includes the bodies'
    /// rigid rows; explicit stages use [`Self::absorb_shared`].
    pub(crate) fn absorb(&mut self, imp: Impulses) {
        self.absorb_with(imp, false);
    }

    /// A moving body's weight over the substep (not a pinned deformable body's: [`Rigid::hung`])
    /// shared with the water beside it, as an
    /// explicit stage's push is ([`super::lumps`]): body and lump move as one under the
    /// body's whole wrench, buoyancy and weight alike. With only the water's pushes shared,
    /// a body kept `M/(M + m)` of its buoyancy against all of its weight: a floating ball
    /// took 1.10–1.15× its weight from the water and handed the excess to the water beside it
    /// as a steady upward push, and an 800 kg/m³ block on a no-slip floor (its lump holding
    /// the flank water, `M/(M + m)` = 0.71) could not lift off. The water's part of the
    /// weight (the lump's support) is booked as the fluid's impulse on the body.
    pub(crate) fn share_weight(&mut self, gravity: Vector, dt: f32) {
        if self.lumps.is_empty() {
            return;
        }
        let mut per = vec![[0.0f64; 6]; self.solids.len()];
        let mut weighed = vec![None; self.rigids.len()];
        let mut seen = vec![false; self.rigids.len()];
        for (b, s) in self.solids.iter().enumerate() {
            let Some(ri) = s.rigid.filter(|&ri| self.rigids[ri].moving()) else {
                continue;
            };
            if std::mem::replace(&mut seen[ri], true) || self.rigids[ri].hung || !self.has_lump(ri)
            {
                continue;
            }
            let r = &self.rigids[ri];
            let free = r.inv_mass().cmpgt(Vector::ZERO);
            let g = Vector::select(free, gravity * (r.gravity_scale * dt), Vector::ZERO);
            let w = g * r.mprops.mass();
            weighed[ri] = Some(g);
            per[b] = [w.x as f64, w.y as f64, w.z as f64, 0.0, 0.0, 0.0];
            // with the walls' provisional support, which the final cut takes back from body
            // and lump alike (`keep_off_walls`)
            add6(&mut per[b], &r.wall_kick_impulse);
        }
        let mut kicked = vec![false; self.rigids.len()];
        for (ri, r) in self.respond(&per, true).into_iter().enumerate() {
            let (Some(r), Some(g)) = (r, weighed[ri]) else {
                continue;
            };
            add6(&mut self.impulses[r.solid], &r.lump);
            let rg = &mut self.rigids[ri];
            add6(&mut rg.impulse, &r.lump);
            // the body had the whole of it in `predict_rigids`
            let (kv, kw) = rg.wall_kick;
            rg.linvel += r.du - g - kv;
            rg.angvel += r.dw - kw;
            kicked[ri] = true;
        }
        // the carriers where (and as fast as) the shared velocity takes the body, as
        // `predict_rigids` placed them by its own
        self.place_rigid_solids(dt, true, Some(&kicked));
    }

    /// Rigid `ri` and the water beside it take the velocity change of the wrench `e`
    /// together, the water's positions moved by it over `dt` too (a change after the
    /// substep's positions were taken: the walls' final cut); the water's part is booked as
    /// its impulse on the body.
    pub(crate) fn kick_with_lump(&mut self, ri: usize, e: &[f64; 6], dt: f32) {
        let (du, dw, kept) = self.rigid_response(ri, e, true);
        self.move_lump_over(ri, du, dw, Some(dt));
        let lump: [f64; 6] = std::array::from_fn(|k| kept[k] - e[k]);
        if let Some(b) = self.solids.iter().position(|s| s.rigid == Some(ri)) {
            add6(&mut self.impulses[b], &lump);
        }
        let rg = &mut self.rigids[ri];
        add6(&mut rg.impulse, &lump);
        rg.linvel += du;
        rg.angvel += dw;
    }

    /// [`Self::absorb`] for an explicit stage: each moving body's wrench is shared with the
    /// fluid beside it ([`super::lumps`]), so a light body cannot overshoot.
    pub(crate) fn absorb_shared(&mut self, imp: Impulses) {
        self.absorb_with(imp, true);
    }

    /// [`Self::absorb_shared`] for the density loop's impulses, each acting at its carrier's
    /// place `at` before the loop's iterations moved the body (the arms [`Self::shift_rigids`]
    /// took, and those the pushes' couples were made against).
    pub(crate) fn absorb_shared_from(&mut self, imp: Impulses, at: &[Vector]) {
        self.absorb_at(imp, true, Some(at));
    }

    fn absorb_with(&mut self, imp: Impulses, shared: bool) {
        self.absorb_at(imp, shared, None);
    }

    fn absorb_at(&mut self, imp: Impulses, shared: bool, at: Option<&[Vector]>) {
        let mut per = self.wrenches(
            (&imp)
                .into_iter()
                .map(|&(s, j)| (s, j, at.map(|a| a[s as usize]))),
        );
        for &(b, l) in imp.couples() {
            let per = per.get_or_insert_with(|| vec![[0.0f64; 6]; self.solids.len()]);
            add6(&mut per[b as usize], &couple(l));
        }
        self.absorb_wrenches(per, shared);
    }

    /// [`Self::absorb_shared`] for impulses that act at given points.
    pub(crate) fn absorb_at_points(&mut self, imp: &[PointImpulse]) {
        let per = self.wrenches(imp.iter().map(|&(s, j, p)| (s, j, Some(p))));
        self.absorb_wrenches(per, true);
    }

    /// Books impulse `j`, acting at solid carrier `s`, on its solid's wrench only (moving no
    /// body, the carrier's own total left as the stages gave it): for momentum a body hands on
    /// to the water beside it, as the lumps of rigid bodies book theirs.
    pub(crate) fn book_on_solid(&mut self, s: usize, j: Vector) {
        let b = self.solid.body[s] as usize;
        let e = rigid::wrench(j, self.solid.x[s] - self.solids[b].com);
        add6(&mut self.impulses[b], &e);
    }

    /// Per solid, the wrench about its centre of mass of impulses `(carrier, j, point)` (the
    /// point the carrier's position when `None`); each carrier's impulse joins its total.
    fn wrenches(
        &mut self,
        imp: impl Iterator<Item = (u32, Vector, Option<Vector>)>,
    ) -> Option<Vec<[f64; 6]>> {
        let mut per: Option<Vec<[f64; 6]>> = None;
        for (s, j, p) in imp {
            let per = per.get_or_insert_with(|| vec![[0.0f64; 6]; self.solids.len()]);
            let s = s as usize;
            // the carrier's impulse so far this step; a force once the step ends
            self.solid.f[s] += j;
            let b = self.solid.body[s] as usize;
            let at = p.unwrap_or(self.solid.x[s]);
            add6(&mut per[b], &rigid::wrench(j, at - self.solids[b].com));
        }
        per
    }

    fn absorb_wrenches(&mut self, per: Option<Vec<[f64; 6]>>, shared: bool) {
        let Some(per) = per else { return };
        for (b, e) in per.iter().enumerate() {
            add6(&mut self.impulses[b], e);
            if let Some(ri) = self.solids[b].rigid.filter(|&ri| !self.rigids[ri].moving()) {
                add6(&mut self.rigids[ri].impulse, e);
            }
        }
        let mut kicked = vec![false; self.rigids.len()];
        for (ri, r) in self.respond(&per, shared).into_iter().enumerate() {
            let Some(r) = r else { continue };
            if shared {
                add6(&mut self.impulses[r.solid], &r.lump);
            }
            let rg = &mut self.rigids[ri];
            add6(&mut rg.impulse, &r.kept);
            rg.linvel += r.du;
            rg.angvel += r.dw;
            kicked[ri] = true;
        }
        if kicked.iter().any(|&k| k) {
            for s in self.solids.iter_mut() {
                if let Some(ri) = s.rigid.filter(|&ri| kicked[ri]) {
                    s.linvel = self.rigids[ri].linvel;
                    s.angvel = self.rigids[ri].angvel;
                    let c = &mut self.solid;
                    for i in s.range.clone() {
                        c.u[i] = s.linvel + s.angvel.cross(c.x[i] - s.com);
                    }
                }
            }
        }
    }

    /// The penetration correction once more, against the solids' current poses (after rapier's
    /// step, which ends at the fluid's pose unless its contacts or joints moved a body, and
    /// moves fixed and kinematic bodies its own way). A moving body shares its wrench with
    /// the water beside it ([`super::lumps`]). Returns the impulse `[J; L]` the body itself
    /// takes (index into [`Self::rigids`]) and the number of carriers corrected.
    pub(crate) fn correct_after_move(&mut self) -> (Vec<[f64; 6]>, usize) {
        let mut per = vec![[0.0f64; 6]; self.rigids.len()];
        if self.lists.offsets.len() != self.fluid.len() + 1 {
            return (per, 0);
        }
        let bodies = self.body_views();
        let shapes = self.shapes();
        let ctx = ctx!(self, &bodies);
        // (deformable bodies were corrected within the step; rapier does not move them)
        let (imp, n) = crate::solver::contact::correct_penetration(
            &ctx,
            &shapes,
            &Default::default(),
            &mut self.fluid.x,
            &mut self.fluid.v,
        );
        // these impulses belong to the step just taken: they join its forces (Eq. 21)
        let dt = (self.report.dt as f32).max(1e-12);
        let mut on_solid = vec![[0.0f64; 6]; self.solids.len()];
        for &(s, j, at) in &imp {
            let s = s as usize;
            let b = self.solid.body[s] as usize;
            if let Some(f) = self.solid.f.get_mut(s) {
                *f += j / dt;
            }
            add6(&mut on_solid[b], &rigid::wrench(j, at - self.solids[b].com));
        }
        for (b, e) in on_solid.iter().enumerate() {
            if let Some(ri) = self.solids[b].rigid {
                add6(&mut per[ri], e);
            }
        }
        // a moving body shares the wrench with the water beside it, as in the step's explicit
        // stages (`lumps`): a body lighter than the carriers it pushed out cannot take their
        // momentum alone (a 10 kg/m³ cube spun up from 36 to 174 rad/s here)
        let current = self.lumps_current();
        for (ri, r) in self.respond(&on_solid, current).into_iter().enumerate() {
            if let Some(r) = r {
                add6(&mut on_solid[r.solid], &r.lump);
                per[ri] = r.kept;
            }
        }
        for (sol, e) in self.solids.iter_mut().zip(&on_solid) {
            let (force, torque) = rigid::split(e);
            sol.force += force / dt;
            sol.torque += torque / dt;
        }
        (per, n)
    }

    /// Each moving rigid's response to the wrenches `per` (per solid, about its centre of
    /// mass), summed over its solids: with the water beside it when `shared` (its lump's
    /// carriers moved, [`super::lumps`]), alone otherwise.
    fn respond(&mut self, per: &[[f64; 6]], shared: bool) -> Vec<Option<Response>> {
        // per moving rigid: its first solid (which books the lump's part) and its wrench
        let mut on_rigid: Vec<Option<(usize, [f64; 6])>> = vec![None; self.rigids.len()];
        for (b, e) in per.iter().enumerate() {
            if let Some(ri) = self.solids[b].rigid.filter(|&ri| self.rigids[ri].moving()) {
                add6(&mut on_rigid[ri].get_or_insert((b, [0.0; 6])).1, e);
            }
        }
        let mut out = Vec::with_capacity(on_rigid.len());
        for (ri, slot) in on_rigid.into_iter().enumerate() {
            out.push(slot.map(|(solid, e)| {
                let (du, dw, kept) = self.rigid_response(ri, &e, shared);
                if shared {
                    self.move_lump(ri, du, dw);
                }
                Response {
                    solid,
                    kept,
                    lump: std::array::from_fn(|k| kept[k] - e[k]),
                    du,
                    dw,
                }
            }));
        }
        out
    }

    /// Each solid's shape and current world pose (what the penetration correction tests).
    pub(crate) fn shapes(&self) -> Vec<Option<(SharedShape, Pose)>> {
        self.solids
            .iter()
            .map(|s| (s.kind != SolidKind::Deformable).then(|| (s.shape.clone(), s.pose)))
            .collect()
    }

    pub(crate) fn body_views(&self) -> Vec<BodyView> {
        let static_share = Share::new(self.mass, self.params.rest_density, self.rest_neighbors);
        self.solids
            .iter()
            .map(|s| BodyView {
                share: static_share,
                viscosity: s.slip.wall_viscosity(self.params.viscosity),
                slip: s.slip,
                stick: s.stick,
                com: s.com,
                rigid: s
                    .rigid
                    .filter(|&r| self.rigids[r].moving())
                    .map_or(u32::MAX, |r| r as u32),
                fixed: s.kind == SolidKind::Static,
                carried: matches!(s.kind, SolidKind::Dynamic | SolidKind::Kinematic),
            })
            .collect()
    }

    /// The mass a solid carrier of each body stands for in Shao's correction (Eq. 13–17):
    /// the body's mass over its carriers for moving dynamic bodies, `∞` for the rest.
    pub(crate) fn carrier_masses(&self) -> Vec<f32> {
        self.solids
            .iter()
            .map(|s| match s.rigid.map(|r| &self.rigids[r]) {
                Some(r) if r.moving() && r.mprops.inv_mass > 0.0 => {
                    1.0 / (r.mprops.inv_mass * s.range.len().max(1) as f32)
                }
                _ => f32::INFINITY,
            })
            .collect()
    }
}

/// `a += b` for `[J; L]` impulse pairs.
/// A moving rigid's response to a stage's wrench ([`FluidWorld::respond`]).
struct Response {
    /// Its first solid, which books the lump's part.
    solid: usize,
    /// The wrench the body itself takes.
    kept: [f64; 6],
    /// The part the water beside it takes (`kept − e`).
    lump: [f64; 6],
    /// Its velocity change.
    du: Vector,
    dw: Vector,
}

fn add6(a: &mut [f64; 6], b: &[f64; 6]) {
    for (x, y) in a.iter_mut().zip(b) {
        *x += y;
    }
}

/// The wrench `[0; l]` of an angular impulse `l`.
fn couple(l: Vector) -> [f64; 6] {
    [0.0, 0.0, 0.0, l.x as f64, l.y as f64, l.z as f64]
}

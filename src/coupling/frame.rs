//! One coupled frame with rapier (He 2012 Eq. 21): the fluid's impulse handed back to rapier,
//! rapier's step, and the penetration correction against the poses rapier reached.

use crate::error::Result;
use crate::math::Vector;
use crate::world::FluidWorld;
use crate::StepReport;
use rapier3d::dynamics::RigidBodySet;
use rapier3d::geometry::ColliderSet;
use rapier3d::pipeline::PhysicsWorld;

impl FluidWorld {
    /// Hands each moving dynamic body back to rapier after the fluid's step (Eq. 21). The
    /// fluid's substeps have already moved the body under gravity and the water's impulse
    /// `[J; L]` (the solid's force and torque over the step); rapier's step must end where they
    /// did, or the next step starts with the body's carriers jumped into the water. So rapier
    /// steps the body with the velocity that takes it from the pose rapier gave at the step's
    /// start to the pose the substeps reached, its weight held by a force `−M g` (`add_force`,
    /// applied in each of rapier's solver substeps as gravity is), and after rapier's step the
    /// body takes the velocity the substeps left it plus whatever rapier's contacts, joints and
    /// gyroscopic terms changed ([`Self::correct_after_rapier`], or the next
    /// [`Self::step_with_rapier`]). Rapier moving the body by its *end* velocity instead left
    /// it 1.4–2.6 mm (0.05–0.1Δx) from the fluid's pose each 1/60 s frame for a light cube
    /// rising at 0.1–0.3 m/s and, spinning at 23 rad/s, 0.41 rad; the next substep found
    /// carriers inside it and pushed them out.
    ///
    /// A sleeping body is woken only if `J` plus its weight, kept up for rapier's
    /// time-until-sleep, would take it past rapier's sleep threshold; the fluid held it still
    /// during the step, so it takes J as a force over rapier's step. Bodies the fluid does not
    /// move (fixed axes all round) take `[J; L]` at once.
    pub fn apply_to_rapier(&mut self, bodies: &mut RigidBodySet, gravity: Vector, dt: f32) {
        self.remove_rapier_forces(bodies);
        if !(dt.is_finite() && dt > 0.0) {
            return;
        }
        let mut added = Vec::new();
        let mut handoff = Vec::new();
        for r in self.rigids() {
            let Some(rb) = bodies.get_mut(r.handle) else {
                continue;
            };
            let (j, l) = crate::rigid::split(&r.impulse);
            let (at_once, turn, force, torque) = if r.sleeping {
                // the speed the net push would build up over rapier's time-until-sleep
                let reach = r.wake_horizon.max(dt) / dt;
                let weight = gravity * (r.gravity_scale * rb.mass() * dt);
                let (dv, dw) = r.response((j + weight) * reach, l * reach);
                if dv.length() <= r.wake_threshold && dw.length() <= r.wake_threshold {
                    continue;
                }
                rb.wake_up(true);
                (Vector::ZERO, l, j / dt, Vector::ZERO)
            } else if r.moving() {
                // the weight held over rapier's substeps, on the axes the body may move along
                let free =
                    Vector::select(r.inv_mass().cmpgt(Vector::ZERO), Vector::ONE, Vector::ZERO);
                let hold = -gravity * (r.gravity_scale * rb.mass()) * free;
                // the velocity that takes the body from the pose rapier gave to the fluid's
                let (c0, q0) = r.frame_start;
                let v_bar = (r.com - c0) / dt;
                let w_bar = (r.rotation * q0.inverse()).normalize().to_scaled_axis() / dt;
                handoff.push((r.handle, [r.linvel, r.angvel, v_bar, w_bar]));
                rb.set_linvel(v_bar, true);
                rb.set_angvel(w_bar, true);
                // the support its walls gave in the substeps, pressed on them again for
                // rapier's contacts to take (and to rub against: friction)
                let (jw, lw) = crate::rigid::split(&r.wall_impulse);
                (Vector::ZERO, Vector::ZERO, hold - jw / dt, -lw / dt)
            } else {
                (j, l, Vector::ZERO, Vector::ZERO)
            };
            rb.apply_impulse(at_once, true);
            rb.apply_torque_impulse(turn, true);
            if force != Vector::ZERO || torque != Vector::ZERO {
                rb.add_force(force, true);
                rb.add_torque(torque, true);
                added.push((r.handle, force, torque));
            }
        }
        self.rapier_forces = added;
        self.rapier_handoff = handoff;
    }

    /// Takes the forces [`Self::apply_to_rapier`] added off the rapier bodies again, and gives
    /// each body it handed over the fluid's end velocity plus what rapier's step changed.
    fn remove_rapier_forces(&mut self, bodies: &mut RigidBodySet) {
        for (h, [v, w, v_bar, w_bar]) in std::mem::take(&mut self.rapier_handoff) {
            if let Some(rb) = bodies.get_mut(h) {
                let (dv, dw) = (rb.linvel() - v_bar, rb.angvel() - w_bar);
                rb.set_linvel(v + dv, false);
                rb.set_angvel(w + dw, false);
            }
        }
        for (h, f, t) in std::mem::take(&mut self.rapier_forces) {
            if let Some(rb) = bodies.get_mut(h) {
                rb.add_force(-f, false);
                rb.add_torque(-t, false);
            }
        }
    }

    /// One coupled step: [`Self::sync_rapier`], [`Self::step`], [`Self::apply_to_rapier`].
    /// Call rapier's `PhysicsPipeline::step` with the same `dt` and gravity afterwards, then
    /// [`Self::correct_after_rapier`]: the three together are [`Self::step_physics_world`],
    /// for a program (or an engine such as bevy) that steps rapier itself.
    pub fn step_with_rapier(
        &mut self,
        gravity: Vector,
        dt: f32,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
    ) -> Result<StepReport> {
        // forces left from a frame whose rapier step was not followed by correct_after_rapier
        self.remove_rapier_forces(bodies);
        let dropped = self.sync_rapier(bodies, colliders)?;
        self.step(gravity, dt)?;
        self.apply_to_rapier(bodies, gravity, dt);
        let rep = self.report_mut();
        rep.solids_dropped = dropped as u64;
        Ok(rep.clone())
    }

    /// After rapier's step: gives the bodies [`Self::apply_to_rapier`] handed over their end
    /// velocity, takes the poses rapier reached ([`Self::sync_rapier`]; the fluid's own unless
    /// rapier's contacts or joints moved a body, or its gyroscopic terms turned an unequal one
    /// a little further: 3e-4 rad a frame for a box spinning at 3.7 rad/s, whose ω the
    /// substeps keep between the water's pushes) and moves every fluid carrier that ended
    /// inside a solid back to its surface (exact parry geometry); the momentum it loses goes
    /// to the body and the water beside it, as in the step's explicit stages (`apply_impulse`,
    /// not waking a sleeping body), and joins the last step's force on them and its report
    /// ([`StepReport::penetrations_corrected`]). Returns the carriers moved.
    ///
    /// ```
    /// use rapier3d::prelude::*;
    /// use staggered_fluid::prelude::*;
    /// let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
    /// let (mut islands, mut broad, mut narrow) =
    ///     (IslandManager::new(), BroadPhaseBvh::new(), NarrowPhase::new());
    /// let (mut joints, mut multibody, mut soft, mut ccd) = (
    ///     ImpulseJointSet::new(),
    ///     MultibodyJointSet::new(),
    ///     SoftBodySet::new(),
    ///     CCDSolver::new(),
    /// );
    /// let mut pipeline = PhysicsPipeline::new();
    /// let params = IntegrationParameters { dt: 0.005, ..Default::default() };
    /// let gravity = Vector::new(0.0, -9.81, 0.0);
    /// let cube = bodies.insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.25, 0.25, 0.25)));
    /// colliders.insert_with_parent(ColliderBuilder::cuboid(0.05, 0.05, 0.05).density(500.0), cube, &mut bodies);
    /// let mut fluid = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() })?;
    /// fluid.add_open_tank(Vector::ZERO, Vector::new(0.5, 0.5, 0.5), Slip::FreeSlip)?;
    /// fluid.add_block_around(Vector::ZERO, Vector::new(0.5, 0.2, 0.5), Vector::ZERO, &colliders)?;
    /// fluid.couple_all(&bodies, &colliders, Slip::FreeSlip)?;
    /// for _ in 0..3 {
    ///     fluid.step_with_rapier(gravity, params.dt, &mut bodies, &colliders)?;
    ///     pipeline.step(gravity, &params, &mut islands, &mut broad, &mut narrow, &mut bodies,
    ///         &mut colliders, &mut joints, &mut multibody, &mut soft, &mut ccd, &(), &());
    ///     fluid.correct_after_rapier(&mut bodies, &colliders)?;
    /// }
    /// # Ok::<(), FluidError>(())
    /// ```
    pub fn correct_after_rapier(
        &mut self,
        bodies: &mut RigidBodySet,
        colliders: &ColliderSet,
    ) -> Result<usize> {
        // rapier has taken the water's forces: off again, before a user's next rapier step
        self.remove_rapier_forces(bodies);
        // rapier moved the bodies its own way: no fluid carrier may be left inside one
        self.sync_rapier(bodies, colliders)?;
        let (per, n) = self.correct_after_move();
        for (r, j) in self.rigids_mut().iter_mut().zip(&per) {
            if let Some(rb) = bodies.get_mut(r.handle) {
                let (lin, ang) = crate::rigid::split(j);
                rb.apply_impulse(lin, false);
                rb.apply_torque_impulse(ang, false);
            }
            for (a, b) in r.impulse.iter_mut().zip(j) {
                *a += b;
            }
        }
        self.report_mut().penetrations_corrected += n as u64;
        Ok(n)
    }

    /// One coupled frame with a rapier [`PhysicsWorld`]: the fluid step
    /// ([`Self::step_with_rapier`] with the world's gravity), the rapier step, both over
    /// `world.integration_parameters.dt`, and a last penetration correction against the poses
    /// rapier reached (its impulses go to the bodies at once).
    ///
    /// ```
    /// use rapier3d::prelude::*;
    /// use rapier3d::pipeline::PhysicsWorld;
    /// use staggered_fluid::prelude::*;
    /// let mut physics = PhysicsWorld::new();
    /// physics.integration_parameters.dt = 0.005;
    /// let cube = physics.bodies.insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.25, 0.3, 0.25)));
    /// physics.colliders.insert_with_parent(ColliderBuilder::cuboid(0.05, 0.05, 0.05).density(500.0), cube, &mut physics.bodies);
    /// let mut fluid = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() }).unwrap();
    /// fluid.add_open_tank(Vector::ZERO, Vector::new(0.5, 0.5, 0.5), Slip::FreeSlip).unwrap();
    /// fluid.add_block(Vector::ZERO, Vector::new(0.5, 0.2, 0.5), Vector::ZERO).unwrap();
    /// fluid.couple_all(&physics.bodies, &physics.colliders, Slip::FreeSlip).unwrap();
    /// for _ in 0..5 {
    ///     fluid.step_physics_world(&mut physics).unwrap();
    /// }
    /// ```
    pub fn step_physics_world(&mut self, world: &mut PhysicsWorld) -> Result<StepReport> {
        let dt = world.integration_parameters.dt;
        self.step_with_rapier(world.gravity, dt, &mut world.bodies, &world.colliders)?;
        world.step();
        self.correct_after_rapier(&mut world.bodies, &world.colliders)?;
        Ok(self.last_report().clone())
    }
}

//! Two-way coupling with rapier (He 2012 §5, Eq. 21): colliders become solid carriers, the
//! fluid's force and torque on each dynamic body go back to rapier as impulses.
//!
//! # How a step interleaves with rapier
//!
//! Call [`FluidWorld::step_with_rapier`] and then rapier's `PhysicsPipeline::step` with the same
//! `dt`, every frame:
//!
//! 1. **sync** — every coupled collider takes its rapier pose; its body's velocity, centre of
//!    mass, mass properties, locked axes, gravity scale and sleep state are copied; colliders
//!    removed from rapier are dropped (their carriers deleted, counted in the return value of
//!    [`FluidWorld::sync_rapier`]).
//! 2. **fluid** — `dt` is split into substeps by the CFL limit (fluid *and* solid speeds). In each
//!    substep a dynamic body first gets gravity, the fluid sees it at its predicted pose, every
//!    fluid stage (viscosity, density constraint, velocity constraint, wall conditions,
//!    penetration correction) kicks it with the impulse on its carriers, and its pose advances
//!    with the final velocity. The velocity constraint solves the bodies' velocities together
//!    with the fluid pressure (their 6 degrees of freedom are unknowns of the same
//!    `D M⁻¹ Dᵀ p = −D ṽ/Δt`), so a light body cannot overshoot the fluid it displaces.
//! 3. **hand back** — only the fluid's impulse `J = Σ_s F_s Δt` and angular impulse
//!    `L = Σ_s (x_s − X) × F_s Δt` (Eq. 21) go to rapier: L at once, J as a force `−M g`
//!    holding the body's weight over rapier's step plus `J + M g Δt` at once, so that rapier
//!    (which applies forces and gravity in each of its solver substeps) ends with the velocity
//!    the fluid's substeps left the body and moves it by that velocity; rapier adds gravity,
//!    resolves body–body contact and integrates (the next sync starts from rapier's pose).
//! 4. **after rapier** — [`FluidWorld::correct_after_rapier`] takes the force off again and
//!    moves carriers left inside a body by rapier's move back to its surface.
//!
//! A sleeping body stays asleep (the fluid treats it as fixed) unless the fluid's impulse
//! plus its weight, kept up for rapier's time-until-sleep, would take it past rapier's sleep
//! threshold. A moving
//! body whose bounding box has no fluid within two support radii costs nothing: its carriers
//! are left out of the neighbour search and rapier moves it alone.

mod frame;

use crate::error::{FluidError, Result};
use crate::math::{finite, Vector};
use crate::params::{MIN_BODY_DENSITY_RATIO, MIN_BODY_DENSITY_RATIO_NO_SLIP};
use crate::rigid::Rigid;
use crate::solver::staggered::Slip;
use crate::world::{named, FluidWorld, SolidHandle, SolidKind};
use rapier3d::dynamics::{RigidBodyHandle, RigidBodySet};
use rapier3d::geometry::Collider;
use rapier3d::geometry::{ColliderHandle, ColliderSet};
use rapier3d::parry::query::PointQuery;
use rapier3d::parry::shape::{TriMesh, TypedShape};

impl FluidWorld {
    /// Couples one rapier collider: samples its shape into solid carriers with the slip
    /// condition `slip`. Fixed bodies (or colliders without a body) become static walls,
    /// kinematic bodies scripted solids, dynamic bodies two-way coupled solids.
    ///
    /// ```
    /// use rapier3d::prelude::*;
    /// use staggered_fluid::prelude::*;
    /// let (mut bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
    /// let ball = bodies.insert(RigidBodyBuilder::dynamic().translation(Vector::new(0.0, 0.5, 0.0)));
    /// let co = colliders.insert_with_parent(ColliderBuilder::ball(0.1).density(500.0), ball, &mut bodies);
    /// let mut fluid = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() }).unwrap();
    /// let solid = fluid.couple_collider(&bodies, &colliders, co, Slip::FreeSlip).unwrap();
    /// assert!(fluid.solid(solid).unwrap().range.len() > 0);
    /// ```
    pub fn couple_collider(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        handle: ColliderHandle,
        slip: Slip,
    ) -> Result<SolidHandle> {
        let name = format!("collider {}", handle.into_raw_parts().0);
        self.couple_collider_named(bodies, colliders, handle, slip, name)
    }

    /// [`Self::couple_collider`] under the name errors and reports use (a scene's body name).
    pub(crate) fn couple_collider_named(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        handle: ColliderHandle,
        slip: Slip,
        name: String,
    ) -> Result<SolidHandle> {
        if let Some(k) = self
            .solids()
            .iter()
            .position(|s| s.collider == Some(handle) && !s.removed)
        {
            return Ok(SolidHandle(k as u32));
        }
        let co = colliders.get(handle).ok_or_else(|| {
            FluidError::Coupling(format!("{name} ({handle:?}) is not in the set"))
        })?;
        let ground = crate::sampling::is_ground(co.shape());
        let fixed = co
            .parent()
            .is_none_or(|bh| bodies.get(bh).is_some_and(|rb| rb.is_fixed()));
        if ground && !fixed {
            return Err(named(
                FluidError::UnsupportedShape {
                    shape: format!("{:?}", co.shape().shape_type()),
                    why: "a half-space or height field can only be a fixed ground (no body, \
                          or a fixed one)"
                        .into(),
                },
                &name,
            ));
        }
        let kind = match co.parent() {
            None => SolidKind::Static,
            Some(bh) => {
                let rb = bodies.get(bh).ok_or_else(|| {
                    FluidError::Coupling(format!("{name}: its body {bh:?} is not in the set"))
                })?;
                if rb.is_dynamic() {
                    self.check_dynamic_body(&name, bh, rb, colliders, slip)?;
                    SolidKind::Dynamic
                } else if rb.is_kinematic() {
                    SolidKind::Kinematic
                } else {
                    SolidKind::Static
                }
            }
        };
        let pose = *co.position();
        if !pose.is_finite() {
            return Err(FluidError::NonFinite {
                what: format!("pose of {name}"),
            });
        }
        crate::sampling::check_supported(co.shape()).map_err(|e| named(e, &name))?;
        let shape = co.shared_shape().clone();
        let h = self
            .add_sampled(name.clone(), shape, pose, slip, kind)
            .map_err(|e| named(e, &name))?;
        self.solid_mut(h).collider = Some(handle);
        self.sync_rapier(bodies, colliders)?;
        Ok(h)
    }

    /// Couples every non-sensor collider of `colliders` that is not coupled yet (nor a wall of
    /// a tank made by [`Self::add_rapier_tank`]), all with the same slip condition. Grounds
    /// couple too: a half-space, a height field or a static shape too large to sample whole
    /// (a cuboid 200 m wide) is sampled where the fluid can reach once the domain is fixed,
    /// at the first step. Colliders whose shape cannot be sampled (an open triangle mesh, a
    /// segment, a half-space on a moving body…) are left to rapier alone and listed in
    /// [`CoupledColliders::skipped`] with the reason; any other problem (a body without mass,
    /// a non-finite pose) is an error.
    ///
    /// ```
    /// use rapier3d::prelude::*;
    /// use staggered_fluid::prelude::*;
    /// let (bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
    /// let ground = colliders.insert(ColliderBuilder::new(SharedShape::halfspace(Vector::Y)));
    /// let line = colliders.insert(ColliderBuilder::segment(Vector::ZERO, Vector::X));
    /// let mut fluid = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() })?;
    /// let done = fluid.couple_all(&bodies, &colliders, Slip::FreeSlip)?;
    /// assert_eq!(done.coupled[0].0, ground);
    /// assert_eq!(done.skipped[0].0, line);
    /// // the ground's carriers come at the first step, within the domain around the water
    /// fluid.add_block(Vector::ZERO, Vector::new(0.3, 0.2, 0.3), Vector::ZERO)?;
    /// assert!(fluid.solid(done.coupled[0].1).unwrap().range.is_empty());
    /// fluid.step(Vector::new(0.0, -9.81, 0.0), 0.005)?;
    /// assert!(fluid.solid(done.coupled[0].1).unwrap().range.len() > 0);
    /// # Ok::<(), FluidError>(())
    /// ```
    pub fn couple_all(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        slip: Slip,
    ) -> Result<CoupledColliders> {
        self.couple_all_with(bodies, colliders, |_, _| Some(slip))
    }

    /// [`Self::couple_all`] with a choice per collider: `choose` returns the slip condition
    /// to couple it with, or `None` to leave it to rapier alone (sensors, colliders already
    /// coupled and tank walls are not offered).
    ///
    /// ```
    /// use rapier3d::prelude::*;
    /// use staggered_fluid::prelude::*;
    /// let (bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
    /// let ball = colliders.insert(ColliderBuilder::ball(0.1).translation(Vector::new(0.2, 0.3, 0.2)));
    /// let decor = colliders.insert(ColliderBuilder::ball(0.1).translation(Vector::new(2.0, 0.3, 0.2)));
    /// let mut fluid = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() })?;
    /// // couple only what is near the pool, the rest stays rapier's
    /// let done = fluid.couple_all_with(&bodies, &colliders, |_, co| {
    ///     (co.translation().x < 1.0).then_some(Slip::NoSlip)
    /// })?;
    /// assert_eq!(done.coupled.len(), 1);
    /// assert_eq!(done.coupled[0].0, ball);
    /// assert!(fluid.solid_of(decor).is_none());
    /// # Ok::<(), FluidError>(())
    /// ```
    pub fn couple_all_with(
        &mut self,
        bodies: &RigidBodySet,
        colliders: &ColliderSet,
        mut choose: impl FnMut(ColliderHandle, &Collider) -> Option<Slip>,
    ) -> Result<CoupledColliders> {
        let mut out = CoupledColliders::default();
        for (h, co) in colliders.iter() {
            if co.is_sensor()
                || self.tank_colliders.contains(&h)
                || self
                    .solids()
                    .iter()
                    .any(|s| s.collider == Some(h) && !s.removed)
            {
                continue;
            }
            let Some(slip) = choose(h, co) else { continue };
            match self.couple_collider(bodies, colliders, h, slip) {
                Ok(s) => out.coupled.push((h, s)),
                Err(e @ FluidError::UnsupportedShape { .. }) => out.skipped.push((h, e)),
                Err(e) => return Err(e),
            }
        }
        Ok(out)
    }

    /// An open tank made once for both worlds: the fluid's walls ([`Self::add_open_tank`],
    /// inner box `[inner_min, inner_max]`, floor and four walls) and five fixed rapier cuboids
    /// around the same box, 5 cm thick, inserted into `colliders` so rapier bodies rest on the
    /// tank the fluid sees. [`Self::couple_all`] leaves these colliders alone (the fluid has
    /// its walls already).
    ///
    /// ```
    /// use rapier3d::prelude::*;
    /// use staggered_fluid::prelude::*;
    /// let (bodies, mut colliders) = (RigidBodySet::new(), ColliderSet::new());
    /// let mut fluid = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() })?;
    /// let tank = fluid.add_rapier_tank(&mut colliders, Vector::ZERO, Vector::new(0.5, 0.4, 0.5), Slip::NoSlip)?;
    /// assert_eq!(colliders.len(), 5);
    /// assert!(fluid.couple_all(&bodies, &colliders, Slip::FreeSlip)?.coupled.is_empty());
    /// assert_eq!(tank.walls.len(), 5);
    /// # Ok::<(), FluidError>(())
    /// ```
    pub fn add_rapier_tank(
        &mut self,
        colliders: &mut ColliderSet,
        inner_min: Vector,
        inner_max: Vector,
        slip: Slip,
    ) -> Result<RapierTank> {
        let walls = self.add_open_tank(inner_min, inner_max, slip)?;
        let (lo, hi, t) = (inner_min, inner_max, 0.05);
        let c = (lo + hi) * 0.5;
        let half = (hi - lo) * 0.5;
        let boxes = [
            (
                Vector::new(c.x, lo.y - t, c.z),
                Vector::new(half.x + 2.0 * t, t, half.z + 2.0 * t),
            ),
            (
                Vector::new(lo.x - t, c.y, c.z),
                Vector::new(t, half.y, half.z + 2.0 * t),
            ),
            (
                Vector::new(hi.x + t, c.y, c.z),
                Vector::new(t, half.y, half.z + 2.0 * t),
            ),
            (
                Vector::new(c.x, c.y, lo.z - t),
                Vector::new(half.x + 2.0 * t, half.y, t),
            ),
            (
                Vector::new(c.x, c.y, hi.z + t),
                Vector::new(half.x + 2.0 * t, half.y, t),
            ),
        ];
        let handles = boxes.map(|(centre, h)| {
            colliders.insert(
                rapier3d::geometry::ColliderBuilder::cuboid(h.x, h.y, h.z).translation(centre),
            )
        });
        self.tank_colliders.extend_from_slice(&handles);
        self.tank_walls.extend_from_slice(&walls);
        Ok(RapierTank {
            walls,
            colliders: handles,
        })
    }

    /// Fills the box `[mins, maxs]` with fluid at rest spacing around the colliders of
    /// `colliders`: lattice points closer than half a spacing to any non-sensor collider are
    /// left out (water poured around bodies already in the world). Returns the number added.
    ///
    /// ```
    /// use rapier3d::prelude::*;
    /// use staggered_fluid::prelude::*;
    /// let mut colliders = ColliderSet::new();
    /// colliders.insert(ColliderBuilder::ball(0.1).translation(Vector::new(0.25, 0.1, 0.25)));
    /// let mut fluid = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() }).unwrap();
    /// let n = fluid.add_block_around(Vector::ZERO, Vector::new(0.5, 0.2, 0.5), Vector::ZERO, &colliders).unwrap();
    /// assert!(n < 10 * 4 * 10);
    /// ```
    pub fn add_block_around(
        &mut self,
        mins: Vector,
        maxs: Vector,
        velocity: Vector,
        colliders: &ColliderSet,
    ) -> Result<usize> {
        if !finite(mins) || !finite(maxs) {
            return Err(FluidError::NonFinite {
                what: "fluid block corners".into(),
            });
        }
        let dx = self.params().spacing;
        // half a spacing, less a hair: lattice points exactly half a spacing from a face (a
        // rapier tank's wall on the fluid's lattice) are kept whatever the rounding (36 % of a
        // small tank's water was lost to it)
        let clear = 0.5 * dx * (1.0 - 1e-3);
        // closed triangle meshes: parry's solid distance is the distance to the surface even
        // inside them, so the block filled them; their inside comes from the pseudo-normals
        // (oriented meshes) or a ray's crossings (the others)
        let solids: Vec<(&Collider, Option<&TriMesh>)> = colliders
            .iter()
            .filter(|(_, c)| !c.is_sensor())
            .map(|(_, c)| {
                let mesh = match c.shape().as_typed_shape() {
                    TypedShape::TriMesh(m)
                        if m.pseudo_normals_if_oriented().is_some()
                            || crate::sampling::is_closed(m) =>
                    {
                        Some(m)
                    }
                    _ => None,
                };
                (c, mesh)
            })
            .collect();
        let pts: Vec<Vector> = crate::sampling::fill_box(mins, maxs, dx)
            .into_iter()
            .filter(|p| {
                solids.iter().all(|(c, mesh)| {
                    let inside = mesh.is_some_and(|m| {
                        let q = c.position().inverse_transform_point(*p);
                        if m.pseudo_normals_if_oriented().is_some() {
                            m.contains_local_point(q)
                        } else {
                            crate::sampling::inside_closed_mesh(m, q)
                        }
                    });
                    !inside && c.shape().distance_to_point(c.position(), *p, true) >= clear
                })
            })
            .collect();
        if pts.is_empty() {
            return Err(FluidError::EmptyBlock {
                mins: crate::math::arr(mins),
                maxs: crate::math::arr(maxs),
                spacing: dx,
            });
        }
        self.add_particles(&pts, velocity)?;
        Ok(pts.len())
    }

    /// The solid coupled to a rapier collider, if any.
    pub fn solid_of(&self, collider: ColliderHandle) -> Option<SolidHandle> {
        self.solids()
            .iter()
            .position(|s| s.collider == Some(collider) && !s.removed)
            .map(|k| SolidHandle(k as u32))
    }

    /// Refuses a dynamic body the coupling cannot hold: no positive mass, or a mean density
    /// over its colliders below the lightest the coupling holds under `slip`.
    fn check_dynamic_body(
        &self,
        name: &str,
        bh: RigidBodyHandle,
        rb: &rapier3d::dynamics::RigidBody,
        colliders: &ColliderSet,
        slip: Slip,
    ) -> Result<()> {
        let m = rb.mass();
        if !(m.is_finite() && m > 0.0) {
            return Err(FluidError::Coupling(format!(
                "{name}: dynamic body {bh:?} has mass {m} (give its colliders a \
                 positive density or the body a mass)"
            )));
        }
        // the body's mean density over its colliders' volume
        let volume: f32 = rb
            .colliders()
            .iter()
            .filter_map(|c| colliders.get(*c))
            .map(|c| c.shape().mass_properties(1.0).mass())
            .sum();
        let (ratio, bound) = if slip == Slip::NoSlip {
            (
                MIN_BODY_DENSITY_RATIO_NO_SLIP,
                "MIN_BODY_DENSITY_RATIO_NO_SLIP",
            )
        } else {
            (MIN_BODY_DENSITY_RATIO, "MIN_BODY_DENSITY_RATIO")
        };
        let lightest = ratio * self.params().rest_density;
        if volume > 0.0 && m / volume < lightest * (1.0 - 1e-4) {
            return Err(FluidError::Coupling(format!(
                "{name}: its body has density {:.1} kg/m³, below the lightest the \
                 coupling holds under {slip:?} ({lightest} kg/m³, params::{bound} of \
                 the fluid's): lighter bodies erupt at rapier's 1/60 s",
                m / volume
            )));
        }
        Ok(())
    }

    /// Copies poses, velocities and mass properties from rapier into the coupled solids and
    /// drops solids whose collider (or body) was removed from rapier. Returns how many were
    /// dropped by this call.
    ///
    /// Each solid follows its body's type now, not the one it was coupled with: a body made
    /// fixed or kinematic is moved with rapier's pose and velocity and no longer pushed by
    /// the water; one made dynamic is moved by the water (refused, as by [`Self::couple_all`], if
    /// it has no mass or is lighter than the coupling holds); a half-space or height field
    /// (or a shape too large to sample whole) whose body moves is an error.
    pub fn sync_rapier(&mut self, bodies: &RigidBodySet, colliders: &ColliderSet) -> Result<usize> {
        let mut dropped = 0;
        let mut rigids: Vec<Rigid> = Vec::new();
        for k in 0..self.solids().len() {
            let s = &self.solids()[k];
            let Some(ch) = s.collider else { continue };
            if s.removed {
                continue;
            }
            let live = colliders
                .get(ch)
                .filter(|co| co.parent().is_none_or(|b| bodies.get(b).is_some()));
            let Some(co) = live else {
                self.remove_solid(SolidHandle(k as u32))?;
                dropped += 1;
                continue;
            };
            let pose = *co.position();
            if !pose.is_finite() {
                return Err(FluidError::NonFinite {
                    what: format!("pose of {}", s.name),
                });
            }
            let (mut com, mut linvel, mut angvel, mut rigid) =
                (pose.translation, Vector::ZERO, Vector::ZERO, None);
            let mut kind = s.kind;
            if let Some((bh, rb)) = co.parent().and_then(|b| Some((b, bodies.get(b)?))) {
                com = rb.center_of_mass();
                if !rb.is_fixed() {
                    linvel = rb.linvel();
                    angvel = rb.angvel();
                }
                if !finite(com) || !finite(linvel) || !finite(angvel) {
                    return Err(FluidError::NonFinite {
                        what: format!("velocity or centre of mass of the body of {}", s.name),
                    });
                }
                // the coupling follows the body's type now, not the one it was coupled with
                kind = match s.kind {
                    SolidKind::Dynamic | SolidKind::Kinematic if rb.is_dynamic() => {
                        SolidKind::Dynamic
                    }
                    SolidKind::Dynamic | SolidKind::Kinematic => SolidKind::Kinematic,
                    SolidKind::Static if !rb.is_fixed() && sampled_where_reached(self, co) => {
                        return Err(FluidError::Coupling(format!(
                            "{}: its body {bh:?} moves now, and a ground (a half-space, a \
                             height field or a shape too large to sample whole, sampled only \
                             where the fluid reaches) can only be fixed",
                            s.name
                        )));
                    }
                    SolidKind::Static if rb.is_dynamic() => SolidKind::Dynamic,
                    SolidKind::Static if rb.is_kinematic() => SolidKind::Kinematic,
                    k => k,
                };
                if kind == SolidKind::Dynamic && s.kind != SolidKind::Dynamic {
                    self.check_dynamic_body(&s.name, bh, rb, colliders, s.slip)?;
                }
                if kind == SolidKind::Dynamic {
                    let idx = match rigids.iter().position(|r| r.handle == bh) {
                        Some(i) => i,
                        None => {
                            let mp = rb.mass_properties();
                            if !(rb.mass().is_finite() && rb.mass() > 0.0) {
                                return Err(FluidError::Coupling(format!(
                                    "{}: dynamic body {bh:?} has mass {}",
                                    s.name,
                                    rb.mass()
                                )));
                            }
                            let act = rb.activation();
                            rigids.push(Rigid {
                                handle: bh,
                                mprops: mp.local_mprops,
                                locks: rb.locked_axes(),
                                gravity_scale: rb.gravity_scale(),
                                com,
                                rotation: rb.position().rotation,
                                linvel,
                                angvel,
                                sleeping: rb.is_sleeping(),
                                active: true,
                                wake_threshold: act.normalized_linear_threshold.max(0.0),
                                wake_horizon: act.time_until_sleep.max(0.0),
                                impulse: [0.0; 6],
                                start: (com, rb.position().rotation),
                                walls: Vec::new(),
                                contacts: Vec::new(),
                                wall_impulse: [0.0; 6],
                                wall_kick: (Vector::ZERO, Vector::ZERO),
                                wall_kick_impulse: [0.0; 6],
                                hung: false,
                                frame_start: (com, rb.position().rotation),
                            });
                            rigids.len() - 1
                        }
                    };
                    rigid = Some(idx);
                    if rigids[idx].sleeping {
                        linvel = Vector::ZERO;
                        angvel = Vector::ZERO;
                    }
                }
            }
            if self.solids()[k].kind == SolidKind::Static && kind != SolidKind::Static {
                // a fixed body's solid keeps world coordinates only: it moves from now on
                self.keep_body_frame(k);
            }
            let s = self.solid_mut(SolidHandle(k as u32));
            s.kind = kind;
            s.pose = pose;
            s.com = com;
            s.linvel = linvel;
            s.angvel = angvel;
            s.rigid = rigid;
            self.place_solid(k);
        }
        self.pair_with_walls(&mut rigids, colliders);
        // the last step's fluid impulse and activity stay readable until the next step
        for r in rigids.iter_mut() {
            if let Some(old) = self.rigids().iter().find(|o| o.handle == r.handle) {
                r.impulse = old.impulse;
                r.active = old.active;
            }
        }
        self.set_rigids(rigids);
        Ok(dropped)
    }
}

/// Whether a static collider is a ground sampled only where the fluid reaches (a half-space,
/// a height field, a shape whose whole shell would take too many carriers).
fn sampled_where_reached(w: &FluidWorld, co: &Collider) -> bool {
    let p = w.params();
    crate::sampling::too_large_to_sample(co.shape(), p.spacing, p.support_radius())
}

/// A tank made by [`FluidWorld::add_rapier_tank`].
#[derive(Debug, Clone, Copy)]
pub struct RapierTank {
    /// The fluid's walls: floor, −x, +x, −z, +z.
    pub walls: [SolidHandle; 5],
    /// The fixed rapier cuboids: floor, −x, +x, −z, +z.
    pub colliders: [ColliderHandle; 5],
}

/// What [`FluidWorld::couple_all`] did.
#[derive(Debug, Default)]
pub struct CoupledColliders {
    /// The colliders now coupled, with their solids.
    pub coupled: Vec<(ColliderHandle, SolidHandle)>,
    /// Colliders left to rapier alone because their shape cannot be sampled, each with the
    /// [`FluidError::UnsupportedShape`] that says why.
    pub skipped: Vec<(ColliderHandle, FluidError)>,
}

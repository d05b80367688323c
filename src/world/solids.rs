//! Solids sampled into solid carriers (He 2012 §5): static walls, kinematic (scripted) solids
//! and the colliders of rapier bodies; adding, moving and removing them.

use super::FluidWorld;
use crate::error::{FluidError, Result};
use crate::math::{arr, finite, Pose, Vector};
use crate::params::MAX_PARTICLES;
use crate::particles::SolidCarriers;
use crate::rigid;
use crate::sampling::sample_shell_on;
use crate::solver::staggered::Slip;
use rapier3d::geometry::ColliderHandle;
use rapier3d::parry::shape::SharedShape;
use serde::{Deserialize, Serialize};

/// Handle of a solid added to a [`FluidWorld`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
pub struct SolidHandle(pub u32);

/// How a solid moves.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum SolidKind {
    /// Never moves (walls, tanks).
    Static,
    /// Scripted (He 2012 §6): moves with the velocity given by
    /// [`FluidWorld::set_kinematic`] (or its rapier body's), pushes the fluid, and reports the
    /// fluid's force and torque, but is not pushed back.
    Kinematic,
    /// A collider of a dynamic rapier body: moved by gravity and the fluid during the fluid
    /// substeps, its fluid impulse handed back to rapier (two-way coupling, Eq. 21).
    Dynamic,
    /// The surface of a deformable body ([`crate::deform`]): its carriers follow the body's
    /// lattice, and their fluid impulses go into its shape matching.
    Deformable,
}

/// A solid sampled into solid carriers.
#[derive(Clone, Serialize, Deserialize)]
pub struct Solid {
    /// Name used in errors and reports.
    pub name: String,
    /// How it moves.
    pub kind: SolidKind,
    /// Its shape (local frame).
    pub shape: SharedShape,
    /// World pose.
    pub pose: Pose,
    /// Slip condition of its walls.
    pub slip: Slip,
    /// If true the no-stick inequality of §5.2 is off: fluid may stick to the wall.
    pub stick: bool,
    /// Its carriers in [`FluidWorld::solid_carriers`].
    pub range: std::ops::Range<usize>,
    /// Force of the fluid on the solid over the last step, N (Eq. 21).
    pub force: Vector,
    /// Torque of the fluid on the solid about [`Self::com`] over the last step, N·m (Eq. 21).
    pub torque: Vector,
    /// Velocity of the point [`Self::com`], m/s.
    pub linvel: Vector,
    /// Angular velocity, rad/s.
    pub angvel: Vector,
    /// Centre of rotation and torque reference: the body's centre of mass for rapier bodies,
    /// the pose origin otherwise.
    pub com: Vector,
    /// Index of the dynamic body in [`FluidWorld::rigids`], for [`SolidKind::Dynamic`].
    pub rigid: Option<usize>,
    /// The rapier collider it was sampled from, if any.
    pub collider: Option<ColliderHandle>,
    /// Whether its carriers take part in the current step (some fluid is near, it is not
    /// removed, it lies inside the domain).
    pub active: bool,
    /// Uncoupled or its collider removed: no carriers any more.
    pub removed: bool,
    /// Pose at the start of the current substep.
    pub(crate) pose_start: Pose,
    /// Body-frame position and outward normal of each carrier, for solids that move (empty
    /// for static ones, whose carriers keep world coordinates only).
    #[serde(default)]
    pub(crate) local: Vec<(Vector, Vector)>,
    /// The pose the carriers were last placed at.
    #[serde(default)]
    pub(crate) placed: Pose,
    /// A ground (half-space, height field, or a static shape too large to sample whole) whose
    /// carriers are sampled when the domain is fixed, within it.
    #[serde(default)]
    pub(crate) deferred: bool,
    /// Carriers (counted from `range.start`) whose normal is ambiguous: midway through a part
    /// thinner than the support ([`crate::sampling::ShellSample::two_sided`]), or at a seam of
    /// a static union where neither their own normal (it points into an earlier static solid)
    /// nor the union's has a direction (the foot of a wall one spacing thick standing on a
    /// floor). Each substep they take the direction of their fluid neighbours.
    #[serde(default)]
    pub(crate) two_sided: Vec<u32>,
    /// Held at a fixed temperature ([`FluidWorld::set_heat_source`]).
    #[serde(default)]
    pub heat: Option<crate::heat::HeatSource>,
}

impl Solid {
    /// A solid of `kind` at `pose` holding the carriers `range`, at rest, no force yet, not
    /// tied to rapier.
    fn at_rest(
        name: String,
        kind: SolidKind,
        shape: SharedShape,
        pose: Pose,
        slip: Slip,
        range: std::ops::Range<usize>,
    ) -> Self {
        Solid {
            name,
            kind,
            shape,
            pose,
            slip,
            stick: false,
            range,
            force: Vector::ZERO,
            torque: Vector::ZERO,
            linvel: Vector::ZERO,
            angvel: Vector::ZERO,
            com: pose.translation,
            rigid: None,
            collider: None,
            active: true,
            removed: false,
            pose_start: pose,
            local: Vec::new(),
            placed: pose,
            deferred: false,
            two_sided: Vec::new(),
            heat: None,
        }
    }
}

impl FluidWorld {
    /// Removes a solid: its carriers are deleted, its handle stays valid (and marked
    /// [`Solid::removed`]) so other handles do not change.
    pub fn remove_solid(&mut self, h: SolidHandle) -> Result<()> {
        let k = h.0 as usize;
        let Some(s) = self.solids.get(k) else {
            return Err(FluidError::OutOfRange {
                name: "solid handle",
                value: h.0 as f64,
                range: "a handle returned by this world",
            });
        };
        if s.removed {
            return Ok(());
        }
        let r = s.range.clone();
        self.solid.remove_range(r.clone());
        let len = r.len();
        for o in self.solids.iter_mut() {
            if o.range.start >= r.end {
                o.range = o.range.start - len..o.range.end - len;
            }
        }
        let s = &mut self.solids[k];
        s.range = r.start..r.start;
        s.local = Vec::new();
        s.two_sided = Vec::new();
        s.removed = true;
        s.active = false;
        s.collider = None;
        s.rigid = None;
        self.solids_dirty = true;
        Ok(())
    }

    /// Uncouples a solid (same as [`Self::remove_solid`]): the fluid no longer sees it.
    pub fn uncouple(&mut self, h: SolidHandle) -> Result<()> {
        self.remove_solid(h)
    }

    /// Samples `shape` at `pose` into a static solid with the given slip condition.
    pub fn add_static_solid(
        &mut self,
        name: impl Into<String>,
        shape: SharedShape,
        pose: Pose,
        slip: Slip,
    ) -> Result<SolidHandle> {
        self.add_sampled(name.into(), shape, pose, slip, SolidKind::Static)
    }

    /// Samples `shape` at `pose` into a kinematic (scripted) solid, at rest until
    /// [`Self::set_kinematic`] gives it a velocity.
    ///
    /// ```
    /// use staggered_fluid::prelude::*;
    /// use rapier3d::parry::shape::SharedShape;
    /// let mut w = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() }).unwrap();
    /// let paddle = w
    ///     .add_kinematic_solid("paddle", SharedShape::cuboid(0.1, 0.2, 0.1), Pose::IDENTITY, Slip::NoSlip)
    ///     .unwrap();
    /// w.set_kinematic(paddle, Pose::IDENTITY, Vector::new(0.5, 0.0, 0.0), Vector::ZERO).unwrap();
    /// ```
    pub fn add_kinematic_solid(
        &mut self,
        name: impl Into<String>,
        shape: SharedShape,
        pose: Pose,
        slip: Slip,
    ) -> Result<SolidHandle> {
        self.add_sampled(name.into(), shape, pose, slip, SolidKind::Kinematic)
    }

    /// Sets a kinematic solid's pose and velocity (linear velocity of the pose origin, angular
    /// velocity about it). Between calls it keeps moving with that velocity.
    pub fn set_kinematic(
        &mut self,
        h: SolidHandle,
        pose: Pose,
        linvel: Vector,
        angvel: Vector,
    ) -> Result<()> {
        let s = self
            .solids
            .get(h.0 as usize)
            .ok_or(FluidError::OutOfRange {
                name: "solid handle",
                value: h.0 as f64,
                range: "a handle returned by this world",
            })?;
        if s.kind != SolidKind::Kinematic {
            return Err(FluidError::OutOfRange {
                name: "solid handle",
                value: h.0 as f64,
                range: "a kinematic solid",
            });
        }
        if !pose.is_finite() || !finite(linvel) || !finite(angvel) {
            return Err(FluidError::NonFinite {
                what: format!("pose or velocity of solid `{}`", s.name),
            });
        }
        let s = &mut self.solids[h.0 as usize];
        s.pose = pose;
        s.com = pose.translation;
        s.linvel = linvel;
        s.angvel = angvel;
        self.place_solid(h.0 as usize);
        Ok(())
    }

    /// Gives a solid that kept world coordinates only (a static one) the body-frame copy of
    /// its carriers that a moving solid is placed from.
    pub(crate) fn keep_body_frame(&mut self, k: usize) {
        let s = &self.solids[k];
        let inv = s.placed.inverse();
        let local = s
            .range
            .clone()
            .map(|i| {
                (
                    inv.transform_point(self.solid.x[i]),
                    inv.rotation * self.solid.n[i],
                )
            })
            .collect();
        self.solids[k].local = local;
    }

    /// Recomputes the world position, normal and velocity of a solid's carriers from its pose
    /// and velocity.
    pub(crate) fn place_solid(&mut self, k: usize) {
        place(&mut self.solids[k], &mut self.solid);
        self.solids_dirty = true;
    }

    /// Moves every kinematic solid with its velocity over `dt`.
    pub(crate) fn advance_kinematic(&mut self, dt: f32) {
        for k in 0..self.solids.len() {
            let s = &mut self.solids[k];
            if s.kind != SolidKind::Kinematic
                || (s.linvel == Vector::ZERO && s.angvel == Vector::ZERO)
            {
                continue;
            }
            (s.pose, s.com) = rigid::advance(s.pose, s.com, s.linvel, s.angvel, dt);
            self.place_solid(k);
        }
    }

    /// A static ground whose carriers wait for the domain ([`Self::sample_deferred`]): a
    /// half-space or height field has no finite shell, and a cuboid 200 m wide at Δx = 2 cm
    /// would need 10⁹ carriers where the fluid touches a square metre of it. Sampled at once if
    /// the domain is fixed already.
    pub(crate) fn add_deferred(
        &mut self,
        name: String,
        shape: SharedShape,
        pose: Pose,
        slip: Slip,
    ) -> Result<SolidHandle> {
        let at = self.solid.len();
        self.solids.push(Solid {
            deferred: true,
            ..Solid::at_rest(name, SolidKind::Static, shape, pose, slip, at..at)
        });
        let k = self.solids.len() - 1;
        if let Some((lo, hi)) = self.domain() {
            if let Err(e) = self.sample_deferred_one(k, lo, hi) {
                self.solids.pop();
                return Err(e);
            }
        }
        Ok(SolidHandle(k as u32))
    }

    /// Samples every deferred ground within the domain `[lo, hi]` grown by a support radius.
    pub(crate) fn sample_deferred(&mut self, lo: Vector, hi: Vector) -> Result<()> {
        for k in 0..self.solids.len() {
            if self.solids[k].deferred && !self.solids[k].removed {
                self.sample_deferred_one(k, lo, hi)?;
            }
        }
        Ok(())
    }

    fn sample_deferred_one(&mut self, k: usize, lo: Vector, hi: Vector) -> Result<()> {
        let h = self.params.support_radius();
        let (lo, hi) = (lo - Vector::splat(h), hi + Vector::splat(h));
        let s = &self.solids[k];
        let (pose, shape) = (s.pose, s.shape.clone());
        // the domain's box in the ground's own frame
        let corners: Vec<Vector> = (0..8)
            .map(|c| {
                let w = Vector::new(
                    if c & 1 == 0 { lo.x } else { hi.x },
                    if c & 2 == 0 { lo.y } else { hi.y },
                    if c & 4 == 0 { lo.z } else { hi.z },
                );
                pose.inverse_transform_point(w)
            })
            .collect();
        let clip = crate::math::bounding_box(&corners);
        let samples = crate::sampling::sample_shell_in(
            shape.as_ref(),
            self.params.spacing,
            h,
            None,
            Some(clip),
        )
        .map_err(|e| named(e, &s.name))?;
        let total = (self.fluid.len() + self.solid.len() + samples.len()) as u64;
        if total > MAX_PARTICLES {
            return Err(named(
                FluidError::TooMany {
                    what: "particles",
                    count: total,
                    limit: MAX_PARTICLES,
                },
                &s.name,
            ));
        }
        let start = self.solid.len();
        for c in &samples {
            let x = pose.transform_point(c.x);
            self.solid.body.push(k as u32);
            self.solid.x.push(x);
            self.solid.n.push(pose.rotation * c.n);
            self.solid.u.push(Vector::ZERO);
            self.solid.f.push(Vector::ZERO);
            self.solid.volume.push(1.0);
            self.solid.depth.push(-c.phi);
        }
        let s = &mut self.solids[k];
        s.range = start..self.solid.len();
        s.deferred = false;
        s.two_sided = super::seams::two_sided_of(&samples);
        self.solids_dirty = true;
        Ok(())
    }

    /// Samples `shape` at `pose` into a solid of the given kind (the shell fluid can reach,
    /// parry's normals). A static ground (a half-space, a height field, a shape whose whole
    /// shell would take over a million carriers) is sampled within the domain once it is
    /// fixed ([`Self::add_deferred`]); a moving one is refused.
    pub(crate) fn add_sampled(
        &mut self,
        name: String,
        shape: SharedShape,
        pose: Pose,
        slip: Slip,
        kind: SolidKind,
    ) -> Result<SolidHandle> {
        crate::sampling::check_supported(shape.as_ref())?;
        let (dx, h) = (self.params.spacing, self.params.support_radius());
        if crate::sampling::is_ground(shape.as_ref()) && kind != SolidKind::Static {
            return Err(FluidError::UnsupportedShape {
                shape: format!("{:?}", shape.shape_type()),
                why: "a half-space or height field can only be a fixed ground (no body, or a \
                      fixed one)"
                    .into(),
            });
        }
        if kind == SolidKind::Static && crate::sampling::too_large_to_sample(shape.as_ref(), dx, h)
        {
            if !pose.is_finite() {
                return Err(FluidError::NonFinite {
                    what: format!("pose of solid `{name}`"),
                });
            }
            return self.add_deferred(name, shape, pose, slip);
        }
        self.add_sampled_on(name, shape, pose, slip, kind, None, &|_| true, &|_, n| n)
    }

    /// Samples a solid on the lattice through the world point `anchor` (see
    /// [`crate::sampling::sample_shell_on`]), keeping only carriers at world points where
    /// `reach` is true (the part of the shell fluid can reach) and giving each the normal
    /// `normal(x, n_shape)`.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn add_sampled_on(
        &mut self,
        name: String,
        shape: SharedShape,
        pose: Pose,
        slip: Slip,
        kind: SolidKind,
        anchor: Option<Vector>,
        reach: &dyn Fn(Vector) -> bool,
        normal: &dyn Fn(Vector, Vector) -> Vector,
    ) -> Result<SolidHandle> {
        if !pose.is_finite() {
            return Err(FluidError::NonFinite {
                what: format!("pose of solid `{name}`"),
            });
        }
        if let Slip::Partial { viscosity } = slip {
            if !(viscosity.is_finite() && viscosity >= 0.0) {
                return Err(FluidError::OutOfRange {
                    name: "Slip::Partial::viscosity",
                    value: viscosity as f64,
                    range: ">= 0",
                });
            }
        }
        let mut samples = sample_shell_on(
            shape.as_ref(),
            self.params.spacing,
            self.params.support_radius(),
            anchor.map(|a| pose.inverse_transform_point(a)),
        )?;
        samples.retain(|s| reach(pose.transform_point(s.x)));
        // Overlapping static solids form a union: carriers already inside an earlier static
        // solid are skipped, so the overlap is sampled once and internal faces carry no carriers.
        // (moving solids are sampled whole: they will not stay where they are)
        if kind == SolidKind::Static {
            samples.retain(|s| {
                let w = pose.transform_point(s.x);
                !self.solids.iter().any(|o| {
                    o.kind == SolidKind::Static
                        && !o.removed
                        && crate::sampling::contains(o.shape.as_ref(), &o.pose, w)
                })
            });
        }
        if kind == SolidKind::Static {
            self.seam_normals(shape.as_ref(), &pose, &mut samples);
        }
        let h = self.add_samples(name, shape, pose, slip, kind, samples, normal)?;
        self.update_volumes(h.0 as usize);
        Ok(h)
    }

    /// Adds a solid of `kind` whose carriers are `samples` (local frame), each with the normal
    /// `normal(x, n_shape)` and relative volume 1 (the caller sets others: a shell sampling's
    /// Akinci volumes, [`Self::update_volumes`]).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn add_samples(
        &mut self,
        name: String,
        shape: SharedShape,
        pose: Pose,
        slip: Slip,
        kind: SolidKind,
        samples: Vec<crate::sampling::ShellSample>,
        normal: &dyn Fn(Vector, Vector) -> Vector,
    ) -> Result<SolidHandle> {
        if samples.is_empty() {
            return Err(FluidError::DegenerateShape {
                shape: format!("{:?}", shape.shape_type()),
                why: format!("solid `{name}` lies entirely inside earlier solids"),
            });
        }
        let total = (self.fluid.len() + self.solid.len() + samples.len()) as u64;
        if total > MAX_PARTICLES {
            return Err(FluidError::TooMany {
                what: "particles",
                count: total,
                limit: MAX_PARTICLES,
            });
        }
        let start = self.solid.len();
        let idx = self.solids.len() as u32;
        // a static solid's carriers never move: no body-frame copy (24 B a carrier)
        let local: Vec<(Vector, Vector)> = if kind == SolidKind::Static {
            Vec::new()
        } else {
            samples.iter().map(|s| (s.x, s.n)).collect()
        };
        for s in &samples {
            self.solid.body.push(idx);
            let x = pose.transform_point(s.x);
            self.solid.x.push(x);
            self.solid.n.push(normal(x, pose.rotation * s.n));
            self.solid.u.push(Vector::ZERO);
            self.solid.f.push(Vector::ZERO);
            self.solid.volume.push(1.0);
            self.solid.depth.push(-s.phi);
        }
        let solid = Solid {
            local,
            two_sided: super::seams::two_sided_of(&samples),
            ..Solid::at_rest(name, kind, shape, pose, slip, start..self.solid.len())
        };
        if let Err(e) = check_overlap(&solid, &self.fluid.x) {
            let end = self.solid.len();
            self.solid.remove_range(start..end);
            return Err(e);
        }
        self.solids.push(solid);
        self.solids_dirty = true;
        Ok(SolidHandle(idx))
    }

    /// Changes the slip condition of a solid (e.g. a no-slip floor in a free-slip tank).
    pub fn set_slip(&mut self, h: SolidHandle, slip: Slip) {
        if let Some(s) = self.solids.get_mut(h.0 as usize) {
            s.slip = slip;
        }
    }

    /// Lets fluid stick to a solid (turns the §5.2 no-stick inequality off), e.g. for the tap
    /// water that flows around a ball in He 2012 Fig. 13(b).
    pub fn set_sticky(&mut self, h: SolidHandle, stick: bool) {
        if let Some(s) = self.solids.get_mut(h.0 as usize) {
            s.stick = stick;
        }
    }

    /// Adds a static axis-aligned box `[mins, maxs]`.
    pub fn add_static_box(
        &mut self,
        name: &str,
        mins: Vector,
        maxs: Vector,
        slip: Slip,
    ) -> Result<SolidHandle> {
        if !finite(mins) || !finite(maxs) {
            return Err(FluidError::NonFinite {
                what: format!("box `{name}` corners"),
            });
        }
        let half = (maxs - mins) * 0.5;
        if half.min_element() <= 0.0 {
            return Err(FluidError::DegenerateShape {
                shape: "Cuboid".into(),
                why: format!(
                    "box `{name}` has non-positive extent {:?}",
                    arr(maxs - mins)
                ),
            });
        }
        self.add_static_solid(
            name,
            SharedShape::cuboid(half.x, half.y, half.z),
            Pose::from_translation((mins + maxs) * 0.5),
            slip,
        )
    }
}

/// `e` with the solid's name in it (which collider of the world a size or shape error is
/// about).
pub(crate) fn named(e: FluidError, name: &str) -> FluidError {
    match e {
        FluidError::TooMany { what, count, limit } => FluidError::TooManyIn {
            solid: name.to_string(),
            what,
            count,
            limit,
        },
        FluidError::DegenerateShape { shape, why } => FluidError::DegenerateShape {
            shape: format!("{shape} ({name})"),
            why,
        },
        FluidError::UnsupportedShape { shape, why } => FluidError::UnsupportedShape {
            shape: format!("{shape} ({name})"),
            why,
        },
        e => e,
    }
}

pub(crate) fn check_overlap(solid: &Solid, positions: &[Vector]) -> Result<()> {
    let inside: Vec<&Vector> = positions
        .iter()
        .filter(|p| crate::sampling::contains(solid.shape.as_ref(), &solid.pose, **p))
        .collect();
    if let Some(first) = inside.first() {
        return Err(FluidError::FluidOverlapsSolid {
            solid: solid.name.clone(),
            count: inside.len(),
            first: arr(**first),
        });
    }
    Ok(())
}

/// Puts a solid's carriers at their world position, normal and velocity from its pose and
/// motion (`u = U + ω × (x − X)`, X the centre of rotation).
///
/// A static solid keeps no body-frame copy: a new pose moves its carriers by the change of
/// pose (applied only when the pose changed, so an unchanged pose adds no rounding).
pub(crate) fn place(s: &mut Solid, c: &mut SolidCarriers) {
    let (pose, v, w, com) = (s.pose, s.linvel, s.angvel, s.com);
    if s.local.is_empty() {
        if s.placed != pose {
            let rel = pose * s.placed.inverse();
            for i in s.range.clone() {
                c.x[i] = rel.transform_point(c.x[i]);
                c.n[i] = rel.rotation * c.n[i];
            }
        }
        for i in s.range.clone() {
            c.u[i] = v + w.cross(c.x[i] - com);
        }
    } else {
        for (i, &(p, n)) in s.range.clone().zip(&s.local) {
            let x = pose.transform_point(p);
            c.x[i] = x;
            c.n[i] = pose.rotation * n;
            c.u[i] = v + w.cross(x - com);
        }
    }
    s.placed = pose;
}

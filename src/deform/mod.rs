//! Deformable solids in the water: lattice shape matching (LSM) bodies after Shao et al. 2014
//! §3.4.1 and Rivers & James 2007.
//!
//! A body is sampled in three layers (Shao §3.2): **inner boundary particles** (IBPs) on a
//! lattice of the fluid spacing inside the shape carry its mass and are moved by shape
//! matching over overlapping regions of half-width `w`; **surface boundary particles** (SBPs)
//! are solid carriers in the shell the fluid can reach — the same carriers a rigid body of that
//! shape has — placed each substep from the IBPs around them (Eq. 19) and seen by the fluid
//! with the velocity that placement gives them; the fluid's impulse on each SBP is shared
//! among those IBPs (Eq. 10, normalised per SBP so the shares add up to the impulse: momentum
//! is kept). Any point of the rest shape (a render mesh's vertices) follows the body the same
//! way ([`Deformable::bind`]).
//!
//! Within a fluid substep the body first takes its elastic step (shape matching); then it
//! enters the fluid's stages as a rigid proxy — a dynamic body of its mass and inertia, pushed
//! as rapier bodies are, implicitly in the velocity constraint — or, once pinned, as one proxy
//! per chunk of its lattice free of pins; afterwards each IBP takes its proxy's motion plus
//! its share of the SBPs' impulses that neither moves nor turns the proxy. Fluid carriers that
//! end inside it are pushed out against its rest shape mapped near each SBP.
//!
//! Limits (measured, `docs/experiments.md`): a pinned soft body (α < 1) holding water can
//! throw it out (an elastic box at α = 0.5 lost 64 of 600 carriers in a second); an undamped
//! pinned box rings until its walls burst (the step then fails); the fluid sees only the rigid part of a
//! proxied body's velocity within a substep (its deformation moves the SBPs between
//! substeps).
//!
//! ```
//! use staggered_fluid::prelude::*;
//! use staggered_fluid::deform::DeformableParams;
//! use rapier3d::parry::shape::SharedShape;
//!
//! let mut world = FluidWorld::new(FluidParams { spacing: 0.025, ..Default::default() })?;
//! world.add_open_tank(Vector::ZERO, Vector::new(0.4, 0.4, 0.4), Slip::FreeSlip)?;
//! world.add_block(Vector::ZERO, Vector::new(0.4, 0.15, 0.4), Vector::ZERO)?;
//! // a soft block of rubber-like stiffness dropped on the water
//! let jelly = world.add_deformable(
//!     "jelly",
//!     SharedShape::cuboid(0.05, 0.05, 0.05),
//!     Pose::from_translation(Vector::new(0.2, 0.25, 0.2)),
//!     DeformableParams { density: 600.0, stiffness: 0.3, ..Default::default() },
//! )?;
//! world.step(Vector::new(0.0, -9.81, 0.0), 0.005)?;
//! let body = world.deformable(jelly).unwrap();
//! assert!(body.linear_momentum().y < 0.0); // falling
//! # Ok::<(), FluidError>(())
//! ```

pub(crate) mod body;
mod chunks;
mod cloth;
mod contact;
mod crossing;
pub(crate) mod lattice;
pub(crate) mod matching;
pub(crate) mod melt;
mod sharing;
mod substep;

pub use body::{
    Deformable, DeformableHandle, DeformableParams, Melting, PointBinding, MAX_HALF_WIDTH,
};

use crate::error::{FluidError, Result};
use crate::math::{Pose, Vector};
use crate::world::{FluidWorld, SolidHandle, SolidKind};
use rapier3d::parry::shape::SharedShape;

impl FluidWorld {
    /// Adds a deformable body of `shape` (any closed shape the fluid couples: a ball, a box, a
    /// compound, a closed triangle mesh) at `pose`, at rest. Its SBPs are sampled as a rigid
    /// body's carriers would be; its IBPs fill the shape on the lattice of the fluid spacing.
    /// Fails, adding nothing, on bad parameters, a shape thinner than a spacing, too many
    /// particles, or fluid inside it.
    pub fn add_deformable(
        &mut self,
        name: impl Into<String>,
        shape: SharedShape,
        pose: Pose,
        params: DeformableParams,
    ) -> Result<DeformableHandle> {
        params.validate()?;
        let name = name.into();
        crate::sampling::check_supported(shape.as_ref())?;
        if crate::sampling::is_ground(shape.as_ref()) {
            return Err(FluidError::UnsupportedShape {
                shape: format!("{:?}", shape.shape_type()),
                why: "a half-space or height field cannot be a deformable body".into(),
            });
        }
        let dx = self.params.spacing;
        let (rest, cells) =
            lattice::inner_points(shape.as_ref(), dx).map_err(|e| crate::world::named(e, &name))?;
        let volume = shape.mass_properties(1.0).mass();
        let h = if params.melting.is_some() {
            // every lattice point a carrier: the fluid reaches each once those outside it melt
            if !pose.is_finite() {
                return Err(FluidError::NonFinite {
                    what: format!("pose of deformable body `{name}`"),
                });
            }
            let samples = lattice::samples(shape.as_ref(), &rest);
            let kind = SolidKind::Deformable;
            self.add_samples(
                name.clone(),
                shape,
                pose,
                params.slip,
                kind,
                samples,
                &|_, n| n,
            )?
        } else {
            self.add_sampled_on(
                name.clone(),
                shape,
                pose,
                params.slip,
                SolidKind::Deformable,
                None,
                &|_| true,
                &|_, n| n,
            )?
        };
        let own = params.melting.map(|_| 1.0);
        let mass = params.density * volume / rest.len() as f32;
        Ok(self.install(name, pose, params, (rest, cells), h, own, mass, false))
    }

    /// Makes the body whose lattice points (shape frame) and cells are `lattice` and whose SBPs
    /// are the carriers of solid `h`, just added: splits them into chunks and ties each SBP to
    /// its IBPs — to the point it stands on, every carrier of relative volume `own`, when
    /// that is given (melting bodies, cloth). Each point weighs `mass`.
    #[allow(clippy::too_many_arguments)]
    fn install(
        &mut self,
        name: String,
        pose: Pose,
        params: DeformableParams,
        (rest, cells): (Vec<Vector>, Vec<[i32; 3]>),
        h: SolidHandle,
        own: Option<f32>,
        mass: f32,
        cloth: bool,
    ) -> DeformableHandle {
        // a cloth's points are each a chunk: pinned ones stay put, the others all move with
        // the water implicitly (with 4² chunks the free points of chunks holding a pin moved
        // explicitly, and a cloth catching a falling column erupted)
        let edge = if cloth { 1 } else { chunks::CHUNK };
        let mut split = self.split_into_chunks(h.0 as usize, &rest, &cells, edge);
        if let Some(volume) = own {
            split.carriers = lattice::own_points(&split.sbp_rest, &rest);
            let (a, b) = (h.0 as usize, self.solids.len() - 1);
            let r = self.solids[a].range.start..self.solids[b].range.end;
            self.solid.volume[r].iter_mut().for_each(|v| *v = volume);
        }
        let n = rest.len();
        let body = Deformable {
            name,
            params,
            mass,
            x: rest.iter().map(|p| pose.transform_point(*p)).collect(),
            v: vec![Vector::ZERO; n],
            pinned: vec![false; n],
            rotation: vec![pose.rotation; n],
            region_rotation: vec![pose.rotation; n],
            regions: lattice::regions(&cells, params.half_width),
            solids: split.solids,
            chunk: split.chunk,
            members: split.members,
            carriers: split.carriers,
            sbp_rest: split.sbp_rest,
            rest,
            seen: Vec::new(),
            groups: Vec::new(),
            rings: Vec::new(),
            elastic_energy: 0.0,
            sbp_rotation: Vec::new(),
            temperature: params
                .melting
                .map_or(Vec::new(), |m| vec![m.temperature; n]),
            absorbed: params.melting.map_or(Vec::new(), |_| vec![0.0; n]),
            cells,
            pool: Default::default(),
            reference_substep: 0.0,
            cloth,
        };
        if params.melting.is_some() {
            self.ensure_heat();
        }
        for &k in &body.solids {
            self.solids[k as usize].com = body.center_of_mass();
        }
        self.deformables.push(body);
        DeformableHandle(self.deformables.len() as u32 - 1)
    }

    /// The fluid's force on a deformable body over the last step, N (the sum over its
    /// solids): the net exchange with the water, what the water beside its walls got back of
    /// their push deducted (so it equals the water's momentum change; its carriers'
    /// `f` in [`crate::particles::SolidCarriers`] keep the stages' gross impulses).
    pub fn deformable_force(&self, h: DeformableHandle) -> Option<Vector> {
        let b = self.deformables.get(h.0 as usize)?;
        Some(
            b.solids
                .iter()
                .map(|&k| self.solids[k as usize].force)
                .sum(),
        )
    }

    fn deformable_mut(&mut self, h: DeformableHandle) -> Result<&mut Deformable> {
        self.deformables
            .get_mut(h.0 as usize)
            .ok_or_else(|| FluidError::Coupling(format!("no deformable body with handle {}", h.0)))
    }

    /// A deformable body.
    pub fn deformable(&self, h: DeformableHandle) -> Option<&Deformable> {
        self.deformables.get(h.0 as usize)
    }

    /// Every deformable body, indexed by `DeformableHandle.0`.
    pub fn deformables(&self) -> &[Deformable] {
        &self.deformables
    }

    /// Sets a deformable body moving rigidly: its centre of mass at `linvel`, turning at
    /// `angvel` (rad/s) about it.
    pub fn set_deformable_velocity(
        &mut self,
        h: DeformableHandle,
        linvel: Vector,
        angvel: Vector,
    ) -> Result<()> {
        if !(crate::math::finite(linvel) && crate::math::finite(angvel)) {
            return Err(FluidError::NonFinite {
                what: "deformable body velocity".into(),
            });
        }
        let b = self.deformable_mut(h)?;
        let c = b.center_of_mass();
        for i in 0..b.x.len() {
            b.v[i] = if b.pinned[i] {
                Vector::ZERO
            } else {
                linvel + angvel.cross(b.x[i] - c)
            };
        }
        Ok(())
    }

    /// Pins the IBPs of a deformable body whose current position satisfies `pin` (they stay
    /// put, at rest: a body fixed at its base); returns how many are pinned now.
    pub fn pin_deformable(
        &mut self,
        h: DeformableHandle,
        pin: impl Fn(Vector) -> bool,
    ) -> Result<usize> {
        let b = self.deformable_mut(h)?;
        for i in 0..b.x.len() {
            if pin(b.x[i]) {
                b.pinned[i] = true;
                b.v[i] = Vector::ZERO;
            }
        }
        Ok(b.pinned.iter().filter(|&&p| p).count())
    }
}

impl Deformable {
    /// The solids whose carriers are the body's SBPs, one per chunk of its lattice (its fluid
    /// force is the sum of theirs, [`FluidWorld::deformable_force`]).
    pub fn solids(&self) -> Vec<SolidHandle> {
        self.solids.iter().map(|&k| SolidHandle(k)).collect()
    }
}

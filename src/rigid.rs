//! Rigid motion of coupled bodies during the fluid substeps (He 2012 §5 and Eq. 21).
//!
//! Rapier owns the bodies: at the start of each [`crate::FluidWorld::step_with_rapier`] their
//! pose, velocity and mass properties are copied here, the fluid substeps move dynamic bodies
//! with gravity and the fluid's impulses (so the fluid sees where they are going), and at the end
//! only the fluid's accumulated impulse and angular impulse are handed back to rapier, which then
//! integrates, resolves contacts and decides the final pose.

use crate::math::{Pose, Rotation, Vector};
use rapier3d::dynamics::{LockedAxes, RigidBodyHandle};
use rapier3d::math::Matrix;
use rapier3d::parry::mass_properties::MassProperties;

/// State of one dynamic rapier body while the fluid steps.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub struct Rigid {
    /// The rapier body.
    pub handle: RigidBodyHandle,
    /// Local mass properties (from rapier, colliders included).
    pub mprops: MassProperties,
    /// Locked translation/rotation axes.
    pub locks: LockedAxes,
    /// Rapier's gravity scale.
    pub gravity_scale: f32,
    /// World centre of mass.
    pub com: Vector,
    /// Orientation of the body (to rotate the inertia tensor).
    pub rotation: Rotation,
    /// Velocity of the centre of mass.
    pub linvel: Vector,
    /// Angular velocity.
    pub angvel: Vector,
    /// Rapier's body is asleep: the fluid treats it as fixed unless it pushes hard enough.
    pub sleeping: bool,
    /// Some fluid is near it: its carriers take part in this step.
    pub active: bool,
    /// Rapier's sleep threshold (speed), m/s.
    pub wake_threshold: f32,
    /// Rapier's time a body must stay below the threshold before it sleeps, s.
    pub wake_horizon: f32,
    /// Fluid impulse `[J; L]` (about the centre of mass) accumulated over the current step.
    pub impulse: [f64; 6],
    /// Pose of the centre of mass at the start of the current substep (com, rotation).
    pub(crate) start: (Vector, Rotation),
    /// Pose of the centre of mass rapier gave at the start of the step (com, rotation).
    pub(crate) frame_start: (Vector, Rotation),
    /// Its solids paired with the static solids whose rapier colliders it collides with
    /// (indices into [`crate::FluidWorld::solids`]; [`crate::FluidWorld::sync_rapier`]).
    #[serde(skip)]
    pub(crate) walls: Vec<(u32, u32)>,
    /// Its contacts with those walls at the start of the current substep: point on the body
    /// (world), normal from the body into the wall, distance (negative when penetrating).
    #[serde(skip)]
    pub(crate) contacts: Vec<(Vector, Vector, f32)>,
    /// Impulse `[J; L]` (about the centre of mass) the walls gave it over the current step
    /// to keep it from moving into them ([`crate::FluidWorld::keep_off_walls`]).
    #[serde(skip)]
    pub(crate) wall_impulse: [f64; 6],
    /// The velocity change `(Δv, Δω)` the walls gave the substep's predicted pose, taken back
    /// before the final velocity is kept off them.
    #[serde(skip)]
    pub(crate) wall_kick: (Vector, Vector),
    /// The impulse `[J; L]` of that change (shared with the water beside the body by
    /// `share_weight`, and taken back the same way).
    #[serde(skip)]
    pub(crate) wall_kick_impulse: [f64; 6],
    /// A chunk of a pinned deformable body, as its rigid proxy: its weight goes to the pins
    /// through its elastic forces, not to the water beside it (`share_weight`; shared with
    /// that water, the elastic support threw water out of a pinned cloth's tank).
    #[serde(skip)]
    pub(crate) hung: bool,
}

impl Rigid {
    /// Inverse mass per axis (0 on locked translations).
    pub fn inv_mass(&self) -> Vector {
        let m = self.mprops.inv_mass;
        let l = self.locks;
        Vector::new(
            if l.contains(LockedAxes::TRANSLATION_LOCKED_X) {
                0.0
            } else {
                m
            },
            if l.contains(LockedAxes::TRANSLATION_LOCKED_Y) {
                0.0
            } else {
                m
            },
            if l.contains(LockedAxes::TRANSLATION_LOCKED_Z) {
                0.0
            } else {
                m
            },
        )
    }

    /// World inverse inertia with rapier's rotation locks.
    pub fn inv_inertia(&self) -> Matrix {
        let i = self.mprops.world_inv_inertia(&self.rotation);
        let mut m = Matrix::from_cols(
            Vector::new(i.m11, i.m12, i.m13),
            Vector::new(i.m12, i.m22, i.m23),
            Vector::new(i.m13, i.m23, i.m33),
        );
        let l = self.locks;
        for (k, flag) in [
            LockedAxes::ROTATION_LOCKED_X,
            LockedAxes::ROTATION_LOCKED_Y,
            LockedAxes::ROTATION_LOCKED_Z,
        ]
        .into_iter()
        .enumerate()
        {
            if l.contains(flag) {
                *m.col_mut(k) = Vector::ZERO;
                for c in 0..3 {
                    m.col_mut(c)[k] = 0.0;
                }
            }
        }
        m
    }

    /// Whether the fluid moves it in this step.
    pub fn moving(&self) -> bool {
        self.active && !self.sleeping
    }

    /// Velocity and angular-velocity change `(ΔU, Δω)` from an impulse `j` and angular impulse
    /// `l` (about the centre of mass), with rapier's locked axes.
    pub fn response(&self, j: Vector, l: Vector) -> (Vector, Vector) {
        (self.inv_mass() * j, self.inv_inertia() * l)
    }

    /// Applies an impulse `j` and angular impulse `l` (about the centre of mass).
    pub fn kick(&mut self, j: Vector, l: Vector) {
        let (du, dw) = self.response(j, l);
        self.linvel += du;
        self.angvel += dw;
    }
}

/// The wrench `[J; L]` of an impulse `j` at lever arm `arm` from the centre of mass, in f64 for
/// accumulation (Eq. 21).
pub(crate) fn wrench(j: Vector, arm: Vector) -> [f64; 6] {
    let t = arm.cross(j);
    [j.x, j.y, j.z, t.x, t.y, t.z].map(|v| v as f64)
}

/// Splits a wrench `[J; L]` into its linear and angular parts.
pub(crate) fn split(e: &[f64; 6]) -> (Vector, Vector) {
    let f = |k: usize| e[k] as f32;
    (Vector::new(f(0), f(1), f(2)), Vector::new(f(3), f(4), f(5)))
}

/// Moves a pose rigidly with velocity `linvel` of the point `com` and angular velocity `angvel`
/// over `dt`; returns the new pose and the new position of `com`.
pub fn advance(pose: Pose, com: Vector, linvel: Vector, angvel: Vector, dt: f32) -> (Pose, Vector) {
    let dq = Rotation::from_scaled_axis(angvel * dt);
    let new_com = com + linvel * dt;
    let t = new_com + dq * (pose.translation - com);
    (
        Pose::from_parts(t, (dq * pose.rotation).normalize()),
        new_com,
    )
}

//! A deformable body through one fluid substep: the elastic step, its chunks entering the
//! fluid's stages as rigid proxies (or, where pinned, as scripted walls), and afterwards the
//! impulses its SBPs took shared among its IBPs.

use super::body::{Group, RigidState};
use super::{matching, Deformable};
use crate::math::{Pose, Rotation, Vector};
use crate::rigid::Rigid;
use crate::solver::contact::Deformed;
use crate::world::FluidWorld;
use rapier3d::dynamics::{LockedAxes, RigidBodyHandle};
use rapier3d::math::Matrix;
use rapier3d::parry::mass_properties::MassProperties;
use rapier3d::parry::shape::SharedShape;

/// Whether a proxy is a deformable chunk's (it has no rapier body).
pub(crate) fn is_proxy(r: &Rigid) -> bool {
    r.handle == RigidBodyHandle::invalid()
}

impl Deformable {
    /// The elastic part of a substep of `dt` (Rivers & James 2007, Müller et al. 2005):
    /// predicted positions, the regions' goals, each free IBP's velocity changed by
    /// `α (g − x*) / Δt` (and by gravity for the IBPs `fall` says; the others take it through
    /// their proxy). Returns the positions `x* + α (g − x*)` the IBPs that move on their own
    /// take. The prediction turns each IBP about the body's centre by the body's rotation over
    /// the substep instead of along its velocity's straight line: a straight line leaves a
    /// spinning body's goals short of its turn (`atan(ω Δt)` for `ω Δt`), and a ball spun at
    /// 20 rad/s kept 85 % of its spin over 0.1 s. Keeps momentum (the goals do, and the turn
    /// moves no centre of mass) and a rigid rotation's angular momentum.
    fn elastic(&mut self, gravity: Vector, dt: f32, fall: &[bool]) -> Vec<Vector> {
        let all: Vec<u32> = (0..self.x.len() as u32).collect();
        let st = self.rigid_state(&all, 0.0, 0);
        let turn = Rotation::from_scaled_axis(st.angvel * dt);
        let keep = 1.0 - self.params.damping;
        // the predicted position, and the velocity turned with the body
        let (pred, turned): (Vec<Vector>, Vec<Vector>) = (0..self.x.len())
            .map(|i| {
                if self.pinned[i] {
                    return (self.x[i], Vector::ZERO);
                }
                let arm = self.x[i] - st.com;
                let own = turn * (self.v[i] - st.linvel - st.angvel.cross(arm)) * keep;
                let g = if fall[i] { gravity * dt } else { Vector::ZERO };
                let v = st.linvel + st.angvel.cross(turn * arm) + own + g;
                (st.com + turn * arm + dt * (st.linvel + own + g), v)
            })
            .unzip();
        let g = matching::goals(
            &self.regions,
            &self.rest,
            &pred,
            self.mass,
            &mut self.region_rotation,
        );
        // a cloth keeps the stiffness α m / Δt₁² of its reference substep Δt₁ (its first step
        // split by the shared body-force limit, `FluidWorld::set_cloth_reference`) whatever the
        // substep: a membrane carries a load by stretching, far, and at a fixed share per
        // substep its stiffness grew as 1/Δt² — a cloth that caught a falling column sprang
        // back as its substeps went 5 → 32 → 218 (stiffness ×1900), throwing the water up at
        // 30 m/s. A volumetric body keeps α per substep: it deforms little, and a pinned
        // elastic box softened by the density controller's shorter substeps threw its water
        // out at the third step
        if self.reference_substep.is_nan() || self.reference_substep <= 0.0 {
            self.reference_substep = dt;
        }
        let alpha = if self.cloth {
            self.params.stiffness * (dt / self.reference_substep).powi(2).min(1.0)
        } else {
            self.params.stiffness
        };
        let mut next = self.x.clone();
        let mut stretch = 0.0f64;
        for (i, p) in pred.iter().enumerate() {
            if self.pinned[i] {
                self.v[i] = Vector::ZERO;
                continue;
            }
            let pull = alpha * (g.goal[i] - *p);
            stretch += (g.goal[i] - *p).length_squared() as f64;
            self.v[i] = turned[i] + pull / dt;
            next[i] = *p + pull;
        }
        self.elastic_energy = 0.5 * (alpha * self.mass / (dt * dt)) as f64 * stretch;
        self.rotation = g.rotation;
        next
    }

    /// The IBPs `ids` as one rigid body: centre of mass, its velocity, the angular velocity
    /// of their angular momentum about it, and the inertia (each IBP a cube of the lattice).
    fn rigid_state(&self, ids: &[u32], dx: f32, proxy: usize) -> RigidState {
        let n = ids.len() as f32;
        let (mut c, mut v) = (Vector::ZERO, Vector::ZERO);
        for &i in ids {
            c += self.x[i as usize];
            v += self.v[i as usize];
        }
        let (c, v) = (c / n, v / n);
        let (mut l, mut inertia) = (
            Vector::ZERO,
            Matrix::from_diagonal(Vector::splat(n * dx * dx / 6.0)),
        );
        for &i in ids {
            let r = self.x[i as usize] - c;
            l += r.cross(self.v[i as usize] - v);
            inertia += Matrix::from_diagonal(Vector::splat(r.length_squared()))
                - Matrix::from_cols(r * r.x, r * r.y, r * r.z);
        }
        let (l, inertia) = (l * self.mass, inertia * self.mass);
        let inv = invert(&inertia);
        RigidState {
            mass: self.mass,
            com: c,
            linvel: v,
            angvel: inv * l,
            inertia,
            inv_inertia: inv,
            proxy,
        }
    }

    /// Where SBP `k`, at rest `(p, n0)`, hangs now (Eq. 19), its turned normal, and the
    /// mean rotation of its IBPs.
    fn place_sbp(&self, k: usize) -> (Vector, Vector, Rotation) {
        let (p, n0) = self.sbp_rest[k];
        let w = self.carriers.row(k);
        let first = self.rotation[w[0].0 as usize];
        let mut q = [0.0f32; 4];
        for &(d, w) in w {
            let r = self.rotation[d as usize];
            let r = if r.dot(first) < 0.0 { -r } else { r };
            for (s, v) in q.iter_mut().zip(r.to_array()) {
                *s += w * v;
            }
        }
        let r = Rotation::from_array(q).normalize();
        (self.carry(p, w), r * n0, r)
    }

    /// The velocity change each IBP takes from the SBPs' impulses `j` (Eq. 10, shares
    /// normalised per SBP).
    fn shares(&self, j: &[Vector]) -> Vec<Vector> {
        let mut dv = vec![Vector::ZERO; self.x.len()];
        for (k, j) in j.iter().enumerate() {
            if *j == Vector::ZERO {
                continue;
            }
            for &(d, w) in self.carriers.row(k) {
                dv[d as usize] += *j * (w / self.mass);
            }
        }
        dv
    }

    /// Whether each chunk holds a pinned IBP (then it is a scripted wall, not a proxy).
    fn anchored(&self) -> Vec<bool> {
        (0..self.members.len())
            .map(|c| self.members.row(c).iter().any(|&i| self.pinned[i as usize]))
            .collect()
    }
}

impl FluidWorld {
    /// Each deformable body at the start of a substep of `dt`: the elastic velocities, then
    /// its SBPs placed from its IBPs (Eq. 19). Each chunk with no pinned IBP enters the
    /// substep as a rigid proxy — a dynamic body of its IBPs' mass and inertia, moving with
    /// their rigid motion, gravity included — so that the fluid's stages push it as they push
    /// rapier bodies: implicitly in the velocity constraint's rigid rows, shared with the
    /// water beside it in the explicit ones. (Without that a floating 500 kg/m³ box, 2 kg
    /// against ~4 kg of water it moves, rang at half the substep rate, ±0.5 kg m/s a frame.)
    /// A pinned chunk, and the IBPs of chunks without SBPs, move on their own (their SBPs a
    /// scripted wall at the end of the substep).
    pub(crate) fn prepare_deformables(&mut self, gravity: Vector, dt: f32) {
        self.rigids.retain(|r| !is_proxy(r));
        let dx = self.params.spacing;
        for bi in 0..self.deformables.len() {
            let b = &mut self.deformables[bi];
            b.groups.clear();
            if b.x.is_empty() || b.solids.iter().any(|&k| self.solids[k as usize].removed) {
                continue;
            }
            // a free body is one proxy; a pinned one a proxy per chunk free of pins
            let anchored = b.anchored();
            let hung = anchored.iter().any(|&a| a);
            let groups: Vec<(Vec<u32>, Vec<usize>)> = if hung {
                (0..b.solids.len())
                    .filter(|&c| !anchored[c])
                    .map(|c| (b.members.row(c).to_vec(), vec![c]))
                    .collect()
            } else {
                vec![(
                    (0..b.x.len() as u32).collect(),
                    (0..b.solids.len()).collect(),
                )]
            };
            // with no fluid near, a group moves on its own (a proxy would not be moved)
            let solids = &self.solids;
            let groups: Vec<(Vec<u32>, Vec<usize>)> = groups
                .into_iter()
                .filter(|(_, chunks)| chunks.iter().any(|&c| solids[b.solids[c] as usize].active))
                .collect();
            let mut fall = vec![true; b.x.len()];
            for (ids, _) in &groups {
                for &i in ids {
                    fall[i as usize] = false;
                }
            }
            let next = b.elastic(gravity, dt, &fall);
            for ((x, n), _) in b.x.iter_mut().zip(next).zip(&fall).filter(|e| *e.1) {
                *x = n;
            }
            let mut proxied: Vec<Option<RigidState>> = vec![None; b.solids.len()];
            for (ids, chunks) in groups {
                let st = b.rigid_state(&ids, dx, self.rigids.len());
                let active = chunks
                    .iter()
                    .any(|&c| self.solids[b.solids[c] as usize].active);
                let mut p = proxy(&st, b.mass * ids.len() as f32, active);
                p.hung = hung;
                self.rigids.push(p);
                for &c in &chunks {
                    proxied[c] = Some(st);
                }
                b.groups.push(Group { ids, st });
            }
            let first = self.solids[b.solids[0] as usize].range.start;
            b.sbp_rotation.resize(b.sbp_rest.len(), Rotation::IDENTITY);
            for (c, &k) in b.solids.iter().enumerate() {
                let s = &mut self.solids[k as usize];
                let car = &mut self.solid;
                for i in s.range.clone() {
                    let (x, n, r) = b.place_sbp(i - first);
                    b.sbp_rotation[i - first] = r;
                    let n = n.normalize_or(car.n[i]);
                    car.u[i] = match &proxied[c] {
                        Some(st) => {
                            s.local[i - s.range.start] = (x - st.com, n);
                            st.linvel + st.angvel.cross(x - st.com)
                        }
                        None => (x - car.x[i]) / dt,
                    };
                    car.x[i] = x;
                    car.n[i] = n;
                }
                s.rigid = proxied[c].map(|st| st.proxy);
                if let Some(st) = proxied[c] {
                    (s.com, s.linvel, s.angvel) = (st.com, st.linvel, st.angvel);
                    s.pose = Pose::from_translation(st.com);
                }
            }
            let last = self.solids[*b.solids.last().unwrap() as usize].range.end;
            b.seen = self.solid.f[first..last].to_vec();
            self.solids_dirty = true;
        }
    }

    /// Each deformable body after the substep's stages: the impulses its SBPs took, shared
    /// among its IBPs (Eq. 10; pinned IBPs pass theirs to whatever holds them) and with the
    /// water beside them ([`Self::share_with_water`]). A proxied group's IBPs take the
    /// proxy's rigid motion (it took the impulses' rigid part) plus the part of the shares
    /// that neither moves nor turns the group: momentum is exact, the deformation kept.
    pub(crate) fn finish_deformables(&mut self, dt: f32) {
        for bi in 0..self.deformables.len() {
            let b = &self.deformables[bi];
            if b.seen.is_empty() {
                continue;
            }
            let first = self.solids[b.solids[0] as usize].range.start;
            let j: Vec<Vector> = b
                .seen
                .iter()
                .enumerate()
                .map(|(k, seen)| self.solid.f[first + k] - *seen)
                .collect();
            let mut dv = b.shares(&j);
            for g in &b.groups {
                let (du, dw) = g.st.rigid_part(&g.ids, &b.x, &dv);
                for &i in &g.ids {
                    let i = i as usize;
                    dv[i] -= du + dw.cross(b.x[i] - g.st.com);
                }
            }
            for (d, p) in dv.iter_mut().zip(&b.pinned) {
                if *p {
                    *d = Vector::ZERO;
                }
            }
            self.share_with_water(bi, &mut dv);
            let b = &mut self.deformables[bi];
            b.seen.clear();
            let mut moved = vec![false; b.x.len()];
            for g in &b.groups {
                let (st, r) = (&g.st, &self.rigids[g.st.proxy]);
                let (c1, q) = (r.com, r.rotation);
                for &i in &g.ids {
                    let i = i as usize;
                    let arm = b.x[i] - st.com;
                    let own = b.v[i] - (st.linvel + st.angvel.cross(arm)) + dv[i];
                    let arm = q * arm;
                    b.x[i] = c1 + arm + own * dt;
                    b.v[i] = r.linvel + r.angvel.cross(arm) + own;
                    moved[i] = true;
                }
            }
            for i in 0..b.x.len() {
                if !moved[i] {
                    b.v[i] += dv[i];
                }
            }
            for &k in &b.solids {
                let s = &mut self.solids[k as usize];
                if let Some(r) = s.rigid.take().map(|ri| &self.rigids[ri]) {
                    (s.linvel, s.angvel) = (r.linvel, r.angvel);
                }
            }
            self.keep_out_of_walls(bi);
        }
        // the proxies live within a substep only
        self.rigids.retain(|r| !is_proxy(r));
    }
}

impl FluidWorld {
    /// Where each deformable body's rest shape lies near each of its SBPs, for the
    /// penetration correction (nothing when there is no deformable body).
    pub(crate) fn deformed_frames(&self) -> Deformed {
        if self.deformables.is_empty() {
            return Deformed::default();
        }
        let mut d = Deformed {
            shapes: vec![None; self.solids.len()],
            frames: vec![(Vector::ZERO, Rotation::IDENTITY); self.solid.len()],
            group: (0..self.solids.len() as u32).collect(),
        };
        for b in &self.deformables {
            if b.sbp_rotation.len() != b.sbp_rest.len() || b.solids.is_empty() {
                continue;
            }
            let first = self.solids[b.solids[0] as usize].range.start;
            // a melting body (what is left of its lattice) and a cloth are a cell around each
            // point
            let h = 0.5 * self.params.spacing;
            let cell = b.is_cells().then(|| SharedShape::cuboid(h, h, h));
            for &k in &b.solids {
                let s = &self.solids[k as usize];
                if b.cloth {
                    // a cloth's points are each a solid: its nearest point stands for it
                    d.group[k as usize] = b.solids[0];
                }
                d.shapes[k as usize] = Some(cell.clone().unwrap_or_else(|| s.shape.clone()));
                for i in s.range.clone() {
                    let (rest, r) = (b.sbp_rest[i - first].0, b.sbp_rotation[i - first]);
                    d.frames[i] = (if cell.is_some() { Vector::ZERO } else { rest }, r);
                }
            }
        }
        d
    }
}

/// The inverse of an inertia; of points on a line (what melting leaves of a body) the inverse
/// about the axes it turns about (a tiny regularisation along the line), of one point zero.
fn invert(inertia: &Matrix) -> Matrix {
    let tr = inertia.x_axis.x + inertia.y_axis.y + inertia.z_axis.z;
    if tr.is_nan() || tr <= 0.0 {
        return Matrix::ZERO;
    }
    if inertia.determinant() > 1e-6 * tr * tr * tr {
        inertia.inverse()
    } else {
        (*inertia + Matrix::from_diagonal(Vector::splat(1e-3 * tr))).inverse()
    }
}

/// The rigid proxy of IBPs of `mass` in state `st`.
fn proxy(st: &RigidState, mass: f32, active: bool) -> Rigid {
    Rigid {
        handle: RigidBodyHandle::invalid(),
        mprops: MassProperties::with_inertia_matrix(Vector::ZERO, mass, st.inertia),
        locks: LockedAxes::empty(),
        gravity_scale: 1.0,
        com: st.com,
        rotation: Rotation::IDENTITY,
        linvel: st.linvel,
        angvel: st.angvel,
        sleeping: false,
        active,
        wake_threshold: 0.0,
        wake_horizon: 0.0,
        impulse: [0.0; 6],
        start: (st.com, Rotation::IDENTITY),
        walls: Vec::new(),
        contacts: Vec::new(),
        wall_impulse: [0.0; 6],
        wall_kick: (Vector::ZERO, Vector::ZERO),
        wall_kick_impulse: [0.0; 6],
        hung: false,
        frame_start: (st.com, Rotation::IDENTITY),
    }
}

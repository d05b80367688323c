//! The water a body drags (issue 20, light bodies): the impulse an explicit stage gives a
//! dynamic body is shared with the fluid carriers beside it, body and carriers moving as one
//! rigid lump.
//!
//! Only the velocity constraint solves fluid and bodies together (the rigid rows); the other
//! stages (viscous prediction, the density constraint, XSPH, the wall conditions of surface
//! carriers, the penetration correction) push a body explicitly. A body much lighter than the
//! water beside it then overshoots many times over per substep — the added-mass instability of
//! explicit coupling: a 10 kg/m³ ball took 100 g of buoyancy per substep and 200 m/s kicks
//! from the density constraint, handed back by the velocity constraint, and erupted. The
//! velocity constraint's own reaction is shared the same way, although its solve has the
//! body's rigid rows: taken by the body alone it turned a light body without the water beside
//! it (a 10 kg/m³ cube's spin grew 15–25 % a substep, to 30 rad/s in three frames; shared:
//! under 8 rad/s). Here the
//! stage's wrench `e` on a body moves the body with the fluid carriers beside it: with weights
//! `w_i` (the fraction of carrier i's neighbours that belong to the body), the carriers' 6×6
//! mass about the centre of mass `S = Σ m w_i [𝟙, −[r_i]×; [r_i]×, −[r_i]×²]` and the body's
//! inverse mass `K` (rapier's locked axes as zeros), the lump's velocity change solves
//! `(𝟙 + K S) Δq = K e`; the body takes `Δq` (its wrench `e − S Δq`) and carrier i
//! `w_i (ΔU + Δω × r_i)`. Momentum and angular momentum are exact; for `M ≫ m w` the body takes
//! all of `e`, as printed.

use super::FluidWorld;
use crate::math::{Pose, Vector};
use crate::solver::staggered::Slip;
use crate::solver::{forces, BodyView, ROWS};
use rapier3d::parry::shape::SharedShape;
use rayon::prelude::*;

/// The fluid carriers beside one moving dynamic body.
#[derive(Default)]
pub(crate) struct Lump {
    /// The fluid carriers that move with it.
    carriers: Vec<Dragged>,
    /// Their 6×6 mass about the centre of mass (`[J; L]` per `[ΔU; Δω]`).
    mass: [[f64; 6]; 6],
}

/// One fluid carrier of a lump.
struct Dragged {
    i: u32,
    /// `w_i`: the fraction of its neighbours in the body.
    w: f32,
    /// `r_i`: its arm from the centre of mass at the build.
    arm: Vector,
    /// The outward normal of the body's surface nearest to it (exact geometry: a ball's
    /// points at its centre, so moving with it does not turn a free-slip ball).
    n: Vector,
    /// `θ_i`: how much of the body's tangential motion it follows (no slip 1, free slip 0, the
    /// boundary layer and partial slip the share their wall shear moves in one substep,
    /// `Δt c / (1 + Δt c)`).
    theta: f32,
}

impl Dragged {
    /// `P = θ 𝟙 + (1 − θ) n nᵀ` applied to `v`: the part of the body's motion it follows.
    fn follow(&self, v: Vector) -> Vector {
        v * self.theta + self.n * (self.n.dot(v) * (1.0 - self.theta))
    }
}

impl FluidWorld {
    /// Gathers each moving dynamic body's lump from the current neighbour lists (none when no
    /// body moves), for a substep of `dt`. Deterministic: rows in fixed blocks, summed in
    /// block order.
    pub(crate) fn build_lumps(&mut self, bodies: &[BodyView], dt: f32) {
        self.lumps.clear();
        let nr = self.rigids.len();
        let nf = self.fluid.len();
        if bodies.iter().all(|b| b.rigid == u32::MAX) || self.lists.offsets.len() != nf + 1 {
            return;
        }
        let h = self.params.support_radius();
        let vol = self.mass / self.params.rest_density;
        let ctx = ctx!(self, bodies);
        let shapes = self.shapes();
        let x = &self.fluid.x;
        let parts: Vec<Vec<(u32, Dragged)>> = (0..nf.div_ceil(ROWS))
            .into_par_iter()
            .map(|c| {
                let mut out = Vec::new();
                // per rigid: neighbours, (nearest carrier, its distance²), no-slip
                // count, boundary-layer (count, Σc)
                let fresh = (0u32, (u32::MAX, f32::INFINITY), 0u32, 0u32, 0.0f32);
                let mut per = vec![fresh; nr];
                for i in c * ROWS..((c + 1) * ROWS).min(nf) {
                    let near = |p: Vector| (p - x[i]).length() < h;
                    let (mut any, mut solid) = (false, 0u32);
                    for &j in &ctx.lists.indices[ctx.lists.solid_range(i)] {
                        let sj = j as usize - nf;
                        if !near(ctx.solid_x[sj]) {
                            continue;
                        }
                        solid += 1;
                        let body = &bodies[ctx.solid_body[sj] as usize];
                        if body.rigid == u32::MAX {
                            continue;
                        }
                        let e = &mut per[body.rigid as usize];
                        e.0 += 1;
                        let d2 = (ctx.solid_x[sj] - x[i]).length_squared();
                        if d2 < e.1 .1 {
                            e.1 = (sj as u32, d2);
                        }
                        match body.slip {
                            Slip::NoSlip => e.2 += 1,
                            Slip::BoundaryLayer | Slip::Partial { .. } => {
                                e.3 += 1;
                                if let Some((_, c, _)) =
                                    forces::wall_shear(&ctx, x[i], Vector::ZERO, sj, h, vol)
                                {
                                    e.4 += c;
                                }
                            }
                            Slip::FreeSlip => {}
                        }
                        any = true;
                    }
                    if !any {
                        continue;
                    }
                    let fluid = ctx.lists.indices[ctx.lists.fluid_range(i)]
                        .iter()
                        .filter(|&&j| j as usize != i && near(x[j as usize]))
                        .count() as u32;
                    let all = (fluid + solid).max(1) as f32;
                    for (r, e) in per.iter_mut().enumerate() {
                        if e.0 == 0 {
                            continue;
                        }
                        let (k, (b, _), no_slip, bl, c) = *e;
                        let layer = dt * c / (1.0 + dt * c);
                        out.push((
                            r as u32,
                            Dragged {
                                i: i as u32,
                                w: k as f32 / all,
                                arm: Vector::ZERO,
                                // (a deformable body: the nearest carrier's normal)
                                n: outward(&shapes[ctx.solid_body[b as usize] as usize], x[i])
                                    .unwrap_or(ctx.solid_n[b as usize]),
                                theta: (no_slip as f32 + layer * bl as f32) / k as f32,
                            },
                        ));
                        *e = fresh;
                    }
                }
                out
            })
            .collect();
        self.lumps.resize_with(nr, Lump::default);
        let m = self.mass as f64;
        for (r, mut d) in parts.into_iter().flatten() {
            let lump = &mut self.lumps[r as usize];
            d.arm = x[d.i as usize] - self.rigids[r as usize].com;
            add_point_mass(&mut lump.mass, m * d.w as f64, &d);
            lump.carriers.push(d);
        }
    }

    /// The velocity change `(ΔU, Δω)` of rigid `ri` under the wrench `e` — with its lump when
    /// `shared` (and it has one), alone otherwise — and the wrench the body itself takes.
    pub(crate) fn rigid_response(
        &self,
        ri: usize,
        e: &[f64; 6],
        shared: bool,
    ) -> (Vector, Vector, [f64; 6]) {
        let r = &self.rigids[ri];
        let (im, ii) = (r.inv_mass(), r.inv_inertia());
        let k = |row: usize, v: &[f64; 6]| -> f64 {
            if row < 3 {
                im[row] as f64 * v[row]
            } else {
                (0..3).map(|c| ii.col(c)[row - 3] as f64 * v[3 + c]).sum()
            }
        };
        let lump = self
            .lumps
            .get(ri)
            .filter(|l| shared && !l.carriers.is_empty());
        let Some(lump) = lump else {
            let (j, l) = crate::rigid::split(e);
            let (du, dw) = r.response(j, l);
            return (du, dw, *e);
        };
        // (𝟙 + K S) Δq = K e
        let mut a = [[0.0f64; 7]; 6];
        for (row, a_row) in a.iter_mut().enumerate() {
            for (col, a_rc) in a_row.iter_mut().take(6).enumerate() {
                let s_col: [f64; 6] = std::array::from_fn(|q| lump.mass[q][col]);
                *a_rc = k(row, &s_col) + if row == col { 1.0 } else { 0.0 };
            }
            a_row[6] = k(row, e);
        }
        let dq = solve6(a);
        let mut kept = *e;
        for (row, kr) in kept.iter_mut().enumerate() {
            *kr -= (0..6).map(|c| lump.mass[row][c] * dq[c]).sum::<f64>();
        }
        let f = |o: usize| Vector::new(dq[o] as f32, dq[o + 1] as f32, dq[o + 2] as f32);
        (f(0), f(3), kept)
    }

    /// The density constraint's pressure carried hydrostatically from rigid `ri`'s lump to
    /// the height `at` along `up`: `Σ w_i (p^d_i + ρ̄|g| (up·x_i − at)) / Σ w_i` (Pa, at least 0),
    /// `None` without water beside the body.
    pub(crate) fn lump_pressure(&self, ri: usize, up: Vector, at: f32, rho_g: f32) -> Option<f32> {
        let lump = self.lumps.get(ri).filter(|l| !l.carriers.is_empty())?;
        let p = &self.fluid.p_density;
        let (mut sum, mut weight) = (0.0f64, 0.0f64);
        for d in &lump.carriers {
            let i = d.i as usize;
            let here = p.get(i).copied().unwrap_or(0.0) + rho_g * (up.dot(self.fluid.x[i]) - at);
            sum += (d.w * here) as f64;
            weight += d.w as f64;
        }
        (weight > 0.0).then(|| (sum / weight).max(0.0) as f32)
    }

    /// Whether the lumps still index the current fluid carriers (they are gathered in each
    /// substep's prediction; carriers added or removed since make them stale).
    pub(crate) fn lumps_current(&self) -> bool {
        let n = self.fluid.len() as u32;
        self.lumps
            .iter()
            .all(|l| l.carriers.iter().all(|d| d.i < n))
    }

    /// Gives rigid `ri`'s lump carriers their share `w_i (ΔU + Δω × r_i)`.
    pub(crate) fn move_lump(&mut self, ri: usize, du: Vector, dw: Vector) {
        self.move_lump_over(ri, du, dw, None);
    }

    /// [`Self::move_lump`], and when `over` is given the carriers' positions moved by that
    /// share over `over` seconds too (a change after the substep's positions were taken).
    pub(crate) fn move_lump_over(&mut self, ri: usize, du: Vector, dw: Vector, over: Option<f32>) {
        if let Some(lump) = self.lumps.get(ri) {
            for d in &lump.carriers {
                let i = d.i as usize;
                let dv = d.follow(du + dw.cross(d.arm)) * d.w;
                self.fluid.v[i] += dv;
                if let Some(dt) = over {
                    self.fluid.x[i] += dv * dt;
                }
            }
        }
    }

    /// Whether rigid `ri` has water beside it that moves with it.
    pub(crate) fn has_lump(&self, ri: usize) -> bool {
        self.lumps.get(ri).is_some_and(|l| !l.carriers.is_empty())
    }
}

/// The outward normal of a solid's shape at its pose at the surface point nearest to `p`.
fn outward(shape: &Option<(SharedShape, Pose)>, p: Vector) -> Option<Vector> {
    shape.as_ref().map(|(shape, pose)| {
        crate::sampling::outward_normal(shape.as_ref(), pose, p)
            .0
            .unwrap_or(Vector::ZERO)
    })
}

/// Adds carrier `d` of mass `m` to a lump's 6×6 mass: `m Jᵀ P J` with `J = [𝟙, −[r]×]` its
/// velocity per `[ΔU; Δω]` and `P` the part of it the carrier follows ([`Dragged::follow`]).
fn add_point_mass(s: &mut [[f64; 6]; 6], m: f64, d: &Dragged) {
    // column c of J: the carrier's velocity for a unit ΔU or Δω along axis c
    let col = |c: usize| -> Vector {
        let mut e = Vector::ZERO;
        e[c % 3] = 1.0;
        if c < 3 {
            e
        } else {
            e.cross(d.arm)
        }
    };
    let cols: [Vector; 6] = std::array::from_fn(col);
    for (a, ca) in cols.iter().enumerate() {
        for (b, cb) in cols.iter().enumerate() {
            s[a][b] += m * ca.dot(d.follow(*cb)) as f64;
        }
    }
}

/// Solves a 6×6 system given as its augmented matrix (Gaussian elimination, partial pivoting).
/// The matrix `𝟙 + K S` is `𝟙` plus a product of two positive semi-definite matrices, so its
/// eigenvalues are at least 1 and it is never singular.
fn solve6(mut a: [[f64; 7]; 6]) -> [f64; 6] {
    for c in 0..6 {
        let p = (c..6)
            .max_by(|&i, &j| a[i][c].abs().total_cmp(&a[j][c].abs()))
            .unwrap_or(c);
        a.swap(c, p);
        let (top, rest) = a.split_at_mut(c + 1);
        let pivot = &top[c];
        for row in rest.iter_mut() {
            let f = row[c] / pivot[c];
            for (x, p) in row[c..].iter_mut().zip(&pivot[c..]) {
                *x -= f * p;
            }
        }
    }
    let mut x = [0.0f64; 6];
    for c in (0..6).rev() {
        let s: f64 = (c + 1..6).map(|k| a[c][k] * x[k]).sum();
        x[c] = (a[c][6] - s) / a[c][c];
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_6x6_solve_inverts_a_rigid_lump() {
        // a unit point mass at (1, 0, 0) and a body of unit mass and inertia: pushing the body
        // along y at its centre moves the lump so that momentum and angular momentum add up
        let mut s = [[0.0; 6]; 6];
        let d = Dragged {
            i: 0,
            w: 1.0,
            arm: Vector::new(1.0, 0.0, 0.0),
            n: Vector::Y,
            theta: 1.0,
        };
        add_point_mass(&mut s, 1.0, &d);
        let mut a = [[0.0; 7]; 6];
        for r in 0..6 {
            for c in 0..6 {
                a[r][c] = s[r][c] + if r == c { 1.0 } else { 0.0 };
            }
        }
        a[1][6] = 1.0;
        let dq = solve6(a);
        // body: J = ΔU, L = Δω; point: J = ΔU + Δω × r, L = r × (ΔU + Δω × r)
        let (du, dw) = (
            Vector::new(dq[0] as f32, dq[1] as f32, dq[2] as f32),
            Vector::new(dq[3] as f32, dq[4] as f32, dq[5] as f32),
        );
        let r = Vector::new(1.0, 0.0, 0.0);
        let vp = du + dw.cross(r);
        let j = du + vp;
        let l = dw + r.cross(vp);
        assert!((j - Vector::new(0.0, 1.0, 0.0)).length() < 1e-6, "{j}");
        assert!(l.length() < 1e-6, "{l}");
        // the lump turns about its own centre: the body's centre moves more than the point
        assert!(du.y > vp.y && vp.y > 0.0);
    }
}

//! Stage: the water's pressure where a body touches a wall (issue 19: a body resting on the
//! floor under water).
//!
//! Where a dynamic body lies on a fixed or scripted solid no fluid carrier fits between them,
//! so no staggered pair carries the water's pressure onto the body's underside: a block of
//! density 800 placed on a tank's floor stayed there for good, held down by the water above
//! it. Here each outer carrier of a moving body whose face *touches* a fixed or scripted
//! solid (the point a spacing out along its normal lies inside it or within half a spacing of
//! it, the face looking at it) takes the push the missing water would give it: the pressure
//! of the water beside the body carried hydrostatically to its face (the density
//! constraint's p^d over the body's lump, [`FluidWorld::lump_pressure`], so it follows the
//! water's own pressure as it builds up) over one carrier's face `Δx²` projected on the wall,
//! times the share of a wetted face's push that its fluid neighbours do not give
//! (`1 − Σ|∇W| cos / Σ_wetted`, the density constraint's wall push measure): inner faces of
//! a contact take all of it, its edges (wetted from the side) about half. The impulse pushes
//! the body off the wall (that much along the wall's normal, directed along the body's exact
//! normal where it faces the wall), at the body's surface point nearest the wall side of the
//! carrier (so a ball's push passes through its centre), shared with the water beside the
//! body like every explicit stage; its reaction is booked on the solid the
//! body rests on. As water reaches the face the share falls to zero and the staggered pairs
//! take over. With `wall_support` the share counts the pushes' part along the wall's normal
//! (the water beside a box then pushes its bottom edges sideways), a face carrier's area is
//! taken where the body faces the wall (a box's edge carrier owns a full Δx² of its bottom),
//! and the pressure is at most the column of water over the body.

use super::Substep;
use crate::kernel::CubicSpline;
use crate::math::{Pose, Vector};
use crate::rigid;
use crate::solver::contact::PointImpulse;
use crate::solver::density;
use crate::world::FluidWorld;
use rapier3d::parry::shape::SharedShape;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

/// Fixed-point scale of the coverage sums.
const FIXED: f32 = 1.0e6;

/// `Σ W` over the fluid a face carrier (half a spacing deep) of a flat, fully wetted wall sees:
/// the lattice half-space from one spacing out.
fn wetted_coverage(kern: &CubicSpline, dx: f32) -> f32 {
    let n = (kern.support() / dx).ceil() as i32 + 1;
    let mut sum = 0.0;
    for a in -n..=n {
        for b in -n..=n {
            for k in 1..=n {
                let r = dx * ((a * a + b * b + k * k) as f32).sqrt();
                sum += kern.grad_mag(r) * k as f32 * dx / r;
            }
        }
    }
    sum
}

impl FluidWorld {
    /// Applies the contact pressure of every sealed face of the moving dynamic bodies over the
    /// substep; returns the number of sealed carriers.
    pub(crate) fn press_sealed_faces(&mut self, s: &Substep) -> usize {
        let g = s.gravity.length();
        if g <= 0.0 || !self.rigids.iter().any(|r| r.moving()) {
            return 0;
        }
        let up = -s.gravity / g;
        let dx = self.params.spacing;
        let nf = self.fluid.len();
        // outer carriers of moving bodies
        let faces: Vec<usize> = self
            .solids
            .iter()
            .filter(|sol| sol.rigid.is_some_and(|r| self.rigids[r].moving()))
            .flat_map(|sol| sol.range.clone())
            .filter(|&c| self.solid.depth.get(c).copied().unwrap_or(0.0) < dx)
            .collect();
        if faces.is_empty() {
            return 0;
        }
        // the faces against a fixed or scripted solid: (face, that solid, its outward normal)
        let shapes = self.shapes();
        let fixed: Vec<usize> = (0..self.solids.len())
            .filter(|&o| self.solids[o].rigid.is_none())
            .collect();
        let (sx, sn) = (&self.solid.x, &self.solid.n);
        let touching: Vec<(usize, usize, Vector)> = faces
            .par_iter()
            .filter_map(|&c| {
                let q = sx[c] + sn[c] * dx;
                fixed.iter().find_map(|&o| {
                    let (shape, pose) = shapes[o].as_ref()?;
                    let (m, phi) = crate::sampling::outward_normal(shape.as_ref(), pose, q);
                    if phi >= 0.5 * dx {
                        return None;
                    }
                    let m = m.unwrap_or(-sn[c]);
                    // the face must look at the wall, not run along it
                    (m.dot(sn[c]) < -0.1).then_some((c, o, m))
                })
            })
            .collect();
        if touching.is_empty() {
            return 0;
        }
        let mut slot = vec![u32::MAX; self.solid.len()];
        for (k, &(c, _, _)) in touching.iter().enumerate() {
            slot[c] = k as u32;
        }
        // each face's fluid coverage Σ W (fixed point: the same sum on any thread count)
        let cover: Vec<AtomicU64> = (0..touching.len()).map(|_| AtomicU64::new(0)).collect();
        let (x, lists, kern) = (&self.fluid.x, &self.lists, &self.kernel);
        let full = wetted_coverage(kern, dx);
        // with `wall_support` the density constraint pushes along the body's normal at the
        // fluid carrier: the coverage counts that push's part along the wall's normal
        let support = self.params.wall_support && !self.params.hydrostatic_walls;
        let body = &self.solid.body;
        (0..nf).into_par_iter().for_each(|i| {
            for &j in &lists.indices[lists.solid_range(i)] {
                let k = slot[j as usize - nf];
                if k != u32::MAX {
                    let (c, _, m) = touching[k as usize];
                    let d = x[i] - sx[c];
                    let r = d.length().max(1e-9);
                    let w = if support {
                        let n = shapes[body[c] as usize].as_ref().and_then(|(shape, pose)| {
                            crate::sampling::outward_normal(shape.as_ref(), pose, x[i]).0
                        });
                        let n = density::push_direction(n, sn[c]);
                        (d.dot(n) / r).max(0.0) * (-n.dot(m)).max(0.0)
                    } else {
                        (d.dot(sn[c]) / r).max(0.0)
                    };
                    let w = kern.grad_mag(r) * w / full;
                    cover[k as usize].fetch_add((w * FIXED) as u64, Ordering::Relaxed);
                }
            }
        });
        // (face, wall, its normal, the uncovered share of the face)
        let sealed: Vec<(usize, usize, Vector, f32)> = touching
            .iter()
            .zip(&cover)
            .map(|(&(c, o, m), w)| (c, o, m, 1.0 - w.load(Ordering::Relaxed) as f32 / FIXED))
            .filter(|t| t.3 > 0.0)
            .collect();
        let rho_g = self.params.rest_density * g;
        // with `wall_support`, at most the column of water over the body: water starting
        // from zero pressure (`hydrostatic_start: false`; the default before the thirtieth
        // session) overshoots in its first frames (p^d up to 1.5× hydrostatic), which threw
        // a 1 500 kg/m³ block off the floor once every face carried its full share
        let mut levels: Vec<Option<f32>> = vec![None; self.solids.len()];
        if support {
            let mut seen = vec![false; self.solids.len()];
            for &(c, ..) in &sealed {
                let b = self.solid.body[c] as usize;
                if !std::mem::replace(&mut seen[b], true) {
                    levels[b] = self.level_over(b, up);
                }
            }
        }
        let mut imp: Vec<PointImpulse> = Vec::with_capacity(sealed.len());
        for &(c, o, m, share) in &sealed {
            let b = self.solid.body[c] as usize;
            let Some(ri) = self.solids[b].rigid else {
                continue;
            };
            let face = self.solid.x[c] + self.solid.n[c] * (0.5 * dx);
            let Some(mut p) = self.lump_pressure(ri, up, up.dot(face), rho_g) else {
                continue;
            };
            if let Some(level) = levels[b] {
                p = p.min(rho_g * (level - up.dot(face)));
            }
            if p <= 0.0 {
                continue;
            }
            let (dir, area, at) = face_push(
                (self.solid.x[c], self.solid.n[c], face),
                m,
                shapes[b].as_ref(),
                support,
                dx,
            );
            let j = dir * (p * area * share * s.dt);
            imp.push((c as u32, j, at));
            let com = self.solids[o].com;
            let e = rigid::wrench(-j, at - com);
            for (a, b) in self.impulses[o].iter_mut().zip(e) {
                *a += b;
            }
        }
        let n = imp.len();
        self.absorb_at_points(&imp);
        n
    }
}

impl FluidWorld {
    /// The free surface's height (along `up`) over solid `b`: the highest fluid carrier within
    /// the solid's horizontal reach plus half a spacing, if any carrier is there.
    fn level_over(&self, b: usize, up: Vector) -> Option<f32> {
        let sol = &self.solids[b];
        let range = sol.range.clone();
        if range.is_empty() {
            return None;
        }
        let flat = |v: Vector| v - up * up.dot(v);
        let com = flat(sol.com);
        let reach = self.solid.x[range]
            .iter()
            .map(|&x| (flat(x) - com).length())
            .fold(0.0f32, f32::max);
        let top = self
            .fluid
            .x
            .par_iter()
            .filter(|&&x| (flat(x) - com).length() <= reach)
            .map(|&x| up.dot(x))
            .reduce(|| f32::NEG_INFINITY, f32::max);
        top.is_finite().then_some(top + 0.5 * self.params.spacing)
    }
}

/// The missing water's push on a face carrier at `x` with outward normal `n` and face point
/// `face` against a wall of outward normal `m`: its direction, the area the pressure acts
/// over and the point where it acts (`shape`: the body's exact geometry; none: `m` at `face`).
fn face_push(
    (x, n, face): (Vector, Vector, Vector),
    m: Vector,
    shape: Option<&(SharedShape, Pose)>,
    support: bool,
    dx: f32,
) -> (Vector, f32, Vector) {
    // the body's exact normal where it faces the wall (a spacing toward the wall)
    // and the body's surface point nearest it, where the push acts (on a ball the
    // push's line then passes through the centre; at the carrier's face point, half a
    // spacing out along its own normal, it had an arm about the centre)
    let below = x - m * dx;
    let (exact, at) = shape
        .and_then(|(shape, pose)| {
            crate::sampling::nearest_surface(shape.as_ref(), pose, below).map(|(f, q)| (Some(f), q))
        })
        .unwrap_or((None, face));
    let facing = match exact {
        Some(f) if support => f,
        _ => n,
    };
    // the part of the missing water's push along the wall's normal (the film's
    // pressure pushes body and wall apart): over the carrier's face projected on the
    // wall (a diagonal edge normal: 0.71; with `wall_support`, the body's normal where
    // it faces the wall: a box's edge carrier owns a full spacing² of its bottom)
    let area = dx * dx * (-m.dot(facing)).max(0.0);
    // and its direction, the body's exact normal where it faces the wall: on a curved
    // face (a ball against a wall) the push passes through the ball's centre (along
    // the wall's normal, the deeper faces' larger push turned a floating ball pressed
    // against a tank wall, 13 rad/s in 5 s); on a flat face, a box's bottom and its
    // edges, it is the wall's normal (a carrier's own diagonal normal at an edge
    // pushed along the wall: a wedge between a slab's walls braked on them)
    let dir = match exact {
        Some(f) if -m.dot(f) >= 0.5 => -f / -m.dot(f),
        _ => m,
    };
    (dir, area, at)
}

//! Relative volumes of the carriers of moving solids (Akinci et al. 2012 boundary volumes).

use super::{FluidWorld, SolidKind};
use crate::kernel::CubicSpline;
use crate::math::Vector;
use rapier3d::parry::shape::Shape;
use rayon::prelude::*;

impl FluidWorld {
    /// Sets the relative volumes ([`SolidCarriers::volume`]) of solid `k`'s carriers
    /// ([`relative_volumes`]). Static walls are sampled on the fluid lattice itself and keep 1.
    pub(crate) fn update_volumes(&mut self, k: usize) {
        let solid = &self.solids[k];
        if solid.kind == SolidKind::Static {
            return;
        }
        let local: Vec<Vector> = solid.local.iter().map(|l| l.0).collect();
        let vols = relative_volumes(
            solid.shape.as_ref(),
            &local,
            &self.kernel,
            self.params.spacing,
            self.params.support_radius(),
        );
        for (i, v) in solid.range.clone().zip(vols) {
            self.solid.volume[i] = v;
        }
    }
}

/// Relative volumes of a solid's carriers at `local` (body frame) in the shell of `shape`
/// `h` deep: the kernel sum that a cubic lattice of spacing `dx` would give over the shell
/// around each carrier, over the sum its actual neighbours in the shell give (Akinci et al.
/// 2012 boundary volumes, made relative so that any lattice-like sampling, flat, convex or at
/// an edge, has volume 1). Where the shell is packed more densely than the lattice (the outer
/// layer of a ball, moved to depth ½Δx) carriers weigh less.
pub fn relative_volumes(
    shape: &dyn Shape,
    local: &[Vector],
    kern: &CubicSpline,
    dx: f32,
    h: f32,
) -> Vec<f32> {
    let reach = (h / dx).ceil() as i32;
    let in_shell = |p: Vector| {
        let d = crate::sampling::signed_distance(shape, p);
        d <= 0.0 && d >= -h
    };
    let key = |p: Vector| {
        (
            (p.x / h).floor() as i32,
            (p.y / h).floor() as i32,
            (p.z / h).floor() as i32,
        )
    };
    let mut cells: std::collections::HashMap<(i32, i32, i32), Vec<usize>> =
        std::collections::HashMap::new();
    for (i, &p) in local.iter().enumerate() {
        cells.entry(key(p)).or_default().push(i);
    }
    local
        .par_iter()
        .map(|&p| {
            let mut lattice = 0.0;
            for a in -reach..=reach {
                for b in -reach..=reach {
                    for c in -reach..=reach {
                        let d = Vector::new(a as f32, b as f32, c as f32) * dx;
                        let r = d.length();
                        if r < h && in_shell(p + d) {
                            lattice += kern.w(r);
                        }
                    }
                }
            }
            let c = key(p);
            let mut actual = 0.0f32;
            for dz in -1..=1 {
                for dy in -1..=1 {
                    for dxc in -1..=1 {
                        for &j in cells
                            .get(&(c.0 + dxc, c.1 + dy, c.2 + dz))
                            .into_iter()
                            .flatten()
                        {
                            let r = (local[j] - p).length();
                            if r < h {
                                actual += kern.w(r);
                            }
                        }
                    }
                }
            }
            (lattice / actual.max(1e-12)).clamp(0.25, 4.0)
        })
        .collect()
}

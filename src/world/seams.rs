//! Solid carriers whose normal is not their own shape's: at a seam of a union of static solids
//! (a wall standing on a floor), and midway through a part thinner than the support (issue 19).

use super::{FluidWorld, Solid, SolidKind};
use crate::math::{Pose, Vector};
use crate::sampling::ShellSample;
use rapier3d::parry::shape::Shape;

impl FluidWorld {
    /// A static solid's carrier whose normal points into an earlier static solid sits at a
    /// seam of the union, where its own normal is an internal face's: it takes the union's
    /// normal (central differences of the least signed distance over the static solids a
    /// spacing either side, across the seam), or, where the union has no direction there
    /// either (the foot of a wall one spacing thick), it is marked two-sided and the step
    /// points it at the fluid.
    pub(crate) fn seam_normals(&self, shape: &dyn Shape, pose: &Pose, samples: &mut [ShellSample]) {
        let dx = self.params.spacing;
        let statics: Vec<&Solid> = self
            .solids
            .iter()
            .filter(|o| o.kind == SolidKind::Static && !o.removed)
            .collect();
        let union = |w: Vector| {
            statics.iter().fold(
                crate::sampling::signed_distance(shape, pose.inverse_transform_point(w)),
                |d, o| {
                    d.min(crate::sampling::signed_distance(
                        o.shape.as_ref(),
                        o.pose.inverse_transform_point(w),
                    ))
                },
            )
        };
        for s in samples.iter_mut() {
            let x = pose.transform_point(s.x);
            let inward = x + pose.rotation * s.n * dx;
            if !statics
                .iter()
                .any(|o| crate::sampling::contains(o.shape.as_ref(), &o.pose, inward))
            {
                continue;
            }
            let g = Vector::new(
                union(x + Vector::X * dx) - union(x - Vector::X * dx),
                union(x + Vector::Y * dx) - union(x - Vector::Y * dx),
                union(x + Vector::Z * dx) - union(x - Vector::Z * dx),
            );
            match (g.length() > 0.1 * dx).then(|| g.try_normalize()).flatten() {
                Some(n) => s.n = pose.rotation.inverse() * n,
                None => s.two_sided = true,
            }
        }
    }
}

/// Indices of the two-sided carriers among `samples`.
pub(crate) fn two_sided_of(samples: &[ShellSample]) -> Vec<u32> {
    (0..samples.len() as u32)
        .filter(|&i| samples[i as usize].two_sided)
        .collect()
}

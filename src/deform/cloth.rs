//! Cloth (Shao et al. 2014 §3.4.1, last paragraph, after Stumpp et al. 2008's cluster shape
//! matching): one layer of lattice points on a regular quad mesh, each both an IBP (shape
//! matching over overlapping two-dimensional regions moves it) and an SBP (a solid carrier
//! the fluid sees). Fluid may lie on either side: each carrier's normal is turned toward the
//! fluid beside it every substep (Shao's carrier direction in place of a surface normal), and
//! the penetration correction keeps fluid out of the cell around each point.

use super::body::{DeformableHandle, DeformableParams};
use crate::error::{FluidError, Result};
use crate::kernel::CubicSpline;
use crate::limits::{check_count, MAX_PARTICLES};
use crate::math::{Pose, Vector};
use crate::sampling::ShellSample;
use crate::world::{FluidWorld, SolidKind};
use rapier3d::parry::shape::SharedShape;

impl FluidWorld {
    /// Adds a cloth: a `size[0] × size[1]` m rectangle in the plane y = 0 of `pose` (its
    /// local x and z), one layer of points at the fluid spacing, at rest. `params.density` is
    /// that of a sheet one spacing thick (a point weighs `density Δx³`); `half_width` sets how
    /// far its regions reach (wider resists bending more) and `stiffness` how firmly they pull.
    /// Pin its edges with [`Self::pin_deformable`]. Fails, adding nothing, on bad parameters,
    /// a melting material, a side shorter than a spacing, too many points, or fluid inside it.
    ///
    /// ```
    /// use staggered_fluid::prelude::*;
    /// use staggered_fluid::deform::DeformableParams;
    ///
    /// let mut world = FluidWorld::new(FluidParams { spacing: 0.025, ..Default::default() })?;
    /// world.add_open_tank(Vector::ZERO, Vector::new(0.5, 0.6, 0.5), Slip::FreeSlip)?;
    /// let pose = Pose::from_translation(Vector::new(0.25, 0.3, 0.25));
    /// let soft = DeformableParams { density: 300.0, stiffness: 0.5, half_width: 1, ..Default::default() };
    /// let cloth = world.add_cloth("sheet", pose, [0.4, 0.4], soft)?;
    /// // held at its edges
    /// let pinned = world.pin_deformable(cloth, |p| (p.x - 0.25).abs() > 0.19 || (p.z - 0.25).abs() > 0.19)?;
    /// assert_eq!(pinned, 17 * 17 - 15 * 15);
    /// # Ok::<(), FluidError>(())
    /// ```
    pub fn add_cloth(
        &mut self,
        name: impl Into<String>,
        pose: Pose,
        size: [f32; 2],
        params: DeformableParams,
    ) -> Result<DeformableHandle> {
        params.validate()?;
        let name = name.into();
        if params.melting.is_some() {
            return Err(FluidError::Coupling(format!(
                "cloth `{name}` cannot melt: give melting bodies a volume (add_deformable)"
            )));
        }
        if !pose.is_finite() {
            return Err(FluidError::NonFinite {
                what: format!("pose of cloth `{name}`"),
            });
        }
        let dx = self.params.spacing;
        for (k, side) in size.iter().enumerate() {
            if !(side.is_finite() && *side >= dx) {
                return Err(FluidError::OutOfRange {
                    name: if k == 0 {
                        "cloth size[0]"
                    } else {
                        "cloth size[1]"
                    },
                    value: *side as f64,
                    range: ">= the spacing",
                });
            }
        }
        let n = size.map(|s| (s / dx).floor() as f64 + 1.0);
        check_count("points of a cloth", n[0] * n[1], MAX_PARTICLES)?;
        let n = n.map(|v| v as usize);
        let (mut rest, mut cells) = (Vec::new(), Vec::new());
        for k in 0..n[1] {
            for i in 0..n[0] {
                let at = |j: usize, m: usize| (j as f32 - 0.5 * (m - 1) as f32) * dx;
                rest.push(Vector::new(at(i, n[0]), 0.0, at(k, n[1])));
                cells.push([i as i32, 0, k as i32]);
            }
        }
        let samples: Vec<ShellSample> = rest
            .iter()
            .map(|&x| ShellSample {
                x,
                n: Vector::Y,
                phi: -0.5 * dx,
                two_sided: true,
            })
            .collect();
        let half = Vector::new(0.5 * size[0], 0.5 * dx, 0.5 * size[1]);
        let shape = SharedShape::cuboid(half.x, half.y, half.z);
        let h = self.add_samples(
            name.clone(),
            shape,
            pose,
            params.slip,
            SolidKind::Deformable,
            samples,
            &|_, n| n,
        )?;
        let volume = sheet_volume(&self.kernel, dx);
        let mass = params.density * dx * dx * dx;
        Ok(self.install(
            name,
            pose,
            params,
            (rest, cells),
            h,
            Some(volume),
            mass,
            true,
        ))
    }
}

/// The relative volume of a carrier in a sheet one layer thick: what a wall's shell (two
/// layers, `Δx` apart) gives the kernel sum at its first layer over what the sheet's one
/// layer gives, so that water on either side sees it as it sees a wall.
fn sheet_volume(kernel: &CubicSpline, dx: f32) -> f32 {
    let reach = (kernel.support() / dx).ceil() as i32;
    let (mut own, mut next) = (0.0f64, 0.0f64);
    for a in -reach..=reach {
        for b in -reach..=reach {
            let d = Vector::new(a as f32, 0.0, b as f32) * dx;
            own += kernel.w(d.length()) as f64;
            next += kernel.w((d + Vector::Y * dx).length()) as f64;
        }
    }
    ((own + next) / own) as f32
}

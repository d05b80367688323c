//! Water surface meshes (marching cubes over an SPH density field, by splashsurf_lib), behind
//! the `surface` feature because it costs build and run time.

use crate::error::{FluidError, Result};
use crate::world::FluidWorld;
use splashsurf_lib::nalgebra::Vector3;
use std::io::Write;
use std::path::Path;

/// A triangle mesh: vertices and triangles (indices into the vertices).
pub struct SurfaceMesh {
    /// Vertex positions, m.
    pub vertices: Vec<[f32; 3]>,
    /// Triangles, counter-clockwise seen from outside the water.
    pub triangles: Vec<[usize; 3]>,
}

/// Reconstructs the water surface of `world`'s fluid carriers. The particle radius is that
/// of a sphere of the carrier's volume Δx³, the kernel support 4 radii and the marching-cubes
/// cell 0.5 radii (splashsurf's usual settings), the iso-surface at 0.6 of the rest density.
pub fn reconstruct(world: &FluidWorld) -> Result<SurfaceMesh> {
    let dx = world.params().spacing;
    let r = dx * (3.0 / (4.0 * std::f32::consts::PI)).cbrt();
    let mut params = splashsurf_lib::Parameters::new(r, 4.0 * r, 0.5 * r);
    params.rest_density = world.params().rest_density;
    let pts: Vec<Vector3<f32>> = world
        .fluid()
        .x
        .iter()
        .map(|p| Vector3::new(p.x, p.y, p.z))
        .collect();
    let rec = splashsurf_lib::reconstruct_surface::<i64, f32>(&pts, &params).map_err(|e| {
        FluidError::Io {
            path: "surface reconstruction".into(),
            message: e.to_string(),
        }
    })?;
    Ok(SurfaceMesh {
        vertices: rec.mesh.vertices.iter().map(|v| [v.x, v.y, v.z]).collect(),
        triangles: rec.mesh.triangles,
    })
}

impl SurfaceMesh {
    /// Writes Wavefront OBJ.
    pub fn write_obj(&self, path: &Path) -> Result<()> {
        let err = |e: std::io::Error| FluidError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        };
        let mut f = std::io::BufWriter::new(std::fs::File::create(path).map_err(err)?);
        writeln!(f, "# staggered-fluid water surface").map_err(err)?;
        for v in &self.vertices {
            writeln!(f, "v {} {} {}", v[0], v[1], v[2]).map_err(err)?;
        }
        for t in &self.triangles {
            writeln!(f, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1).map_err(err)?;
        }
        f.flush().map_err(err)
    }

    /// Enclosed volume (divergence theorem), m³: the water's volume when the mesh is closed.
    pub fn volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i].map(f64::from));
                let cross = [
                    b[1] * c[2] - b[2] * c[1],
                    b[2] * c[0] - b[0] * c[2],
                    b[0] * c[1] - b[1] * c[0],
                ];
                (a[0] * cross[0] + a[1] * cross[1] + a[2] * cross[2]) / 6.0
            })
            .sum()
    }
}

/// Reconstructs the surface of `world` and writes it to `path` as OBJ.
pub fn write_obj(world: &FluidWorld, path: &Path) -> Result<()> {
    reconstruct(world)?.write_obj(path)
}

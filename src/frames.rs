//! Frames people can open, written from any [`FluidWorld`] (a program of your own) or a
//! [`Scene`]: fluid carriers as point clouds with velocity, pressure, density, the
//! free-surface flag and the stable id, in zlib-compressed binary VTK PolyData (`.vtp`,
//! ParaView, written by vtkio) indexed by a `.pvd` time series (ParaView shows simulated
//! seconds), and binary PLY (Blender, written by ply-rs-bw); the moving solids' carriers
//! likewise, the static walls once, tracked rapier bodies' poses in one CSV, and (by choice)
//! PNG previews ([`crate::preview`]) and water surface meshes (feature `surface`).
//!
//! ```
//! use staggered_fluid::frames::{FrameFormats, FrameWriter};
//! use staggered_fluid::prelude::*;
//! let mut world = FluidWorld::new(FluidParams { spacing: 0.05, ..Default::default() })?;
//! world.add_open_tank(Vector::ZERO, Vector::new(0.5, 0.5, 0.5), Slip::FreeSlip)?;
//! world.add_block(Vector::ZERO, Vector::new(0.25, 0.4, 0.5), Vector::ZERO)?;
//! let dir = std::env::temp_dir().join("staggered_fluid_frames_doc");
//! let formats = FrameFormats { ply: false, ..FrameFormats::default() };
//! let mut frames = FrameWriter::new(&dir, formats)?;
//! for _ in 0..3 {
//!     world.step(Vector::new(0.0, -9.81, 0.0), 0.01)?;
//!     frames.write_world(&world, None)?;
//! }
//! assert!(dir.join("fluid_00002.vtp").exists() && dir.join("walls.vtp").exists());
//! let series = std::fs::read_to_string(dir.join("fluid.pvd")).unwrap();
//! assert!(series.contains(r#"timestep="0.03""#) && series.contains("fluid_00002.vtp"));
//! # std::fs::remove_dir_all(&dir).ok();
//! # Ok::<(), FluidError>(())
//! ```

use crate::error::{FluidError, Result};
use crate::math::Vector;
use crate::preview::{self, PreviewOptions};
use crate::scenes::Scene;
use crate::world::{FluidWorld, SolidKind};
use ply_rs_bw::ply::{
    Addable, DefaultElement, ElementDef, Encoding, Ply, Property, PropertyDef, PropertyType,
    ScalarType,
};
use rapier3d::dynamics::{RigidBodyHandle, RigidBodySet};
use std::io::Write;
use std::path::{Path, PathBuf};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, DataArray, DataSet, ElementType, IOBuffer, PolyDataPiece,
    Version, VertexNumbers, Vtk,
};
use vtkio::xml::Compressor;

/// One named per-point field of a frame.
pub enum Field {
    /// One value per point.
    Scalar(&'static str, Vec<f32>),
    /// Three values per point.
    Vector(&'static str, Vec<[f32; 3]>),
    /// One unsigned integer per point (ids, flags, indices): `UInt32` in VTK, `uint` in PLY.
    Int(&'static str, Vec<u32>),
}

/// A point cloud with named fields (what one frame file holds).
pub struct PointCloud {
    /// Positions.
    pub points: Vec<[f32; 3]>,
    /// Per-point fields.
    pub fields: Vec<Field>,
}

/// zlib level of the `.vtp` payload (6: zlib's default balance; the five-ball frames shrink to
/// about a third).
const VTK_COMPRESSION: u32 = 6;

fn io_err(path: &Path, e: impl std::fmt::Display) -> FluidError {
    FluidError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

impl PointCloud {
    /// The fluid carriers of `world`: velocity (m/s), pressure `p^d + p^v`, p^d and p^v (Pa),
    /// density (kg/m³), the free-surface flag (1/0) and the stable id.
    pub fn fluid(world: &FluidWorld) -> Self {
        let f = world.fluid();
        let arr = |v: &Vector| [v.x, v.y, v.z];
        PointCloud {
            points: f.x.iter().map(arr).collect(),
            fields: vec![
                Field::Vector("velocity", f.v.iter().map(arr).collect()),
                Field::Scalar(
                    "pressure",
                    f.p_density
                        .iter()
                        .zip(&f.p_velocity)
                        .map(|(a, b)| a + b)
                        .collect(),
                ),
                Field::Scalar("p_density", f.p_density.clone()),
                Field::Scalar("p_velocity", f.p_velocity.clone()),
                Field::Scalar("density", f.density.clone()),
                Field::Int("surface", f.surface.iter().map(|&s| s as u32).collect()),
                Field::Int("id", f.id.clone()),
            ],
        }
    }

    /// The solid carriers of `world` that belong to moving solids (`moving = true`) or to
    /// static ones: velocity (m/s), outward normal, fluid force (N) and solid index.
    pub fn solids(world: &FluidWorld, moving: bool) -> Self {
        let s = world.solid_carriers();
        let solids = world.solids();
        let arr = |v: &Vector| [v.x, v.y, v.z];
        let pick: Vec<usize> = (0..s.len())
            .filter(|&i| (solids[s.body[i] as usize].kind != SolidKind::Static) == moving)
            .collect();
        let zero = Vector::ZERO;
        PointCloud {
            points: pick.iter().map(|&i| arr(&s.x[i])).collect(),
            fields: vec![
                Field::Vector("velocity", pick.iter().map(|&i| arr(&s.u[i])).collect()),
                Field::Vector("normal", pick.iter().map(|&i| arr(&s.n[i])).collect()),
                Field::Vector(
                    "force",
                    pick.iter()
                        .map(|&i| arr(s.f.get(i).unwrap_or(&zero)))
                        .collect(),
                ),
                Field::Int("solid", pick.iter().map(|&i| s.body[i]).collect()),
            ],
        }
    }

    /// Writes VTK XML PolyData (`.vtp`): points as vertices, fields as point data, binary
    /// and zlib-compressed.
    pub fn write_vtp(&self, path: &Path) -> Result<()> {
        let n = self.points.len() as u64;
        let point = self
            .fields
            .iter()
            .map(|f| {
                let (name, elem, data) = match f {
                    Field::Scalar(name, v) => (name, scalars(), IOBuffer::F32(v.clone())),
                    Field::Vector(name, v) => (
                        name,
                        ElementType::Vectors,
                        IOBuffer::F32(v.iter().flatten().copied().collect()),
                    ),
                    Field::Int(name, v) => (name, scalars(), IOBuffer::U32(v.clone())),
                };
                Attribute::DataArray(DataArray {
                    name: name.to_string(),
                    elem,
                    data,
                })
            })
            .collect();
        let vtk = Vtk {
            version: Version::new_xml(1, 0),
            title: String::from("staggered-fluid frame"),
            byte_order: ByteOrder::LittleEndian,
            file_path: None,
            data: DataSet::inline(PolyDataPiece {
                points: IOBuffer::F32(self.points.iter().flatten().copied().collect()),
                verts: Some(VertexNumbers::XML {
                    connectivity: (0..n).collect(),
                    offsets: (1..=n).collect(),
                }),
                lines: None,
                polys: None,
                strips: None,
                data: Attributes {
                    point,
                    cell: Vec::new(),
                },
            }),
        };
        vtk.try_into_xml_format(Compressor::ZLib, VTK_COMPRESSION)
            .and_then(|xml| xml.export(path))
            .map_err(|e| io_err(path, e))
    }

    /// Writes binary little-endian PLY: `x y z` and one property per scalar and per vector
    /// component (`velocity_x` …), `float` for real fields and `uint` for integer ones.
    pub fn write_ply(&self, path: &Path) -> Result<()> {
        let mut ply = Ply::<DefaultElement>::new();
        ply.header.encoding = Encoding::BinaryLittleEndian;
        ply.header
            .comments
            .push("staggered-fluid frame".to_string());
        let mut names: Vec<(String, ScalarType)> = ["x", "y", "z"]
            .iter()
            .map(|c| (c.to_string(), ScalarType::Float))
            .collect();
        for f in &self.fields {
            match f {
                Field::Scalar(name, _) => names.push((name.to_string(), ScalarType::Float)),
                Field::Int(name, _) => names.push((name.to_string(), ScalarType::UInt)),
                Field::Vector(name, _) => {
                    for c in ["x", "y", "z"] {
                        names.push((format!("{name}_{c}"), ScalarType::Float));
                    }
                }
            }
        }
        let mut def = ElementDef::new("vertex".to_string());
        for (name, ty) in &names {
            def.properties.add(PropertyDef::new(
                name.clone(),
                PropertyType::Scalar(ty.clone()),
            ));
        }
        ply.header.elements.add(def);
        let file = std::fs::File::create(path).map_err(|e| io_err(path, e))?;
        let mut out = std::io::BufWriter::new(file);
        let writer = ply_rs_bw::writer::Writer::<DefaultElement>::new();
        ply.header.elements["vertex"].count = self.points.len();
        writer
            .write_header(&mut out, &ply.header)
            .map_err(|e| io_err(path, e))?;
        // one reused element, streamed: a whole payload of maps cost ≈ 400 B per point
        let def = &ply.header.elements["vertex"];
        let mut e = DefaultElement::new();
        let mut values = Vec::with_capacity(names.len());
        for (i, p) in self.points.iter().enumerate() {
            values.clear();
            values.extend(p.iter().map(|&v| Property::Float(v)));
            for f in &self.fields {
                match f {
                    Field::Scalar(_, v) => values.push(Property::Float(v[i])),
                    Field::Int(_, v) => values.push(Property::UInt(v[i])),
                    Field::Vector(_, v) => values.extend(v[i].iter().map(|&c| Property::Float(c))),
                }
            }
            for ((name, _), v) in names.iter().zip(values.drain(..)) {
                match e.get_mut(name) {
                    Some(slot) => *slot = v,
                    None => {
                        e.insert(name.clone(), v);
                    }
                }
            }
            writer
                .write_little_endian_element(&mut out, &e, def)
                .map_err(|e| io_err(path, e))?;
        }
        out.flush().map_err(|e| io_err(path, e))
    }
}

/// A single-component VTK data array.
fn scalars() -> ElementType {
    ElementType::Scalars {
        num_comp: 1,
        lookup_table: None,
    }
}

/// Which files each frame of a [`FrameWriter`] produces.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameFormats {
    /// Compressed VTK PolyData (`.vtp`) with `.pvd` time series (ParaView).
    pub vtk: bool,
    /// Binary PLY (Blender).
    pub ply: bool,
    /// A PNG preview per frame ([`crate::preview`]).
    pub png: bool,
    /// A water surface mesh per frame (OBJ; needs the `surface` feature, else skipped).
    pub surface: bool,
}

impl Default for FrameFormats {
    /// VTK and PNG: what ParaView and a quick look need (PLY and surfaces by choice).
    fn default() -> Self {
        Self {
            vtk: true,
            ply: false,
            png: true,
            surface: false,
        }
    }
}

impl FrameFormats {
    /// Formats named in a comma-separated list (`vtk,ply,png,surface`; `none` for none).
    ///
    /// ```
    /// use staggered_fluid::frames::FrameFormats;
    /// let f = FrameFormats::parse("vtk, png").unwrap();
    /// assert!(f.vtk && f.png && !f.ply && !f.surface);
    /// assert!(FrameFormats::parse("vtk,obj").is_err());
    /// ```
    pub fn parse(list: &str) -> Result<Self> {
        let mut f = Self {
            vtk: false,
            ply: false,
            png: false,
            surface: false,
        };
        for name in list.split(',').map(str::trim).filter(|s| !s.is_empty()) {
            match name {
                "vtk" | "vtp" => f.vtk = true,
                "ply" => f.ply = true,
                "png" => f.png = true,
                "surface" => f.surface = true,
                "none" => {}
                other => {
                    return Err(FluidError::BadParams(format!(
                        "unknown frame format `{other}` (vtk, ply, png, surface or none)"
                    )))
                }
            }
        }
        Ok(f)
    }
}

/// Rapier bodies whose poses go into `bodies.csv`: the set and the named handles.
pub type TrackedBodies<'a> = (&'a RigidBodySet, &'a [(String, RigidBodyHandle)]);

/// Writes a run's frames into a directory: `fluid_NNNNN.vtp/.ply` indexed by `fluid.pvd`,
/// the moving solids' carriers `solid_NNNNN.vtp/.ply` (`solid.pvd`), the static walls once
/// (`walls.vtp/.ply`), `preview_NNNNN.png`, `surface_NNNNN.obj`, and `bodies.csv` (one row per
/// tracked body per frame), as its [`FrameFormats`] say.
pub struct FrameWriter {
    dir: PathBuf,
    formats: FrameFormats,
    preview: PreviewOptions,
    frame: usize,
    /// Simulated time of every frame written (the `.pvd` series).
    times: Vec<f64>,
    /// Frames that had moving solids (the solid series).
    solid_frames: Vec<usize>,
    bodies: Option<std::io::BufWriter<std::fs::File>>,
}

impl FrameWriter {
    /// Creates `dir` (and parents) and the body-pose CSV.
    pub fn new(dir: &Path, formats: FrameFormats) -> Result<Self> {
        std::fs::create_dir_all(dir).map_err(|e| io_err(dir, e))?;
        let path = dir.join("bodies.csv");
        let mut f =
            std::io::BufWriter::new(std::fs::File::create(&path).map_err(|e| io_err(&path, e))?);
        writeln!(f, "frame,t,body,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz")
            .map_err(|e| io_err(&path, e))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            formats,
            preview: PreviewOptions::default(),
            frame: 0,
            times: Vec::new(),
            solid_frames: Vec::new(),
            bodies: Some(f),
        })
    }

    /// The same writer drawing its PNG previews with `preview` (view, colours, size).
    pub fn with_preview(mut self, preview: PreviewOptions) -> Self {
        self.preview = preview;
        self
    }

    /// Frames written so far.
    pub fn frames(&self) -> usize {
        self.frame
    }

    /// Path of frame `k`'s file `kind` (`fluid`, `solid`, `preview`, `surface`) with `ext`.
    pub fn path(&self, kind: &str, k: usize, ext: &str) -> PathBuf {
        self.dir.join(format!("{kind}_{k:05}.{ext}"))
    }

    /// Writes the next frame of `scene` (its world, its tracked rapier bodies, its name on the
    /// preview); returns the frame's index.
    pub fn write(&mut self, scene: &Scene) -> Result<usize> {
        if self.preview.title.is_empty() {
            self.preview.title = scene.name.clone();
        }
        let bodies = scene
            .physics
            .as_ref()
            .map(|ph| (&ph.bodies, scene.tracked.as_slice()));
        self.write_world(&scene.world, bodies)
    }

    /// Writes the next frame of `world`, with the poses of `bodies` (a rapier body set and the
    /// named handles to record) if given; returns the frame's index.
    pub fn write_world(
        &mut self,
        world: &FluidWorld,
        bodies: Option<TrackedBodies>,
    ) -> Result<usize> {
        let k = self.frame;
        let mut clouds = vec![(PointCloud::fluid(world), format!("fluid_{k:05}"))];
        let moving = PointCloud::solids(world, true);
        if !moving.points.is_empty() {
            clouds.push((moving, format!("solid_{k:05}")));
            self.solid_frames.push(k);
        }
        if k == 0 {
            clouds.push((PointCloud::solids(world, false), "walls".to_string()));
        }
        for (cloud, name) in &clouds {
            if self.formats.vtk {
                cloud.write_vtp(&self.dir.join(format!("{name}.vtp")))?;
            }
            if self.formats.ply {
                cloud.write_ply(&self.dir.join(format!("{name}.ply")))?;
            }
        }
        self.times.push(world.time());
        if self.formats.vtk {
            self.write_series("fluid", &(0..=k).collect::<Vec<_>>())?;
            if !self.solid_frames.is_empty() {
                self.write_series("solid", &self.solid_frames.clone())?;
            }
        }
        if self.formats.png {
            preview::write_preview(world, &self.path("preview", k, "png"), &self.preview)?;
        }
        if self.formats.surface {
            surface_frame(world, &self.path("surface", k, "obj"))?;
        }
        if let (Some(out), Some((set, tracked))) = (self.bodies.as_mut(), bodies) {
            let path = self.dir.join("bodies.csv");
            for (name, h) in tracked {
                let Some(rb) = set.get(*h) else {
                    continue;
                };
                let (p, q, v, w) = (rb.translation(), rb.rotation(), rb.linvel(), rb.angvel());
                writeln!(
                    out,
                    "{k},{},{name},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                    world.time(),
                    p.x,
                    p.y,
                    p.z,
                    q.x,
                    q.y,
                    q.z,
                    q.w,
                    v.x,
                    v.y,
                    v.z,
                    w.x,
                    w.y,
                    w.z
                )
                .map_err(|e| io_err(&path, e))?;
            }
            out.flush().map_err(|e| io_err(&path, e))?;
        }
        self.frame += 1;
        Ok(k)
    }

    /// Rewrites `{kind}.pvd`, ParaView's time series of the frames `frames` of `kind`, so a
    /// run stopped early still opens with its simulated times.
    fn write_series(&self, kind: &str, frames: &[usize]) -> Result<()> {
        let path = self.dir.join(format!("{kind}.pvd"));
        let mut text = String::from(
            "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n",
        );
        for &k in frames {
            text += &format!(
                "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{kind}_{k:05}.vtp\"/>\n",
                seconds(self.times[k])
            );
        }
        text += "  </Collection>\n</VTKFile>\n";
        std::fs::write(&path, text).map_err(|e| io_err(&path, e))
    }
}

/// A simulated time to the microsecond, without the noise of summed f32 steps (`0.034`, not
/// `0.034000001614913344`).
fn seconds(t: f64) -> String {
    let s = format!("{t:.6}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s.is_empty() || s == "-" {
        "0".into()
    } else {
        s.into()
    }
}

#[cfg(feature = "surface")]
fn surface_frame(world: &FluidWorld, path: &Path) -> Result<()> {
    crate::surface::write_obj(world, path)
}

#[cfg(not(feature = "surface"))]
fn surface_frame(_: &FluidWorld, _: &Path) -> Result<()> {
    Ok(())
}

//! Frames people can open: fluid carriers as point clouds with velocity, pressure, density and
//! the free-surface flag, in VTK PolyData (`.vtp`, ParaView, written by vtkio) and PLY
//! (Blender, written by ply-rs-bw); solid carriers likewise, and the tracked bodies' poses in
//! one CSV per run.
//!
//! ```
//! use staggered_fluid::{frames::FrameWriter, scenes};
//! let scene = scenes::hydrostatic(0.2, 0.1, 0.05, Default::default()).unwrap();
//! let dir = std::env::temp_dir().join("staggered_fluid_frames_doc");
//! let mut frames = FrameWriter::new(&dir, true, true).unwrap();
//! assert_eq!(frames.write(&scene).unwrap(), 0);
//! assert!(dir.join("fluid_00000.vtp").exists() && dir.join("walls.ply").exists());
//! # std::fs::remove_dir_all(&dir).ok();
//! ```

use crate::error::{FluidError, Result};
use crate::math::Vector;
use crate::scenes::Scene;
use crate::world::SolidKind;
use ply_rs_bw::ply::{
    Addable, DefaultElement, ElementDef, Encoding, Ply, Property, PropertyDef, PropertyType,
    ScalarType,
};
use std::io::Write;
use std::path::{Path, PathBuf};
use vtkio::model::{
    Attribute, Attributes, ByteOrder, DataArray, DataSet, ElementType, IOBuffer, PolyDataPiece,
    Version, VertexNumbers, Vtk,
};

/// One named per-point field of a frame.
pub enum Field {
    /// One value per point.
    Scalar(&'static str, Vec<f32>),
    /// Three values per point.
    Vector(&'static str, Vec<[f32; 3]>),
}

/// A point cloud with named fields (what one frame file holds).
pub struct PointCloud {
    /// Positions.
    pub points: Vec<[f32; 3]>,
    /// Per-point fields.
    pub fields: Vec<Field>,
}

fn io_err(path: &Path, e: impl std::fmt::Display) -> FluidError {
    FluidError::Io {
        path: path.display().to_string(),
        message: e.to_string(),
    }
}

impl PointCloud {
    /// The fluid carriers of `scene`: velocity, pressure `p^d + p^v`, p^d, p^v, density,
    /// free-surface flag (1/0) and stable id.
    pub fn fluid(scene: &Scene) -> Self {
        let f = scene.world.fluid();
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
                Field::Scalar(
                    "surface",
                    f.surface.iter().map(|s| *s as u8 as f32).collect(),
                ),
                Field::Scalar("id", f.id.iter().map(|i| *i as f32).collect()),
            ],
        }
    }

    /// The solid carriers of `scene` that belong to moving solids (`moving = true`) or to
    /// static ones: velocity, outward normal, fluid force and solid index.
    pub fn solids(scene: &Scene, moving: bool) -> Self {
        let s = scene.world.solid_carriers();
        let solids = scene.world.solids();
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
                Field::Scalar("solid", pick.iter().map(|&i| s.body[i] as f32).collect()),
            ],
        }
    }

    /// Writes VTK XML PolyData (`.vtp`): points as vertices, fields as point data.
    pub fn write_vtp(&self, path: &Path) -> Result<()> {
        let n = self.points.len() as u64;
        let point = self
            .fields
            .iter()
            .map(|f| {
                let (name, elem, data): (&str, _, Vec<f32>) = match f {
                    Field::Scalar(name, v) => (
                        name,
                        ElementType::Scalars {
                            num_comp: 1,
                            lookup_table: None,
                        },
                        v.clone(),
                    ),
                    Field::Vector(name, v) => (
                        name,
                        ElementType::Vectors,
                        v.iter().flatten().copied().collect(),
                    ),
                };
                Attribute::DataArray(DataArray {
                    name: name.to_string(),
                    elem,
                    data: IOBuffer::F32(data),
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
        vtk.export(path).map_err(|e| io_err(path, e))
    }

    /// Writes binary little-endian PLY: `x y z` and one float property per scalar and per
    /// vector component (`velocity_x` …).
    pub fn write_ply(&self, path: &Path) -> Result<()> {
        let mut ply = Ply::<DefaultElement>::new();
        ply.header.encoding = Encoding::BinaryLittleEndian;
        ply.header
            .comments
            .push("staggered-fluid frame".to_string());
        let mut names: Vec<String> = vec!["x".into(), "y".into(), "z".into()];
        for f in &self.fields {
            match f {
                Field::Scalar(name, _) => names.push(name.to_string()),
                Field::Vector(name, _) => {
                    for c in ["x", "y", "z"] {
                        names.push(format!("{name}_{c}"));
                    }
                }
            }
        }
        let mut def = ElementDef::new("vertex".to_string());
        for name in &names {
            def.properties.add(PropertyDef::new(
                name.clone(),
                PropertyType::Scalar(ScalarType::Float),
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
            values.extend_from_slice(p);
            for f in &self.fields {
                match f {
                    Field::Scalar(_, v) => values.push(v[i]),
                    Field::Vector(_, v) => values.extend_from_slice(&v[i]),
                }
            }
            for (name, v) in names.iter().zip(&values) {
                match e.get_mut(name) {
                    Some(slot) => *slot = Property::Float(*v),
                    None => {
                        e.insert(name.clone(), Property::Float(*v));
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

/// Writes a run's frames into a directory: `fluid_NNNNN.vtp/.ply`, the moving solids'
/// carriers `solid_NNNNN.vtp/.ply`, the static walls once (`walls.vtp/.ply`), and
/// `bodies.csv` (one row per tracked body per frame).
pub struct FrameWriter {
    dir: PathBuf,
    vtk: bool,
    ply: bool,
    frame: usize,
    bodies: Option<std::io::BufWriter<std::fs::File>>,
}

impl FrameWriter {
    /// Creates `dir` (and parents) and the body-pose CSV.
    pub fn new(dir: &Path, vtk: bool, ply: bool) -> Result<Self> {
        std::fs::create_dir_all(dir).map_err(|e| io_err(dir, e))?;
        let path = dir.join("bodies.csv");
        let mut f =
            std::io::BufWriter::new(std::fs::File::create(&path).map_err(|e| io_err(&path, e))?);
        writeln!(f, "frame,t,body,x,y,z,qx,qy,qz,qw,vx,vy,vz,wx,wy,wz")
            .map_err(|e| io_err(&path, e))?;
        Ok(Self {
            dir: dir.to_path_buf(),
            vtk,
            ply,
            frame: 0,
            bodies: Some(f),
        })
    }

    /// Frames written so far.
    pub fn frames(&self) -> usize {
        self.frame
    }

    /// Path of frame `k`'s file `kind` (`fluid`, `solid`, `preview`, `surface`) with `ext`.
    pub fn path(&self, kind: &str, k: usize, ext: &str) -> PathBuf {
        self.dir.join(format!("{kind}_{k:05}.{ext}"))
    }

    /// Writes the next frame of `scene`; returns its index.
    pub fn write(&mut self, scene: &Scene) -> Result<usize> {
        let k = self.frame;
        let mut clouds = vec![(PointCloud::fluid(scene), format!("fluid_{k:05}"))];
        let moving = PointCloud::solids(scene, true);
        if !moving.points.is_empty() {
            clouds.push((moving, format!("solid_{k:05}")));
        }
        if k == 0 {
            clouds.push((PointCloud::solids(scene, false), "walls".to_string()));
        }
        for (cloud, name) in &clouds {
            if self.vtk {
                cloud.write_vtp(&self.dir.join(format!("{name}.vtp")))?;
            }
            if self.ply {
                cloud.write_ply(&self.dir.join(format!("{name}.ply")))?;
            }
        }
        if let (Some(out), Some(ph)) = (self.bodies.as_mut(), scene.physics.as_ref()) {
            let path = self.dir.join("bodies.csv");
            for (name, h) in &scene.tracked {
                let Some(rb) = ph.bodies.get(*h) else {
                    continue;
                };
                let (p, q, v, w) = (rb.translation(), rb.rotation(), rb.linvel(), rb.angvel());
                writeln!(
                    out,
                    "{k},{},{name},{},{},{},{},{},{},{},{},{},{},{},{},{}",
                    scene.world.time(),
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
}

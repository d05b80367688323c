//! Snapshots: the full state of a running [`Scene`] (the fluid world, the rapier world through
//! rapier's own serde support, emitters, sinks and the scene description) saved to a file and
//! resumed. A resumed run matches the uninterrupted one step for step.
//!
//! The file is postcard (a compact serde binary format) behind an 8-byte magic and a version.
//!
//! ```
//! use staggered_fluid::{scenes, snapshot::Snapshot};
//! let mut a = scenes::hydrostatic(0.2, 0.1, 0.04, Default::default()).unwrap();
//! a.run(0.01, |_, _| {}).unwrap();
//! let bytes = Snapshot::encode(&a).unwrap();
//! let mut b = Snapshot::from_bytes(&bytes).unwrap().resume().unwrap();
//! a.run(0.01, |_, _| {}).unwrap();
//! b.run(0.01, |_, _| {}).unwrap();
//! assert_eq!(a.world.fluid().x, b.world.fluid().x);
//! ```

use crate::emitter::{Emitter, Sink};
use crate::error::{FluidError, Result};
use crate::scenes::SceneFile;
use crate::scenes::{Probe, Scene};
use crate::world::{FluidWorld, WorldState};
use rapier3d::dynamics::RigidBodyHandle;
use rapier3d::pipeline::PhysicsWorld;
use serde::{Deserialize, Serialize};
use std::path::Path;

const MAGIC: &[u8; 8] = b"SFSNAP\0\x01";

/// The state of a scene at a step boundary.
#[derive(Serialize, Deserialize)]
pub struct Snapshot {
    /// The description the scene was built from (probe, output, step, gravity), as RON: the
    /// scene format leaves default fields out, which a binary format cannot read back.
    pub spec: String,
    /// The fluid world.
    pub world: WorldState,
    /// The rapier world, if the scene has one.
    pub physics: Option<PhysicsWorld>,
    /// The tracked rapier bodies.
    pub tracked: Vec<(String, RigidBodyHandle)>,
    /// Emitters with their progress.
    pub emitters: Vec<Emitter>,
    /// Sinks.
    pub sinks: Vec<Sink>,
    /// What the scene measures (holds handles into the world).
    pub probe: Probe,
    /// Name, step, gravity and duration as the scene had them (they may differ from the
    /// description's if changed after building).
    pub run: (String, f32, [f32; 3], f32),
}

/// The same layout as [`Snapshot`], borrowing from a scene (rapier's world is not `Clone`).
#[derive(Serialize)]
struct SnapshotRef<'a> {
    spec: String,
    world: WorldState,
    physics: Option<&'a PhysicsWorld>,
    tracked: &'a [(String, RigidBodyHandle)],
    emitters: &'a [Emitter],
    sinks: &'a [Sink],
    probe: &'a Probe,
    run: (&'a str, f32, [f32; 3], f32),
}

impl Snapshot {
    /// Encodes the state of `scene` now.
    pub fn encode(scene: &Scene) -> Result<Vec<u8>> {
        let r = SnapshotRef {
            spec: scene.spec.to_ron(),
            world: scene.world.state(),
            physics: scene.physics.as_ref(),
            tracked: &scene.tracked,
            emitters: &scene.emitters,
            sinks: &scene.sinks,
            probe: &scene.probe,
            run: (&scene.name, scene.dt, scene.gravity.into(), scene.seconds),
        };
        let mut out = MAGIC.to_vec();
        postcard::to_io(&r, &mut out).map_err(|e| FluidError::Io {
            path: "snapshot".into(),
            message: e.to_string(),
        })?;
        Ok(out)
    }

    /// Writes the state of `scene` to `path`.
    pub fn save(scene: &Scene, path: &Path) -> Result<()> {
        let bytes = Self::encode(scene)?;
        std::fs::write(path, bytes).map_err(|e| FluidError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })
    }

    /// A scene that continues from this state (nothing is sampled again).
    pub fn resume(self) -> Result<Scene> {
        let spec = SceneFile::parse(&self.spec, "snapshot")?;
        let (name, dt, gravity, seconds) = self.run;
        Ok(Scene {
            name,
            world: FluidWorld::from_state(self.world)?,
            gravity: crate::math::Vector::from(gravity),
            dt,
            seconds,
            probe: self.probe,
            physics: self.physics,
            tracked: self.tracked,
            emitters: self.emitters,
            sinks: self.sinks,
            spec,
            // (a snapshot is of a scene that has run, so settled if it was to be)
            settled: None,
        })
    }

    /// Decodes a snapshot written by [`Self::encode`].
    pub fn from_bytes(bytes: &[u8]) -> Result<Self> {
        let bad = |m: String| FluidError::Io {
            path: "snapshot".into(),
            message: m,
        };
        if bytes.len() < MAGIC.len() || &bytes[..MAGIC.len()] != MAGIC {
            return Err(bad(
                "not a staggered-fluid snapshot (or another version)".into()
            ));
        }
        postcard::from_bytes(&bytes[MAGIC.len()..]).map_err(|e| bad(e.to_string()))
    }

    /// Reads a snapshot from `path`.
    pub fn load(path: &Path) -> Result<Self> {
        let bytes = std::fs::read(path).map_err(|e| FluidError::Io {
            path: path.display().to_string(),
            message: e.to_string(),
        })?;
        Self::from_bytes(&bytes).map_err(|e| match e {
            FluidError::Io { message, .. } => FluidError::Io {
                path: path.display().to_string(),
                message,
            },
            e => e,
        })
    }
}

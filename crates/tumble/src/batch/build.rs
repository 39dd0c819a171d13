//! What a batch is built from ([`WorldSpec`]) and how one world is built into it, with the
//! errors that name the world.

use rayon::prelude::*;
use tumble_geometry::Vec3;
use tumble_scenes::Scene;

use super::{BatchError, Entry, History, WorldId};
use crate::{Backend, BodyDesc, Error, World, WorldConfig, body_desc};

/// A world to add to a batch: its config and its bodies, added in order.
#[derive(Clone, Debug, PartialEq)]
pub struct WorldSpec {
    /// The world's settings; `config.backend` must be the batch's.
    pub config: WorldConfig,
    /// The bodies, in the order they are added (their handles come back in this order).
    pub bodies: Vec<BodyDesc>,
}

impl WorldSpec {
    /// A world of `config` with no bodies yet.
    pub fn new(config: WorldConfig) -> Self {
        Self {
            config,
            bodies: Vec::new(),
        }
    }

    /// Adds a body.
    pub fn body(mut self, desc: BodyDesc) -> Self {
        self.bodies.push(desc);
        self
    }

    /// The world [`World::from_scene`] builds: `scene`'s bodies, its gravity and time step,
    /// and the rest of `config`. Errs when the scene fails its own validation.
    pub fn from_scene(scene: &Scene, config: WorldConfig) -> Result<Self, Error> {
        scene
            .validate()
            .map_err(|e| Error::InvalidScene(e.to_string()))?;
        Ok(Self {
            config: WorldConfig {
                gravity: Vec3::from(scene.gravity),
                dt: scene.dt,
                ..config
            },
            bodies: scene.bodies.iter().map(body_desc).collect(),
        })
    }
}

/// A world's error, as the batch's.
pub(super) fn world_error(world: WorldId, e: Error) -> Error {
    BatchError::World {
        world,
        error: Box::new(e),
    }
    .into()
}

/// A build error of world `world` (its position in the list given).
pub(super) fn build_error(world: usize, body: Option<usize>, e: Error) -> Error {
    BatchError::Build {
        world,
        body,
        error: Box::new(e),
    }
    .into()
}

/// Builds one world (`index` names it in errors).
pub(super) fn build(backend: Backend, index: usize, spec: WorldSpec) -> Result<Entry, Error> {
    check_backend(backend, index, &spec)?;
    let world = World::new(spec.config).map_err(|e| build_error(index, None, e))?;
    fill(world, index, spec)
}

/// Errs unless `spec` runs on the batch's `backend`.
pub(super) fn check_backend(backend: Backend, index: usize, spec: &WorldSpec) -> Result<(), Error> {
    if spec.config.backend != backend {
        return Err(BatchError::BackendMismatch {
            world: index,
            given: spec.config.backend,
            batch: backend,
        }
        .into());
    }
    Ok(())
}

/// `world` (empty) with `spec`'s bodies added and logged, its saved state the present one.
pub(super) fn fill(mut world: World, index: usize, spec: WorldSpec) -> Result<Entry, Error> {
    let mut history = History::new(spec.config);
    for (b, desc) in spec.bodies.into_iter().enumerate() {
        world
            .add_body(desc)
            .map_err(|e| build_error(index, Some(b), e))?;
        history.add(desc);
    }
    history.save();
    Ok(Entry {
        world,
        history,
        #[cfg(feature = "gpu")]
        gpu: None,
    })
}

/// Builds every world of `specs`, in parallel on the CPU backend.
pub(super) fn build_all(backend: Backend, specs: Vec<WorldSpec>) -> Result<Vec<Entry>, Error> {
    let built: Vec<Result<Entry, Error>> = if backend == Backend::Cpu {
        specs
            .into_par_iter()
            .enumerate()
            .map(|(i, s)| build(backend, i, s))
            .collect()
    } else {
        specs
            .into_iter()
            .enumerate()
            .map(|(i, s)| build(backend, i, s))
            .collect()
    };
    // The first failure by position, so the error does not depend on scheduling.
    built.into_iter().collect()
}

//! Tumble: a rigid-body physics engine for boxes whose whole step runs on the GPU through wgpu
//! compute shaders, with a CPU twin of every stage.
//!
//! ```
//! use tumble::prelude::*;
//!
//! let mut world = World::new(WorldConfig::default())?;
//! world.add_body(BodyDesc::fixed().cuboid(Vec3::new(5.0, 0.5, 5.0)).translation(0.0, -0.5, 0.0))?;
//! let cube = world.add_body(BodyDesc::dynamic().translation(0.0, 2.0, 0.0))?;
//! for _ in 0..120 {
//!     world.step()?;
//! }
//! // The cube fell 1.5 m and rests on the floor.
//! assert!((world.pose(cube)?.translation.y - 0.5).abs() < 0.01);
//! # Ok::<(), tumble::Error>(())
//! ```
#![warn(missing_docs)]

mod backend;
mod batch;
mod body_desc;
mod config;
mod contact_report;
#[cfg(feature = "gpu")]
mod draw;
mod effects;
mod error;
mod events;
#[cfg(feature = "gpu")]
mod gpu_reads;
mod handle;
mod query;
mod scene;
mod sleep;
mod snapshot;
pub mod stages;
mod stats;
mod world;
mod world_bodies;
mod world_body_properties;

pub use batch::{
    Action, ActionKind, BatchError, POSE_FLOATS, VELOCITY_FLOATS, WorldBatch, WorldId, WorldSpec,
};
pub use body_desc::{BodyDesc, DEFAULT_HALF_EXTENTS};
pub use config::{Backend, DEFAULT_MARGIN, STANDARD_GRAVITY, WorldConfig};
pub use contact_report::{ContactPointReport, ContactReport};
pub use effects::{EffectOverrides, EffectSwitch, ReadbackOverrides};
pub use error::Error;
pub use events::{ContactEvent, ContactEventKind, TouchingPair};
pub use handle::BodyHandle;
pub use query::{BoxHit, PointHit, QueryFilter, Ray, RayHit};
pub use scene::body_desc;
pub use sleep::{ANGULAR_SLEEP_TOLERANCE, LINEAR_SLEEP_TOLERANCE, TIME_TO_SLEEP};
pub use snapshot::WorldSnapshot;
pub use stats::{StageTimings, StepStats};
pub use world::World;

pub use tumble_geometry as geometry;
pub use tumble_geometry::{Aabb, Cuboid, Point3, Pose, Real, Rot, Vec3, nalgebra};
/// The GPU crate (devices, buffers and their layouts), for code drawing or reading a
/// `Backend::Gpu` world's buffers directly ([`World::gpu_draw_buffers`]).
#[cfg(feature = "gpu")]
pub use tumble_gpu as gpu;
pub use tumble_scenes as scenes;
pub use tumble_solver as solver;
pub use tumble_solver::{
    BodyKind, CollisionGroups, Effects, FrictionPasses, Locks, Material, SolveOrder, SolverConfig,
    SolverKind,
};

/// The names most programs need, in one import.
pub mod prelude {
    pub use crate::{
        Backend, BodyDesc, BodyHandle, BodyKind, Error, FrictionPasses, Point3, Pose, Real, Rot,
        SolveOrder, SolverConfig, SolverKind, Vec3, World, WorldConfig,
    };
}

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

//! Tumble's canonical scenes as plain serde data: bodies (boxes), gravity, time step, run
//! length and a pass criterion, loadable from and savable to JSON. Behind the feature
//! `rapier`, the same scene built in rapier3d for side-by-side comparison.
#![warn(missing_docs)]

mod body;
pub mod builders;
mod canonical;
mod check;
mod embedded;
mod error;
mod evaluate;
mod penetration;
#[cfg(feature = "rapier")]
mod rapier_world;
mod scene;
mod state;
mod validate;

pub use body::{BodyKind, BodySpec, DEFAULT_DENSITY, DEFAULT_FRICTION, DEFAULT_RESTITUTION};
pub use builders::{
    dominoes, far_from_origin, friction_ramp, high_speed, mass_ratio, overlap_recovery, pool,
    pyramid, pyramid_cube_count, spinning_box, stack, wall, wide_on_small,
};
pub use canonical::{CANONICAL_FAR_OFFSET, CANONICAL_POOL, canonical};
pub use check::SceneCheck;
pub use embedded::{EMBEDDED_SCENES, embedded, embedded_sources};
pub use error::SceneError;
pub use evaluate::{CheckReport, CheckTracker};
pub use penetration::cuboid_penetration;
#[cfg(feature = "rapier")]
pub use rapier_world::{RapierOptions, RapierWorld, build_rapier, build_rapier_with};
pub use scene::{DEFAULT_DT, DEFAULT_STEPS, FORMAT_VERSION, STANDARD_GRAVITY, Scene};
pub use state::BodyState;
pub use validate::ROTATION_NORM_TOLERANCE;

//! Tumble's solver layer: bodies (cold data apart from hot state), contact constraints with a
//! normal and two friction rows per point, the Baumgarte and soft-step sequential-impulse
//! solvers, graph coloring for parallel solving, integration and contact persistence.
//!
//! The solve stage is a list of stages, each a plain function on slices so the GPU kernels can
//! mirror them one to one: [`prepare_contact`], [`integrate_velocities`],
//! [`warm_start_contact`], [`solve_contact`], [`integrate_positions`],
//! [`restitution_contact`], [`ContactConstraint::store_impulses`], [`finalize_bodies`].
//!
//! The step's stages are named once, in order, by [`Stage`]; [`stages`] holds the CPU stages
//! on the body arrays (narrow phase through the [`ContactCache`], top-down coloring, finish)
//! and [`SleepState`] the islands, rest timers and wake rules of the sleep stage
//! ([`SleepLabels`]: the same stage by label propagation, the form the GPU runs).
//!
//! One CPU step is these stages in order; here a cube resting on a floor for one second:
//!
//! ```
//! use tumble_broad::KeptPairs;
//! use tumble_geometry::{Cuboid, Pose, Real, Vec3};
//! use tumble_solver::{
//!     Body, BodyKind, BodyState, ContactCache, Material, SolverConfig, solve, stages,
//! };
//!
//! let floor = Body::new(
//!     BodyKind::Fixed,
//!     Cuboid::new(Vec3::new(5.0, 0.5, 5.0)),
//!     Pose::translation(0.0, -0.5, 0.0),
//!     1.0,
//!     Material::default(),
//! )?;
//! let cube = Body::new(
//!     BodyKind::Dynamic,
//!     Cuboid::new(Vec3::repeat(0.5)),
//!     Pose::translation(0.0, 0.5, 0.0),
//!     1.0,
//!     Material::default(),
//! )?;
//! let mut bodies = vec![floor, cube];
//! let mut states = vec![BodyState::default(); bodies.len()];
//! let ids = [0, 1];
//! let (config, dt, margin): (SolverConfig, Real, Real) = (SolverConfig::default(), 1.0 / 60.0, 0.02);
//! let gravity = Vec3::new(0.0, -9.81, 0.0);
//! // Pairs that barely moved reuse last step's manifold (0.0 computes every one afresh).
//! let recycle = tumble_solver::DEFAULT_RECYCLE_DISTANCE;
//! let (mut grid, mut cache) = (KeptPairs::new(), ContactCache::new());
//! for _ in 0..60 {
//!     let aabbs = stages::update_aabbs(&bodies, &states, margin, dt);
//!     let pairs = stages::broad_phase(&mut grid, &aabbs, &bodies);
//!     let mut found =
//!         stages::narrow_phase(&bodies, &states, &pairs, &ids, &cache, margin, dt, recycle);
//!     let coloring = stages::color(&found.contacts, &bodies, config.order, &gravity);
//!     solve(&bodies, &mut states, &mut found.contacts, &coloring, &config, dt, &gravity);
//!     stages::finish(&mut bodies, &mut states, &mut cache, &found.keys, &found.contacts);
//! }
//! // Unsupported, the cube would have fallen 4.9 m; the contact holds it within a millimetre.
//! assert!((bodies[1].pose.translation.y - 0.5).abs() < 1e-3);
//! assert!(states[1].linear_velocity.norm() < 1e-2);
//! # Ok::<(), tumble_solver::InvalidParameter>(())
//! ```
#![warn(missing_docs)]

mod body;
pub mod bounds;
mod coloring;
mod concat;
mod config;
mod constraint;
mod contact;
mod contact_cache;
mod contact_solver;
mod effects;
mod error;
mod gyroscopic;
mod integrate;
mod islands;
mod lanes;
mod mass;
mod material;
mod pair_hash;
mod pair_table;
mod recycle;
mod sleep;
mod softness;
mod solve;
mod stage;
pub mod stages;
mod sweep;
mod tangent_basis;
#[cfg(test)]
mod tests;

pub use body::{Body, BodyKind, BodyState, Locks};
pub use coloring::{
    COLOR_ROUNDS, ColorCandidate, Coloring, ColoringError, EMPTY_COLOR, GRAPH_COLOR_COUNT,
    NO_COLOR, OVERFLOW_COLOR, color_constraints, color_constraints_in_order, color_contacts,
    color_in_rounds, color_priority, hash_u32, validate_coloring,
};
pub use config::{
    DEFAULT_BAUMGARTE, DEFAULT_BAUMGARTE_ITERATIONS, DEFAULT_CONTACT_HERTZ, DEFAULT_DAMPING_RATIO,
    DEFAULT_MAX_PUSH_OUT, DEFAULT_PARALLEL_THRESHOLD, DEFAULT_RESTITUTION_THRESHOLD, DEFAULT_SLOP,
    DEFAULT_SUBSTEPS, FrictionPasses, SolveKernel, SolveOrder, SolverConfig, SolverKind,
};
pub use constraint::{
    AngularRow, ConstraintPoint, ContactConstraint, PrepareContext, patch_radius, prepare_contact,
};
pub use contact::{Contact, PointImpulse};
pub use contact_cache::{
    CachedManifold, ContactCache, PERSIST_DISTANCE, PERSIST_NORMAL_COS, PairKey,
};
pub use contact_solver::{PassContext, restitution_contact, solve_contact, warm_start_contact};
pub use effects::Effects;
pub use error::{InvalidParameter, require_finite3, require_non_negative, require_positive};
pub use gyroscopic::{NEWTON_ITERATIONS as GYROSCOPIC_NEWTON_ITERATIONS, gyroscopic_midpoint};
pub use integrate::{
    MAX_LINEAR_SPEED, MAX_ROTATION_PER_SUBSTEP, begin_step, finalize_bodies, integrate_positions,
    integrate_velocities, integrate_velocities_with,
};
pub use islands::Islands;
pub use lanes::LANES;
pub use mass::MassProperties;
pub use material::{DEFAULT_FRICTION, Material, mix_friction, mix_restitution};
pub use pair_hash::{PairBuildHasher, PairHasher};
pub use recycle::{
    DEFAULT_RECYCLE_DISTANCE, RECYCLE_NORMAL_COS, RECYCLE_SIZE_FRACTION, recycle_tolerance,
};
pub use sleep::labels::{IslandSearch, SleepLabels, SleepLink, island_search};
pub use sleep::{
    ANGULAR_SLEEP_TOLERANCE, AWAKE, Gathered, LINEAR_SLEEP_TOLERANCE, SleepState, TIME_TO_SLEEP,
    is_moving_kinematic, is_resting,
};
pub use softness::Softness;
pub use solve::{SolveBuffers, SolveStats, solve, solve_with_buffers, solve_with_effects};
pub use stage::Stage;
pub use tangent_basis::tangent_basis;
pub use tumble_broad::CollisionGroups;

/// A 3x3 matrix (world inverse inertia).
pub type Mat3 = tumble_geometry::nalgebra::Matrix3<tumble_geometry::Real>;

/// The README's examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;

//! The whole step on the GPU: [`GpuWorld`] records the collision stages and the solver stages
//! and submits them without a wait inside the step, reading back only on request;
//! [`HybridCollision`] runs the collision on the GPU for a CPU solver.

pub mod config;
mod events;
pub mod gpu_world;
pub mod hybrid;
pub mod idle;
mod read_plan;
pub mod snapshot;
pub mod stats_ring;

pub use config::{ColorDispatch, GpuWorldConfig, PathPolicy};
pub use gpu_world::{DrawBuffers, GpuWorld, GpuWorldState, SavedCollision, SavedIdle, SavedStats};
pub use hybrid::{HybridCollision, SavedHybrid};
pub use snapshot::{ContactSnapshot, ReadRequest, Snapshot};

//! The traffic model of `bench-gpu`'s "bytes per step" column.
//!
//! Bytes a GPU step must move at least, counted from the record sizes of the buffers each pass
//! reads and writes (`tumble_gpu::layout` and `tumble_gpu::solver::layout`, so the count
//! follows the engine's own structs) times the passes per step; every record is taken to
//! cross the memory bus once per pass that touches it (no cache reuse, no bank conflicts).
//! With `N` bodies, `M` manifolds with contact points, `P` contact points and `S` substeps:
//!
//! | pass | bytes |
//! |---|---|
//! | update_aabbs | `N * (pose + velocity + shape + aabb)` |
//! | broad phase | `N * (4 radix passes * 2 * 8 + aabb) + M * 8` (sorted keys, the sweep, the pair list) |
//! | narrow phase | `M * 2 * (pose + shape + manifold) + P * 2 * contact` (inputs, the previous manifold matched, the new one written) |
//! | prepare | `M * (manifold + constraint) + P * contact` |
//! | each substep | `N * 4 * (velocity + solver body)` (integrate velocities, positions) `+ 3 * M * (constraint + 2 * (2 * velocity + solver body))` (warm start, solve, relax: each reads its constraint, whose impulse writes are counted nowhere, and reads and writes both bodies' velocities) |
//! | restitution, finish | `M * (3 * constraint + 2 * (2 * velocity + solver body)) + N * (solver body + pose + velocity)` |
//!
//! The pair sort, the coloring rounds and the sleep stage are left out: the model is a floor,
//! and `x floor` (the measured time over bytes / bandwidth) says how far a step is from
//! streaming its data once at the device's bandwidth.

use super::*;

/// The counts the traffic model needs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct TrafficCounts {
    /// Bodies, fixed ones included.
    pub bodies: u64,
    /// Manifolds with contact points.
    pub manifolds: u64,
    /// Contact points.
    pub points: u64,
    /// Substeps per step.
    pub substeps: u64,
}

impl TrafficCounts {
    /// Bytes per step by the model of this module's documentation.
    pub fn bytes_per_step(&self) -> u64 {
        let size = |s: usize| s as u64;
        let pose = size(size_of::<GpuPose>());
        let velocity = size(size_of::<GpuVelocity>());
        let shape = size(size_of::<GpuShape>());
        let aabb = size(size_of::<GpuAabb>());
        let manifold = size(size_of::<GpuManifold>());
        let contact = size(size_of::<GpuContact>());
        let constraint = size(size_of::<GpuConstraint>());
        let solver_body = size(size_of::<GpuSolverBody>());
        let Self {
            bodies: n,
            manifolds: m,
            points: p,
            substeps: s,
        } = *self;
        let body_pair = 2 * (2 * velocity + solver_body);
        let update_aabbs = n * (pose + velocity + shape + aabb);
        let broad = n * (4 * 2 * 8 + aabb) + m * 8;
        let narrow = m * 2 * (pose + shape + manifold) + p * 2 * contact;
        let prepare = m * (manifold + constraint) + p * contact;
        let substep = n * 4 * (velocity + solver_body) + 3 * m * (constraint + body_pair);
        let finish = m * (3 * constraint + body_pair) + n * (solver_body + pose + velocity);
        update_aabbs + broad + narrow + prepare + s * substep + finish
    }
}

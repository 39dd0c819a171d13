//! Stage 1: poses to AABBs, grown by the speculative margin and by the motion of the step.

use tumble_geometry::{Aabb, Real};
use tumble_solver::{Body, BodyState};

/// The world AABB of every body, grown by `margin` on all sides, stretched by `v dt` in the
/// direction of motion, and grown by `|w| r dt` (the farthest a corner at radius `r` can
/// turn), so a pair that can meet within the step is found by the broad phase.
pub fn update_aabbs(bodies: &[Body], states: &[BodyState], margin: Real, dt: Real) -> Vec<Aabb> {
    bodies
        .iter()
        .zip(states)
        .map(|(body, state)| {
            let mut aabb = body.shape.aabb(&body.pose, margin);
            let travel = state.linear_velocity * dt;
            let turn = state.angular_velocity.norm() * body.shape.half_extents.norm() * dt;
            for i in 0..3 {
                aabb.min[i] += travel[i].min(0.0) - turn;
                aabb.max[i] += travel[i].max(0.0) + turn;
            }
            aabb
        })
        .collect()
}

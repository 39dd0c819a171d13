//! The engine-neutral interface every validation run goes through, so that Tumble (any solver,
//! any backend) and rapier3d are stepped, timed and measured by the same code.

use tumble_geometry::{Pose, Vec3};

/// One body's state after a step, in the scene's body order.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BodyState {
    /// World pose of the body's centre.
    pub pose: Pose,
    /// Velocity of the centre, in m/s.
    pub linear_velocity: Vec3,
    /// Angular velocity in world axes, in rad/s.
    pub angular_velocity: Vec3,
}

impl BodyState {
    /// True when every component of the pose and both velocities is finite.
    pub fn is_finite(&self) -> bool {
        let t = self.pose.translation.vector;
        let q = self.pose.rotation.coords;
        t.iter()
            .chain(q.iter())
            .chain(self.linear_velocity.iter())
            .chain(self.angular_velocity.iter())
            .all(|c| c.is_finite())
    }
}

/// Time one named stage of a step took, in milliseconds.
#[derive(Clone, Debug, PartialEq)]
pub struct StageTime {
    /// The stage's name, as the engine reports it (`broad_phase`, `solve`, ...).
    pub name: String,
    /// Wall time of that stage in the last step, in milliseconds.
    pub ms: f64,
}

/// A physics engine loaded with one scene.
pub trait Engine {
    /// Advances the scene by one fixed time step.
    fn step(&mut self) -> Result<(), String>;

    /// Writes every body's state into `out` (cleared first), in the scene's body order.
    fn read_states(&self, out: &mut Vec<BodyState>);

    /// Per-stage wall times of the last step, when the engine measures them.
    fn stage_times(&self) -> Vec<StageTime> {
        Vec::new()
    }

    /// The deepest penetration the engine itself saw in the last step, when it reports one.
    fn reported_max_penetration(&self) -> Option<f32> {
        None
    }
}

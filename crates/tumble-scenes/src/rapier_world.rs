//! The same scene built in rapier3d, for side-by-side accuracy and speed comparisons.
//!
//! Matching choices, so that a difference in results is a difference in solvers:
//! - sizes, poses, velocities, densities (so masses and inertias), friction, restitution and
//!   the time step are copied from the scene;
//! - materials combine as in Tumble: friction by geometric mean (`GeometricMean`),
//!   restitution by maximum (`Max`); rapier's default would average both;
//! - zero contact skin (rapier's default), so resting boxes touch face to face; rapier still
//!   creates speculative contacts within its prediction distance (0.02 m by default, about the
//!   speculative margin Tumble grows its AABBs by);
//! - sleeping is off unless asked for, so drift is measured on every step rather than frozen
//!   once an island sleeps; gyroscopic forces stay on (rapier's default), as in Tumble.

use rapier3d::prelude::*;

use crate::{BodyKind, BodySpec, BodyState, Scene};

/// How to configure rapier beyond what the scene fixes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RapierOptions {
    /// `IntegrationParameters::num_solver_iterations`: in rapier's soft-step solver each
    /// iteration is a substep (velocity solve, position update, relax), so this plays the role
    /// of Tumble's `substeps`. Rapier's default is 4.
    pub solver_iterations: usize,
    /// Whether bodies may fall asleep.
    pub sleep: bool,
    /// Whether dynamic bodies get continuous collision detection.
    pub ccd: bool,
}

impl Default for RapierOptions {
    fn default() -> Self {
        Self {
            solver_iterations: IntegrationParameters::default().num_solver_iterations,
            sleep: false,
            ccd: false,
        }
    }
}

/// A rapier3d world built from a scene: all the sets and pipelines one step needs, plus the
/// body handles in scene order.
pub struct RapierWorld {
    /// Gravity, m/s^2.
    pub gravity: Vector,
    /// Time step, iterations and tolerances.
    pub integration_parameters: IntegrationParameters,
    /// Runs one step.
    pub physics_pipeline: PhysicsPipeline,
    /// Islands and sleeping.
    pub islands: IslandManager,
    /// Rapier's broad phase.
    pub broad_phase: DefaultBroadPhase,
    /// Rapier's narrow phase (contact manifolds).
    pub narrow_phase: NarrowPhase,
    /// The rigid bodies.
    pub bodies: RigidBodySet,
    /// One cuboid collider per body.
    pub colliders: ColliderSet,
    /// Joints (unused by the scenes, needed by the step).
    pub impulse_joints: ImpulseJointSet,
    /// Multibody joints (unused by the scenes, needed by the step).
    pub multibody_joints: MultibodyJointSet,
    /// Soft bodies (unused by the scenes, needed by the step).
    pub soft_bodies: SoftBodySet,
    /// Continuous collision detection.
    pub ccd_solver: CCDSolver,
    /// Body handles in scene body order.
    pub handles: Vec<RigidBodyHandle>,
}

/// Builds `scene` in rapier3d with default options (rapier's iteration count, no sleep, no CCD).
pub fn build_rapier(scene: &Scene) -> RapierWorld {
    build_rapier_with(scene, &RapierOptions::default())
}

/// Builds `scene` in rapier3d with the given options.
pub fn build_rapier_with(scene: &Scene, options: &RapierOptions) -> RapierWorld {
    let mut integration_parameters = IntegrationParameters {
        dt: scene.dt,
        ..IntegrationParameters::default()
    };
    integration_parameters.num_solver_iterations = options.solver_iterations;
    let mut world = RapierWorld {
        gravity: Vector::from_array(scene.gravity),
        integration_parameters,
        physics_pipeline: PhysicsPipeline::new(),
        islands: IslandManager::new(),
        broad_phase: DefaultBroadPhase::default(),
        narrow_phase: NarrowPhase::new(),
        bodies: RigidBodySet::new(),
        colliders: ColliderSet::new(),
        impulse_joints: ImpulseJointSet::new(),
        multibody_joints: MultibodyJointSet::new(),
        soft_bodies: SoftBodySet::new(),
        ccd_solver: CCDSolver::new(),
        handles: Vec::with_capacity(scene.bodies.len()),
    };
    for spec in &scene.bodies {
        let handle = world.bodies.insert(rigid_body(spec, options));
        world
            .colliders
            .insert_with_parent(collider(spec), handle, &mut world.bodies);
        world.handles.push(handle);
    }
    world
}

fn rigid_body(spec: &BodySpec, options: &RapierOptions) -> RigidBody {
    let builder = match spec.kind {
        BodyKind::Fixed => RigidBodyBuilder::fixed(),
        BodyKind::Dynamic => RigidBodyBuilder::dynamic(),
        BodyKind::Kinematic => RigidBodyBuilder::kinematic_velocity_based(),
    };
    let [x, y, z, w] = spec.rotation;
    let rotation = Rotation::from_xyzw(x, y, z, w).normalize();
    builder
        .pose(Pose::from_parts(
            Vector::from_array(spec.position),
            rotation,
        ))
        .linvel(Vector::from_array(spec.linear_velocity))
        .angvel(Vector::from_array(spec.angular_velocity))
        .can_sleep(options.sleep)
        .ccd_enabled(options.ccd && spec.is_dynamic())
        .build()
}

fn collider(spec: &BodySpec) -> Collider {
    let [hx, hy, hz] = spec.half_extents;
    ColliderBuilder::cuboid(hx, hy, hz)
        .density(spec.density)
        .friction(spec.friction)
        .friction_combine_rule(CoefficientCombineRule::GeometricMean)
        .restitution(spec.restitution)
        .restitution_combine_rule(CoefficientCombineRule::Max)
        .build()
}

impl RapierWorld {
    /// Sets rapier's solver iteration count (its substep count, see `RapierOptions`).
    pub fn set_solver_iterations(&mut self, iterations: usize) {
        self.integration_parameters.num_solver_iterations = iterations;
    }

    /// Advances the world by one time step.
    pub fn step(&mut self) {
        self.physics_pipeline.step(
            self.gravity,
            &self.integration_parameters,
            &mut self.islands,
            &mut self.broad_phase,
            &mut self.narrow_phase,
            &mut self.bodies,
            &mut self.colliders,
            &mut self.impulse_joints,
            &mut self.multibody_joints,
            &mut self.soft_bodies,
            &mut self.ccd_solver,
            &(),
            &(),
        );
    }

    /// Every body's `(position, rotation [x, y, z, w])`, in scene body order.
    pub fn body_poses(&self) -> Vec<([f32; 3], [f32; 4])> {
        self.handles
            .iter()
            .map(|&h| {
                let pose = self.bodies[h].position();
                (pose.translation.to_array(), pose.rotation.to_array())
            })
            .collect()
    }

    /// Every body's `(linear velocity, angular velocity)` in world axes, in scene body order.
    pub fn body_velocities(&self) -> Vec<([f32; 3], [f32; 3])> {
        self.handles
            .iter()
            .map(|&h| {
                let body = &self.bodies[h];
                (body.linvel().to_array(), body.angvel().to_array())
            })
            .collect()
    }

    /// Every body's pose and velocities as a [`BodyState`], in scene body order (what a
    /// [`crate::CheckTracker`] observes).
    pub fn body_states(&self) -> Vec<BodyState> {
        self.body_poses()
            .into_iter()
            .zip(self.body_velocities())
            .map(
                |((position, rotation), (linear_velocity, angular_velocity))| BodyState {
                    position,
                    rotation,
                    linear_velocity,
                    angular_velocity,
                },
            )
            .collect()
    }

    /// Every body's mass in kg as rapier computed it (zero for fixed and kinematic bodies).
    pub fn body_masses(&self) -> Vec<f32> {
        self.handles
            .iter()
            .map(|&h| self.bodies[h].mass())
            .collect()
    }
}

//! Per-world actions given as one array per call, checked in full before any is applied.
//!
//! [`crate::WorldBatch::apply_actions`] runs [`plan`] first: every entry is checked against
//! the state it will meet (the world's current state, changed by the earlier entries of the
//! same array for the same body), with the same bounds and the same arithmetic as the
//! `World` method that applies it. Only when every entry passes are they applied, in order,
//! through those `World` methods, so an array is applied whole or not at all.

use std::collections::HashMap;

use tumble_geometry::{Point3, Pose, Vec3};
use tumble_solver::{BodyKind, BodyState, InvalidParameter, bounds};

use super::error::{BatchError, WorldId};
use crate::world_bodies::{target_velocities, velocities_after_impulse};
use crate::{BodyHandle, Error, World};

/// What an [`Action`] does to its body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ActionKind {
    /// An impulse (N s, world axes) at a world point, as [`World::apply_impulse`]; fixed and
    /// kinematic bodies are unaffected.
    Impulse {
        /// The impulse, N s.
        impulse: Vec3,
        /// Where it acts, world coordinates.
        point: Point3,
    },
    /// Sets both velocities, as [`World::set_linear_velocity`] then
    /// [`World::set_angular_velocity`].
    SetVelocity {
        /// Linear velocity, m/s.
        linear: Vec3,
        /// Angular velocity, world axes, rad/s.
        angular: Vec3,
    },
    /// Moves a kinematic body to `target` by the end of the next step, as
    /// [`World::set_kinematic_target`].
    KinematicTarget {
        /// The pose to reach.
        target: Pose,
    },
}

/// One action: a body of one world of the batch, and what to do to it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Action {
    /// The world.
    pub world: WorldId,
    /// The body, a handle of that world.
    pub body: BodyHandle,
    /// What to do.
    pub kind: ActionKind,
}

impl Action {
    /// An impulse at a world point.
    pub fn impulse(world: WorldId, body: BodyHandle, impulse: Vec3, point: Point3) -> Self {
        Self {
            world,
            body,
            kind: ActionKind::Impulse { impulse, point },
        }
    }

    /// Sets the linear and angular velocities.
    pub fn set_velocity(world: WorldId, body: BodyHandle, linear: Vec3, angular: Vec3) -> Self {
        Self {
            world,
            body,
            kind: ActionKind::SetVelocity { linear, angular },
        }
    }

    /// A kinematic body's target for the next step.
    pub fn kinematic_target(world: WorldId, body: BodyHandle, target: Pose) -> Self {
        Self {
            world,
            body,
            kind: ActionKind::KinematicTarget { target },
        }
    }
}

/// The error of entry `index`, from a bound's error.
fn entry_error(index: usize, e: InvalidParameter) -> BatchError {
    BatchError::Action {
        index,
        field: e.field,
        value: e.value,
        expected: e.expected.to_string(),
    }
}

/// The error of entry `index`, from a world's error about its body.
fn body_error(index: usize, body: BodyHandle, e: Error) -> BatchError {
    match e {
        Error::InvalidValue {
            field,
            value,
            expected,
        } => BatchError::Action {
            index,
            field,
            value,
            expected: expected.to_string(),
        },
        other => BatchError::Action {
            index,
            field: "body",
            value: format!("{body:?}"),
            expected: format!("a live body of the entry's world ({other})"),
        },
    }
}

/// Checks every entry of `actions` against the state it will meet; `world_of` resolves an
/// entry's world (its error names the entry). Reads only: the batch is untouched.
pub(crate) fn plan<'w>(
    actions: &[Action],
    mut world_of: impl FnMut(WorldId) -> Result<&'w World, BatchError>,
) -> Result<(), BatchError> {
    // The velocities earlier entries leave, by (world slot, dense index): an impulse adds to
    // them, not to the world's.
    let mut pending: HashMap<(u32, usize), BodyState> = HashMap::new();
    for (index, action) in actions.iter().enumerate() {
        let world = world_of(action.world).map_err(|e| BatchError::Action {
            index,
            field: "world",
            value: action.world.to_string(),
            expected: format!("a world of the batch ({e})"),
        })?;
        let d = world
            .handles
            .dense(action.body)
            .map_err(|e| body_error(index, action.body, e))?;
        let key = (action.world.index, d);
        let body = &world.host.bodies[d];
        let (dt, substeps) = (world.config.dt, world.config.solver.substeps);
        let fail = |e| entry_error(index, e);
        match action.kind {
            ActionKind::SetVelocity { linear, angular } => {
                bounds::require_linear_speed("linear_velocity", &linear).map_err(fail)?;
                bounds::require_angular_speed("angular_velocity", &angular, dt, substeps)
                    .map_err(fail)?;
                if body.kind == BodyKind::Fixed {
                    for (field, v) in [("linear_velocity", linear), ("angular_velocity", angular)] {
                        if v != Vec3::zeros() {
                            return Err(fail(InvalidParameter::new(
                                field,
                                [v.x, v.y, v.z],
                                "zero for a fixed body",
                            )));
                        }
                    }
                }
                let masked = BodyState::moving(
                    linear.component_mul(&body.locks.translation_mask()),
                    angular.component_mul(&body.locks.rotation_mask()),
                );
                pending.insert(key, masked);
            }
            ActionKind::KinematicTarget { target } => {
                bounds::require_pose("pose", &target).map_err(fail)?;
                if body.kind != BodyKind::Kinematic {
                    return Err(fail(InvalidParameter::new(
                        "kind",
                        body.kind,
                        "a kinematic body",
                    )));
                }
                // The function `World::set_kinematic_target` uses; no action moves a pose, so
                // the world's pose is the one the target will be reached from.
                let pose = world
                    .backend
                    .pose(&world.host, d)
                    .map_err(|e| body_error(index, action.body, e))?;
                let (v, w) = target_velocities(&pose, &target, dt, substeps).map_err(fail)?;
                pending.insert(key, BodyState::moving(v, w));
            }
            ActionKind::Impulse { impulse, point } => {
                bounds::require_length_at_most(
                    "impulse",
                    &impulse,
                    bounds::MAX_IMPULSE,
                    bounds::EXPECTED_IMPULSE,
                )
                .map_err(fail)?;
                bounds::require_position("point", &point.coords).map_err(fail)?;
                if !body.is_dynamic() {
                    continue;
                }
                // The function `World::apply_impulse` uses, from the velocities the earlier
                // entries leave.
                let pose = world
                    .backend
                    .pose(&world.host, d)
                    .map_err(|e| body_error(index, action.body, e))?;
                let state = match pending.get(&key) {
                    Some(s) => *s,
                    None => world
                        .backend
                        .state(&world.host, d)
                        .map_err(|e| body_error(index, action.body, e))?,
                };
                let (v, w) =
                    velocities_after_impulse(body, pose, &state, &impulse, &point, dt, substeps)
                        .map_err(fail)?;
                pending.insert(key, BodyState::moving(v, w));
            }
        }
    }
    Ok(())
}

/// Applies one checked action to `world` through the `World` method it stands for.
pub(crate) fn apply(world: &mut World, body: BodyHandle, kind: &ActionKind) -> Result<(), Error> {
    match *kind {
        ActionKind::Impulse { impulse, point } => world.apply_impulse(body, impulse, point),
        ActionKind::SetVelocity { linear, angular } => {
            world.set_linear_velocity(body, linear)?;
            world.set_angular_velocity(body, angular)
        }
        ActionKind::KinematicTarget { target } => world.set_kinematic_target(body, target),
    }
}

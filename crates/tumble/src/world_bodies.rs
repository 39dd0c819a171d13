//! Adding, removing, reading and setting bodies.

use tumble_geometry::{Point3, Pose, Real, Vec3};
use tumble_solver::{Body, BodyKind, BodyState, InvalidParameter, Locks, bounds};

use crate::{BodyDesc, BodyHandle, Error, World};

impl World {
    /// Adds a body. Errs, leaving the world unchanged, on any bad field of `desc`.
    pub fn add_body(&mut self, desc: BodyDesc) -> Result<BodyHandle, Error> {
        let (body, state) = desc.build(&self.config)?;
        self.backend.sync_all(&mut self.host)?;
        self.query.invalidate();
        self.host.bodies.push(body);
        self.host.states.push(state);
        self.host.user_data.push(desc.user_data);
        self.host.sleep.push();
        Ok(self.handles.insert())
    }

    /// Removes a body; its handle is never valid again. Every body with a manifold against it
    /// (last step's, or kept by a sleeping island) wakes: a box asleep on a removed floor must
    /// fall, not hang where it slept (Box2D wakes the bodies touching a destroyed body too).
    pub fn remove_body(&mut self, h: BodyHandle) -> Result<(), Error> {
        let d = self.handles.dense(h)?;
        self.backend.sync_all(&mut self.host)?;
        let touching: Vec<BodyHandle> = {
            let (_, handles) = self.backend.contacts(&self.host);
            let kept = self
                .host
                .sleep
                .sleeping_keys()
                .map(|(a, b)| (BodyHandle::from_bits(a), BodyHandle::from_bits(b)));
            handles
                .iter()
                .copied()
                .chain(kept)
                .filter_map(|(a, b)| match (a == h, b == h) {
                    (true, false) => Some(b),
                    (false, true) => Some(a),
                    _ => None,
                })
                .collect()
        };
        for other in touching {
            if self.contains(other) {
                self.wake_up(other)?;
            }
        }
        self.query.invalidate();
        self.host.bodies.swap_remove(d);
        self.host.states.swap_remove(d);
        self.host.user_data.swap_remove(d);
        self.host.sleep.swap_remove(d);
        self.handles.remove(h, d);
        self.forget_contacts_of(h);
        Ok(())
    }

    /// Number of bodies.
    pub fn body_count(&self) -> usize {
        self.host.bodies.len()
    }

    /// True when `h` names a live body of this world.
    pub fn contains(&self, h: BodyHandle) -> bool {
        self.handles.dense(h).is_ok()
    }

    /// The handles of all live bodies, in the world's internal order.
    pub fn handles(&self) -> &[BodyHandle] {
        self.handles.handles()
    }

    /// The body's pose (centre and rotation).
    pub fn pose(&self, h: BodyHandle) -> Result<Pose, Error> {
        self.backend.pose(&self.host, self.handles.dense(h)?)
    }

    /// The body's linear velocity, m/s.
    pub fn linear_velocity(&self, h: BodyHandle) -> Result<Vec3, Error> {
        Ok(self
            .backend
            .state(&self.host, self.handles.dense(h)?)?
            .linear_velocity)
    }

    /// The body's angular velocity in world axes, rad/s.
    pub fn angular_velocity(&self, h: BodyHandle) -> Result<Vec3, Error> {
        Ok(self
            .backend
            .state(&self.host, self.handles.dense(h)?)?
            .angular_velocity)
    }

    /// Fixed, dynamic or kinematic.
    pub fn kind(&self, h: BodyHandle) -> Result<BodyKind, Error> {
        Ok(self.host.bodies[self.handles.dense(h)?].kind)
    }

    /// The box's half extents, m.
    pub fn half_extents(&self, h: BodyHandle) -> Result<Vec3, Error> {
        Ok(self.host.bodies[self.handles.dense(h)?].shape.half_extents)
    }

    /// The body's mass, kg (infinite for fixed and kinematic bodies).
    pub fn mass(&self, h: BodyHandle) -> Result<Real, Error> {
        let b = &self.host.bodies[self.handles.dense(h)?];
        Ok(if b.inverse_mass > 0.0 {
            1.0 / b.inverse_mass
        } else {
            Real::INFINITY
        })
    }

    /// The body's angular momentum about its centre, world axes, kg m^2/s (zero for
    /// fixed and kinematic bodies).
    pub fn angular_momentum(&self, h: BodyHandle) -> Result<Vec3, Error> {
        let d = self.handles.dense(h)?;
        let (b, pose, s) = (
            &self.host.bodies[d],
            self.backend.pose(&self.host, d)?,
            self.backend.state(&self.host, d)?,
        );
        let local = pose.rotation.inverse_transform_vector(&s.angular_velocity);
        Ok(pose.rotation * b.inertia_local().component_mul(&local))
    }

    /// The body's kinetic energy, J (zero for fixed and kinematic bodies).
    pub fn kinetic_energy(&self, h: BodyHandle) -> Result<Real, Error> {
        let d = self.handles.dense(h)?;
        let b = &self.host.bodies[d];
        if b.inverse_mass == 0.0 {
            return Ok(0.0);
        }
        let (pose, s) = (
            self.backend.pose(&self.host, d)?,
            self.backend.state(&self.host, d)?,
        );
        let local = pose.rotation.inverse_transform_vector(&s.angular_velocity);
        let rotational = 0.5 * local.dot(&b.inertia_local().component_mul(&local));
        Ok(0.5 * s.linear_velocity.norm_squared() / b.inverse_mass + rotational)
    }

    /// Teleports the body (its velocities are kept). Errs on a centre beyond
    /// [`bounds::MAX_POSITION`] or a rotation that is not a unit quaternion.
    pub fn set_pose(&mut self, h: BodyHandle, pose: Pose) -> Result<(), Error> {
        let d = self.handles.dense(h)?;
        bounds::require_pose("pose", &pose)?;
        self.backend.sync_motion(&mut self.host)?;
        let mut pose = pose;
        pose.rotation.renormalize();
        self.query.invalidate();
        self.host.bodies[d].pose = pose;
        self.host.sleep.wake(d);
        Ok(())
    }

    /// Sets the linear velocity. Errs for a fixed body unless `v` is zero, and above
    /// [`bounds::MAX_SPEED`].
    pub fn set_linear_velocity(&mut self, h: BodyHandle, v: Vec3) -> Result<(), Error> {
        let d = self.handles.dense(h)?;
        bounds::require_linear_speed("linear_velocity", &v)?;
        self.set_velocity(d, "linear_velocity", v, Locks::translation_mask, |s| {
            &mut s.linear_velocity
        })
    }

    /// Sets the angular velocity (world axes). Errs for a fixed body unless `w` is zero, and
    /// above the spin the world's substeps carry ([`bounds::max_angular_speed`]).
    pub fn set_angular_velocity(&mut self, h: BodyHandle, w: Vec3) -> Result<(), Error> {
        let d = self.handles.dense(h)?;
        let (dt, substeps) = (self.config.dt, self.config.solver.substeps);
        bounds::require_angular_speed("angular_velocity", &w, dt, substeps)?;
        self.set_velocity(d, "angular_velocity", w, Locks::rotation_mask, |s| {
            &mut s.angular_velocity
        })
    }

    /// The rest of `set_linear_velocity` and `set_angular_velocity` for body `d`, once the
    /// bound on `value` (the velocity named `field`) is checked: errs for a fixed body unless
    /// `value` is zero, else writes `value` with the locked axes (`mask` of the body's locks)
    /// zeroed into the velocity `slot` picks, and wakes the body.
    fn set_velocity(
        &mut self,
        d: usize,
        field: &'static str,
        value: Vec3,
        mask: fn(&Locks) -> Vec3,
        slot: fn(&mut BodyState) -> &mut Vec3,
    ) -> Result<(), Error> {
        let body = &self.host.bodies[d];
        if body.kind == BodyKind::Fixed && value != Vec3::zeros() {
            return Err(InvalidParameter::new(
                field,
                [value.x, value.y, value.z],
                "zero for a fixed body",
            )
            .into());
        }
        let mask = mask(&body.locks);
        self.backend.sync_motion(&mut self.host)?;
        *slot(&mut self.host.states[d]) = value.component_mul(&mask);
        self.host.sleep.wake(d);
        Ok(())
    }

    /// Sets a kinematic body's velocities so that it reaches `target` at the end of the next
    /// step. Errs for bodies that are not kinematic, for a target beyond
    /// [`bounds::MAX_POSITION`], and for one that would take a speed above
    /// [`bounds::MAX_SPEED`] or a spin above [`bounds::max_angular_speed`] to reach.
    pub fn set_kinematic_target(&mut self, h: BodyHandle, target: Pose) -> Result<(), Error> {
        let d = self.handles.dense(h)?;
        // Named `pose`, as in `set_pose`: the same check of the same kind of value.
        bounds::require_pose("pose", &target)?;
        let body = &self.host.bodies[d];
        if body.kind != BodyKind::Kinematic {
            return Err(InvalidParameter::new("kind", body.kind, "a kinematic body").into());
        }
        let (dt, substeps) = (self.config.dt, self.config.solver.substeps);
        let pose = self.backend.pose(&self.host, d)?;
        let (v, w) = target_velocities(&pose, &target, dt, substeps)?;
        self.backend.sync_motion(&mut self.host)?;
        self.host.states[d].linear_velocity = v;
        self.host.states[d].angular_velocity = w;
        Ok(())
    }

    /// Applies an impulse `impulse` (N s, world) at world point `point` to a dynamic body;
    /// fixed and kinematic bodies are unaffected.
    pub fn apply_impulse(
        &mut self,
        h: BodyHandle,
        impulse: Vec3,
        point: Point3,
    ) -> Result<(), Error> {
        let d = self.handles.dense(h)?;
        let impulse_bound = (bounds::MAX_IMPULSE, bounds::EXPECTED_IMPULSE);
        bounds::require_length_at_most("impulse", &impulse, impulse_bound.0, impulse_bound.1)?;
        bounds::require_position("point", &point.coords)?;
        if !self.host.bodies[d].is_dynamic() {
            return Ok(());
        }
        // The velocities the impulse leaves are checked before anything is written.
        let (pose, state) = (
            self.backend.pose(&self.host, d)?,
            self.backend.state(&self.host, d)?,
        );
        let (dt, substeps) = (self.config.dt, self.config.solver.substeps);
        let body = &self.host.bodies[d];
        let (v, w) = velocities_after_impulse(body, pose, &state, &impulse, &point, dt, substeps)?;
        self.backend.sync_motion(&mut self.host)?;
        let state = &mut self.host.states[d];
        state.linear_velocity = v;
        state.angular_velocity = w;
        self.host.sleep.wake(d);
        Ok(())
    }
}

/// The velocities that take a kinematic body from `pose` to `target` in one step of `dt`
/// (`substeps` substeps), refused (as `target`) beyond the speed and spin bounds. Shared by
/// [`World::set_kinematic_target`] and the batch's check of the same action.
pub(crate) fn target_velocities(
    pose: &Pose,
    target: &Pose,
    dt: Real,
    substeps: u32,
) -> Result<(Vec3, Vec3), InvalidParameter> {
    let inv_dt = 1.0 / dt;
    let v = (target.translation.vector - pose.translation.vector) * inv_dt;
    let turn = target.rotation * pose.rotation.inverse();
    let w = turn.scaled_axis() * inv_dt;
    bounds::require_length_at_most(
        "target",
        &v,
        bounds::MAX_SPEED,
        bounds::EXPECTED_TARGET_SPEED,
    )?;
    let max_w = bounds::max_angular_speed(dt, substeps);
    bounds::require_length_at_most("target", &w, max_w, bounds::EXPECTED_TARGET_SPIN)?;
    Ok((v, w))
}

/// The velocities `impulse` at world `point` leaves on `body` (at `pose`, moving at `state`),
/// refused (as `impulse`) when they exceed the speed or spin bounds of a step of `dt` in
/// `substeps` substeps. Shared by [`World::apply_impulse`] and the batch's check of the same
/// action.
pub(crate) fn velocities_after_impulse(
    body: &Body,
    pose: Pose,
    state: &BodyState,
    impulse: &Vec3,
    point: &Point3,
    dt: Real,
    substeps: u32,
) -> Result<(Vec3, Vec3), InvalidParameter> {
    let mut body = *body;
    body.pose = pose;
    let r = point.coords - body.pose.translation.vector;
    let v = state.linear_velocity + body.inverse_mass_axes().component_mul(impulse);
    let w = state.angular_velocity + body.inverse_inertia_world() * r.cross(impulse);
    let result = bounds::EXPECTED_IMPULSE_RESULT;
    let too_fast = bounds::require_length_at_most("impulse", &v, bounds::MAX_SPEED, result)
        .and_then(|()| {
            let max_w = bounds::max_angular_speed(dt, substeps);
            bounds::require_length_at_most("impulse", &w, max_w, result)
        });
    match too_fast {
        Ok(()) => Ok((v, w)),
        Err(_) => Err(InvalidParameter::new(
            "impulse",
            [impulse.x, impulse.y, impulse.z],
            result,
        )),
    }
}

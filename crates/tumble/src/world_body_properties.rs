//! Reading and setting the bodies' collision groups, persistent forces and torques, gravity
//! scales and user data.

use tumble_geometry::{Real, Vec3};
use tumble_solver::{Body, CollisionGroups, bounds};

use crate::{BodyHandle, Error, World};

impl World {
    /// The body's collision groups.
    pub fn collision_groups(&self, h: BodyHandle) -> Result<CollisionGroups, Error> {
        Ok(self.host.bodies[self.handles.dense(h)?].groups)
    }

    /// Sets which bodies this one may collide with, from the next step on (the broad phase
    /// forms no pair whose groups do not interact: see [`CollisionGroups`]). Wakes the body
    /// when the groups change.
    pub fn set_collision_groups(
        &mut self,
        h: BodyHandle,
        groups: CollisionGroups,
    ) -> Result<(), Error> {
        let d = self.handles.dense(h)?;
        self.change_body(d, |b| b.groups = groups)
    }

    /// The persistent force on the body, N (world axes, at the centre of mass).
    pub fn force(&self, h: BodyHandle) -> Result<Vec3, Error> {
        Ok(self.host.bodies[self.handles.dense(h)?].force)
    }

    /// Sets the force (N, world axes, at the centre of mass) that acts on the body in every
    /// substep of every step until it is set again; `Vec3::zeros()` removes it. It replaces
    /// the force set before (it is not added to it, and steps do not clear it). Fixed and
    /// kinematic bodies keep it but are not moved by it. Wakes the body when the force
    /// changes. Errs on a non-finite force, one above [`bounds::MAX_FORCE`], or one that
    /// would add more than [`bounds::MAX_SPEED`] to the body's velocity in one step.
    pub fn set_force(&mut self, h: BodyHandle, force: Vec3) -> Result<(), Error> {
        let d = self.handles.dense(h)?;
        bounds::require_force(&self.host.bodies[d], &force, self.config.dt)?;
        self.change_body(d, |b| b.force = force)
    }

    /// The persistent torque on the body, N m (world axes).
    pub fn torque(&self, h: BodyHandle) -> Result<Vec3, Error> {
        Ok(self.host.bodies[self.handles.dense(h)?].torque)
    }

    /// Sets the torque (N m, world axes) that acts on the body in every substep of every step
    /// until it is set again, as [`World::set_force`] does for the force. Errs on a
    /// non-finite torque, one above [`bounds::MAX_TORQUE`], or one that would add more than
    /// [`bounds::max_angular_speed`] of spin in one step.
    pub fn set_torque(&mut self, h: BodyHandle, torque: Vec3) -> Result<(), Error> {
        let d = self.handles.dense(h)?;
        let (dt, substeps) = (self.config.dt, self.config.solver.substeps);
        bounds::require_torque(&self.host.bodies[d], &torque, dt, substeps)?;
        self.change_body(d, |b| b.torque = torque)
    }

    /// The multiple of the world's gravity acting on the body.
    pub fn gravity_scale(&self, h: BodyHandle) -> Result<Real, Error> {
        Ok(self.host.bodies[self.handles.dense(h)?].gravity_scale)
    }

    /// Sets the multiple of the world's gravity acting on the body: 0 floats, 2 falls twice
    /// as fast, -1 rises. Errs outside `[-10, 10]` ([`bounds::MAX_GRAVITY_SCALE`]) and on NaN.
    /// Wakes the body when the scale changes.
    pub fn set_gravity_scale(&mut self, h: BodyHandle, scale: Real) -> Result<(), Error> {
        let d = self.handles.dense(h)?;
        bounds::require_gravity_scale(scale)?;
        self.change_body(d, |b| b.gravity_scale = scale)
    }

    /// The body's user data (`BodyDesc::user_data`, 0 unless set).
    pub fn user_data(&self, h: BodyHandle) -> Result<u128, Error> {
        Ok(self.host.user_data[self.handles.dense(h)?])
    }

    /// Sets the body's user data: a value kept for the caller, never read by the physics.
    pub fn set_user_data(&mut self, h: BodyHandle, data: u128) -> Result<(), Error> {
        let d = self.handles.dense(h)?;
        self.host.user_data[d] = data;
        Ok(())
    }

    /// Applies `change` to body `d`'s cold data (already validated); when that changed it,
    /// tells the backend and wakes the body, so that the next step uses it.
    fn change_body(&mut self, d: usize, change: impl FnOnce(&mut Body)) -> Result<(), Error> {
        let mut body = self.host.bodies[d];
        change(&mut body);
        if body == self.host.bodies[d] {
            return Ok(());
        }
        let old = std::mem::replace(&mut self.host.bodies[d], body);
        if let Err(e) = self
            .backend
            .body_changed(&self.host, d)
            .and_then(|()| self.backend.wake(&mut self.host, d))
        {
            self.host.bodies[d] = old;
            return Err(e);
        }
        Ok(())
    }
}

//! Building a world from a canonical scene.

use tumble_geometry::{Rot, Vec3, nalgebra::Quaternion};
use tumble_scenes::{BodyKind as SceneKind, BodySpec, Scene};
use tumble_solver::BodyKind;

use crate::{BodyDesc, BodyHandle, Error, World, WorldConfig};

/// The descriptor of one scene body. The scene's rotation is normalized (scenes allow a
/// small round-off in the stored quaternion).
pub fn body_desc(spec: &BodySpec) -> BodyDesc {
    let kind = match spec.kind {
        SceneKind::Fixed => BodyKind::Fixed,
        SceneKind::Dynamic => BodyKind::Dynamic,
        SceneKind::Kinematic => BodyKind::Kinematic,
    };
    let [x, y, z, w] = spec.rotation;
    let desc = match kind {
        BodyKind::Fixed => BodyDesc::fixed(),
        BodyKind::Dynamic => BodyDesc::dynamic(),
        BodyKind::Kinematic => BodyDesc::kinematic(),
    };
    let mut pose = tumble_geometry::Pose::identity();
    pose.translation.vector = Vec3::from(spec.position);
    pose.rotation = Rot::new_normalize(Quaternion::new(w, x, y, z));
    desc.cuboid(Vec3::from(spec.half_extents))
        .pose(pose)
        .density(spec.density)
        .friction(spec.friction)
        .restitution(spec.restitution)
        .linear_velocity(Vec3::from(spec.linear_velocity))
        .angular_velocity(Vec3::from(spec.angular_velocity))
}

impl World {
    /// Builds `scene` in a new world. The scene's gravity and time step replace those of
    /// `config`; the solver, backend and margin come from `config`. Returns the world and the
    /// handle of each scene body, in scene order. The scene's `steps` is for the caller to run.
    pub fn from_scene(
        scene: &Scene,
        config: WorldConfig,
    ) -> Result<(World, Vec<BodyHandle>), Error> {
        scene
            .validate()
            .map_err(|e| Error::InvalidScene(e.to_string()))?;
        let config = WorldConfig {
            gravity: Vec3::from(scene.gravity),
            dt: scene.dt,
            ..config
        };
        let mut world = World::new(config)?;
        // A body outside the engine's bounds is named by its index in the scene.
        let handles = scene
            .bodies
            .iter()
            .enumerate()
            .map(|(i, spec)| {
                world
                    .add_body(body_desc(spec))
                    .map_err(|e| Error::InvalidScene(format!("bodies[{i}]: {e}")))
            })
            .collect::<Result<Vec<_>, _>>()?;
        Ok((world, handles))
    }
}

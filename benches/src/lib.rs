//! Shared helpers for the criterion benches.
#![warn(missing_docs)]
pub mod effect_pool;
pub mod gpu_pool;

/// The value after `--name` on the command line, parsed, or `default` when it is missing or
/// does not parse (the table binaries' options).
pub fn arg(name: &str, default: usize) -> usize {
    let args: Vec<String> = std::env::args().collect();
    args.iter()
        .position(|a| a == name)
        .and_then(|i| args.get(i + 1))
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

use tumble_geometry::nalgebra::{Quaternion, Translation3, UnitQuaternion};
use tumble_geometry::{Cuboid, Pose, Vec3};
use tumble_scenes::{BodyKind as SceneKind, Scene};
use tumble_solver::{Body, BodyKind, BodyState, Material};

/// The solver's bodies and states of a scene.
pub fn bodies_of(scene: &Scene) -> (Vec<Body>, Vec<BodyState>) {
    scene
        .bodies
        .iter()
        .map(|s| {
            let kind = match s.kind {
                SceneKind::Fixed => BodyKind::Fixed,
                SceneKind::Dynamic => BodyKind::Dynamic,
                SceneKind::Kinematic => BodyKind::Kinematic,
            };
            let [x, y, z, w] = s.rotation;
            let pose = Pose::from_parts(
                Translation3::new(s.position[0], s.position[1], s.position[2]),
                UnitQuaternion::from_quaternion(Quaternion::new(w, x, y, z)),
            );
            let material = Material {
                friction: s.friction,
                restitution: s.restitution,
            };
            let body = Body::new(
                kind,
                Cuboid::new(Vec3::from(s.half_extents)),
                pose,
                s.density,
                material,
            )
            .expect("canonical scenes are valid");
            let state = BodyState::moving(
                Vec3::from(s.linear_velocity),
                Vec3::from(s.angular_velocity),
            );
            (body, state)
        })
        .unzip()
}

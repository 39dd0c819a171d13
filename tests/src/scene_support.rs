//! Scene helpers shared by the tests and the benches: the solver's bodies of a canonical
//! scene, how far its bodies moved from where the scene put them, and random boxes for the
//! broad phase.

use std::ops::Range;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::nalgebra::{Quaternion, Translation3, UnitQuaternion};
use tumble_geometry::{Aabb, Cuboid, Point3, Pose, Real, Rot, Vec3};
use tumble_gpu::step::{GpuWorld, GpuWorldConfig};
use tumble_gpu::{GpuContext, GpuError};
use tumble_scenes::{BodyKind as SceneKind, Scene};
use tumble_solver::{Body, BodyKind, BodyState, Material};

/// A `GpuWorld` on `ctx` holding `scene`'s bodies, stepping at the scene's gravity and time
/// step with the rest of `config`.
pub fn gpu_world_of(
    ctx: &GpuContext,
    scene: &Scene,
    config: GpuWorldConfig,
) -> Result<GpuWorld, GpuError> {
    let (bodies, states) = bodies_of(scene);
    let mut world = GpuWorld::new(
        ctx,
        GpuWorldConfig {
            gravity: Vec3::from(scene.gravity),
            dt: scene.dt,
            ..config
        },
    )?;
    world.set_bodies(&bodies, &states)?;
    Ok(world)
}

/// A vector whose components are drawn from `range` in turn, x first.
pub fn random_vec(rng: &mut impl Rng, range: Range<Real>) -> Vec3 {
    Vec3::new(
        rng.random_range(range.clone()),
        rng.random_range(range.clone()),
        rng.random_range(range),
    )
}

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

/// The largest horizontal (x-z) displacement of any dynamic body from its scene position.
pub fn horizontal_drift(scene: &Scene, positions: &[[f32; 3]]) -> f32 {
    scene
        .bodies
        .iter()
        .zip(positions)
        .filter(|(spec, _)| spec.is_dynamic())
        .map(|(spec, p)| {
            let dx = p[0] - spec.position[0];
            let dz = p[2] - spec.position[2];
            (dx * dx + dz * dz).sqrt()
        })
        .fold(0.0, f32::max)
}

/// The start pose of box `i` of the loose pile of twelve tilted unit boxes that the effect
/// tests (`effects`, `gpu_wide_effects.rs`) throw onto a floor: four across, three high.
pub fn thrown_pile_pose(i: usize) -> Pose {
    let (x, y, z) = (
        (i % 4) as Real * 0.9,
        0.6 + (i / 4) as Real * 1.1,
        0.3 * (i % 3) as Real,
    );
    let tilt = Rot::from_euler_angles(0.1 * i as Real, 0.2, -0.05 * i as Real);
    Pose::from_parts(Vec3::new(x, y, z).into(), tilt)
}

/// `n` boxes with centres uniform in a cube of side `extent` and half sizes in `[0.05, 0.5]`
/// m, seeded by `seed`.
pub fn sparse_boxes(n: usize, extent: f32, seed: u64) -> Vec<Aabb> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    (0..n)
        .map(|_| {
            let c = Point3::new(
                rng.random_range(0.0..extent),
                rng.random_range(0.0..extent),
                rng.random_range(0.0..extent),
            );
            let h = random_vec(&mut rng, 0.05..0.5);
            Aabb::new(c - h, c + h)
        })
        .collect()
}

/// Each body's step AABB at rest (zero velocities, the default margin, a 60 Hz step) and its
/// immovable flag: the broad phase's input for a scene standing still.
pub fn resting_aabbs(scene: &Scene) -> (Vec<Aabb>, Vec<bool>) {
    let zero = Vec3::zeros();
    let aabbs = scene
        .bodies
        .iter()
        .map(|b| {
            tumble_broad::motion_aabb(
                &b.cuboid(),
                &b.pose(),
                &zero,
                &zero,
                tumble::DEFAULT_MARGIN,
                1.0 / 60.0,
            )
        })
        .collect();
    let immovable = scene.bodies.iter().map(|b| !b.is_dynamic()).collect();
    (aabbs, immovable)
}

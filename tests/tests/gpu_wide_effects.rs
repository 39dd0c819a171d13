//! The effects contract of `effects.rs` on the GPU solver's wide path (one dispatch per color
//! and pass, separate pipelines for the body and constraint stages), which the facade only
//! takes for large scenes: for a scene that does not use an effect, the step with the effect
//! compiled in and the step with it compiled out end with the same bits.
//!
//! The comparison is bitwise because skipping an effect may only remove work whose result is
//! exactly zero for such a scene (a locked body's angular terms, a frictionless contact's
//! friction rows...), and the solver runs the remaining operations the same way in both
//! specializations: for rotation, a constraint between bodies that cannot turn skips its
//! angular terms instead of adding zeros (`body_turns` in `contact_math.wgsl`), because a
//! shader compiler may reorder the additions around such terms differently in two programs.
//! On an H100, a pool of 1,000 rotation-locked cubes (wide path) ended with different bits
//! with rotation compiled in and out before that change; lavapipe gives equal bits with and
//! without it, so there these tests hold the contract rather than reproduce that run. Each
//! scene also runs twice with the effect on: the wide path is deterministic
//! (`gpu_determinism.rs`), so a difference can only come from the specializations.
//!
//! Needs a GPU or lavapipe; without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`.

use tumble_geometry::{Cuboid, Pose, Real, Rot, Vec3};
use tumble_gpu::GpuContext;
use tumble_gpu::solver::{Effects, SolvePath};
use tumble_gpu::step::{GpuWorld, GpuWorldConfig, PathPolicy, ReadRequest};
use tumble_solver::{Body, BodyKind, BodyState, Material};

/// Steps per run: 0.5 s at 60 Hz, in which the bottom layer lands and the thrown boxes
/// collide, so every stage has work; short because lavapipe, the CI adapter, is slow.
const STEPS: usize = 30;

const G: Vec3 = Vec3::new(0.0, -9.81, 0.0);

/// The scene of `effects.rs`: a floor and a loose pile of twelve tilted boxes thrown
/// sideways, spinning unless `lock_rotations` (then a locked body is given no spin, as the
/// facade masks it).
fn pile(friction: Real, restitution: Real, lock_rotations: bool) -> (Vec<Body>, Vec<BodyState>) {
    let material = Material {
        friction,
        restitution,
    };
    let mut bodies = vec![
        Body::new(
            BodyKind::Fixed,
            Cuboid::new(Vec3::new(20.0, 0.5, 20.0)),
            Pose::translation(0.0, -0.5, 0.0),
            1.0,
            material,
        )
        .unwrap(),
    ];
    let mut states = vec![BodyState::default()];
    for i in 0..12 {
        let (x, y, z) = (
            (i % 4) as Real * 0.9,
            0.6 + (i / 4) as Real * 1.1,
            0.3 * (i % 3) as Real,
        );
        let tilt = Rot::from_euler_angles(0.1 * i as Real, 0.2, -0.05 * i as Real);
        let mut body = Body::new(
            BodyKind::Dynamic,
            Cuboid::new(Vec3::repeat(0.5)),
            Pose::from_parts(Vec3::new(x, y, z).into(), tilt),
            1.0,
            material,
        )
        .unwrap();
        let mut spin = Vec3::new(0.0, 1.0, 0.3);
        if lock_rotations {
            body.locks.rotation = [true; 3];
            spin = Vec3::zeros();
        }
        bodies.push(body);
        states.push(BodyState::moving(
            Vec3::new(1.5, 0.0, 0.5 * (i % 2) as Real),
            spin,
        ));
    }
    (bodies, states)
}

/// Every bit of every body's pose and velocities after [`STEPS`] wide-path steps with
/// exactly `effects` compiled in, after checking that the scene moved and that locked
/// rotations stayed locked.
fn run(
    ctx: &GpuContext,
    gravity: Vec3,
    scene: &(Vec<Body>, Vec<BodyState>),
    effects: Effects,
) -> Vec<u32> {
    let mut world = GpuWorld::new(
        ctx,
        GpuWorldConfig {
            gravity,
            path: PathPolicy::Always(SolvePath::Wide),
            ..Default::default()
        },
    )
    .unwrap();
    world.set_bodies(&scene.0, &scene.1).unwrap();
    world.set_effects(effects).unwrap();
    for _ in 0..STEPS {
        world.step().unwrap();
    }
    assert_eq!(world.last_path(), Some(SolvePath::Wide));
    let snapshot = world.read_now(ReadRequest::MOTION).unwrap();
    // Thrown at 1.5 m/s, a box would travel 0.75 m in 0.5 s; the rough floor stops one in
    // about 0.2 m, and a locked box can wedge on a corner sooner, but every box moves: these
    // scenes move each box 4 cm at least and 0.45 m on average. A step that did nothing would
    // make equal bits prove nothing.
    let mut total = 0.0;
    for (i, body) in scene.0.iter().enumerate().skip(1) {
        let (start, end) = (&body.pose, snapshot.pose(i));
        let moved = (end.translation.vector - start.translation.vector).norm();
        assert!(moved > 0.01, "body {i} moved only {moved} m");
        total += moved;
        if body.locks.all_rotations() {
            // A locked box never turns: its angular velocity is masked every substep and no
            // contact adds to it; only the pose's renormalization may move the quaternion by
            // a few ulps (a free box here turns by several hundredths of a radian at least).
            let w = &snapshot.velocities[i].angular[..3];
            assert_eq!(w, &[0.0; 3], "body {i} spins");
            let turned = end.rotation.angle_to(&start.rotation);
            assert!(turned < 1e-6, "body {i} turned {turned} rad");
        }
    }
    let mean = total / (scene.0.len() - 1) as Real;
    assert!(mean > 0.25, "the boxes moved {mean} m on average");
    let mut bits = Vec::new();
    for (p, v) in snapshot.poses.iter().zip(&snapshot.velocities) {
        let values = p.position[..3].iter().chain(&p.rotation);
        let values = values.chain(&v.linear[..3]).chain(&v.angular[..3]);
        bits.extend(values.map(|x| x.to_bits()));
    }
    assert_eq!(bits.len(), scene.0.len() * 13);
    bits
}

/// Asserts that the scene does not need the effect and that the wide path gives the same
/// bits with it compiled in (twice: the path is deterministic) and compiled out.
fn same_bits_on_and_off(
    name: &str,
    gravity: Vec3,
    scene: (Vec<Body>, Vec<BodyState>),
    set: fn(&mut Effects, bool),
) {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let derived = Effects::of_scene(&scene.0, &gravity);
    let (mut on, mut off) = (derived, derived);
    set(&mut on, true);
    set(&mut off, false);
    assert_eq!(derived, off, "{name}: the scene should not need it");
    let first = run(&ctx, gravity, &scene, on);
    let second = run(&ctx, gravity, &scene, on);
    assert_eq!(first, second, "{name}: two wide runs with it on differ");
    let skipped = run(&ctx, gravity, &scene, off);
    assert_eq!(first, skipped, "{name}: forced on and skipped differ");
}

#[test]
fn wide_rotation_skipped_when_every_rotation_is_locked() {
    same_bits_on_and_off("rotation", G, pile(0.6, 0.0, true), |e, on| e.rotation = on);
}

#[test]
fn wide_friction_skipped_in_a_frictionless_pool() {
    same_bits_on_and_off("friction", G, pile(0.0, 0.0, false), |e, on| {
        e.friction = on
    });
}

#[test]
fn wide_restitution_skipped_when_nothing_bounces() {
    same_bits_on_and_off("restitution", G, pile(0.6, 0.0, false), |e, on| {
        e.restitution = on
    });
}

#[test]
fn wide_gravity_skipped_in_zero_gravity() {
    same_bits_on_and_off("gravity", Vec3::zeros(), pile(0.6, 0.0, false), |e, on| {
        e.gravity = on
    });
}

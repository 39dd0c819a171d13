//! The effects contract of `effects/` on the GPU solver's wide path (one dispatch per color
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
//! Equal bits alone would also come from pipelines that ignore the switches, and lavapipe
//! cannot show the H100's rounding, so two more kinds of test make this file able to fail
//! on lavapipe: each effect a scene uses, forced off on the wide path, changes the motion as
//! leaving that physics out must (friction, restitution, gravity, rotation); and the wide
//! path's contact kernels, specialized as it builds them, are one SPIR-V program with
//! rotation (and gravity and restitution) compiled in and out, which is what keeps any
//! compiler from rounding the two variants differently.
//!
//! Needs a GPU or lavapipe; without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`.

use tumble_geometry::{Cuboid, Pose, Real, Rot, Vec3};
use tumble_gpu::solver::prepare::PREPARE_CONTACTS;
use tumble_gpu::solver::solve_color::{PassKind, SOLVE_COLOR, SOLVE_COLOR_IMMEDIATE};
use tumble_gpu::solver::store::STORE_IMPULSES;
use tumble_gpu::solver::{Effects, SolvePath, effect_overrides};
use tumble_gpu::step::{GpuWorld, GpuWorldConfig, PathPolicy, ReadRequest};
use tumble_gpu::{GpuContext, KernelSpec};
use tumble_solver::{Body, BodyKind, BodyState, Material};
use tumble_tests::effect_bounds::{
    Apex, BOUNCE, DROP, TILT, assert_free_fall, assert_friction_stops_the_slide,
    assert_restitution_bounces, assert_tipped_cube_turns, tipped_height,
};
use tumble_tests::gpu_solver_util::floor;
use tumble_tests::scene_support::thrown_pile_pose;
use tumble_tests::shader_checks::compute_spirv;

/// Steps per run: 0.5 s at 60 Hz, in which the bottom layer lands and the thrown boxes
/// collide, so every stage has work; short because lavapipe, the CI adapter, is slow.
const STEPS: usize = 30;

const G: Vec3 = Vec3::new(0.0, -9.81, 0.0);

/// The scene of `effects/`: a floor and a loose pile of twelve tilted boxes thrown
/// sideways, spinning unless `lock_rotations` (then a locked body is given no spin, as the
/// facade masks it).
fn pile(friction: Real, restitution: Real, lock_rotations: bool) -> (Vec<Body>, Vec<BodyState>) {
    let material = Material {
        friction,
        restitution,
    };
    let mut bodies = vec![floor(material)];
    let mut states = vec![BodyState::default()];
    for i in 0..12 {
        let mut body = Body::new(
            BodyKind::Dynamic,
            Cuboid::new(Vec3::repeat(0.5)),
            thrown_pile_pose(i),
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

/// A GPU world of `scene` under `gravity`, held on the wide solver path, with exactly
/// `effects` compiled in.
fn wide_world(
    ctx: &GpuContext,
    gravity: Vec3,
    scene: &(Vec<Body>, Vec<BodyState>),
    effects: Effects,
) -> GpuWorld {
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
    world
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
    let mut world = wide_world(ctx, gravity, scene, effects);
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
    let derived = Effects::of_bodies(&scene.0, &gravity);
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

// ---------------------------------------------------------------------------------------------
// The switches reach the wide path's pipelines: an effect the scene uses, forced off there,
// changes the motion as leaving that physics out must
// ---------------------------------------------------------------------------------------------
//
// Without these, every test above would also pass if the wide path were built with every
// effect compiled in whatever the switches say: on and off would then be one program, and
// equal bits would prove nothing about skipping.

/// A unit cube of `material` at `pose`.
fn unit_cube(pose: Pose, material: Material) -> Body {
    Body::new(
        BodyKind::Dynamic,
        Cuboid::new(Vec3::repeat(0.5)),
        pose,
        1.0,
        material,
    )
    .unwrap()
}

const ROUGH: Material = Material {
    friction: 0.6,
    restitution: 0.0,
};

/// Steps `scene` `steps` times on the wide path with its derived effects, one of them (chosen
/// by `set`) forced to `on`, calling `watch` with body 1's pose and velocities after every
/// step. The scene must need that effect.
fn watch_wide(
    ctx: &GpuContext,
    gravity: Vec3,
    scene: &(Vec<Body>, Vec<BodyState>),
    set: fn(&mut Effects, bool),
    on: bool,
    steps: usize,
    mut watch: impl FnMut(&Pose, &BodyState),
) {
    let derived = Effects::of_bodies(&scene.0, &gravity);
    let mut without = derived;
    set(&mut without, false);
    assert_ne!(without, derived, "the scene should need the effect");
    let mut effects = derived;
    set(&mut effects, on);
    let mut world = wide_world(ctx, gravity, scene, effects);
    for _ in 0..steps {
        world.step().unwrap();
        let snapshot = world.read_now(ReadRequest::MOTION).unwrap();
        watch(&snapshot.pose(1), &snapshot.state(1));
    }
    assert_eq!(world.last_path(), Some(SolvePath::Wide));
}

/// [`watch_wide`] under gravity `G` with the effect forced on, then off: each run starts a
/// value with `start` and lets `watch` update it after every step; the two values.
fn on_and_off<T>(
    ctx: &GpuContext,
    scene: &(Vec<Body>, Vec<BodyState>),
    set: fn(&mut Effects, bool),
    steps: usize,
    start: impl Fn() -> T,
    watch: impl Fn(&mut T, &Pose, &BodyState),
) -> (T, T) {
    let run = |on| {
        let mut value = start();
        watch_wide(ctx, G, scene, set, on, steps, |p, s| {
            watch(&mut value, p, s)
        });
        value
    };
    (run(true), run(false))
}

#[test]
fn wide_friction_forced_off_lets_a_thrown_cube_slide_on() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let cube = unit_cube(Pose::translation(0.0, 0.5, 0.0), ROUGH);
    let scene = (
        vec![floor(ROUGH), cube],
        vec![
            BodyState::default(),
            BodyState::moving(Vec3::new(3.0, 0.0, 0.0), Vec3::zeros()),
        ],
    );
    let set = |e: &mut Effects, s| e.friction = s;
    let (on, off) = on_and_off(&ctx, &scene, set, 36, Vec3::zeros, |v, _, s| {
        *v = s.linear_velocity;
    });
    assert_friction_stops_the_slide(on.x, off.x);
}

#[test]
fn wide_restitution_forced_off_stops_the_bounce() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let bouncy = Material {
        restitution: BOUNCE,
        ..ROUGH
    };
    let cube = unit_cube(Pose::translation(0.0, 0.5 + DROP, 0.0), bouncy);
    let scene = (
        vec![floor(ROUGH), cube],
        vec![BodyState::default(), BodyState::default()],
    );
    let set = |e: &mut Effects, s| e.restitution = s;
    let (on, off) = on_and_off(&ctx, &scene, set, 45, Apex::default, |apex, p, s| {
        apex.watch(p.translation.y - 0.5, s.linear_velocity.y);
    });
    assert_restitution_bounces(on.height, off.height);
}

#[test]
fn wide_gravity_forced_off_leaves_a_cube_in_the_air() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let start = Pose::translation(0.0, 5.0, 0.0);
    let scene = (
        vec![floor(ROUGH), unit_cube(start, ROUGH)],
        vec![BodyState::default(), BodyState::default()],
    );
    let steps = 30;
    let set = |e: &mut Effects, s| e.gravity = s;
    let at_rest = || (start, BodyState::default());
    let ((on, _), (off, state)) = on_and_off(&ctx, &scene, set, steps, at_rest, |end, p, s| {
        *end = (*p, *s);
    });
    let config = GpuWorldConfig::default();
    let dropped = 5.0 - on.translation.y;
    assert_free_fall(dropped, G.y, config.dt, config.solver.substeps, steps);
    // Without it nothing acts on the cube: it stays exactly where it was, at rest.
    assert_eq!(
        off.translation, start.translation,
        "the cube moved without gravity"
    );
    assert_eq!(state.linear_velocity, Vec3::zeros());
}

#[test]
fn wide_rotation_forced_off_keeps_a_tipped_cube_from_turning() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let y = tipped_height();
    let tilt = Rot::from_euler_angles(0.0, 0.0, TILT);
    let start = Pose::from_parts(Vec3::new(0.0, y, 0.0).into(), tilt);
    let scene = (
        vec![floor(ROUGH), unit_cube(start, ROUGH)],
        vec![BodyState::default(), BodyState::default()],
    );
    let set = |e: &mut Effects, s| e.rotation = s;
    let (on, off) = on_and_off(
        &ctx,
        &scene,
        set,
        45,
        || 0.0,
        |turned: &mut Real, p, _| {
            *turned = turned.max(p.rotation.angle_to(&tilt));
        },
    );
    assert_tipped_cube_turns(on, off);
}

// ---------------------------------------------------------------------------------------------
// The contact rows are one program with rotation compiled in and out
// ---------------------------------------------------------------------------------------------

/// The SPIR-V of `spec` specialized as the wide path builds it with `effects` (and `pass`
/// for the per-color pass kernel), through the same override processing wgpu applies.
fn specialized_spirv(spec: &'static KernelSpec, effects: Effects, pass: Option<u32>) -> Vec<u32> {
    let mut extra = effect_overrides(&effects).to_vec();
    if let Some(pass) = pass {
        extra.push(("PASS", f64::from(pass)));
    }
    let values = spec.declared(&extra).unwrap();
    let (module, info) = spec
        .check_specialized(&values)
        .unwrap_or_else(|e| panic!("{e}"));
    compute_spirv(&module, &info, spec.name)
}

/// The wide path's per-contact kernels, each with its `PASS` values.
fn contact_kernels() -> Vec<(&'static KernelSpec, Option<u32>)> {
    let mut kernels = vec![(&PREPARE_CONTACTS, None), (&STORE_IMPULSES, None)];
    for spec in [&SOLVE_COLOR, &SOLVE_COLOR_IMMEDIATE] {
        kernels.extend(PassKind::ALL.iter().map(|p| (spec, Some(p.code()))));
    }
    kernels
}

#[test]
fn wide_contact_kernels_are_the_same_program_with_rotation_in_and_out() {
    // The failure the bitwise rotation test guards needs a compiler that contracts or
    // reorders float arithmetic differently in two programs (NVIDIA's did, on an H100);
    // lavapipe's does not, so equal bits there cannot show the contact rows are safe. Equal
    // SPIR-V can: one program cannot round two ways. The rotation switch may only act in
    // the body passes (body_math.wgsl); a contact row that tests it again, to drop angular
    // terms at compile time, makes the two variants different programs and fails here on
    // any machine. Gravity and restitution do not reach the contact rows either.
    let off = |set: fn(&mut Effects)| {
        let mut e = Effects::ALL;
        set(&mut e);
        e
    };
    for (spec, pass) in contact_kernels() {
        let all = specialized_spirv(spec, Effects::ALL, pass);
        for (name, effects) in [
            ("rotation", off(|e| e.rotation = false)),
            ("gravity", off(|e| e.gravity = false)),
            ("restitution", off(|e| e.restitution = false)),
        ] {
            let without = specialized_spirv(spec, effects, pass);
            assert!(
                all == without,
                "{} (pass {pass:?}): {name} compiled out changes the program",
                spec.name
            );
        }
    }
    // The comparison can tell programs apart: friction rows are compiled out of the solve
    // passes (a frictionless contact skips them at run time as well, as a whole block).
    let solve = Some(PassKind::Solve.code());
    let rough = specialized_spirv(&SOLVE_COLOR, Effects::ALL, solve);
    let smooth = specialized_spirv(&SOLVE_COLOR, off(|e| e.friction = false), solve);
    assert!(
        rough != smooth,
        "friction compiled out left the solve pass unchanged"
    );
}

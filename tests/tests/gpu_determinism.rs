//! The GPU step is deterministic: the same scene run twice gives bitwise equal poses, and the
//! wide and fused solver paths (different dispatch layouts, the same arithmetic) agree
//! bitwise. No floating-point atomics are used anywhere in the step, coloring uses integer
//! atomics whose outcome does not depend on thread order, and the constraints of one color
//! share no dynamic body, so the order in which a color's threads run cannot change a result.
//!
//! Needs a GPU (or lavapipe): without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Cuboid, Pose, Real, Vec3};
use tumble_gpu::GpuContext;
use tumble_gpu::layout::GpuPose;
use tumble_gpu::solver::constants::GRAPH_COLOR_COUNT;
use tumble_gpu::solver::{FusedMemory, SolvePath, SubstepDispatch, WarmStartSweep};
use tumble_gpu::step::{ColorDispatch, GpuWorld, GpuWorldConfig, PathPolicy, ReadRequest};
use tumble_solver::{Body, BodyKind, BodyState, Material};
use tumble_tests::gpu_solver_util::{floor, pose_bits};
use tumble_tests::scene_support::random_vec;

/// Steps per run: 5 s at 60 Hz, long enough for the dropped boxes to land, tumble and pile up.
const STEPS: usize = 300;

/// A floor, a pyramid four cubes high, and twelve boxes of mixed sizes dropped onto it with
/// random spins: contacts appear, change feature and vanish, so colors and warm starts churn.
fn scene() -> (Vec<Body>, Vec<BodyState>) {
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let mut bodies = vec![floor(Material::default())];
    for level in 0..4 {
        for i in 0..(4 - level) {
            let x = i as Real * 1.02 - (3 - level) as Real * 0.51;
            bodies.push(
                Body::new(
                    BodyKind::Dynamic,
                    Cuboid::new(Vec3::repeat(0.5)),
                    Pose::translation(x, 0.5 + level as Real, 0.0),
                    1.0,
                    Material::default(),
                )
                .unwrap(),
            );
        }
    }
    let mut states = vec![BodyState::default(); bodies.len()];
    for k in 0..12 {
        let h = random_vec(&mut rng, 0.2..0.6);
        let p = Vec3::new(
            rng.random_range(-2.0..2.0),
            5.0 + 1.3 * k as Real,
            rng.random_range(-1.0..1.0),
        );
        let spin = random_vec(&mut rng, -1.0..1.0);
        bodies.push(
            Body::new(
                BodyKind::Dynamic,
                Cuboid::new(h),
                Pose::new(p, spin),
                rng.random_range(0.5..3.0),
                Material {
                    friction: rng.random_range(0.3..0.9),
                    restitution: 0.0,
                },
            )
            .unwrap(),
        );
        states.push(BodyState::moving(
            Vec3::new(
                rng.random_range(-1.0..1.0),
                0.0,
                rng.random_range(-1.0..1.0),
            ),
            random_vec(&mut rng, -3.0..3.0),
        ));
    }
    (bodies, states)
}

/// The default settings with the solver path fixed to `path`.
fn on_path(path: SolvePath) -> GpuWorldConfig {
    GpuWorldConfig {
        path: PathPolicy::Always(path),
        ..Default::default()
    }
}

/// Runs the scene for [`STEPS`] steps on the GPU along `path` and returns the poses.
fn run(ctx: &GpuContext, path: PathPolicy) -> Vec<GpuPose> {
    let config = GpuWorldConfig {
        path,
        ..Default::default()
    };
    run_with(ctx, config, STEPS).0
}

/// [`run`] for `steps` steps (at least 80: by then every dropped box has fallen 4 m or more)
/// with `config`; also gives the colors the wide path dispatched one by one in the last step.
fn run_with(ctx: &GpuContext, config: GpuWorldConfig, steps: usize) -> (Vec<GpuPose>, u32) {
    let bodies = scene().0;
    let mut world = world_with(ctx, config, scene());
    for _ in 0..steps {
        world.step().unwrap();
    }
    let dispatched = world.solver().color_dispatches();
    let snapshot = world.read_now(ReadRequest::MOTION).unwrap();
    // The scene must have done something for the comparison to mean anything: the dropped
    // boxes fell at least 2 m, and nothing left the world.
    let start_top: Real = bodies[11..].iter().map(|b| b.pose.translation.y).sum();
    let end_top: Real = (11..bodies.len())
        .map(|i| snapshot.pose(i).translation.y)
        .sum();
    assert!(
        start_top - end_top > 2.0 * 12.0,
        "the boxes did not fall: {start_top} -> {end_top}"
    );
    for p in &snapshot.poses {
        assert!(
            p.position.iter().chain(&p.rotation).all(|c| c.is_finite()),
            "{p:?}"
        );
    }
    (snapshot.poses, dispatched)
}

/// A GPU world with `config` over `scene`'s bodies.
fn world_with(
    ctx: &GpuContext,
    config: GpuWorldConfig,
    scene: (Vec<Body>, Vec<BodyState>),
) -> GpuWorld {
    let (bodies, states) = scene;
    let mut world = GpuWorld::new(ctx, config).unwrap();
    world.set_bodies(&bodies, &states).unwrap();
    world
}

/// [`plate_on_cubes`] after 40 steps with `config`: the poses, once the plate is checked
/// still lying on the cubes.
fn plate_after_40_steps(ctx: &GpuContext, config: GpuWorldConfig) -> Vec<GpuPose> {
    let mut world = world_with(ctx, config, plate_on_cubes());
    for _ in 0..40 {
        world.step().unwrap();
    }
    let poses = world.read_now(ReadRequest::MOTION).unwrap().poses;
    // The plate (last body) still lies on the cubes: its centre within 2 cm of the 0.6 m it
    // settles at (cube tops at 0.5 m plus its half thickness); a plate that sank through or
    // jumped off would mean the overflow set was not solved.
    let y = poses.last().unwrap().position[1];
    assert!((y - 0.6).abs() < 0.02, "plate centre at y = {y}");
    poses
}

/// Bitwise equality of two pose lists, reporting the first difference.
fn assert_bitwise_equal(a: &[GpuPose], b: &[GpuPose], what: &str) {
    assert_eq!(a.len(), b.len());
    for (i, (x, y)) in a.iter().zip(b).enumerate() {
        assert_eq!(
            pose_bits(x),
            pose_bits(y),
            "{what}: body {i} differs: {x:?} vs {y:?}"
        );
    }
}

#[test]
fn two_gpu_runs_of_one_scene_give_bitwise_equal_poses_after_300_steps() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let first = run(&ctx, PathPolicy::Auto);
    let second = run(&ctx, PathPolicy::Auto);
    assert_bitwise_equal(&first, &second, "two runs");
}

#[test]
fn wide_and_fused_solver_paths_give_bitwise_equal_poses() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let (wide, dispatched) = run_with(&ctx, on_path(SolvePath::Wide), STEPS);
    // The wide path dispatches the colors in use one by one (ColorDispatch::InUse, the
    // default): the pile needs a few colors, far from all 24.
    assert!(
        (2..GRAPH_COLOR_COUNT).contains(&dispatched),
        "colors dispatched one by one: {dispatched}"
    );
    let fused = run(&ctx, PathPolicy::Always(SolvePath::Fused));
    assert_bitwise_equal(&wide, &fused, "wide (colors in use) vs fused");
}

#[test]
fn fused_path_gives_the_same_bits_with_bodies_in_workgroup_memory() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // solve_fused_shared runs the same functions in the same order as solve_fused, with the
    // bodies in workgroup memory and workgroup-only barriers between colors: a barrier too
    // weak, or a slot visited by another thread than the one that last wrote it, would show
    // as a different bit somewhere in these steps of falling, landing and piling. 80 steps,
    // not 300: lavapipe runs the workgroup-memory kernel about ten times slower.
    let fused = |fused_memory| GpuWorldConfig {
        fused_memory,
        ..on_path(SolvePath::Fused)
    };
    let storage = run_with(&ctx, fused(FusedMemory::Storage), 80).0;
    let workgroup = run_with(&ctx, fused(FusedMemory::Workgroup), 80).0;
    assert_bitwise_equal(&storage, &workgroup, "fused: storage vs workgroup memory");
}

#[test]
fn wide_path_gives_the_same_bits_whichever_colors_are_dispatched_one_by_one() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // Each pass dispatches its first colors one by one and ends with a single thread that
    // visits the remaining colors' constraints in turn and then the overflow set. With
    // First(0) that thread solves everything, every color in the order the per-color
    // dispatches take them; a color visited twice or skipped, or colors out of order, would
    // change a bit in these 80 steps of falling, landing and piling. (The colors in use,
    // the default, are compared with the fused path in the test above.)
    let wide = |color_dispatch| GpuWorldConfig {
        color_dispatch,
        ..on_path(SolvePath::Wide)
    };
    let (all, dispatched_all) = run_with(&ctx, wide(ColorDispatch::All), 80);
    assert_eq!(dispatched_all, GRAPH_COLOR_COUNT);
    let (tail, dispatched) = run_with(&ctx, wide(ColorDispatch::First(0)), 80);
    assert_eq!(dispatched, 0);
    assert_bitwise_equal(&all, &tail, "all colors one by one vs all in the tail");
}

/// A 6 m plate resting on a 6 x 6 grid of spaced cubes on the floor: the plate has 36
/// constraints, more than the 24 graph colors, so at least 12 of them go to the overflow set.
fn plate_on_cubes() -> (Vec<Body>, Vec<BodyState>) {
    let mut bodies = vec![floor(Material::default())];
    let cube = |x: Real, z: Real| {
        Body::new(
            BodyKind::Dynamic,
            Cuboid::new(Vec3::repeat(0.25)),
            Pose::translation(x, 0.25, z),
            1.0,
            Material::default(),
        )
        .unwrap()
    };
    for i in 0..6 {
        for j in 0..6 {
            bodies.push(cube(i as Real - 2.5, j as Real - 2.5));
        }
    }
    bodies.push(
        Body::new(
            BodyKind::Dynamic,
            Cuboid::new(Vec3::new(3.2, 0.1, 3.2)),
            Pose::new(Vec3::new(0.0, 0.62, 0.0), Vec3::new(0.02, 0.0, 0.01)),
            1.0,
            Material::default(),
        )
        .unwrap(),
    );
    let states = vec![BodyState::default(); bodies.len()];
    (bodies, states)
}

#[test]
fn per_body_warm_start_gives_the_bits_of_the_colored_warm_start() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // The wide path's warm start runs one thread per body over the body's constraints in
    // color order, then the overflow set in one thread; the colored sweep runs one dispatch
    // per color. Every velocity must take the same operations in the same order: a constraint
    // applied twice, skipped or out of order, a lost running total, or an overflow constraint
    // applied before the colors would change a bit. Two scenes: the landing pile (colors and
    // warm starts churn), and a tilted plate settling on 36 cubes (at least 12 of its
    // constraints in the overflow set, every step).
    let wide = |warm_start_sweep| GpuWorldConfig {
        warm_start_sweep,
        color_dispatch: ColorDispatch::All,
        ..on_path(SolvePath::Wide)
    };
    let per_body = run_with(&ctx, wide(WarmStartSweep::PerBody), 80).0;
    let by_color = run_with(&ctx, wide(WarmStartSweep::ByColor), 80).0;
    assert_bitwise_equal(&per_body, &by_color, "pile: per-body vs colored warm start");

    let plate = |sweep| plate_after_40_steps(&ctx, wide(sweep));
    assert_bitwise_equal(
        &plate(WarmStartSweep::PerBody),
        &plate(WarmStartSweep::ByColor),
        "plate on 36 cubes: per-body vs colored warm start",
    );
}

#[test]
fn one_substep_dispatch_gives_the_bits_of_the_per_color_dispatches() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // `solve_step` runs every phase of the substeps (integrate velocities, the per-body warm
    // start, the overflow set, each color of each solve and relax sweep, integrate positions,
    // restitution) in one dispatch, as chunks handed out by a ticket counter, a chunk waiting
    // until the phases before it are done. A chunk run before its phase's predecessors were
    // done, a body or constraint visited twice or skipped, a phase out of order or a read of
    // another workgroup's stale write would change a bit against the per-color dispatches.
    // One workgroup takes every chunk in turn; on a GPU three, and as many as the step picks
    // (`SOLVE_STEP_GROUPS`, most of them without a chunk in this small scene), compete for
    // them. A CPU adapter always runs one workgroup
    // (`SOLVE_STEP_CPU_GROUPS` says why), so there the comparison checks the phases' order and
    // content, and a GPU run checks the hand-over between workgroups too. Three scenes: the
    // landing pile (colors churn), the plate on 36 cubes (an overflow set every step), and
    // the pile with bouncy dropped boxes (the restitution sweep).
    if !ctx.has_coherent {
        eprintln!("skipped: the adapter has no @coherent storage, so no one-dispatch substeps");
        return;
    }
    let config = |substep_dispatch| GpuWorldConfig {
        warm_start_sweep: WarmStartSweep::PerBody,
        substep_dispatch,
        ..on_path(SolvePath::Wide)
    };
    let per_color = config(SubstepDispatch::PerColor);
    let one = |groups| config(SubstepDispatch::OneDispatch { groups });
    // The one-dispatch setting does run solve_step (a silent fallback to the per-color
    // dispatches would make every comparison below vacuous), the per-color one does not.
    let ran_one_dispatch = |config| {
        let mut world = world_with(&ctx, config, scene());
        for _ in 0..3 {
            world.step().unwrap();
        }
        world.solver().substep_fault().is_some()
    };
    assert!(ran_one_dispatch(one(None)), "solve_step did not run");
    assert!(
        !ran_one_dispatch(per_color),
        "solve_step ran on the per-color setting"
    );
    let reference = run_with(&ctx, per_color, 80).0;
    for groups in [Some(1), Some(3), None] {
        let poses = run_with(&ctx, one(groups), 80).0;
        assert_bitwise_equal(&poses, &reference, &format!("pile: {groups:?} workgroups"));
    }

    assert_bitwise_equal(
        &plate_after_40_steps(&ctx, one(Some(3))),
        &plate_after_40_steps(&ctx, per_color),
        "plate on 36 cubes",
    );

    let bouncy = |config: GpuWorldConfig| {
        let (mut bodies, states) = scene();
        for body in &mut bodies[11..] {
            body.material.restitution = 0.6;
        }
        let count = bodies.len();
        let mut world = world_with(&ctx, config, (bodies, states));
        let mut highest_rebound: Real = 0.0;
        let mut poses = Vec::new();
        for _ in 0..120 {
            world.step().unwrap();
            let snapshot = world.read_now(ReadRequest::MOTION).unwrap();
            // Some dropped box moves up after landing: the restitution sweep ran.
            let up = (11..count)
                .map(|i| snapshot.velocities[i].linear[1])
                .fold(0.0, Real::max);
            highest_rebound = highest_rebound.max(up);
            poses = snapshot.poses;
        }
        // A box that lands at 4 m/s or more with restitution 0.6 leaves at well over 1 m/s.
        assert!(
            highest_rebound > 1.0,
            "no box bounced: {highest_rebound} m/s up at most"
        );
        poses
    };
    assert_bitwise_equal(&bouncy(one(None)), &bouncy(per_color), "bouncy pile");
}

#[test]
fn a_step_undone_on_the_wide_path_and_taken_again_gives_the_bits_of_one_never_undone() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // The motion check's checkpoint leaves out the solver's per-step scratch (the constraint
    // store, the coloring's marks, which hold the per-body warm-start lists, its undecided
    // lists, the color sort keys): every step must rewrite them before reading them. After an
    // undone step they hold that step's values, where a world that never took it holds the
    // step before's; if any were read before being rewritten, the steps after the undo would
    // differ from the twin's. It also leaves out every buffer kept in two parities (pairs,
    // manifolds, contact points, local manifolds, colors, tilts): the undone step must have
    // left last step's parity untouched and rewrite its own before reading it. The wide path with the per-body warm start runs every one of
    // them (the small scenes of the facade's bounds tests take the fused path).
    let config = GpuWorldConfig {
        warm_start_sweep: WarmStartSweep::PerBody,
        ..on_path(SolvePath::Wide)
    };
    let (bodies, states) = scene();
    let mut undone = GpuWorld::new(&ctx, config).unwrap();
    undone.set_motion_check(true).unwrap();
    undone.set_bodies(&bodies, &states).unwrap();
    let mut twin = GpuWorld::new(&ctx, config).unwrap();
    twin.set_bodies(&bodies, &states).unwrap();
    // Long enough for the dropped boxes to reach the pile: contacts carried, colors seeded.
    for _ in 0..60 {
        undone.step().unwrap();
        twin.step().unwrap();
    }
    undone.step().unwrap();
    assert_eq!(
        undone.motion_flag().unwrap(),
        None,
        "a normal step is not flagged"
    );
    undone.roll_back().unwrap();
    for _ in 0..20 {
        undone.step().unwrap();
        twin.step().unwrap();
    }
    let a = undone.read_now(ReadRequest::MOTION).unwrap().poses;
    let b = twin.read_now(ReadRequest::MOTION).unwrap().poses;
    assert_bitwise_equal(&a, &b, "undone and taken again vs never undone");
}

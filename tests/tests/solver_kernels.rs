//! The solver's kernels give the same bits: the lane kernels (eight constraints of a color side
//! by side, on AVX2 when the processor has it, or on the build's baseline instructions) against
//! the scalar kernel that visits one constraint at a time.
//!
//! The lanes turn every branch of the scalar kernel into a mask (a point a lane does not have,
//! a patch or not, friction or none, the second visit of a patch that does not slide,
//! restitution that applies to some points only) and must still reproduce its every floating
//! point operation in order. The scenes below reach each of those: piles of four-point patches,
//! dominoes that tip onto edges (two points), a cube sliding down a ramp (every point clamped,
//! no second visit), a pool of boxes of mixed sizes that bounce (restitution) with friction
//! from zero up, mass ratios of 100, a fast box that needs speculative points, and a pyramid
//! on a kinematic floor that slides and turns. Each ends after enough steps that any
//! difference in any bit would have spread to the poses. The Baumgarte solver, the step
//! without warm starting and the step with friction switched off run the same kernels through
//! other paths and are compared too.

use tumble::{Backend, EffectOverrides, EffectSwitch, World, WorldConfig};
use tumble_scenes::{
    BodyKind, Scene, dominoes, friction_ramp, high_speed, mass_ratio, pool, pyramid, wide_on_small,
};
use tumble_solver::{SolveKernel, SolverConfig};

/// Steps per run: 2.5 s at 60 Hz, past the first impacts, the dominoes' chain and the bounces.
const STEPS: usize = 150;

/// The pool with restitution on every third body and friction from 0 to 0.8, so that blocks
/// of eight constraints mix lanes with and without restitution and friction.
fn bouncing_pool() -> Scene {
    let mut scene = pool(120);
    for (k, body) in scene.bodies.iter_mut().enumerate() {
        body.restitution = if k % 3 == 0 { 0.6 } else { 0.0 };
        body.friction = [0.0, 0.3, 0.8][k % 3];
    }
    scene.name = "bouncing_pool".into();
    scene
}

/// A small pyramid on a kinematic floor that slides and turns: lanes whose static side is a
/// moving body (read by several lanes, written by none).
fn turntable() -> Scene {
    let mut scene = pyramid(4);
    for body in scene
        .bodies
        .iter_mut()
        .filter(|b| b.kind == BodyKind::Fixed)
    {
        body.kind = BodyKind::Kinematic;
        body.linear_velocity = [0.3, 0.0, 0.1];
        body.angular_velocity = [0.0, 0.4, 0.0];
    }
    scene.name = "turntable".into();
    scene
}

fn scenes() -> Vec<Scene> {
    vec![
        pyramid(8),
        turntable(),
        dominoes(12),
        friction_ramp(30.0, 0.3),
        bouncing_pool(),
        mass_ratio(),
        wide_on_small(),
        high_speed(),
    ]
}

/// Every pose and velocity bit of `scene` after `steps` steps on the CPU backend, and the
/// most colors any step solved on the thread pool.
fn run(
    scene: &Scene,
    solver: SolverConfig,
    effects: EffectOverrides,
    steps: usize,
) -> (Vec<u32>, usize) {
    let (mut world, handles) = World::from_scene(
        scene,
        WorldConfig {
            backend: Backend::Cpu,
            solver,
            effects,
            ..Default::default()
        },
    )
    .expect("the scene builds");
    let mut pooled = 0;
    for _ in 0..steps {
        world.step().expect("the step runs");
        pooled = pooled.max(world.stats().parallel_colors);
    }
    let mut bits = Vec::new();
    for &h in &handles {
        let pose = world.pose(h).expect("a live handle");
        let q = pose.rotation.quaternion();
        let v = world.linear_velocity(h).expect("a live handle");
        let w = world.angular_velocity(h).expect("a live handle");
        let coords = pose
            .translation
            .vector
            .iter()
            .chain([&q.i, &q.j, &q.k, &q.w])
            .chain(v.iter())
            .chain(w.iter());
        bits.extend(coords.map(|c| {
            assert!(c.is_finite(), "{}: a non-finite state", scene.name);
            c.to_bits()
        }));
    }
    (bits, pooled)
}

fn on_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("a thread pool")
        .install(f)
}

/// Runs each scene with every kernel and checks that they agree bit for bit. The scalar run
/// must also differ from the scene's start, or equality would prove nothing.
///
/// Colors from 8 constraints up go to the thread pool (the default waits for 256, more than
/// these scenes' colors hold), so that on 2 threads the pyramid of 8's colors of several dozen
/// constraints are claimed block by block by both workers: the staged lane path, not the
/// one-thread loop.
fn check(solver: SolverConfig, effects: EffectOverrides) {
    let solver = SolverConfig {
        parallel_threshold: 8,
        ..solver
    };
    for scene in scenes() {
        let with = |kernel, threads| {
            let config = SolverConfig { kernel, ..solver };
            on_threads(threads, || run(&scene, config, effects, STEPS))
        };
        let (scalar, pooled) = with(SolveKernel::Scalar, 1);
        if scene.name.starts_with("pyramid") {
            assert!(
                pooled > 0,
                "{}: no color reached the thread pool",
                scene.name
            );
        }
        let (start, _) = run(&scene, solver, effects, 0);
        assert_ne!(
            scalar.len(),
            0,
            "{}: a scene with no bodies proves nothing",
            scene.name
        );
        // Every body's state after the run against its state before: the run must have moved
        // something, or equal bits would prove nothing.
        assert_ne!(scalar, start, "{}: nothing moved", scene.name);
        for (kernel, threads) in [
            (SolveKernel::Lanes, 1),
            (SolveKernel::Lanes, 2),
            (SolveKernel::PortableLanes, 1),
        ] {
            let (lanes, _) = with(kernel, threads);
            let first = scalar.iter().zip(&lanes).position(|(a, b)| a != b);
            assert!(
                first.is_none() && lanes.len() == scalar.len(),
                "{}: {kernel:?} on {threads} threads differs from the scalar kernel at body {} \
                 (value {} of its 13)",
                scene.name,
                first.unwrap_or(0) / 13,
                first.unwrap_or(0) % 13,
            );
        }
    }
}

#[test]
fn lane_kernels_match_the_scalar_kernel_bit_for_bit() {
    check(SolverConfig::default(), EffectOverrides::NO_SLEEP);
}

#[test]
fn lane_kernels_match_the_scalar_kernel_for_baumgarte_cold_starts_and_without_friction() {
    // Baumgarte: rigid rows, a slop, several biased passes and no relax pass.
    check(SolverConfig::baumgarte(), EffectOverrides::NO_SLEEP);
    // Without warm starting every block starts from zero impulses.
    check(
        SolverConfig {
            warm_start: false,
            ..SolverConfig::default()
        },
        EffectOverrides::NO_SLEEP,
    );
    // Friction off: every lane skips its tangent rows and the second visit.
    check(
        SolverConfig::default(),
        EffectOverrides {
            friction: EffectSwitch::Off,
            ..EffectOverrides::NO_SLEEP
        },
    );
}

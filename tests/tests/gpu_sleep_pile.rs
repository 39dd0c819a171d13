//! A settled pile of 1,000 boxes falls asleep on `Backend::Gpu` through the facade, with the
//! GPU's own sleep stage: every box asleep within 10 s of simulated time, where it landed, at
//! zero velocity, and unchanged bit for bit while asleep. The smaller pools of `gpu_sleep`
//! check the stage's rules (waking, kinematic bodies, determinism); this checks that a pile
//! of the size the GPU backend exists for actually comes to rest under the GPU solver, whose
//! residual jitter is what keeps a pile awake when it does not.
//!
//! Needs a GPU (or lavapipe): without one it prints a loud "skipped" unless
//! `TUMBLE_REQUIRE_GPU=1`, which makes a missing adapter a failure.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble::TIME_TO_SLEEP;
use tumble::prelude::*;
use tumble_tests::facade::sleepy_world;

/// Half extent of the boxes, m.
const HALF: Real = 0.25;
/// Columns of the pile along x and z, and boxes per column: 25 x 20 x 2 = 1,000 boxes.
const NX: usize = 25;
const NZ: usize = 20;
const LAYERS: usize = 2;
/// Column pitch, m: 2 cm gaps, which the sideways shifts below (up to 8 mm each way) leave
/// open or nearly so, so the boxes of a layer land as separate columns that rest together.
const PITCH: Real = 2.0 * HALF + 0.02;
/// The world's step, s (the default 60 Hz).
const DT: Real = 1.0 / 60.0;
/// The criterion: asleep within 10 s of simulated time.
const LIMIT_STEPS: usize = (10.0 / DT) as usize;

/// A GPU world with sleep on, a floor and the pile: each box raised 3 cm per layer, shifted
/// sideways by up to 8 mm and tilted by up to 0.02 rad about each axis (seeded), so that the
/// boxes fall, land unevenly and must settle before they can sleep. `None` without an adapter.
fn pile_world() -> Option<(World, Vec<BodyHandle>)> {
    let mut world = sleepy_world(Backend::Gpu)?;
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let (ox, oz) = (
        (NX as Real - 1.0) * PITCH / 2.0,
        (NZ as Real - 1.0) * PITCH / 2.0,
    );
    let mut boxes = Vec::with_capacity(NX * NZ * LAYERS);
    for layer in 0..LAYERS {
        for i in 0..NX {
            for k in 0..NZ {
                let x = i as Real * PITCH - ox + rng.random_range(-0.008..0.008);
                let z = k as Real * PITCH - oz + rng.random_range(-0.008..0.008);
                let y = HALF + layer as Real * 2.0 * HALF + 0.03 * (layer + 1) as Real;
                let tilt = Vec3::from_fn(|_, _| rng.random_range(-0.02..0.02));
                let desc = BodyDesc::dynamic()
                    .cuboid(Vec3::repeat(HALF))
                    .pose(Pose::new(Vec3::new(x, y, z), tilt));
                boxes.push(world.add_body(desc).unwrap());
            }
        }
    }
    Some((world, boxes))
}

#[test]
fn a_settled_pile_of_1000_boxes_falls_asleep_on_the_gpu_within_10_s() {
    let Some((mut world, boxes)) = pile_world() else {
        return;
    };
    assert_eq!(boxes.len(), 1000);
    let mut asleep_at = None;
    for step in 1..=LIMIT_STEPS {
        world.step().unwrap();
        if world.sleeping_count() == boxes.len() {
            asleep_at = Some(step);
            break;
        }
    }
    let awake = boxes.len() - world.sleeping_count();
    let steps = asleep_at.unwrap_or_else(|| {
        panic!("{awake} of 1,000 boxes still awake after {LIMIT_STEPS} steps (10 s)")
    });
    eprintln!("1,000-box pile asleep on the GPU after {steps} steps");
    // An island must rest for TIME_TO_SLEEP before it sleeps, and the top layer falls 6 cm
    // first (0.11 s): asleep sooner means the stage did not wait.
    assert!(
        steps as Real * DT >= TIME_TO_SLEEP,
        "asleep after {steps} steps"
    );

    let rest: Vec<Pose> = boxes.iter().map(|&h| world.pose(h).unwrap()).collect();
    for (n, (&h, pose)) in boxes.iter().zip(&rest).enumerate() {
        // Asleep where it landed: each box within 5 mm of its layer's resting height (the
        // soft contacts' penetration under two layers is about a millimetre; a box that
        // slid off its column or tipped over would be 0.25 m or more off), and at exactly
        // zero velocity (a sleeping body is not integrated).
        let layer = (n / (NX * NZ)) as Real;
        let expected = HALF + layer * 2.0 * HALF;
        let y = pose.translation.y;
        assert!(
            (y - expected).abs() < 0.005,
            "box {n}: y {y}, expected {expected}"
        );
        let (v, w) = (
            world.linear_velocity(h).unwrap(),
            world.angular_velocity(h).unwrap(),
        );
        assert!(
            v.iter().chain(w.iter()).all(|&c| c == 0.0),
            "box {n} asleep with velocity {v:?} {w:?}"
        );
    }
    // Asleep means out of the step: half a second more changes no bit of any pose.
    for _ in 0..30 {
        world.step().unwrap();
    }
    assert_eq!(
        world.sleeping_count(),
        boxes.len(),
        "boxes woke by themselves"
    );
    for (n, (&h, before)) in boxes.iter().zip(&rest).enumerate() {
        let after = world.pose(h).unwrap();
        let bits = |p: &Pose| {
            let q = p.rotation.quaternion();
            p.translation
                .vector
                .iter()
                .chain([q.i, q.j, q.k, q.w].iter())
                .map(|c| c.to_bits())
                .collect::<Vec<_>>()
        };
        assert_eq!(bits(&after), bits(before), "box {n} moved while asleep");
    }
}

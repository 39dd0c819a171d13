//! Contact recycling in the CPU step (`WorldConfig::recycle_distance`): a pair that barely
//! moved keeps last step's manifold. It must engage where piles rest, stay out of the way where
//! bodies move, and leave piles standing as they stand with every manifold computed afresh.

use tumble::{Backend, EffectOverrides, World, WorldConfig};
use tumble_scenes::{BodyKind, Scene, friction_ramp, pyramid};
use tumble_solver::DEFAULT_RECYCLE_DISTANCE;

fn world(scene: &Scene, recycle_distance: f32) -> World {
    let config = WorldConfig {
        backend: Backend::Cpu,
        effects: EffectOverrides::NO_SLEEP,
        recycle_distance,
        ..WorldConfig::default()
    };
    World::from_scene(scene, config)
        .unwrap_or_else(|e| panic!("{}: {e}", scene.name))
        .0
}

/// Every dynamic body's position, in the scene's order.
fn positions(world: &World) -> Vec<[f32; 3]> {
    world
        .handles()
        .iter()
        .copied()
        .filter(|&h| world.kind(h).unwrap() == tumble::BodyKind::Dynamic)
        .map(|h| {
            let t = world.pose(h).unwrap().translation.vector;
            [t.x, t.y, t.z]
        })
        .collect()
}

fn largest_gap(a: &[[f32; 3]], b: &[[f32; 3]]) -> f32 {
    a.iter()
        .zip(b)
        .map(|(p, q)| {
            ((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)).sqrt()
        })
        .fold(0.0, f32::max)
}

#[test]
fn a_resting_pyramid_reuses_most_manifolds_and_stands_as_it_does_without() {
    let scene = pyramid(8);
    let start = positions(&world(&scene, 0.0));
    let mut recycled = world(&scene, DEFAULT_RECYCLE_DISTANCE);
    let mut fresh = world(&scene, 0.0);
    let mut reused_share: f32 = 1.0;
    for step in 0..240 {
        recycled.step().unwrap();
        fresh.step().unwrap();
        assert_eq!(fresh.stats().recycled_manifolds, 0, "recycling off");
        if step >= 60 {
            let s = recycled.stats();
            reused_share = reused_share.min(s.recycled_manifolds as f32 / s.manifolds as f32);
        }
    }
    // The mechanism engages: a settled pyramid moves by micrometres a step, so after the
    // first second most pairs keep their manifold in every step (the measure of its
    // speed-up).
    assert!(
        reused_share > 0.5,
        "as few as {reused_share} of manifolds reused"
    );
    // And changes nothing that matters: each box ends within 1 mm of where it ends with every
    // manifold computed afresh (the tolerance a point may slide before it is recomputed), and
    // the pyramid creeps no more than 1 mm beyond what the fresh run creeps over 4 s.
    let (a, b) = (positions(&recycled), positions(&fresh));
    let gap = largest_gap(&a, &b);
    println!("reused at least {reused_share}; runs {gap} m apart");
    assert!(gap < 1e-3, "recycled and fresh runs {gap} m apart");
    let (drift, fresh_drift) = (largest_gap(&a, &start), largest_gap(&b, &start));
    assert!(
        drift < fresh_drift + 1e-3,
        "a box moved {drift} m, without recycling {fresh_drift} m"
    );
}

#[test]
fn a_sliding_cube_gets_a_fresh_manifold_every_step() {
    // A cube launched down a 30 degree ramp (friction 0.3, so it keeps sliding and speeding
    // up) moves far more than the 1 mm tolerance each step: no manifold of it may be reused,
    // so its run is bitwise the run without recycling.
    let mut scene = friction_ramp(30.0, 0.3);
    for body in scene
        .bodies
        .iter_mut()
        .filter(|b| b.kind == BodyKind::Dynamic)
    {
        // Down the slope, (-cos 30, -sin 30, 0), at 1 m/s.
        body.linear_velocity = [-0.866, -0.5, 0.0];
    }
    let mut recycled = world(&scene, DEFAULT_RECYCLE_DISTANCE);
    let mut fresh = world(&scene, 0.0);
    for _ in 0..90 {
        recycled.step().unwrap();
        fresh.step().unwrap();
        assert_eq!(recycled.stats().recycled_manifolds, 0);
    }
    let (a, b) = (positions(&recycled), positions(&fresh));
    assert_eq!(a, b);
    // It did slide: more than a metre in 1.5 s.
    let start = positions(&world(&scene, 0.0));
    assert!(largest_gap(&a, &start) > 1.0);
}

#[test]
fn the_recycle_distance_is_validated() {
    for bad in [-1e-3, 0.02, f32::NAN, f32::INFINITY] {
        let config = WorldConfig {
            recycle_distance: bad,
            ..WorldConfig::default()
        };
        let Err(err) = World::new(config) else {
            panic!("recycle_distance {bad} accepted");
        };
        let err = err.to_string();
        assert!(err.contains("recycle_distance"), "{err}");
    }
}

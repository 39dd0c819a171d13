//! The batch's sorts at sizes past the single-workgroup ones: the radix pair sort, the sort of
//! bodies one workgroup per world, and a world too large for it, which sorts all bodies at once.

use super::*;

#[test]
fn a_batch_of_130_worlds_matches_on_the_radix_sort_and_without_long_box_lists() {
    // 130 worlds: more than 1,024 bodies and pair slots (the pair sort is the radix sort
    // rather than the single-workgroup one; the bodies sort one workgroup per world,
    // sort_world_bodies, where each world alone takes rank_sort), more floors than the
    // long-box list holds (64, so every floor is swept with its world's boxes) and 8 bits of
    // world index in the sort keys.
    batch_matches_alone(130, 60, GpuWorldConfig::default());
}

#[test]
fn a_batch_with_a_world_of_over_1024_bodies_sorts_all_bodies_at_once_and_matches() {
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    // A world of 1,157 bodies (a floor and a 34 x 34 grid of cubes dropped from 2 to 6 cm)
    // beside a small world: the sort by world takes worlds of at most 1,024 bodies, so this
    // batch's bodies go through the radix sort of the whole list, with the world leading the
    // keys. Each world must still end with the bits it gets alone.
    let material = Material {
        friction: 0.6,
        restitution: 0.0,
    };
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    let mut bodies = vec![floor(material)];
    for i in 0..34 * 34 {
        let (x, z) = ((i % 34) as Real * 1.1 - 18.0, (i / 34) as Real * 1.1 - 18.0);
        let y = 0.5 + rng.random_range(0.02..0.06);
        bodies.push(
            Body::new(
                BodyKind::Dynamic,
                Cuboid::new(Vec3::repeat(0.5)),
                Pose::new(Vec3::new(x, y, z), Vec3::zeros()),
                1.0,
                material,
            )
            .unwrap(),
        );
    }
    let states = vec![BodyState::default(); bodies.len()];
    let scenes = [(bodies, states), small_world(2)];
    let (bodies, states, worlds, firsts) = concat(&scenes);
    let steps = 20;
    let batch = run_on(
        &ctx,
        GpuWorldConfig::default(),
        &bodies,
        &states,
        &worlds,
        steps,
    );
    for (w, (b, s)) in scenes.iter().enumerate() {
        let alone = run(&ctx, b, s, &[], steps);
        for (i, pose) in alone.iter().enumerate() {
            assert_eq!(
                pose_bits(pose),
                pose_bits(&batch[firsts[w] + i]),
                "world {w}, body {i}"
            );
        }
    }
    // The grid landed: every cube of the large world ends resting on the floor (centre
    // within 1 cm of 0.5 m), which it reaches only through its own floor contacts.
    let grid = &batch[1..scenes[0].0.len()];
    assert!(
        grid.iter().all(|p| (p.position[1] - 0.5).abs() < 0.01),
        "a cube of the large world is not resting on its floor"
    );
}

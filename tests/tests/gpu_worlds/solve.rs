//! The batch's solve on each path and grouping: the worlds path one world per workgroup or
//! packed in groups, bodies in storage or workgroup memory, and the wide path; every world ends
//! bitwise equal to the world stepped alone.

use super::*;

#[test]
fn worlds_stepped_as_one_batch_end_bitwise_equal_to_each_stepped_alone() {
    // Twelve worlds, 200 steps (3.3 s): landings, slides into the wall, piles settling; the
    // bodies (under 1,024) and pairs take the single-workgroup sorts, and the solve one
    // fused workgroup per world (SolvePath::Worlds; a batch this small is not packed into
    // groups), where each world alone takes the single-workgroup fused path.
    batch_matches_alone(12, 200, GpuWorldConfig::default());
}

#[test]
fn groups_of_worlds_with_and_without_contacts_end_bitwise_equal_to_each_stepped_alone() {
    // The solve runs consecutive worlds as one group per workgroup (up to 64 bodies), over
    // the union of their manifold ranges. Every third world here never touches anything (a
    // cube falling from 100 m, 4.9 m in these 60 steps), so groups begin, hold and end with
    // worlds that have no manifold range (their entries stay 0, 0): a group range taken from
    // such an entry would reach into other groups' constraints and change their bits.
    let material = Material {
        friction: 0.6,
        restitution: 0.0,
    };
    let scenes: Vec<_> = (0..24u64)
        .map(|w| {
            if w % 3 == 1 {
                let cube = Body::new(
                    BodyKind::Dynamic,
                    Cuboid::new(Vec3::repeat(0.5)),
                    Pose::translation(0.0, 100.0, 0.0),
                    1.0,
                    material,
                )
                .unwrap();
                (vec![floor(material), cube], vec![BodyState::default(); 2])
            } else {
                small_world(w)
            }
        })
        .collect();
    let packed = GpuWorldConfig {
        world_grouping: WorldGrouping::Packed,
        ..GpuWorldConfig::default()
    };
    scenes_match_alone(&scenes, 60, packed);
    let shared = GpuWorldConfig {
        fused_memory: FusedMemory::Workgroup,
        ..packed
    };
    scenes_match_alone(&scenes, 60, shared);
}

#[test]
fn a_batch_is_packed_into_groups_of_worlds_only_when_asked_or_large() {
    // The grouping never changes a bit (the test above), so what it must get right is which
    // workgroups run: a small batch one world per workgroup (it would leave most of a GPU
    // idle packed), a large one or one asked for packed as few workgroups as fit 64 bodies.
    let Some(ctx) = GpuContext::for_tests() else {
        return;
    };
    let groups = |count: usize, grouping| {
        let scenes: Vec<_> = (0..count as u64).map(|w| small_world(w % 4)).collect();
        let (bodies, states, worlds, firsts) = concat(&scenes);
        let config = GpuWorldConfig {
            world_grouping: grouping,
            ..GpuWorldConfig::default()
        };
        let mut world = GpuWorld::new(&ctx, config).unwrap();
        world
            .set_bodies_in_worlds(&bodies, &states, &worlds)
            .unwrap();
        (world.solver().world_group_count(), bodies.len(), firsts)
    };
    let (alone, _, _) = groups(24, WorldGrouping::Alone);
    assert_eq!(alone, 24, "one group per world when alone");
    let (auto, bodies, _) = groups(24, WorldGrouping::Auto);
    assert!((bodies as u32) < WORLDS_PACK_MIN_BODIES);
    assert_eq!(
        auto, 24,
        "a batch of {bodies} bodies is small: one world per group"
    );
    let (packed, bodies, firsts) = groups(24, WorldGrouping::Packed);
    let mut starts: Vec<u32> = firsts.iter().map(|&f| f as u32).collect();
    starts.push(bodies as u32);
    assert_eq!(
        packed as usize,
        world_groups(&starts, WORLD_GROUP_BODIES).len()
    );
    assert!(
        packed < 24,
        "{packed} groups: the small worlds were not packed"
    );
    // Enough worlds for WORLDS_PACK_MIN_BODIES: Auto packs them as Packed does.
    let count = 24 * (WORLDS_PACK_MIN_BODIES as usize / bodies + 1);
    let (auto, bodies, _) = groups(count, WorldGrouping::Auto);
    assert!(bodies as u32 >= WORLDS_PACK_MIN_BODIES);
    let (packed, _, _) = groups(count, WorldGrouping::Packed);
    assert_eq!(auto, packed);
    assert!((auto as usize) < count, "{auto} groups for {count} worlds");
}
#[test]
fn worlds_with_their_bodies_in_workgroup_memory_end_bitwise_equal_to_each_stepped_alone() {
    // solve_worlds_shared (each world's bodies in workgroup memory, workgroup barriers only),
    // which GPUs take and lavapipe only when asked: a barrier too weak or a body slot off by
    // the world's first body would change a bit in these 120 steps.
    let config = GpuWorldConfig {
        fused_memory: FusedMemory::Workgroup,
        ..GpuWorldConfig::default()
    };
    batch_matches_alone(12, 120, config);
}

#[test]
fn worlds_on_the_wide_solver_path_end_bitwise_equal_to_each_stepped_alone() {
    // The batch on the wide path (one dispatch per color and pass for all worlds), as large
    // worlds take it: the coloring numbers each world's constraints from its first.
    let config = GpuWorldConfig {
        path: PathPolicy::Always(SolvePath::Wide),
        ..GpuWorldConfig::default()
    };
    batch_matches_alone(12, 120, config);
}

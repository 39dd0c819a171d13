//! The CPU stages of the step on the solver's body arrays, named as in docs/architecture.md
//! and [`crate::Stage`]: [`update_aabbs`], [`broad_phase`], [`narrow_phase`], [`color`], the
//! solve ([`crate::solve_with_effects`]) and [`finish`].
//!
//! The geometric cores live in the layers below, on plain slices: the grown AABB in
//! [`tumble_broad::motion_aabb`], the immovable-pair filter in
//! [`tumble_broad::BroadPhase::find_pairs_filtered`], the pair margin in
//! [`tumble_narrow::pair_margin`]. The functions here feed them from [`Body`] and
//! [`BodyState`] and add what needs this layer: the contact cache and the coloring.

use rayon::prelude::*;
use tumble_broad::{CollisionGroups, KeptPairs};
use tumble_geometry::{Aabb, Real, Vec3};

use crate::coloring::color_visits;
use crate::{
    Body, BodyState, ColorCandidate, Coloring, Contact, ContactCache, PairKey, SolveOrder,
    color_in_rounds, finalize_bodies,
};

mod narrow;

pub use narrow::{NarrowBuffers, NarrowPhaseOutput, box_motion, narrow_phase, narrow_phase_with};

/// Pairs per rayon task below which the narrow phase stays on one thread: a box-box test
/// costs about a microsecond, a task a few.
const PARALLEL_MIN_PAIRS: usize = 256;

/// Whether a step of `bodies` bodies whose broad phase finds `pairs` candidate pairs runs
/// every stage on the calling thread whatever the pool: each stage's parallel path starts
/// above these sizes (a body loop at 2,048 bodies; the narrow phase at 256 pairs; the
/// solver's sweep at a color of more than 32 constraints, and a color holds at most one
/// constraint per pair; the rest at 512 or more), so such a step gains nothing from starting
/// on a worker of the pool, which costs a wake-up of that worker and a sleep of the caller.
/// The result does not depend on where a step runs.
pub const fn runs_on_one_thread(bodies: usize, pairs: usize) -> bool {
    bodies < crate::integrate::PARALLEL_MIN_BODIES && pairs <= crate::sweep::BLOCK
}

// Every other parallel path starts above the pairs (or the contacts and keys, one per pair
// at most) that `runs_on_one_thread` allows.
const _: () = assert!(
    crate::sweep::BLOCK < PARALLEL_MIN_PAIRS
        && crate::sweep::BLOCK < PARALLEL_MIN_SORT
        && crate::sweep::BLOCK < crate::solve::PARALLEL_PREPARE_MIN
        && crate::sweep::BLOCK < crate::contact_cache::PARALLEL_MIN_STORE
        && crate::sweep::BLOCK < crate::pair_table::PARALLEL_MIN_KEYS
);

/// Stage 1: the AABB of every body for the step ([`tumble_broad::motion_aabb`]: grown by
/// `margin`, stretched by `v dt`, grown by `|w| r dt`).
pub fn update_aabbs(bodies: &[Body], states: &[BodyState], margin: Real, dt: Real) -> Vec<Aabb> {
    bodies
        .iter()
        .zip(states)
        .map(|(body, state)| {
            tumble_broad::motion_aabb(
                &body.shape,
                &body.pose,
                &state.linear_velocity,
                &state.angular_velocity,
                margin,
                dt,
            )
        })
        .collect()
}

/// One flag per body: true for the bodies contacts cannot move (fixed and kinematic), whose
/// pairs with each other the broad phase leaves out.
pub fn immovable(bodies: &[Body]) -> Vec<bool> {
    bodies.iter().map(|b| !b.is_dynamic()).collect()
}

/// Stage 2: overlapping AABB pairs `(i, j)`, `i < j`, sorted, leaving out pairs of two
/// bodies that contacts cannot move (static-static is never formed) and pairs whose
/// [`CollisionGroups`] do not interact. `aabbs[i]` belongs to
/// `bodies[i]`; an AABB without a body counts as immovable. `grid` keeps its pair list
/// between steps and searches the grid again only when more than a few boxes left the
/// enlarged boxes they were searched with (fewer have their pairs found again alone:
/// [`KeptPairs`]); the pairs are the same either way.
pub fn broad_phase(grid: &mut KeptPairs, aabbs: &[Aabb], bodies: &[Body]) -> Vec<(u32, u32)> {
    let mut pairs = Vec::new();
    broad_phase_into(grid, aabbs, bodies, &mut pairs);
    pairs
}

/// [`broad_phase`] into `pairs` (its old contents replaced, its allocation kept: the pair list
/// of a large pile is megabytes, written every step).
pub fn broad_phase_into(
    grid: &mut KeptPairs,
    aabbs: &[Aabb],
    bodies: &[Body],
    pairs: &mut Vec<(u32, u32)>,
) {
    let flags: Vec<bool> = (0..aabbs.len())
        .map(|i| bodies.get(i).is_none_or(|b| !b.is_dynamic()))
        .collect();
    // One flag (and one groups entry) per box by construction: the length checks cannot fail.
    let grouped = bodies.iter().any(|b| b.groups != CollisionGroups::ALL);
    let found = if grouped {
        let groups: Vec<CollisionGroups> = (0..aabbs.len())
            .map(|i| bodies.get(i).map_or(CollisionGroups::ALL, |b| b.groups))
            .collect();
        grid.find_pairs(aabbs, &flags, Some(&groups), pairs)
    } else {
        grid.find_pairs(aabbs, &flags, None, pairs)
    };
    if found.is_err() {
        pairs.clear();
    }
}

/// Stage 5: colors the contacts for the colored order (no two of a color share a dynamic
/// body); the sequential order needs no coloring and gets an empty one.
/// [`SolveOrder::ColoredInRounds`] takes the GPU's algorithm instead ([`color_in_rounds`]).
///
/// The greedy coloring visits the contacts in [`top_down_order`], so the low colors, which
/// each pass solves first, hold the top of a pile: a pass carries the weight of the upper
/// bodies down through the pile instead of meeting it one pass late. In manifold order
/// (bodies numbered bottom-up, as scenes are built) the 4,901-cube pyramid drifted 19 cm in
/// 1 s; top-down it holds within 1.5 cm (docs/solver.md).
pub fn color(contacts: &[Contact], bodies: &[Body], order: SolveOrder, gravity: &Vec3) -> Coloring {
    match order {
        SolveOrder::Sequential => Coloring::default(),
        SolveOrder::Colored => {
            // `color_constraints_in_order(pairs, dynamic, top_down_order(..))`, with the
            // contacts' body pairs gathered in visiting order on the pool: the greedy loop,
            // the one part that must run on one thread, then reads them one after the other
            // instead of picking each out of a 210-byte contact in the visiting order's
            // jumps (a 69 MB array on the 42,926-cube pyramid). The same colors.
            let order = top_down_order(contacts, gravity);
            let parallel = contacts.len() >= PARALLEL_MIN_SORT && rayon::current_num_threads() > 1;
            let visit = |&i: &usize| {
                let c = &contacts[i];
                (i, (c.body_a, c.body_b))
            };
            let dynamic = |b: &Body| b.is_dynamic();
            let (visits, dynamic): (Vec<_>, Vec<bool>) = if parallel {
                rayon::join(
                    || {
                        order
                            .par_iter()
                            .with_min_len(PARALLEL_MIN_SORT / 4)
                            .map(visit)
                            .collect()
                    },
                    || {
                        bodies
                            .par_iter()
                            .with_min_len(PARALLEL_MIN_SORT / 4)
                            .map(dynamic)
                            .collect()
                    },
                )
            } else {
                (
                    order.iter().map(visit).collect(),
                    bodies.iter().map(dynamic).collect(),
                )
            };
            color_visits(&visits, &dynamic, contacts.len())
        }
        SolveOrder::ColoredInRounds => {
            let candidates: Vec<ColorCandidate> = contacts
                .iter()
                .map(|c| ColorCandidate {
                    bodies: (c.body_a, c.body_b),
                    touching: true,
                    seed: None,
                })
                .collect();
            let dynamic: Vec<bool> = bodies.iter().map(Body::is_dynamic).collect();
            Coloring::from_colors(color_in_rounds(&candidates, &dynamic))
        }
    }
}

/// Contact indices from the highest manifold centre along `-gravity` to the lowest (ties in
/// manifold order); manifold order without gravity.
///
/// Each contact's height becomes one `u64` sort key: the height's bits mapped so that
/// unsigned order is [`Real::total_cmp`]'s, inverted (highest first), over the contact index
/// (ties in manifold order). The keys are distinct, so an unstable sort, on the pool or not,
/// gives exactly the order of a stable sort by height, and it sorts plain integers instead of
/// indices compared through a height array.
pub fn top_down_order(contacts: &[Contact], gravity: &Vec3) -> Vec<usize> {
    let g = gravity.norm();
    if g == 0.0 {
        return (0..contacts.len()).collect();
    }
    assert!(
        contacts.len() <= u32::MAX as usize,
        "a contact index is a u32 in the sort key"
    );
    let up = -gravity / g;
    let key = |(i, c): (usize, &Contact)| {
        let points = c.manifold.points();
        let sum: Vec3 = points.iter().map(|p| p.position.coords).sum();
        let height = sum.dot(&up) / points.len().max(1) as Real;
        (u64::from(!total_order_bits(height)) << 32) | i as u64
    };
    let parallel = contacts.len() >= PARALLEL_MIN_SORT && rayon::current_num_threads() > 1;
    let keys: Vec<u64> = if parallel {
        let mut keys = Vec::with_capacity(contacts.len());
        contacts
            .par_iter()
            .enumerate()
            .with_min_len(PARALLEL_MIN_SORT / 4)
            .map(key)
            .collect_into_vec(&mut keys);
        keys.par_sort_unstable();
        keys
    } else {
        let mut keys: Vec<u64> = contacts.iter().enumerate().map(key).collect();
        keys.sort_unstable();
        keys
    };
    let index = |&k: &u64| (k & u64::from(u32::MAX)) as usize;
    if parallel {
        keys.par_iter()
            .with_min_len(PARALLEL_MIN_SORT / 4)
            .map(index)
            .collect()
    } else {
        keys.iter().map(index).collect()
    }
}

/// Contacts below which [`top_down_order`] stays on the calling thread.
const PARALLEL_MIN_SORT: usize = 8192;

/// The bits of `x` mapped so that comparing them as unsigned integers orders them as
/// [`Real::total_cmp`] does (negative numbers flipped whole, positive ones above them).
fn total_order_bits(x: Real) -> u32 {
    let bits = x.to_bits();
    if bits >> 31 == 1 {
        !bits
    } else {
        bits | 1 << 31
    }
}

/// Stage 7: writes the step's displacements into the poses and stores this step's impulses,
/// keyed by body pair, for warm starting the next step.
pub fn finish(
    bodies: &mut [Body],
    states: &mut [BodyState],
    cache: &mut ContactCache,
    keys: &[PairKey],
    contacts: &[Contact],
) {
    // The cache records points in body A's frame at the poses the manifolds came from, so it
    // is written before the poses move.
    cache.store(keys, contacts, bodies);
    finalize_bodies(bodies, states);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{BodyKind, Material, SolverConfig, color_constraints_in_order};
    use tumble_geometry::{Cuboid, Point3, Pose};

    fn cube(kind: BodyKind, x: Real, y: Real) -> Body {
        crate::tests::cube(kind, Pose::translation(x, y, 0.0), Material::default())
    }

    /// A fixed floor (top at y = 0), a cube resting on it, a second cube resting on the first,
    /// and a fixed wall overlapping the floor.
    fn stack() -> (Vec<Body>, Vec<BodyState>) {
        let mut floor = cube(BodyKind::Fixed, 0.0, -0.5);
        floor.shape = Cuboid::new(Vec3::new(5.0, 0.5, 5.0));
        let wall = cube(BodyKind::Fixed, 4.0, 0.0);
        let bodies = vec![
            floor,
            cube(BodyKind::Dynamic, 0.0, 0.5),
            cube(BodyKind::Dynamic, 0.0, 1.5),
            wall,
        ];
        let states = vec![BodyState::default(); bodies.len()];
        (bodies, states)
    }

    #[test]
    fn update_aabbs_is_the_broad_layers_motion_aabb_of_each_body() {
        let (bodies, mut states) = stack();
        states[1].linear_velocity = Vec3::new(0.0, -6.0, 0.0);
        let aabbs = update_aabbs(&bodies, &states, 0.02, 0.5);
        assert_eq!(aabbs.len(), 4);
        // The falling cube's box reaches 3 m further down (6 m/s over 0.5 s).
        assert!((aabbs[1].min.y - (0.0 - 0.02 - 3.0)).abs() < 1e-6);
        assert!((aabbs[1].max.y - 1.02).abs() < 1e-6);
        assert!((aabbs[2].min.y - 0.98).abs() < 1e-6);
    }

    #[test]
    fn the_broad_phase_leaves_out_the_floor_wall_pair() {
        let (bodies, states) = stack();
        assert_eq!(immovable(&bodies), vec![true, false, false, true]);
        let aabbs = update_aabbs(&bodies, &states, 0.02, 1.0 / 60.0);
        let pairs = broad_phase(&mut KeptPairs::new(), &aabbs, &bodies);
        // Floor-cube, cube-cube; the floor and the wall overlap but neither can move.
        assert_eq!(pairs, vec![(0, 1), (1, 2)]);
    }

    #[test]
    fn the_narrow_phase_orients_pairs_by_id_and_warm_starts_from_the_cache() {
        let (mut bodies, mut states) = stack();
        let aabbs = update_aabbs(&bodies, &states, 0.02, 1.0 / 60.0);
        let pairs = broad_phase(&mut KeptPairs::new(), &aabbs, &bodies);
        // Ids in reverse of the dense order: body A is the one with the smaller id.
        let ids = [40, 30, 20, 10];
        // Every manifold afresh (no recycling): the warm start by feature id is tested.
        let narrow = |bodies: &[Body], states: &[BodyState], cache: &ContactCache| {
            narrow_phase(bodies, states, &pairs, &ids, cache, 0.02, 1.0 / 60.0, 0.0)
        };
        let mut cache = ContactCache::new();
        let out = narrow(&bodies, &states, &cache);
        assert_eq!(out.keys, vec![(30, 40), (20, 30)]);
        assert_eq!((out.contacts[0].body_a, out.contacts[0].body_b), (1, 0));
        assert_eq!(out.contacts[0].manifold.len, 4);
        assert!(out.contacts[0].impulses.iter().all(|j| j.normal == 0.0));
        // Impulses stored by finish come back on the next step's matching points.
        let mut contacts = out.contacts.clone();
        for c in &mut contacts {
            for j in &mut c.impulses {
                j.normal = 2.5;
            }
        }
        finish(&mut bodies, &mut states, &mut cache, &out.keys, &contacts);
        assert_eq!(cache.len(), 2);
        let again = narrow(&bodies, &states, &cache);
        assert_eq!(again.contacts.len(), 2);
        for c in &again.contacts {
            let n = c.manifold.len as usize;
            assert!(c.impulses[..n].iter().all(|j| j.normal == 2.5));
        }
    }

    #[test]
    fn the_colored_order_on_the_pool_gives_the_greedy_colors() {
        // 9,000 constraints (past PARALLEL_MIN_SORT) between 1,500 bodies, some fixed, at
        // seeded heights: the pool's gather of the pairs in visiting order and its body flags
        // must give exactly the colors of the greedy reference on the same top-down order.
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let bodies: Vec<Body> = (0..1500)
            .map(|i| {
                let kind = if i % 37 == 0 {
                    BodyKind::Fixed
                } else {
                    BodyKind::Dynamic
                };
                cube(kind, 0.0, 0.0)
            })
            .collect();
        let contacts: Vec<Contact> = (0..9000)
            .map(|_| {
                let a = rng.random_range(0..1500u32);
                let b = (a + rng.random_range(1..1500u32)) % 1500;
                let mut m = tumble_geometry::Manifold {
                    normal: Vec3::y(),
                    ..Default::default()
                };
                m.push(tumble_geometry::ContactPoint {
                    position: Point3::new(0.0, rng.random_range(-5.0..5.0), 0.0),
                    depth: 0.0,
                    id: 0,
                });
                Contact::new(a, b, m)
            })
            .collect();
        let down = Vec3::new(0.0, -9.81, 0.0);
        let pairs: Vec<(u32, u32)> = contacts.iter().map(|c| (c.body_a, c.body_b)).collect();
        let dynamic: Vec<bool> = bodies.iter().map(Body::is_dynamic).collect();
        let reference =
            color_constraints_in_order(&pairs, &dynamic, top_down_order(&contacts, &down));
        assert!(reference.used_colors() > 4, "a coloring worth the name");
        for threads in [1, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let colored = pool.install(|| color(&contacts, &bodies, SolveOrder::Colored, &down));
            assert_eq!(colored, reference, "{threads} threads");
        }
    }

    #[test]
    fn coloring_visits_the_top_of_the_pile_first() {
        let (bodies, states) = stack();
        let aabbs = update_aabbs(&bodies, &states, 0.02, 1.0 / 60.0);
        let pairs = broad_phase(&mut KeptPairs::new(), &aabbs, &bodies);
        let ids = [0, 1, 2, 3];
        let out = narrow_phase(
            &bodies,
            &states,
            &pairs,
            &ids,
            &ContactCache::new(),
            0.02,
            1.0,
            0.0,
        );
        let down = Vec3::new(0.0, -9.81, 0.0);
        // Contact 0 (floor-cube, at y = 0) is below contact 1 (cube-cube, at y = 1).
        assert_eq!(top_down_order(&out.contacts, &down), vec![1, 0]);
        assert_eq!(top_down_order(&out.contacts, &-down), vec![0, 1]);
        assert_eq!(top_down_order(&out.contacts, &Vec3::zeros()), vec![0, 1]);
        // Both share cube 1: the upper contact takes color 0, the lower one color 1.
        let coloring = color(&out.contacts, &bodies, SolveOrder::Colored, &down);
        assert_eq!(coloring.colors, vec![1, 0]);
        let sequential = color(&out.contacts, &bodies, SolveOrder::Sequential, &down);
        assert_eq!(sequential, Coloring::default());
    }

    #[test]
    fn finish_moves_the_poses_by_the_solved_displacements() {
        let (mut bodies, mut states) = stack();
        let mut contacts = Vec::new();
        let coloring = Coloring::default();
        let config = SolverConfig::default();
        // No contacts: the cube falls freely for one step.
        crate::solve(
            &bodies,
            &mut states,
            &mut contacts,
            &coloring,
            &config,
            0.1,
            &Vec3::new(0.0, -10.0, 0.0),
        );
        let y = bodies[2].pose.translation.y;
        finish(&mut bodies, &mut states, &mut ContactCache::new(), &[], &[]);
        assert!(bodies[2].pose.translation.y < y);
        assert_eq!(states[2].delta_position, Vec3::zeros());
        assert_eq!(
            bodies[0].pose.translation.vector,
            Point3::new(0.0, -0.5, 0.0).coords
        );
    }
}

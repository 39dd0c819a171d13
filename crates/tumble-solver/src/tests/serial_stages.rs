//! The stages that were serial and now run on the pool (the contact cache's store, the
//! coloring's top-down order) give the same answer as the serial algorithm they replaced, on
//! one thread and on several: the step's bits depend on it.

use std::collections::HashMap;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tumble_geometry::{Point3, Pose, Real, Rot, Vec3};

use super::{manifold, material, unit_cube};
use crate::stages::top_down_order;
use crate::{Body, CachedManifold, Contact, ContactCache, PairKey};

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
}

/// `n` contacts between random bodies of `bodies`, one to four points each at random heights
/// drawn from a few levels (so many manifold centres tie, at zero among others).
fn contacts(rng: &mut ChaCha8Rng, n: usize, bodies: u32) -> Vec<Contact> {
    contacts_at(rng, n, bodies, false)
}

/// [`contacts`], or with `spread` each manifold at a height drawn from -50 to 50 m (few ties,
/// and heights across many binades, so that every byte of the sort key varies).
fn contacts_at(rng: &mut ChaCha8Rng, n: usize, bodies: u32, spread: bool) -> Vec<Contact> {
    let levels = [-0.0, 0.0, 0.5, 1.0, 1.5, -2.0, 3.25];
    (0..n)
        .map(|_| {
            let y = if spread {
                rng.random_range(-50.0..50.0)
            } else {
                levels[rng.random_range(0..levels.len())]
            };
            let count = rng.random_range(1..=4);
            let points: Vec<(Point3, Real, u32)> = (0..count)
                .map(|k| {
                    // Points of one manifold share a height, so the centre is exactly `y`.
                    let x = rng.random_range(-1.0..1.0);
                    (Point3::new(x, y, 0.1 * k as Real), 0.01, k)
                })
                .collect();
            let a = rng.random_range(0..bodies);
            let b = (a + rng.random_range(1..bodies)) % bodies;
            let mut c = Contact::new(a, b, manifold(Vec3::y(), &points));
            for (k, imp) in c.impulses.iter_mut().enumerate() {
                imp.normal = rng.random_range(0.0..2.0) + k as Real;
            }
            c.tilt_impulse = Vec3::new(rng.random_range(-1.0..1.0), 0.0, 0.0);
            c
        })
        .collect()
}

#[test]
fn the_top_down_order_is_the_stable_sort_by_height_on_any_pool() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    // 20,000 contacts: past the parallel threshold; 500: below it; each with tied heights
    // and with spread ones.
    for (n, spread) in [(20_000, false), (500, false), (20_000, true), (500, true)] {
        let contacts = contacts_at(&mut rng, n, 300, spread);
        for gravity in [Vec3::new(0.0, -9.81, 0.0), Vec3::new(0.0, 9.81, 0.0)] {
            // The order this replaced: indices stably sorted by height, highest first.
            let up = -gravity / gravity.norm();
            let height: Vec<Real> = contacts
                .iter()
                .map(|c| {
                    let points = c.manifold.points();
                    let sum: Vec3 = points.iter().map(|p| p.position.coords).sum();
                    sum.dot(&up) / points.len() as Real
                })
                .collect();
            let mut expected: Vec<usize> = (0..n).collect();
            expected.sort_by(|&i, &j| height[j].total_cmp(&height[i]));
            for threads in [1, 4] {
                let got = pool(threads).install(|| top_down_order(&contacts, &gravity));
                assert_eq!(got, expected, "{n} contacts, {threads} threads");
            }
        }
        assert_eq!(
            top_down_order(&contacts, &Vec3::zeros()),
            (0..n).collect::<Vec<_>>()
        );
    }
}

/// 64 unit cubes in a row, each turned differently, so that no two bodies share a pose.
fn turned_cubes() -> Vec<Body> {
    (0..64)
        .map(|i| {
            let pose = Pose::from_parts(
                Vec3::new(i as Real, 0.5, -1.0).into(),
                Rot::from_euler_angles(0.1 * i as Real, 0.3, -0.2),
            );
            unit_cube(1.0, pose, material(0.5, 0.0))
        })
        .collect()
}

#[test]
fn the_cache_stored_on_any_pool_holds_what_a_map_of_the_last_manifold_per_pair_holds() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let bodies = turned_cubes();
    // 6,000 manifolds (past the parallel threshold) over pair keys drawn from a small set,
    // so some pairs are stored twice: the later manifold must win.
    let contacts = contacts(&mut rng, 6000, 64);
    let keys: Vec<PairKey> = contacts
        .iter()
        .map(|_| {
            let a = rng.random_range(0..90u64);
            (a | 1 << 32, (a + rng.random_range(1..70u64)) | 1 << 32)
        })
        .collect();
    let mut reference: HashMap<PairKey, CachedManifold> = HashMap::new();
    for (k, c) in keys.iter().zip(&contacts) {
        reference.insert(
            *k,
            CachedManifold::of(
                c,
                &bodies[c.body_a as usize].pose,
                &bodies[c.body_b as usize].pose,
            ),
        );
    }
    let mut expected: Vec<_> = reference.into_iter().collect();
    expected.sort_unstable_by_key(|(k, _)| *k);
    assert!(expected.len() < keys.len(), "some pair is stored twice");
    for threads in [1, 4] {
        let mut cache = ContactCache::new();
        // Twice into one cache: the second store replaces the first.
        for _ in 0..2 {
            pool(threads).install(|| cache.store(&keys, &contacts, &bodies));
            assert_eq!(cache.len(), expected.len(), "{threads} threads");
            assert_eq!(cache.entries(), expected, "{threads} threads");
            for (k, m) in &expected {
                assert_eq!(cache.get(k), Some(m));
            }
            // Looking near a slot gives what the table gives from any hint: the pair's own
            // slot, an earlier slot of a pair stored twice (where the later manifold wins, so
            // the slot tried first must not answer), another pair's slot, or none.
            for (slot, k) in keys.iter().enumerate() {
                for hint in [slot, slot + 1, 0, keys.len()] {
                    assert_eq!(
                        cache.get_near(k, hint).map(|(_, m)| m),
                        cache.get(k),
                        "{threads} threads, slot {slot}, hint {hint}"
                    );
                }
            }
        }
        // Each pair once: the slot tried first is the pair's own, and it answers with it.
        let mut seen = std::collections::HashSet::new();
        let (once_keys, once): (Vec<PairKey>, Vec<Contact>) = keys
            .iter()
            .zip(&contacts)
            .filter(|(k, _)| seen.insert(**k))
            .map(|(k, c)| (*k, *c))
            .unzip();
        let mut distinct = ContactCache::new();
        pool(threads).install(|| distinct.store(&once_keys, &once, &bodies));
        for (slot, k) in once_keys.iter().enumerate() {
            let near = distinct.get_near(k, slot);
            assert_eq!(near.map(|(s, _)| s), Some(slot));
            assert_eq!(near.map(|(_, m)| m), distinct.get(k));
            assert_eq!(distinct.get_near(k, slot + 1).map(|(s, _)| s), Some(slot));
        }
        // The entries rebuild the same cache; forgetting a body drops exactly its pairs.
        let again = ContactCache::from_entries(cache.entries());
        assert_eq!(again.entries(), expected);
        let gone = keys[0].0;
        cache.forget_body(gone);
        let left: Vec<_> = expected
            .iter()
            .filter(|(k, _)| k.0 != gone && k.1 != gone)
            .copied()
            .collect();
        assert!(left.len() < expected.len());
        assert_eq!(cache.entries(), left);
        assert_eq!(cache.get(&keys[0]), None);
    }
    // An empty store empties the cache.
    let mut cache = ContactCache::from_entries(expected);
    cache.store(&[], &[], &bodies);
    assert!(cache.is_empty());
    assert_eq!(cache.entries(), vec![]);
}

#[test]
fn storing_last_steps_pairs_again_gives_the_entries_a_rebuilt_table_gives() {
    // A resting pile stores the same pairs in the same order every step, and the store then
    // keeps its table and finds a recycled contact's old entry at its own index. The same
    // store into a cache whose table was built from the same pairs in another order takes the
    // general path (a lookup per pair); both must hold the same entries, bit for bit, on one
    // thread and past the parallel threshold on four.
    let mut rng = ChaCha8Rng::seed_from_u64(23);
    let bodies = turned_cubes();
    let n = 6000;
    // Distinct keys in a shuffled order (the general path's table is rebuilt sorted).
    let mut keys: Vec<PairKey> = (0..n as u64)
        .map(|i| (i | 1 << 32, (i + 7) | 1 << 32))
        .collect();
    for i in (1..keys.len()).rev() {
        keys.swap(i, rng.random_range(0..=i));
    }
    let first = contacts(&mut rng, n, 64);
    // This step's contacts: the same bodies, new manifolds, two in three recycled (a recycled
    // entry keeps its old anchors, so it depends on which old entry the store found).
    let mut second = contacts(&mut rng, n, 64);
    for (i, (c, old)) in second.iter_mut().zip(&first).enumerate() {
        (c.body_a, c.body_b) = (old.body_a, old.body_b);
        c.recycled = i % 3 != 0;
    }
    let mut old = ContactCache::new();
    old.store(&keys, &first, &bodies);
    for threads in [1, 4] {
        let pool = pool(threads);
        let mut kept = ContactCache::new();
        pool.install(|| kept.store(&keys, &first, &bodies));
        let mut rebuilt = ContactCache::from_entries(kept.entries());
        pool.install(|| kept.store(&keys, &second, &bodies));
        pool.install(|| rebuilt.store(&keys, &second, &bodies));
        let entries = kept.entries();
        assert_eq!(entries.len(), n, "{threads} threads");
        assert_eq!(entries, rebuilt.entries(), "{threads} threads");
        // And each entry is what the contact and its pair's first entry make of it.
        for (key, c) in keys.iter().zip(&second) {
            let pose_a = &bodies[c.body_a as usize].pose;
            let expected = if c.recycled {
                CachedManifold::recycled_of(c, pose_a, old.get(key).unwrap())
            } else {
                CachedManifold::of(c, pose_a, &bodies[c.body_b as usize].pose)
            };
            assert_eq!(
                kept.get(key),
                Some(&expected),
                "{threads} threads, pair {key:?}"
            );
        }
    }
}

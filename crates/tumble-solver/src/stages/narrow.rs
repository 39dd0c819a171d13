//! Stage 3, the narrow phase: the box-box test on every candidate pair, with recycling and
//! warm starting from the contact cache, and the working memory it keeps between steps.

use rayon::prelude::*;
use tumble_geometry::Real;
use tumble_narrow::{BoxMotion, collide_cuboids_cached};

use super::PARALLEL_MIN_PAIRS;
use crate::concat::concat_into;
use crate::{Body, BodyState, Contact, ContactCache, PairKey, recycle_tolerance};

/// What the pair margin needs of a body ([`tumble_narrow::pair_margin`]).
pub fn box_motion(body: &Body, state: &BodyState) -> BoxMotion {
    BoxMotion {
        half_extents: body.shape.half_extents,
        linear: state.linear_velocity,
        angular: state.angular_velocity,
    }
}

/// The manifolds found this step and the stable key of each one's body pair.
#[derive(Clone, Debug, Default)]
pub struct NarrowPhaseOutput {
    /// One contact per touching (or speculatively close) pair, A's key below B's.
    pub contacts: Vec<Contact>,
    /// The pair key of each contact, for persistence.
    pub keys: Vec<PairKey>,
}

/// Stage 3: the box-box test on every pair. Each pair is oriented so body A has the smaller
/// stable id (`ids`), which keeps the cached feature and impulses meaningful when dense
/// indices change; last step's feature is passed for hysteresis and last step's impulses are
/// matched by feature id for warm starting.
///
/// With `recycle_distance` above 0, a pair whose bodies barely moved relative to each other
/// since its manifold was last computed reuses it ([`crate::CachedManifold::recycle`], within
/// [`recycle_tolerance`]) with last step's impulses as they were, and the contact is marked
/// [`Contact::recycled`]; 0 computes every manifold afresh.
#[allow(clippy::too_many_arguments)]
pub fn narrow_phase(
    bodies: &[Body],
    states: &[BodyState],
    pairs: &[(u32, u32)],
    ids: &[u64],
    cache: &ContactCache,
    margin: Real,
    dt: Real,
    recycle_distance: Real,
) -> NarrowPhaseOutput {
    let mut buffers = NarrowBuffers::default();
    narrow_phase_with(
        bodies,
        states,
        pairs,
        ids,
        cache,
        margin,
        dt,
        recycle_distance,
        &mut buffers,
    )
}

/// The narrow phase's working memory, kept between steps: each pool task's arrays, and the
/// arrays the next output is written into (the caller hands back the last step's output when
/// it is done with it, [`NarrowBuffers::give_back`]).
///
/// On a large pile the output is tens of megabytes (about 210 bytes a manifold: 69 MB on the
/// 42,926-cube pyramid), above the size from which the allocator maps fresh pages for each
/// allocation and unmaps them on free. Allocated every step, the tasks' arrays and the output
/// were faulted in page by page every step (some 20,000 faults a step there, and twice as many
/// on two threads); kept, they are faulted in once. They stay at their largest size (about
/// three times the largest output: the tasks' arrays and two output arrays) for the life of
/// the buffers.
#[derive(Debug, Default)]
pub struct NarrowBuffers {
    /// One pair of arrays per pool task of the last parallel run.
    parts: Vec<(Vec<Contact>, Vec<PairKey>)>,
    /// Arrays the next output is written into (empty, with the capacity they had).
    contacts: Vec<Contact>,
    keys: Vec<PairKey>,
}

impl NarrowBuffers {
    /// Takes back a finished output's arrays, to be written over by the next narrow phase.
    /// Of two arrays, the larger is kept.
    pub fn give_back(&mut self, mut contacts: Vec<Contact>, mut keys: Vec<PairKey>) {
        contacts.clear();
        keys.clear();
        if contacts.capacity() > self.contacts.capacity() {
            self.contacts = contacts;
        }
        if keys.capacity() > self.keys.capacity() {
            self.keys = keys;
        }
    }
}

/// [`narrow_phase`] with its working memory in `buffers` (the same output, bit for bit): the
/// output's arrays are `buffers`' spare ones, and the pool tasks write into arrays kept there.
#[allow(clippy::too_many_arguments)]
pub fn narrow_phase_with(
    bodies: &[Body],
    states: &[BodyState],
    pairs: &[(u32, u32)],
    ids: &[u64],
    cache: &ContactCache,
    margin: Real,
    dt: Real,
    recycle_distance: Real,
    buffers: &mut NarrowBuffers,
) -> NarrowPhaseOutput {
    // `hint`: the cache slot after the last pair's, where this pair's entry usually is.
    let test = |&(i, j): &(u32, u32), hint: &mut usize| {
        let (a, b) = if ids[i as usize] <= ids[j as usize] {
            (i, j)
        } else {
            (j, i)
        };
        let (ba, bb) = (&bodies[a as usize], &bodies[b as usize]);
        let key = (ids[a as usize], ids[b as usize]);
        let m = tumble_narrow::pair_margin(
            &box_motion(ba, &states[a as usize]),
            &box_motion(bb, &states[b as usize]),
            margin,
            dt,
        );
        // One lookup serves the recycling, the hysteresis and both warm starts.
        let old = cache.get_near(&key, *hint).map(|(slot, entry)| {
            *hint = slot + 1;
            entry
        });
        if recycle_distance > 0.0
            && let Some(old) = old
            && let Some(manifold) = old.recycle(
                &ba.pose,
                &bb.pose,
                m,
                recycle_tolerance(recycle_distance, &ba.shape, &bb.shape),
            )
        {
            // The same points under the same ids and reference feature: each inherits its
            // own impulse, which is what `warm_start` would match, and the normal turned by
            // less than `warm_tilt`'s angle.
            let contact = Contact {
                impulses: old.impulses,
                tilt_impulse: old.tilt_impulse,
                recycled: true,
                ..Contact::new(a, b, manifold)
            };
            return Some((contact, key));
        }
        let manifold = collide_cuboids_cached(
            &ba.shape,
            &ba.pose,
            &bb.shape,
            &bb.pose,
            m,
            old.map(|o| (o.kind, o.feature)),
        )?;
        let mut contact = Contact::new(a, b, manifold);
        if let Some(old) = old {
            contact.impulses = old.warm_start(&manifold, &ba.pose);
            contact.tilt_impulse = old.warm_tilt(&manifold, &ba.pose);
        }
        Some((contact, key))
    };
    // In pair order on either path. On the pool, each task's pairs fill two kept arrays
    // reserved at their pair count (no regrowth), which are then joined on the pool into the
    // output (`concat_into`). One thread writes the output directly: the concatenation would
    // copy every contact once more for nothing.
    let mut contacts = std::mem::take(&mut buffers.contacts);
    let mut keys = std::mem::take(&mut buffers.keys);
    contacts.clear();
    keys.clear();
    if pairs.len() >= PARALLEL_MIN_PAIRS && rayon::current_num_threads() > 1 {
        let tasks = 4 * rayon::current_num_threads();
        let chunk = pairs.len().div_ceil(tasks).max(PARALLEL_MIN_PAIRS);
        let parts = &mut buffers.parts;
        parts.resize_with(pairs.len().div_ceil(chunk), Default::default);
        parts
            .par_iter_mut()
            .zip(pairs.par_chunks(chunk))
            .for_each(|(found, chunk)| {
                found.0.clear();
                found.1.clear();
                found.0.reserve(chunk.len());
                found.1.reserve(chunk.len());
                let mut hint = 0;
                found.extend(chunk.iter().filter_map(|p| test(p, &mut hint)));
            });
        let parts = &buffers.parts;
        rayon::join(
            || concat_into(parts.iter().map(|p| &p.0[..]), &mut contacts),
            || concat_into(parts.iter().map(|p| &p.1[..]), &mut keys),
        );
    } else {
        // Reserved at the pair count, as each task's arrays are: grown by doubling, the
        // contacts were copied again at every growth.
        contacts.reserve(pairs.len());
        keys.reserve(pairs.len());
        let mut hint = 0;
        let mut found = (contacts, keys);
        found.extend(pairs.iter().filter_map(|p| test(p, &mut hint)));
        (contacts, keys) = found;
    }
    NarrowPhaseOutput { contacts, keys }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stages::{broad_phase, update_aabbs};
    use crate::{BodyKind, Material};
    use tumble_broad::KeptPairs;
    use tumble_geometry::{Cuboid, Point3, Pose, Vec3};

    #[test]
    fn the_narrow_phase_with_kept_buffers_gives_the_fresh_output_on_any_pool() {
        // A 24 x 24 layer of cubes 1 mm apart on a floor, each turned a little: about 1,700
        // pairs, past PARALLEL_MIN_PAIRS, so pools of more than one thread split them into
        // tasks. The kept buffers first hold another scene's output (a 40 x 40 layer raised
        // 5 cm, its side contacts only: more pairs, so more tasks, found on eight threads)
        // and a larger array given back, so stale contents, a stale task's array or a wrong
        // length would show; the output must equal the fresh one in every bit, in order.
        let layer = |n: usize, lift: Real| {
            let mut floor = crate::tests::cube(
                BodyKind::Fixed,
                Pose::translation(0.0, -0.5, 0.0),
                Material::default(),
            );
            floor.shape = Cuboid::new(Vec3::new(20.0, 0.5, 20.0));
            let mut bodies = vec![floor];
            for i in 0..n {
                for j in 0..n {
                    let turn = 0.001 * ((i * n + j) % 7) as Real;
                    let pose = Pose::from_parts(
                        Point3::new(i as Real * 1.001, 0.5 + lift, j as Real * 1.001).into(),
                        tumble_geometry::Rot::from_euler_angles(0.0, turn, 0.0),
                    );
                    bodies.push(crate::tests::cube(
                        BodyKind::Dynamic,
                        pose,
                        Material::default(),
                    ));
                }
            }
            let states = vec![BodyState::default(); bodies.len()];
            (bodies, states)
        };
        let run = |n: usize, lift: Real, buffers: Option<&mut NarrowBuffers>| {
            let (bodies, states) = layer(n, lift);
            let aabbs = update_aabbs(&bodies, &states, 0.02, 1.0 / 60.0);
            let pairs = broad_phase(&mut KeptPairs::new(), &aabbs, &bodies);
            let ids: Vec<u64> = (0..bodies.len() as u64).rev().collect();
            let cache = ContactCache::new();
            let (margin, dt) = (0.02, 1.0 / 60.0);
            match buffers {
                Some(b) => {
                    narrow_phase_with(&bodies, &states, &pairs, &ids, &cache, margin, dt, 0.0, b)
                }
                None => narrow_phase(&bodies, &states, &pairs, &ids, &cache, margin, dt, 0.0),
            }
        };
        for threads in [1, 4] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let fresh = pool.install(|| run(24, 0.0, None));
            assert!(
                fresh.contacts.len() > 1000,
                "{} manifolds",
                fresh.contacts.len()
            );
            let mut buffers = NarrowBuffers::default();
            // First on eight threads (more tasks than the pool below has), so the kept run
            // must drop the extra tasks' arrays, not join them into its output.
            let wide = rayon::ThreadPoolBuilder::new()
                .num_threads(8)
                .build()
                .unwrap();
            let other = wide.install(|| run(40, 0.05, Some(&mut buffers)));
            assert_ne!(other.contacts.len(), fresh.contacts.len());
            let junk = vec![Contact::new(9, 9, Default::default()); 3 * fresh.contacts.len()];
            buffers.give_back(junk, vec![(9, 9); 3 * fresh.keys.len()]);
            buffers.give_back(other.contacts, other.keys);
            let kept = pool.install(|| run(24, 0.0, Some(&mut buffers)));
            assert_eq!(kept.keys, fresh.keys, "{threads} threads");
            assert_eq!(kept.contacts.len(), fresh.contacts.len());
            for (k, f) in kept.contacts.iter().zip(&fresh.contacts) {
                // Debug prints each float's shortest round-trip form: equal text, equal bits.
                assert_eq!(format!("{k:?}"), format!("{f:?}"), "{threads} threads");
            }
            // The larger array given back was written over, not a new one allocated.
            assert!(kept.contacts.capacity() >= 3 * fresh.contacts.len());
        }
    }
}

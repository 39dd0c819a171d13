//! Stage 3: candidate pairs to contact manifolds, with last step's impulses attached.

use rayon::prelude::*;
use tumble_geometry::Real;
use tumble_narrow::collide_cuboids_cached;
use tumble_solver::{Body, BodyState, Contact, ContactCache, PairKey};

/// Pairs per rayon task below which the narrow phase stays on one thread: a box-box test
/// costs about a microsecond, a task a few.
const PARALLEL_MIN_PAIRS: usize = 256;

/// The manifolds found this step and the stable key of each one's body pair.
#[derive(Clone, Debug, Default)]
pub struct NarrowPhaseOutput {
    /// One contact per touching (or speculatively close) pair, A's key below B's.
    pub contacts: Vec<Contact>,
    /// The pair key of each contact, for persistence.
    pub keys: Vec<PairKey>,
}

/// The speculative margin of a pair: the base margin plus how far the two boxes can close in
/// one step (relative speed of the centres plus the rim speed of each spin, times `dt`).
pub fn pair_margin(a: (&Body, &BodyState), b: (&Body, &BodyState), margin: Real, dt: Real) -> Real {
    let closing = (b.1.linear_velocity - a.1.linear_velocity).norm()
        + a.1.angular_velocity.norm() * a.0.shape.half_extents.norm()
        + b.1.angular_velocity.norm() * b.0.shape.half_extents.norm();
    margin + closing * dt
}

/// Runs the box-box test on every pair. Each pair is oriented so body A has the smaller
/// stable id (`ids`), which keeps the cached feature and impulses meaningful when dense
/// indices change; last step's feature is passed for hysteresis and last step's impulses are
/// matched by feature id for warm starting.
pub fn narrow_phase(
    bodies: &[Body],
    states: &[BodyState],
    pairs: &[(u32, u32)],
    ids: &[u64],
    cache: &ContactCache,
    margin: Real,
    dt: Real,
) -> NarrowPhaseOutput {
    let test = |&(i, j): &(u32, u32)| {
        let (a, b) = if ids[i as usize] <= ids[j as usize] {
            (i, j)
        } else {
            (j, i)
        };
        let (ba, bb) = (&bodies[a as usize], &bodies[b as usize]);
        let key = (ids[a as usize], ids[b as usize]);
        let m = pair_margin(
            (ba, &states[a as usize]),
            (bb, &states[b as usize]),
            margin,
            dt,
        );
        let manifold = collide_cuboids_cached(
            &ba.shape,
            &ba.pose,
            &bb.shape,
            &bb.pose,
            m,
            cache.previous_feature(&key),
        )?;
        let mut contact = Contact::new(a, b, manifold);
        contact.impulses = cache.warm_start(&key, &manifold, &ba.pose);
        contact.tilt_impulse = cache.warm_tilt(&key, &manifold, &ba.pose);
        Some((contact, key))
    };
    let found: Vec<(Contact, PairKey)> = if pairs.len() >= PARALLEL_MIN_PAIRS {
        pairs.par_iter().filter_map(test).collect()
    } else {
        pairs.iter().filter_map(test).collect()
    };
    let (contacts, keys) = found.into_iter().unzip();
    NarrowPhaseOutput { contacts, keys }
}

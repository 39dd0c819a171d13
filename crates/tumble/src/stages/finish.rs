//! Stage 7: poses out, impulses kept for the next step.

use tumble_solver::{Body, BodyState, Contact, ContactCache, PairKey, finalize_bodies};

/// Writes the step's displacements into the poses and stores this step's impulses, keyed by
/// body pair, for warm starting the next step.
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

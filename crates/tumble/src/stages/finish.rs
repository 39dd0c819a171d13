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
    finalize_bodies(bodies, states);
    cache.store(keys, contacts);
}

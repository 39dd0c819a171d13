//! Visiting constraints in solve order: batches run one after another; a parallel batch (one
//! graph color) runs its constraints on the rayon pool, a sequential batch (the reference
//! order, or the overflow set) one at a time.
//!
//! A parallel batch gathers each constraint's two body states, solves on the copies and
//! scatters the dynamic ones back. Inside a color no dynamic body appears twice, so every
//! copy sees exactly the state a sequential visit would see, and the result does not depend on
//! the number of threads or on scheduling.

use std::ops::Range;

use rayon::prelude::*;

use crate::{BodyState, ContactConstraint};

/// A run of constraints (indices into the step's constraint array) visited as one unit.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Batch {
    /// The constraints of the batch.
    pub range: Range<usize>,
    /// True when no two constraints of the batch share a dynamic body and it is large enough
    /// to be worth the thread pool.
    pub parallel: bool,
}

/// Applies `op` to every constraint, batch by batch.
pub fn sweep<F>(
    constraints: &mut [ContactConstraint],
    batches: &[Batch],
    states: &mut [BodyState],
    scratch: &mut Vec<(BodyState, BodyState)>,
    op: &F,
) where
    F: Fn(&mut ContactConstraint, &mut BodyState, &mut BodyState) + Sync,
{
    for batch in batches {
        let slice = &mut constraints[batch.range.clone()];
        if batch.parallel {
            scratch.resize(slice.len(), Default::default());
            let read: &[BodyState] = states;
            slice
                .par_iter_mut()
                .zip(scratch.par_iter_mut())
                .for_each(|(c, out)| {
                    let mut a = read[c.body_a as usize];
                    let mut b = read[c.body_b as usize];
                    op(c, &mut a, &mut b);
                    *out = (a, b);
                });
            for (c, (a, b)) in slice.iter().zip(scratch.iter()) {
                write_back(c, states, a, b);
            }
        } else {
            for c in slice.iter_mut() {
                let mut a = states[c.body_a as usize];
                let mut b = states[c.body_b as usize];
                op(c, &mut a, &mut b);
                write_back(c, states, &a, &b);
            }
        }
    }
}

/// Stores the solved copies of the dynamic bodies; fixed and kinematic bodies are read-only.
#[inline]
fn write_back(c: &ContactConstraint, states: &mut [BodyState], a: &BodyState, b: &BodyState) {
    if c.dynamic_a {
        let s = &mut states[c.body_a as usize];
        s.linear_velocity = a.linear_velocity;
        s.angular_velocity = a.angular_velocity;
    }
    if c.dynamic_b {
        let s = &mut states[c.body_b as usize];
        s.linear_velocity = b.linear_velocity;
        s.angular_velocity = b.angular_velocity;
    }
}

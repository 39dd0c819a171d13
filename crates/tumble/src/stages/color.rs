//! Stage 5: manifolds to graph colors.

use tumble_solver::{Body, Coloring, Contact, SolveOrder, color_constraints};

/// Colors the contacts for the colored order (no two of a color share a dynamic body); the
/// sequential order needs no coloring and gets an empty one.
pub fn color(contacts: &[Contact], bodies: &[Body], order: SolveOrder) -> Coloring {
    match order {
        SolveOrder::Sequential => Coloring::default(),
        SolveOrder::Colored => {
            let pairs: Vec<(u32, u32)> = contacts.iter().map(|c| (c.body_a, c.body_b)).collect();
            let dynamic: Vec<bool> = bodies.iter().map(Body::is_dynamic).collect();
            color_constraints(&pairs, &dynamic)
        }
    }
}

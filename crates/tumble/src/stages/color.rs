//! Stage 5: manifolds to graph colors.

use tumble_geometry::{Real, Vec3};
use tumble_solver::{Body, Coloring, Contact, SolveOrder, color_constraints_in_order};

/// Colors the contacts for the colored order (no two of a color share a dynamic body); the
/// sequential order needs no coloring and gets an empty one.
///
/// The greedy coloring visits the contacts from the highest to the lowest along `-gravity`,
/// so the low colors, which each pass solves first, hold the top of a pile: a pass carries the
/// weight of the upper bodies down through the pile instead of meeting it one pass late. In
/// manifold order (bodies numbered bottom-up, as scenes are built) the 4,901-cube pyramid
/// drifted 19 cm in 1 s; top-down it holds within 1.5 cm (docs/solver.md). Without gravity the
/// manifold order is kept.
pub fn color(contacts: &[Contact], bodies: &[Body], order: SolveOrder, gravity: &Vec3) -> Coloring {
    match order {
        SolveOrder::Sequential => Coloring::default(),
        SolveOrder::Colored => {
            let pairs: Vec<(u32, u32)> = contacts.iter().map(|c| (c.body_a, c.body_b)).collect();
            let dynamic: Vec<bool> = bodies.iter().map(Body::is_dynamic).collect();
            color_constraints_in_order(&pairs, &dynamic, top_down(contacts, gravity))
        }
    }
}

/// Contact indices from the highest manifold centre along `-gravity` to the lowest (ties in
/// manifold order); manifold order without gravity.
fn top_down(contacts: &[Contact], gravity: &Vec3) -> Vec<usize> {
    let mut visit: Vec<usize> = (0..contacts.len()).collect();
    let g = gravity.norm();
    if g == 0.0 {
        return visit;
    }
    let up = -gravity / g;
    let height: Vec<Real> = contacts
        .iter()
        .map(|c| {
            let points = c.manifold.points();
            let sum: Vec3 = points.iter().map(|p| p.position.coords).sum();
            sum.dot(&up) / points.len().max(1) as Real
        })
        .collect();
    visit.sort_by(|&i, &j| height[j].total_cmp(&height[i]));
    visit
}

//! Choice of the sweep axis: the one along which the box centres spread most.

use tumble_geometry::Aabb;

/// The axis (0 = x, 1 = y, 2 = z) along which the centres of `aabbs` have the largest variance.
///
/// Sweeping along the axis of largest spread keeps the sweep window (boxes whose intervals
/// overlap along that axis) smallest, since the sorted lower bounds are farthest apart there;
/// this is the heuristic of the thesis and of Bullet's and Box2D's SAP variants. Sums are
/// kept in f64 so that 100k boxes far from the origin do not cancel to noise. Ties (and a
/// spread that is not a number, from non-finite boxes) go to the lower axis, so the choice
/// is deterministic.
pub fn sweep_axis(aabbs: &[Aabb]) -> usize {
    if aabbs.len() < 2 {
        return 0;
    }
    let mut sum = [0.0f64; 3];
    let mut sum_sq = [0.0f64; 3];
    for b in aabbs {
        for k in 0..3 {
            // Twice the centre: the factor 2 does not change which axis wins.
            let c = f64::from(b.min[k]) + f64::from(b.max[k]);
            sum[k] += c;
            sum_sq[k] += c * c;
        }
    }
    let n = aabbs.len() as f64;
    let variance = |k: usize| sum_sq[k] / n - (sum[k] / n).powi(2);
    let mut best = 0;
    for k in 1..3 {
        if variance(k) > variance(best) {
            best = k;
        }
    }
    best
}

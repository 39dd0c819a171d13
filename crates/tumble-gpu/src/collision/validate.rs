//! Checks of host input before it reaches the GPU: a NaN pose would not crash a kernel, it
//! would silently poison the sort and every pair after it, so bad input is refused here with
//! the field and value named.

use crate::GpuError;
use crate::error::invalid;
use crate::layout::{BODY_WORLD_SHIFT, GpuPose, GpuShape, GpuVelocity};

/// How far a rotation quaternion's norm may be from 1. Poses integrated in `f32` drift by a
/// few ulps per step before renormalisation; 1e-3 leaves room for that while catching
/// quaternions that were never normalised (which would scale the box).
pub const UNIT_QUATERNION_TOLERANCE: f32 = 1e-3;

fn all_finite(v: &[f32]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Errs unless there are `n` poses and `n` velocities, every position and velocity finite and
/// every rotation a unit quaternion.
pub fn check_motion(
    poses: &[GpuPose],
    velocities: &[GpuVelocity],
    n: usize,
) -> Result<(), GpuError> {
    check_count("poses", poses.len(), n)?;
    check_count("velocities", velocities.len(), n)?;
    for (i, p) in poses.iter().enumerate() {
        if !all_finite(&p.position[..3]) {
            return Err(invalid(format!("poses[{i}].position"), p.position));
        }
        let q = p.rotation;
        let off_unit = (q.iter().map(|x| x * x).sum::<f32>().sqrt() - 1.0).abs();
        // A NaN component makes the norm NaN, refused here too.
        if off_unit.is_nan() || off_unit > UNIT_QUATERNION_TOLERANCE {
            return Err(invalid(format!("poses[{i}].rotation"), q));
        }
    }
    for (i, v) in velocities.iter().enumerate() {
        for (part, value) in [("linear", v.linear), ("angular", v.angular)] {
            if !all_finite(&value[..3]) {
                return Err(invalid(format!("velocities[{i}].{part}"), value));
            }
        }
    }
    Ok(())
}

/// Errs on a half extent that is not a positive finite number.
pub fn check_shapes(shapes: &[GpuShape]) -> Result<(), GpuError> {
    let mut last_world = 0;
    for (i, s) in shapes.iter().enumerate() {
        // The pair list is sorted by body index and the coloring numbers a world's pairs from
        // its first: each world's bodies must be one run, the worlds in increasing order.
        let world = s.flags >> BODY_WORLD_SHIFT;
        if world < last_world {
            return Err(invalid(
                format!("shapes[{i}].flags"),
                format!(
                    "world {world} after a body of world {last_world} (a world's bodies \
                     must be contiguous, the worlds in increasing order)"
                ),
            ));
        }
        last_world = world;
        for (name, h) in [("hx", s.hx), ("hy", s.hy), ("hz", s.hz)] {
            if !(h.is_finite() && h > 0.0) {
                return Err(invalid(format!("shapes[{i}].{name}"), h));
            }
        }
    }
    Ok(())
}

/// Errs unless every per-body slice has `expected` entries.
pub fn check_count(field: &str, len: usize, expected: usize) -> Result<(), GpuError> {
    if len != expected {
        return Err(GpuError::InvalidInput {
            field: format!("{field}.len()"),
            value: format!("{len} (expected {expected}, one per body)"),
        });
    }
    Ok(())
}

/// Errs unless `value` is a contact recycling distance: finite, in
/// `[0, tumble_solver::bounds::MAX_RECYCLE_DISTANCE]` (the facade's bound).
pub fn check_recycle_distance(field: &str, value: f32) -> Result<(), GpuError> {
    use tumble_solver::bounds::MAX_RECYCLE_DISTANCE;
    if !(value.is_finite() && (0.0..=MAX_RECYCLE_DISTANCE).contains(&value)) {
        return Err(invalid(field, value));
    }
    Ok(())
}

/// Errs unless `value` is finite and at least `min`.
pub fn check_at_least(field: &str, value: f32, min: f32) -> Result<(), GpuError> {
    if !(value.is_finite() && value >= min) {
        return Err(invalid(field, value));
    }
    Ok(())
}

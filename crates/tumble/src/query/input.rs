//! The checks of the queries' arguments: each names the argument (as the method's parameter
//! is named) and the value, and none of them panics.

use tumble_geometry::{Aabb, Point3, Pose, Real, Vec3};
use tumble_solver::{InvalidParameter, bounds};

use crate::Error;

/// What a cast's direction or velocity must be.
pub(crate) const EXPECTED_DIRECTION: &str = "finite components, not all zero";
/// What a cast's reach must be.
pub(crate) const EXPECTED_REACH: &str = "a number >= 0 (infinity allowed)";
/// What a query box's half extent must be.
pub(crate) const EXPECTED_QUERY_HALF_EXTENT: &str = "a finite number > 0";
/// What an AABB's corners must be.
pub(crate) const EXPECTED_AABB: &str = "finite corners with min <= max on every axis";

/// A query point (a ray's origin, a queried point): finite, within
/// [`bounds::MAX_POSITION`] like every position the world takes.
pub(crate) fn position(field: &'static str, p: &Point3) -> Result<(), Error> {
    Ok(bounds::require_position(field, &p.coords)?)
}

/// A ray's direction or a cast's velocity: finite and not zero. Its length is free: the time
/// of impact is in its units.
pub(crate) fn direction(field: &'static str, d: &Vec3) -> Result<(), Error> {
    if d.iter().all(|x| x.is_finite()) && d.iter().any(|&x| x != 0.0) {
        Ok(())
    } else {
        Err(InvalidParameter::new(field, [d.x, d.y, d.z], EXPECTED_DIRECTION).into())
    }
}

/// A cast's largest time of impact (or a distance): not NaN, not negative.
pub(crate) fn reach(field: &'static str, t: Real) -> Result<(), Error> {
    if t >= 0.0 {
        Ok(())
    } else {
        Err(InvalidParameter::new(field, t, EXPECTED_REACH).into())
    }
}

/// A query box's half extents: each finite and positive.
pub(crate) fn half_extents(h: &Vec3) -> Result<(), Error> {
    const FIELDS: [&str; 3] = ["half_extents.x", "half_extents.y", "half_extents.z"];
    for (k, field) in FIELDS.into_iter().enumerate() {
        if !(h[k].is_finite() && h[k] > 0.0) {
            return Err(InvalidParameter::new(field, h[k], EXPECTED_QUERY_HALF_EXTENT).into());
        }
    }
    Ok(())
}

/// A query box's pose: as `World::set_pose` takes it (finite, within `MAX_POSITION`, a unit
/// rotation).
pub(crate) fn pose(p: &Pose) -> Result<(), Error> {
    Ok(bounds::require_pose("pose", p)?)
}

/// A query AABB: finite corners, `min <= max`.
pub(crate) fn aabb(a: &Aabb) -> Result<(), Error> {
    let finite = a.min.iter().chain(a.max.iter()).all(|x| x.is_finite());
    let ordered = (0..3).all(|k| a.min[k] <= a.max[k]);
    if finite && ordered {
        Ok(())
    } else {
        let value = ([a.min.x, a.min.y, a.min.z], [a.max.x, a.max.y, a.max.z]);
        Err(InvalidParameter::new("aabb", value, EXPECTED_AABB).into())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_check_names_its_field_and_value() {
        let e = direction("dir", &Vec3::zeros()).unwrap_err();
        assert_eq!(e.field(), Some("dir"));
        assert!(e.to_string().contains("[0.0, 0.0, 0.0]"), "{e}");
        assert!(direction("dir", &Vec3::new(0.0, Real::NAN, 1.0)).is_err());
        assert!(direction("dir", &Vec3::new(0.0, 1e-40, 0.0)).is_ok());
        assert_eq!(reach("max_toi", -1.0).unwrap_err().field(), Some("max_toi"));
        assert!(reach("max_toi", Real::NAN).is_err());
        assert!(reach("max_toi", Real::INFINITY).is_ok() && reach("max_toi", 0.0).is_ok());
        let e = half_extents(&Vec3::new(1.0, 0.0, 1.0)).unwrap_err();
        assert_eq!(e.field(), Some("half_extents.y"));
        assert!(half_extents(&Vec3::new(1.0, 1.0, Real::INFINITY)).is_err());
        let flipped = Aabb::new(Point3::new(1.0, 0.0, 0.0), Point3::origin());
        assert_eq!(aabb(&flipped).unwrap_err().field(), Some("aabb"));
        assert!(aabb(&Aabb::new(Point3::origin(), Point3::origin())).is_ok());
        assert_eq!(
            position("origin", &Point3::new(Real::NAN, 0.0, 0.0))
                .unwrap_err()
                .field(),
            Some("origin")
        );
    }
}

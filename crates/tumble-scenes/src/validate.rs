//! Scene validation: every number the engine will read is finite and physically meaningful.

use tumble_geometry::Real;

use crate::{BodyKind, BodySpec, Scene, SceneCheck, SceneError};

/// How far a rotation quaternion's length may be from 1. JSON written by hand with four or
/// five decimals (e.g. `0.7071`) is off by about 1e-4; anything past 1e-3 is a mistake, not
/// rounding.
pub const ROTATION_NORM_TOLERANCE: Real = 1e-3;

impl Scene {
    /// Checks every field; the error names the first bad field and its value.
    pub fn validate(&self) -> Result<(), SceneError> {
        if self.version != crate::FORMAT_VERSION {
            return Err(SceneError::UnsupportedVersion(self.version.to_string()));
        }
        finite_vec("gravity", &self.gravity)?;
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(SceneError::invalid("dt", self.dt, "must be finite and > 0"));
        }
        for (i, body) in self.bodies.iter().enumerate() {
            body.validate_at(&format!("bodies[{i}]"))?;
        }
        self.check.validate_at("check")
    }
}

impl BodySpec {
    /// Checks one body; `path` prefixes the field names in the error.
    pub fn validate_at(&self, path: &str) -> Result<(), SceneError> {
        for (k, &h) in self.half_extents.iter().enumerate() {
            if !(h.is_finite() && h > 0.0) {
                return Err(SceneError::invalid(
                    format!("{path}.half_extents[{k}]"),
                    h,
                    "must be finite and > 0",
                ));
            }
        }
        finite_vec(&format!("{path}.position"), &self.position)?;
        finite_vec(&format!("{path}.rotation"), &self.rotation)?;
        let norm = self.rotation.iter().map(|c| c * c).sum::<Real>().sqrt();
        if (norm - 1.0).abs() > ROTATION_NORM_TOLERANCE {
            return Err(SceneError::invalid(
                format!("{path}.rotation"),
                self.rotation,
                "must be a unit quaternion [x, y, z, w]",
            ));
        }
        finite_vec(&format!("{path}.linear_velocity"), &self.linear_velocity)?;
        finite_vec(&format!("{path}.angular_velocity"), &self.angular_velocity)?;
        let density_ok = if self.kind == BodyKind::Dynamic {
            self.density.is_finite() && self.density > 0.0
        } else {
            self.density.is_finite() && self.density >= 0.0
        };
        if !density_ok {
            return Err(SceneError::invalid(
                format!("{path}.density"),
                self.density,
                "must be finite and > 0 (>= 0 for fixed and kinematic bodies)",
            ));
        }
        if !(self.friction.is_finite() && self.friction >= 0.0) {
            return Err(SceneError::invalid(
                format!("{path}.friction"),
                self.friction,
                "must be finite and >= 0",
            ));
        }
        if !(0.0..=1.0).contains(&self.restitution) {
            return Err(SceneError::invalid(
                format!("{path}.restitution"),
                self.restitution,
                "must be in [0, 1]",
            ));
        }
        Ok(())
    }
}

impl SceneCheck {
    /// Checks the criterion's numbers; `path` prefixes the field names in the error.
    pub fn validate_at(&self, path: &str) -> Result<(), SceneError> {
        let non_negative = |name: &str, v: Real| {
            if v.is_finite() && v >= 0.0 {
                Ok(())
            } else {
                Err(SceneError::invalid(
                    format!("{path}.{name}"),
                    v,
                    "must be finite and >= 0",
                ))
            }
        };
        match self {
            SceneCheck::Finite => Ok(()),
            SceneCheck::MaxDrift { meters } | SceneCheck::StaysPut { meters } => {
                non_negative("meters", *meters)
            }
            SceneCheck::NoTunneling { min_y } => finite_vec(&format!("{path}.min_y"), &[*min_y]),
            SceneCheck::Slides {
                direction,
                expected_acceleration,
                tolerance,
            } => {
                finite_vec(&format!("{path}.direction"), direction)?;
                let len = direction.iter().map(|c| c * c).sum::<Real>().sqrt();
                if (len - 1.0).abs() > ROTATION_NORM_TOLERANCE {
                    return Err(SceneError::invalid(
                        format!("{path}.direction"),
                        direction,
                        "must be a unit vector",
                    ));
                }
                non_negative("expected_acceleration", *expected_acceleration)?;
                non_negative("tolerance", *tolerance)
            }
            SceneCheck::AngularMomentum { rel_tol } => non_negative("rel_tol", *rel_tol),
            SceneCheck::Separates {
                max_depth,
                max_speed,
            } => {
                non_negative("max_depth", *max_depth)?;
                non_negative("max_speed", *max_speed)
            }
            SceneCheck::Contained { min, max } => {
                finite_vec(&format!("{path}.min"), min)?;
                finite_vec(&format!("{path}.max"), max)?;
                for k in 0..3 {
                    if min[k] > max[k] {
                        return Err(SceneError::invalid(
                            format!("{path}.min[{k}]"),
                            min[k],
                            "must not exceed max",
                        ));
                    }
                }
                Ok(())
            }
            SceneCheck::Topples { min_tilt_deg } => non_negative("min_tilt_deg", *min_tilt_deg),
            SceneCheck::All { checks } => checks
                .iter()
                .enumerate()
                .try_for_each(|(i, c)| c.validate_at(&format!("{path}.checks[{i}]"))),
        }
    }
}

/// Errs on the first non-finite component of `v`, naming `field[k]`.
fn finite_vec(field: &str, v: &[Real]) -> Result<(), SceneError> {
    match v.iter().position(|c| !c.is_finite()) {
        Some(k) if v.len() > 1 => Err(SceneError::invalid(
            format!("{field}[{k}]"),
            v[k],
            "must be finite",
        )),
        Some(k) => Err(SceneError::invalid(field, v[k], "must be finite")),
        None => Ok(()),
    }
}

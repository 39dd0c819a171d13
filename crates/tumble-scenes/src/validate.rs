//! Scene validation: every number the engine will read is finite, physically meaningful and
//! within the ranges the world accepts (`tumble_solver::bounds`), so a scene that reads
//! without error also builds a world.

use tumble_geometry::{Real, Vec3};
use tumble_solver::{InvalidParameter, bounds};

use crate::{BodySpec, Scene, SceneCheck, SceneError};

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
        // The world's ranges (WorldConfig::validate checks the same two).
        bounds::require_in_range(
            "dt",
            self.dt,
            bounds::MIN_DT,
            bounds::MAX_DT,
            bounds::EXPECTED_DT,
        )
        .map_err(|e| out_of_bounds("", e))?;
        bounds::require_length_at_most(
            "gravity",
            &Vec3::from(self.gravity),
            bounds::MAX_GRAVITY,
            bounds::EXPECTED_GRAVITY,
        )
        .map_err(|e| out_of_bounds("", e))?;
        for (i, body) in self.bodies.iter().enumerate() {
            let path = format!("bodies[{i}]");
            body.validate_at(&path)?;
            body.within_bounds(self.dt)
                .map_err(|e| out_of_bounds(&path, e))?;
        }
        self.check.validate_at("check")
    }
}

/// A world bound's error as a scene error naming `path.field`.
fn out_of_bounds(path: &str, e: InvalidParameter) -> SceneError {
    /// The value as the bound formatted it (no quotes added).
    struct Formatted(String);
    impl std::fmt::Debug for Formatted {
        fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
            f.write_str(&self.0)
        }
    }
    let field = if path.is_empty() {
        e.field.to_string()
    } else {
        format!("{path}.{}", e.field)
    };
    SceneError::invalid(field, Formatted(e.value), e.expected)
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
        // Of every kind: the world checks a fixed body's density too.
        if !(self.density.is_finite() && self.density > 0.0) {
            return Err(SceneError::invalid(
                format!("{path}.density"),
                self.density,
                "must be finite and > 0",
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

impl BodySpec {
    /// The world's ranges for one body (`tumble_solver::Body::new` and the facade's body
    /// check apply the same ones): half extents, density (of every kind: the world validates
    /// it whatever the body's kind), friction, the centre's distance from the origin and the
    /// speeds. The angular speed's bound grows with the substeps; a scene has none, so it is
    /// checked at the default solver's `DEFAULT_SUBSTEPS` with the scene's `dt`, the
    /// configuration a scene is built with unless the caller picks fewer substeps.
    pub fn within_bounds(&self, dt: Real) -> Result<(), InvalidParameter> {
        bounds::require_half_extents(&Vec3::from(self.half_extents))?;
        bounds::require_density(self.density)?;
        bounds::require_in_range(
            "friction",
            self.friction,
            0.0,
            bounds::MAX_FRICTION,
            bounds::EXPECTED_FRICTION,
        )?;
        bounds::require_position("position", &Vec3::from(self.position))?;
        bounds::require_linear_speed("linear_velocity", &Vec3::from(self.linear_velocity))?;
        bounds::require_angular_speed(
            "angular_velocity",
            &Vec3::from(self.angular_velocity),
            dt,
            tumble_solver::DEFAULT_SUBSTEPS,
        )
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

//! The error every solver-level validation returns.

/// A parameter outside its valid range: names the field, the value, and what was expected.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("invalid {field}: {value} (expected {expected})")]
pub struct InvalidParameter {
    /// The name of the offending field, as the user wrote it (`density`, `dt`, ...).
    pub field: &'static str,
    /// The rejected value, formatted.
    pub value: String,
    /// What a valid value looks like.
    pub expected: &'static str,
}

impl InvalidParameter {
    /// An error for `field` holding `value`, which should have been `expected`.
    pub fn new(field: &'static str, value: impl std::fmt::Debug, expected: &'static str) -> Self {
        Self {
            field,
            value: format!("{value:?}"),
            expected,
        }
    }
}

/// Checks that `value` is finite and strictly positive.
pub fn require_positive(field: &'static str, value: f32) -> Result<f32, InvalidParameter> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(InvalidParameter::new(field, value, "a finite number > 0"))
    }
}

/// Checks that `value` is finite and not negative.
pub fn require_non_negative(field: &'static str, value: f32) -> Result<f32, InvalidParameter> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(InvalidParameter::new(field, value, "a finite number >= 0"))
    }
}

/// Checks that every component of `value` is finite.
pub fn require_finite3(
    field: &'static str,
    value: &tumble_geometry::Vec3,
) -> Result<(), InvalidParameter> {
    if value.iter().all(|c| c.is_finite()) {
        Ok(())
    } else {
        Err(InvalidParameter::new(
            field,
            [value.x, value.y, value.z],
            "finite components",
        ))
    }
}

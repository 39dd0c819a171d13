//! The facade's error: every bad input is a value naming the field and what was wrong.

use tumble_solver::InvalidParameter;

use crate::{Backend, BodyHandle};

/// Why a call on the world failed. The world is unchanged whenever a call returns `Err`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum Error {
    /// A field holds a value outside its valid range (NaN, infinity, negative size, ...).
    #[error("invalid {field}: {value} (expected {expected})")]
    InvalidValue {
        /// The field, as named in the API (`density`, `dt`, `half_extents.x`, ...).
        field: &'static str,
        /// The rejected value, formatted.
        value: String,
        /// What a valid value looks like.
        expected: &'static str,
    },
    /// The handle was never issued by this world.
    #[error("unknown body handle {0:?}")]
    UnknownHandle(BodyHandle),
    /// The handle's body has been removed.
    #[error("body {0:?} was removed")]
    RemovedHandle(BodyHandle),
    /// The chosen backend cannot run here (yet).
    #[error("backend {backend:?} is unavailable: {reason}")]
    BackendUnavailable {
        /// The backend asked for.
        backend: Backend,
        /// Why it cannot run.
        reason: String,
    },
    /// A scene failed its own validation.
    #[error("invalid scene: {0}")]
    InvalidScene(String),
}

impl From<InvalidParameter> for Error {
    fn from(e: InvalidParameter) -> Self {
        Error::InvalidValue {
            field: e.field,
            value: e.value,
            expected: e.expected,
        }
    }
}

impl Error {
    /// The name of the offending field, when the error is about one.
    pub fn field(&self) -> Option<&'static str> {
        match self {
            Error::InvalidValue { field, .. } => Some(field),
            _ => None,
        }
    }
}

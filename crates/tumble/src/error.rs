//! The facade's error: every bad input is a value naming the field and what was wrong.

use tumble_solver::InvalidParameter;

use crate::{Backend, BatchError, BodyHandle};

/// Why a call on the world failed. The world is unchanged whenever a call returns `Err`,
/// with one exception: [`Error::InvalidGpuState`] reports a `Backend::Gpu` step that already
/// ran (docs/errors.md).
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
    /// A scene failed its own validation, or one of its bodies or settings is outside the
    /// engine's bounds (the message names the body index and the field).
    #[error("invalid scene: {0}")]
    InvalidScene(String),
    /// The step would have left a body with a non-finite pose or velocity, or its centre
    /// beyond `tumble_solver::bounds::MAX_POSITION`. The step was not taken: every pose,
    /// velocity, contact and the step count are as they were before it.
    #[error(
        "step refused: body {body:?} would have {quantity} = {value} (expected {expected}); \
         the world is left as it was before the step"
    )]
    InvalidStep {
        /// The first body (in the world's order) whose state would leave its bounds.
        body: BodyHandle,
        /// Which quantity: `position`, `rotation`, `linear_velocity` or `angular_velocity`.
        quantity: &'static str,
        /// The value the step computed, formatted.
        value: String,
        /// What the quantity must satisfy.
        expected: &'static str,
    },
    /// `Backend::Gpu`'s last step left a body with a non-finite pose or velocity, or its
    /// centre beyond `MAX_POSITION`, found when the results reached the host. The GPU step is
    /// not waited for, so it cannot be undone: the host keeps the state it last read, and
    /// every later step and write returns this error.
    #[error(
        "the GPU step left body {body:?} with {quantity} = {value} (expected {expected}); \
         the world cannot step further"
    )]
    InvalidGpuState {
        /// The first body (in the world's order) whose state left its bounds.
        body: BodyHandle,
        /// Which quantity: `position`, `rotation`, `linear_velocity` or `angular_velocity`.
        quantity: &'static str,
        /// The value read back, formatted.
        value: String,
        /// What the quantity must satisfy.
        expected: &'static str,
    },
    /// A call on a [`crate::WorldBatch`] failed: a bad world id, action entry or buffer, or
    /// one world's own error (named by its id).
    #[error("batch: {0}")]
    Batch(#[from] BatchError),
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

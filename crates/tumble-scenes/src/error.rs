//! Errors from loading or validating a scene.

/// Why a scene could not be loaded or is not valid.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The text is not JSON of the scene schema.
    #[error("scene JSON does not parse: {0}")]
    Json(#[from] serde_json::Error),
    /// The file's `version` is not [`crate::FORMAT_VERSION`].
    #[error("unsupported scene format version {0} (this build reads version {v})", v = crate::FORMAT_VERSION)]
    UnsupportedVersion(String),
    /// Body `index` of the `bodies` list does not parse: an unknown or misspelt field, a
    /// missing one, or a value of the wrong type (the message names it).
    #[error("scene body bodies[{index}] does not parse: {source}")]
    Body {
        /// Index in the scene's `bodies`.
        index: usize,
        /// What serde found wrong.
        source: serde_json::Error,
    },
    /// A field holds a value the engine cannot simulate.
    #[error("invalid scene field `{field}` = {value}: {reason}")]
    InvalidField {
        /// Path of the field, e.g. `bodies[3].half_extents[1]`.
        field: String,
        /// The offending value, as written by `Debug`.
        value: String,
        /// What the field must satisfy.
        reason: &'static str,
    },
}

impl SceneError {
    /// An `InvalidField` error for `field` holding `value`.
    pub(crate) fn invalid(
        field: impl Into<String>,
        value: impl std::fmt::Debug,
        reason: &'static str,
    ) -> Self {
        Self::InvalidField {
            field: field.into(),
            value: format!("{value:?}"),
            reason,
        }
    }
}

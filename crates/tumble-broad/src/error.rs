//! Errors from the broad phase's inputs.

/// Why a broad-phase query was refused.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum BroadPhaseError {
    /// The per-box flag slice does not have one entry per box.
    #[error("is_static has {flags} entries but there are {boxes} boxes")]
    FlagCountMismatch {
        /// Number of boxes given.
        boxes: usize,
        /// Number of flags given.
        flags: usize,
    },
    /// The per-box collision-groups slice does not have one entry per box.
    #[error("groups has {groups} entries but there are {boxes} boxes")]
    GroupCountMismatch {
        /// Number of boxes given.
        boxes: usize,
        /// Number of groups given.
        groups: usize,
    },
}

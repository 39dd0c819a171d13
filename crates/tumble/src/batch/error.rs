//! The batch's errors: which world, which action entry, which buffer, and what was wrong.

use std::fmt;

use crate::{Backend, Error};

/// Identifies a world of a [`crate::WorldBatch`]: a slot index plus a generation, so the id
/// of a removed world never names a later one.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct WorldId {
    pub(crate) index: u32,
    pub(crate) generation: u32,
}

impl WorldId {
    /// The slot index. While no world is removed, the worlds are numbered 0, 1, 2, ... in
    /// the order they were added.
    pub fn index(&self) -> u32 {
        self.index
    }

    /// The slot's generation when the world was added.
    pub fn generation(&self) -> u32 {
        self.generation
    }
}

impl fmt::Display for WorldId {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "world {} (generation {})", self.index, self.generation)
    }
}

/// Why a call on a [`crate::WorldBatch`] failed. Unless said otherwise below, the batch is
/// unchanged whenever a call returns `Err`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum BatchError {
    /// The id was never issued by this batch.
    #[error("unknown {0}: never issued by this batch")]
    UnknownWorld(WorldId),
    /// The id's world has been removed from the batch.
    #[error("{0} was removed from the batch")]
    RemovedWorld(WorldId),
    /// A world's config asks for another backend than the batch's.
    #[error(
        "world {world}: config.backend is {given:?}, but the batch runs on {batch:?} \
         (every world of a batch runs on the batch's backend)"
    )]
    BackendMismatch {
        /// The position of the world in the list given (or 0 for `add_world`).
        world: usize,
        /// The world config's backend.
        given: Backend,
        /// The batch's backend.
        batch: Backend,
    },
    /// A world could not be built: its config, its scene or one of its bodies is bad.
    #[error("world {world}{}: {error}", .body.map(|b| format!(", bodies[{b}]")).unwrap_or_default())]
    Build {
        /// The position of the world in the list given (or 0 for `add_world`).
        world: usize,
        /// The body, when one is at fault.
        body: Option<usize>,
        /// The world's own error.
        error: Box<Error>,
    },
    /// An entry of an action array is bad; no action of the array was applied.
    #[error("actions[{index}].{field}: {value} (expected {expected}); no action was applied")]
    Action {
        /// The entry's position in the array.
        index: usize,
        /// The entry's field: `world`, `body`, `impulse`, `point`, `linear_velocity`,
        /// `angular_velocity`, `target` or `kind`.
        field: &'static str,
        /// The rejected value, formatted.
        value: String,
        /// What a valid value looks like, or why the value was refused.
        expected: String,
    },
    /// A caller's buffer has the wrong length; nothing was written to it.
    #[error("{what}: buffer of {given} floats, expected {expected}; nothing was written")]
    BufferLength {
        /// The read (`read_poses`, `read_all_velocities`, ...).
        what: &'static str,
        /// The length the read needs.
        expected: usize,
        /// The length given.
        given: usize,
    },
    /// A strided read's stride is too short for one world's bodies; nothing was written.
    #[error(
        "{what}: stride {stride} is shorter than the {needed} floats of {world} \
         ({bodies} bodies); nothing was written"
    )]
    Stride {
        /// The read.
        what: &'static str,
        /// The stride given, floats.
        stride: usize,
        /// The world that does not fit.
        world: WorldId,
        /// Its body count.
        bodies: usize,
        /// The floats its bodies need.
        needed: usize,
    },
    /// A world's own call failed (a bad body, a removed handle, a refused step). For
    /// [`crate::WorldBatch::step`], the world named is the first (by slot) whose step failed:
    /// it is left as before the step, like a `World` whose step errs, while every other world
    /// took its step.
    #[error("{world}: {error}")]
    World {
        /// The world.
        world: WorldId,
        /// Its error.
        error: Box<Error>,
    },
}

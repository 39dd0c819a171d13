//! What a batch world keeps to return to a saved state: its config and the log of every call
//! that changed it, replayed into a fresh `World` on reset.
//!
//! `World` has no snapshot of its whole state (the contact cache that warm-starts the solver,
//! the broad phase's buffers, the sleep timers and, on `Backend::Gpu`, the state on the
//! device), and the step is deterministic: the same calls in the same order give the same
//! bits, on one thread or many (the CPU step's parallel loops write each result to its own
//! slot, and the solver's parallel colors share no body). So a saved state is a position in
//! the log, and a reset builds a new world from the config and replays the log up to it.
//!
//! Cost: a reset to the state right after the world was added rebuilds its bodies and steps
//! nothing; a reset to a state saved `k` steps later replays those `k` steps and the calls
//! between them. The log holds one entry per added or removed body and per action, and one
//! per run of steps; a reset drops the entries after the saved position.

use crate::batch::action::{self, ActionKind};
use crate::{BodyDesc, BodyHandle, Error, World, WorldConfig};

/// One logged call.
#[derive(Clone, Debug)]
enum Op {
    /// `World::add_body`.
    Add(BodyDesc),
    /// `World::remove_body`.
    Remove(BodyHandle),
    /// This many steps.
    Steps(u64),
    /// An action applied to a body.
    Action(BodyHandle, ActionKind),
}

/// A world's config and log, and the position of its saved state.
#[derive(Clone, Debug)]
pub(crate) struct History {
    config: WorldConfig,
    ops: Vec<Op>,
    /// Entries of `ops` up to the saved state.
    saved: usize,
}

impl History {
    /// An empty log for a world built with `config`.
    pub(crate) fn new(config: WorldConfig) -> Self {
        Self {
            config,
            ops: Vec::new(),
            saved: 0,
        }
    }

    /// Logs an added body.
    pub(crate) fn add(&mut self, desc: BodyDesc) {
        self.ops.push(Op::Add(desc));
    }

    /// Logs a removed body.
    pub(crate) fn remove(&mut self, h: BodyHandle) {
        self.ops.push(Op::Remove(h));
    }

    /// Logs an applied action.
    pub(crate) fn action(&mut self, h: BodyHandle, kind: ActionKind) {
        self.ops.push(Op::Action(h, kind));
    }

    /// Logs a step, merged into the last run of steps unless that run ends the saved state.
    pub(crate) fn step(&mut self) {
        if self.ops.len() > self.saved
            && let Some(Op::Steps(n)) = self.ops.last_mut()
        {
            *n += 1;
            return;
        }
        self.ops.push(Op::Steps(1));
    }

    /// Makes the present the saved state.
    pub(crate) fn save(&mut self) {
        self.saved = self.ops.len();
    }

    /// Steps between the world's creation and its saved state: what a reset replays.
    pub(crate) fn saved_steps(&self) -> u64 {
        self.ops[..self.saved]
            .iter()
            .map(|op| match op {
                Op::Steps(n) => *n,
                _ => 0,
            })
            .sum()
    }

    /// A new world in the saved state: the config's world with the log replayed up to it.
    pub(crate) fn replay(&self) -> Result<World, Error> {
        let mut world = World::new(self.config)?;
        for op in &self.ops[..self.saved] {
            match op {
                Op::Add(desc) => {
                    world.add_body(*desc)?;
                }
                Op::Remove(h) => world.remove_body(*h)?,
                Op::Steps(n) => {
                    for _ in 0..*n {
                        world.step()?;
                    }
                }
                Op::Action(h, kind) => action::apply(&mut world, *h, kind)?,
            }
        }
        Ok(world)
    }

    /// Drops the log after the saved state (the world was just reset to it).
    pub(crate) fn rewind(&mut self) {
        self.ops.truncate(self.saved);
    }
}

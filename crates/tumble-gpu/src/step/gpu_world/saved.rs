//! The state a GPU world carries from one step to the next, copied to host memory
//! ([`GpuWorld::save_state`]) and written into a new world on the same kind of device
//! ([`GpuWorld::load_state`]), so that the new world's next steps compute the same bits.
//!
//! What the next steps read: every device buffer the stages keep in their pools (bodies,
//! poses, velocities, shapes, collision groups, both pair parities with their manifolds,
//! points, impulses and local manifolds, the solver's colors and tilt impulses of both
//! parities, the sleep stage's rest times, islands and labels), the parities themselves, the
//! pair capacity, and on the host the lagged step statistics that choose the solver path and
//! grow the pair buffers, and the idle-step tracker. Buffers are saved whole (trailing zeros
//! left out), scratch included, so that no state a kernel keeps is missed.

use tumble_solver::Body;

use crate::GpuError;
use crate::buffer_pool::SavedBuffer;
use crate::error::invalid;
use crate::layout::WorkList;
use crate::solver::{Effects, SolvePath};

use super::GpuWorld;
use crate::step::idle::IdleSteps;
use crate::step::stats_ring::StepStats;

/// The collision stages' state ([`crate::GpuCollision::save_state`]).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SavedCollision {
    /// Bodies uploaded.
    pub body_count: u32,
    /// Pair slots allocated.
    pub pair_capacity: u32,
    /// Boxes longer than this on the sweep axis are paired apart from the sweep (m).
    pub long_extent: f32,
    /// Steps recorded (their parity picks this step's pair set).
    pub steps: u64,
    /// Times the pair history was dropped.
    pub history_resets: u64,
    /// The pooled buffers.
    pub buffers: Vec<SavedBuffer>,
}

/// One step's lagged statistics, as [`crate::step::stats_ring::StepStats`] holds them.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SavedStats {
    /// The pair work list, as its eight `u32`s.
    pub work: [u32; 8],
    /// Bodies the step moved, when the sleep stage ran.
    pub active: Option<u32>,
    /// The host's change count when the step was recorded.
    pub changes: u64,
    /// Graph colors used, when the step took the wide path.
    pub colors: Option<u32>,
}

// A work list is saved as eight `u32`s.
const _: () = assert!(std::mem::size_of::<WorkList>() == 32);

impl SavedStats {
    pub(crate) fn of(s: &StepStats) -> Self {
        Self {
            work: bytemuck::cast(s.work),
            active: s.active,
            changes: s.changes,
            colors: s.colors,
        }
    }

    pub(crate) fn to_stats(self) -> StepStats {
        StepStats {
            work: bytemuck::cast::<[u32; 8], WorkList>(self.work),
            active: self.active,
            changes: self.changes,
            colors: self.colors,
            // Not saved: a step whose wait gave up is reported when its stats are taken, and a
            // world saved before that shows its poses, not the fault.
            substep_wait_gave_up: false,
        }
    }
}

/// The idle-step tracker ([`crate::step::idle::IdleSteps`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SavedIdle {
    /// Host changes counted.
    pub changes: u64,
    /// The manifold count of the step before the one last observed.
    pub previous_count: Option<u32>,
    /// Whether the step last observed was idle.
    pub idle: bool,
    /// Steps skipped.
    pub skipped: u64,
}

/// A [`GpuWorld`]'s state between two steps (see the module documentation).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GpuWorldState {
    /// The bodies as uploaded (cold data, with their last properties set).
    pub bodies: Vec<Body>,
    /// The effects compiled in: gravity, friction, restitution, rotation, kinematic, sleep.
    pub effects: [bool; 6],
    /// Steps taken.
    pub steps: u64,
    /// The manifold count of the last stats read.
    pub known_manifolds: Option<u32>,
    /// Pair buffer overflows so far.
    pub pair_overflows: u32,
    /// Whether the last step took the wide path (`None` before any step).
    pub last_path_wide: Option<bool>,
    /// The statistics of the steps not yet read, in the order they will be read.
    pub lagged: Vec<Option<SavedStats>>,
    /// The idle-step tracker.
    pub idle: SavedIdle,
    /// The world's own buffers (the solver bodies).
    pub world_buffers: Vec<SavedBuffer>,
    /// The collision stages.
    pub collision: SavedCollision,
    /// The solver's buffers (empty before its first step).
    pub solver_buffers: Vec<SavedBuffer>,
    /// The solver's coloring parity.
    pub solver_parity: u32,
    /// The sleep stage's buffers (empty while it is off).
    pub sleep_buffers: Vec<SavedBuffer>,
    /// Bodies whose islands are queued to wake at the start of the next step.
    pub sleep_queued: Vec<u32>,
}

fn effects_bits(e: &Effects) -> [bool; 6] {
    [
        e.gravity,
        e.friction,
        e.restitution,
        e.rotation,
        e.kinematic,
        e.sleep,
    ]
}

fn effects_of(b: [bool; 6]) -> Effects {
    let [gravity, friction, restitution, rotation, kinematic, sleep] = b;
    Effects {
        gravity,
        friction,
        restitution,
        rotation,
        kinematic,
        sleep,
    }
}

impl GpuWorld {
    /// Everything the next steps read, copied to the host (blocking: waits for the submitted
    /// steps). Impulses queued for the next step are submitted first, as the step would.
    /// Errs for a world of several worlds ([`Self::set_bodies_in_worlds`]): the saved state
    /// holds one world's layout.
    pub fn save_state(&mut self) -> Result<GpuWorldState, GpuError> {
        if self.world_count() > 1 {
            return Err(invalid(
                "worlds",
                format!(
                    "{} (a saved state holds one world; save each world alone)",
                    self.world_count()
                ),
            ));
        }
        self.flush_impulses()?;
        self.ctx.wait_idle()?;
        let lagged = self.stats.peek()?;
        let (sleep_buffers, sleep_queued) = self.sleep.save_state()?;
        Ok(GpuWorldState {
            bodies: self.bodies.clone(),
            effects: effects_bits(&self.effects()),
            steps: self.steps,
            known_manifolds: self.known_manifolds,
            pair_overflows: self.pair_overflows,
            last_path_wide: self.last_path.map(|p| p == SolvePath::Wide),
            lagged: lagged
                .iter()
                .map(|s| s.as_ref().map(SavedStats::of))
                .collect(),
            idle: self.idle.save(),
            world_buffers: self.pool.save()?,
            collision: self.collision.save_state()?,
            solver_buffers: self.solver.pool().save()?,
            solver_parity: self.solver.parity() as u32,
            sleep_buffers,
            sleep_queued,
        })
    }

    /// Puts this world, new on a device of the same kind with the same settings, in the state
    /// `saved` holds. Errs when the state does not fit together (a buffer this world's stages
    /// do not hold, a size the device cannot bind), naming the part; the world must then be
    /// dropped, as some parts may already have been written.
    pub fn load_state(&mut self, saved: &GpuWorldState) -> Result<(), GpuError> {
        if self.steps != 0 || !self.bodies.is_empty() {
            return Err(GpuError::InvalidInput {
                field: "world".into(),
                value: format!(
                    "{} steps and {} bodies (load_state needs a new world)",
                    self.steps,
                    self.bodies.len()
                ),
            });
        }
        if saved.solver_parity > 1 {
            return Err(GpuError::InvalidInput {
                field: "solver_parity".into(),
                value: saved.solver_parity.to_string(),
            });
        }
        if !saved.bodies.is_empty() {
            let states = vec![tumble_solver::BodyState::default(); saved.bodies.len()];
            self.set_bodies(&saved.bodies, &states)?;
        }
        self.set_effects(effects_of(saved.effects))?;
        self.collision.load_state(&saved.collision)?;
        if !saved.solver_buffers.is_empty() {
            let (bodies, capacity) = (self.bodies.len() as u32, self.collision.pair_capacity());
            self.solver.write_previous_tilts(bodies, capacity, &[])?;
            self.solver.pool_mut().load(&saved.solver_buffers)?;
        }
        self.solver.set_parity(saved.solver_parity as usize);
        self.sleep
            .load_state(&saved.sleep_buffers, &saved.sleep_queued)?;
        if !saved.world_buffers.is_empty() {
            self.pool.load(&saved.world_buffers)?;
        }
        self.steps = saved.steps;
        self.known_manifolds = saved.known_manifolds;
        self.pair_overflows = saved.pair_overflows;
        self.last_path = saved
            .last_path_wide
            .map(|w| if w { SolvePath::Wide } else { SolvePath::Fused });
        self.stats
            .preset(saved.lagged.iter().map(|s| s.map(SavedStats::to_stats)));
        self.idle = IdleSteps::from_saved(saved.idle);
        Ok(())
    }
}

//! Sleep on the GPU: islands of touching dynamic bodies that have all rested for
//! `tumble_solver::TIME_TO_SLEEP` leave the step, and wake when an awake body touches them
//! or the host moves one of their bodies, as the CPU step's sleep does.
//!
//! ```text
//! start of a step   wake_bodies (host-touched bodies) -> wake_islands (flagged islands)
//! after the solver  update_rest -> touch_sleepers -> kinematic_wake (if any kinematic body)
//!                   -> plan_search -> ISLAND_ROUNDS x (hook_labels, jump_labels)
//!                   -> check_labels -> island_rest -> fall_asleep
//!                   (from hook_labels on, zero workgroups unless some body rested long enough)
//! ```
//!
//! A sleeping body is taken out of the step by turning it, in the solver's body buffer and
//! the collision shapes, into a fixed and static body: the broad phase never pairs it with
//! another sleeping or fixed body, the narrow phase and the solver see only its pairs with
//! awake bodies (it is an immovable obstacle to them), and integration leaves it where it is.
//! The awake copy of every body is kept here for waking. See `docs/gpu.md` for why the island
//! search is deterministic. The CPU twin of the stage is `tumble_solver::SleepLabels`.

pub mod constants;
pub mod islands;
pub mod kinematic;
pub mod layout;
pub mod pipelines;
pub mod plan_search;
pub mod rest;
pub mod stage;
pub mod touch;
pub mod wake;

pub use stage::GpuSleep;
pub use tumble_solver::{IslandSearch, SleepLabels, SleepLink, island_search};

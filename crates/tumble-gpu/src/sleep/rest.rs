//! Rest times and falling asleep: `update_rest` (rest timers, and each body its own island),
//! `island_rest` (each island's shortest rest time), `fall_asleep` (islands that rested long
//! enough leave the step). Their CPU twins are the methods of [`tumble_solver::SleepLabels`] of the
//! same names.

use crate::kernel::kernel;

kernel! {
    /// Buffers of [`UPDATE_REST`].
    pub struct UpdateRestArgs {
        /// `SleepParams`.
        params,
        /// `array<GpuBody>`: every body as uploaded (its real kind).
        awake_bodies,
        /// `array<GpuVelocity>`: the step's final velocities.
        velocities,
        /// `array<u32>`: island labels.
        island,
        /// `array<f32>`: rest times, updated.
        rest_time,
        /// `array<u32>`: search labels, each body its own.
        labels,
        /// `array<u32>`: the first round's copy of them.
        next_labels,
        /// `array<u32>`: shortest rest time bits by label, reset to `REST_UNSET`.
        shortest_rest,
        /// One `atomic<u32>`: bodies whose rest reached `TIME_TO_SLEEP`, counted up.
        ready,
    }
    /// Kernel: one thread per body.
    pub static UPDATE_REST = "sleep/update_rest.wgsl";
}

kernel! {
    /// Buffers of [`ISLAND_REST`].
    pub struct IslandRestArgs {
        /// `SleepParams`.
        params,
        /// `array<GpuBody>`: every body as uploaded.
        awake_bodies,
        /// `array<u32>`: island labels.
        island,
        /// `array<u32>`: the finished search labels.
        labels,
        /// `array<f32>`: rest times.
        rest_time,
        /// `array<atomic<u32>>`: shortest rest time bits by label, lowered.
        shortest_rest,
    }
    /// Kernel: one thread per body.
    pub static ISLAND_REST = "sleep/island_rest.wgsl";
}

kernel! {
    /// Buffers of [`FALL_ASLEEP`].
    pub struct FallAsleepArgs {
        /// `SleepParams`.
        params,
        /// `array<u32>`, one entry: nonzero when the island search did not finish.
        unfinished,
        /// `array<GpuBody>`: every body as uploaded.
        awake_bodies,
        /// `array<u32>`: the finished search labels.
        labels,
        /// `array<u32>`: shortest rest time bits by label.
        shortest_rest,
        /// `array<u32>`: island labels, set for the bodies falling asleep.
        island,
        /// `array<GpuVelocity>`: zeroed for the bodies falling asleep.
        velocities,
        /// `array<GpuBody>`: the solver's bodies, made fixed for the bodies falling asleep.
        bodies,
        /// `array<GpuShape>`: the collision shapes, flagged static for the bodies falling asleep.
        shapes,
    }
    /// Kernel: one thread per body.
    pub static FALL_ASLEEP = "sleep/fall_asleep.wgsl";
}

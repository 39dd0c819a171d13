//! The `color` stage on the GPU: `color_propose` and `color_resolve` run the first (seeded)
//! round with one thread per constraint, `color_finish` runs the remaining rounds in one
//! workgroup, counts the colors and writes the per-color dispatch sizes; a stable radix sort
//! by color then gives the constraint order. [`color_rounds_cpu`] is the CPU twin.

use std::collections::HashMap;

use crate::kernel::kernel;

use super::constants::{COLOR_ROUNDS, EMPTY_COLOR, GRAPH_COLOR_COUNT, NO_COLOR, OVERFLOW_COLOR};

kernel! {
    /// Buffers of [`COLOR_PROPOSE`] and [`COLOR_RESOLVE`].
    pub struct ColorRoundArgs {
        /// `SolverParams` (for the body count).
        params,
        /// The contacts' `WorkList`.
        contact_work,
        /// `array<GpuManifold>`.
        manifolds,
        /// `array<GpuBody>`.
        bodies,
        /// Last step's `array<ColorSlot>`.
        previous_colors,
        /// This step's `array<ColorSlot>`.
        color_state,
        /// Used-color masks then claims, `u32`.
        color_marks,
    }
    /// Kernel: round 0 proposals, one thread per constraint.
    pub static COLOR_PROPOSE = "solver/color_propose.wgsl";
    /// Kernel: round 0 decisions, one thread per constraint.
    pub static COLOR_RESOLVE = "solver/color_resolve.wgsl";
}

kernel! {
    /// Buffers of [`COLOR_FINISH`]: those of [`ColorRoundArgs`], then its own.
    pub struct ColorFinishArgs {
        /// `SolverParams` (for the body count).
        params,
        /// The contacts' `WorkList`.
        contact_work,
        /// `array<GpuManifold>`.
        manifolds,
        /// `array<GpuBody>`.
        bodies,
        /// Last step's `array<ColorSlot>`.
        previous_colors,
        /// This step's `array<ColorSlot>`.
        color_state,
        /// Used-color masks then claims, `u32`.
        color_marks,
        /// Two lists of undecided constraints, `2 * capacity` `u32`.
        color_scratch,
        /// Output: `COLOR_OFFSETS_LEN` offsets.
        color_offsets,
        /// Output: `array<DispatchArgs>`, one per color slot.
        color_args,
        /// Output: sort keys (the colors).
        sort_keys,
        /// Output: sort values (the constraint indices).
        sort_values,
    }
    /// Kernel: the remaining rounds, counts, offsets, dispatch sizes and sort keys (one
    /// workgroup).
    pub static COLOR_FINISH = "solver/color_finish.wgsl";
}

/// Wellons' "lowbias32" hash, the same bijection as `hash_u32` in `coloring.wgsl`.
pub fn hash_u32(mut x: u32) -> u32 {
    x ^= x >> 16;
    x = x.wrapping_mul(0x7feb_352d);
    x ^= x >> 15;
    x = x.wrapping_mul(0x846c_a68b);
    x ^= x >> 16;
    x
}

/// Constraint `i`'s priority in the rounds (distinct and nonzero).
pub fn color_priority(i: u32) -> u32 {
    hash_u32(i + 1)
}

/// One manifold as the coloring sees it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ColorCandidate {
    /// Its two bodies.
    pub bodies: (u32, u32),
    /// False for a candidate pair not in contact (no points): it gets [`EMPTY_COLOR`].
    pub touching: bool,
    /// Last step's color of the pair, proposed in round 0 when free.
    pub seed: Option<u32>,
}

/// The CPU twin of the GPU coloring (every path): [`COLOR_ROUNDS`] rounds of proposals and
/// claims, exactly as the kernels run them, then the undecided to [`OVERFLOW_COLOR`].
/// `dynamic[b]` says whether body `b` counts.
pub fn color_rounds_cpu(candidates: &[ColorCandidate], dynamic: &[bool]) -> Vec<u32> {
    let all = if GRAPH_COLOR_COUNT >= 32 {
        u32::MAX
    } else {
        (1u32 << GRAPH_COLOR_COUNT) - 1
    };
    let mut colors = vec![NO_COLOR; candidates.len()];
    let mut used = vec![0u32; dynamic.len()];
    let mut undecided = Vec::with_capacity(candidates.len());
    for (i, c) in candidates.iter().enumerate() {
        if c.touching {
            undecided.push(i);
        } else {
            colors[i] = EMPTY_COLOR;
        }
    }
    for round in 0..COLOR_ROUNDS {
        if undecided.is_empty() {
            break;
        }
        // Proposals, and the highest priority claiming each (body, color).
        let mut proposals = Vec::with_capacity(undecided.len());
        let mut claims: HashMap<(u32, u32), u32> = HashMap::new();
        for &i in &undecided {
            let (a, b) = candidates[i].bodies;
            let (da, db) = (dynamic[a as usize], dynamic[b as usize]);
            let taken =
                if da { used[a as usize] } else { 0 } | if db { used[b as usize] } else { 0 };
            let free = !taken & all;
            if free == 0 {
                colors[i] = OVERFLOW_COLOR;
                continue;
            }
            let mut color = free.trailing_zeros();
            if round == 0
                && let Some(seed) = candidates[i].seed
                && seed < GRAPH_COLOR_COUNT
                && (free >> seed) & 1 != 0
            {
                color = seed;
            }
            proposals.push((i, color));
            for (body, counts) in [(a, da), (b, db)] {
                if counts {
                    let claim = claims.entry((body, color)).or_insert(0);
                    *claim = (*claim).max(color_priority(i as u32));
                }
            }
        }
        let mut next = Vec::new();
        for (i, color) in proposals {
            let (a, b) = candidates[i].bodies;
            let priority = color_priority(i as u32);
            let holds = |body: u32| !dynamic[body as usize] || claims[&(body, color)] == priority;
            if holds(a) && holds(b) {
                colors[i] = color;
                for body in [a, b] {
                    if dynamic[body as usize] {
                        used[body as usize] |= 1 << color;
                    }
                }
            } else {
                next.push(i);
            }
        }
        undecided = next;
    }
    for i in undecided {
        colors[i] = OVERFLOW_COLOR;
    }
    colors
}

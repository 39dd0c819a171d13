//! The `color` stage on the GPU: `color_propose` and `color_resolve` run the first (seeded)
//! round with one thread per constraint, `color_finish` runs the remaining rounds in one
//! workgroup, counts the colors and writes the per-color dispatch sizes; a stable radix sort
//! by color then gives the constraint order. [`color_rounds_cpu`] is the CPU twin.

use std::collections::HashMap;

use crate::kernel::{KernelArgs, KernelSpec};
use crate::shader::{Binding, ShaderSource, wgsl_file};

use super::constants::{COLOR_ROUNDS, EMPTY_COLOR, GRAPH_COLOR_COUNT, NO_COLOR, OVERFLOW_COLOR};
use super::shaders::{COLOR_COMMON, COLOR_FINISH_COMMON};

const ROUND_BINDINGS: &[Binding] = &[
    Binding::Uniform,
    Binding::StorageRead,
    Binding::StorageRead,
    Binding::StorageRead,
    Binding::StorageRead,
    Binding::StorageReadWrite,
    Binding::StorageReadWrite,
];

/// Kernel: round 0 proposals, one thread per constraint.
pub static COLOR_PROPOSE: KernelSpec = KernelSpec {
    name: "color_propose",
    source: ShaderSource {
        common: COLOR_COMMON,
        kernel: wgsl_file!("solver/color_propose.wgsl"),
    },
    bindings: ROUND_BINDINGS,
};

/// Kernel: round 0 decisions, one thread per constraint.
pub static COLOR_RESOLVE: KernelSpec = KernelSpec {
    name: "color_resolve",
    source: ShaderSource {
        common: COLOR_COMMON,
        kernel: wgsl_file!("solver/color_resolve.wgsl"),
    },
    bindings: ROUND_BINDINGS,
};

/// Kernel: the remaining rounds, counts, offsets, dispatch sizes and sort keys (one workgroup).
pub static COLOR_FINISH: KernelSpec = KernelSpec {
    name: "color_finish",
    source: ShaderSource {
        common: COLOR_FINISH_COMMON,
        kernel: wgsl_file!("solver/color_finish.wgsl"),
    },
    bindings: &[
        Binding::Uniform,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageRead,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
        Binding::StorageReadWrite,
    ],
};

/// Buffers of [`COLOR_PROPOSE`] and [`COLOR_RESOLVE`].
pub struct ColorRoundArgs<'a> {
    /// `SolverParams` (for the body count).
    pub params: &'a wgpu::Buffer,
    /// The contacts' `WorkList`.
    pub contact_work: &'a wgpu::Buffer,
    /// `array<GpuManifold>`.
    pub manifolds: &'a wgpu::Buffer,
    /// `array<GpuBody>`.
    pub bodies: &'a wgpu::Buffer,
    /// Last step's `array<ColorSlot>`.
    pub previous_colors: &'a wgpu::Buffer,
    /// This step's `array<ColorSlot>`.
    pub color_state: &'a wgpu::Buffer,
    /// Used-color masks then claims, `u32`.
    pub color_marks: &'a wgpu::Buffer,
}

impl KernelArgs for ColorRoundArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        vec![
            self.params,
            self.contact_work,
            self.manifolds,
            self.bodies,
            self.previous_colors,
            self.color_state,
            self.color_marks,
        ]
    }
}

/// Buffers of [`COLOR_FINISH`].
pub struct ColorFinishArgs<'a> {
    /// The round buffers.
    pub round: ColorRoundArgs<'a>,
    /// Two lists of undecided constraints, `2 * capacity` `u32`.
    pub color_scratch: &'a wgpu::Buffer,
    /// Output: `COLOR_OFFSETS_LEN` offsets.
    pub color_offsets: &'a wgpu::Buffer,
    /// Output: `array<DispatchArgs>`, one per color slot.
    pub color_args: &'a wgpu::Buffer,
    /// Output: sort keys (the colors).
    pub sort_keys: &'a wgpu::Buffer,
    /// Output: sort values (the constraint indices).
    pub sort_values: &'a wgpu::Buffer,
}

impl KernelArgs for ColorFinishArgs<'_> {
    fn buffers(&self) -> Vec<&wgpu::Buffer> {
        let mut buffers = self.round.buffers();
        buffers.extend([
            self.color_scratch,
            self.color_offsets,
            self.color_args,
            self.sort_keys,
            self.sort_values,
        ]);
        buffers
    }
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

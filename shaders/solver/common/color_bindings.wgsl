// requires: solver/common/coloring.wgsl
// The bindings of the coloring kernels that run rounds (color_propose, color_resolve,
// color_withdraw, color_finish): what coloring.wgsl expects, the pair work list, and the
// undecided list and tally that color_withdraw writes and color_finish reads (the first
// round's two kernels bind them too, unused, so that all four take one set of buffers).

// `SolverParams` (for the body count).
@group(0) @binding(0) var<uniform> params: SolverParams;
// The contacts' `WorkList`.
@group(0) @binding(1) var<storage, read> contact_work: WorkList;
@group(0) @binding(2) var<storage, read> manifolds: array<GpuManifold>;
@group(0) @binding(3) var<storage, read> bodies: array<GpuBody>;
// Last step's `array<ColorSlot>`.
@group(0) @binding(4) var<storage, read> previous_colors: array<ColorSlot>;
// This step's `array<ColorSlot>`.
@group(0) @binding(5) var<storage, read_write> color_state: array<ColorSlot>;
// Used-color masks then claims, `u32`.
@group(0) @binding(6) var<storage, read_write> color_marks: array<atomic<u32>>;
// Two lists of undecided constraints (2 x capacity).
@group(0) @binding(7) var<storage, read_write> color_scratch: array<u32>;
// The coloring tally (TALLY_UNDECIDED, then TALLY_COUNTS + color), zeroed before the stage.
@group(0) @binding(8) var<storage, read_write> color_tally: array<atomic<u32>>;
// Per world, the index of its first constraint (world_starts.wgsl; zero and unused while
// the step holds one world).
@group(0) @binding(9) var<storage, read> world_first: array<u32>;

// Constraint i's index among its world's: the manifolds are sorted by body pair and a
// world's bodies are one run, so a world's constraints are one run too.
fn constraint_rank(i: u32) -> u32 {
    return i - world_first[bodies[manifolds[i].body_a].world];
}

// The bindings of the fused solve kernels (solve_fused, solve_fused_shared and solve_worlds),
// all but binding 9 (the per-color offsets of solve_fused and solve_fused_shared, the worlds'
// first constraints of solve_worlds, whose offsets are per workgroup) and the bodies'
// velocities and solver state (bindings 12 and 13), which solve_fused reads in place and
// solve_fused_shared copies into workgroup memory under the same names. Each kernel defines
// constraint_rank (coloring.wgsl).

@group(0) @binding(0) var<uniform> params: SolverParams;
// The contacts' `WorkList`.
@group(0) @binding(1) var<storage, read> contact_work: WorkList;
@group(0) @binding(2) var<storage, read> manifolds: array<GpuManifold>;
// `array<GpuContact>` (points), impulses updated.
@group(0) @binding(3) var<storage, read_write> contacts: array<GpuContact>;
@group(0) @binding(4) var<storage, read> bodies: array<GpuBody>;
// Last step's `array<ColorSlot>`.
@group(0) @binding(5) var<storage, read> previous_colors: array<ColorSlot>;
// This step's `array<ColorSlot>`.
@group(0) @binding(6) var<storage, read_write> color_state: array<ColorSlot>;
// Used-color masks and claims.
@group(0) @binding(7) var<storage, read_write> color_marks: array<atomic<u32>>;
// Undecided lists.
@group(0) @binding(8) var<storage, read_write> color_scratch: array<u32>;
// Constraint order by color.
@group(0) @binding(10) var<storage, read_write> color_order: array<u32>;
// `array<GpuPose>`, updated.
@group(0) @binding(11) var<storage, read_write> poses: array<GpuPose>;
// The constraint store (`GpuConstraint` rows, by slot).
@group(0) @binding(14) var<storage, read_write> constraints: array<vec4<f32>>;
// Last step's `array<GpuTilt>`.
@group(0) @binding(15) var<storage, read> previous_tilts: array<GpuTilt>;
// This step's `array<GpuTilt>`.
@group(0) @binding(16) var<storage, read_write> tilts: array<GpuTilt>;

// The bindings of the two fused solve kernels (solve_fused and solve_fused_shared), all but
// the bodies' velocities and solver state (bindings 12 and 13), which solve_fused reads in
// place and solve_fused_shared copies into workgroup memory under the same names.

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
// Per-color offsets.
@group(0) @binding(9) var<storage, read_write> color_offsets: array<u32>;
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

// Constraint i's index among its world's: the fused path steps one world only
// (crates/tumble-gpu/src/solver/path.rs), whose constraints are numbered from 0.
fn constraint_rank(i: u32) -> u32 {
    return i;
}

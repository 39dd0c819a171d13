// requires: solver/common/fused_solve.wgsl
// solve_fused: the whole color-and-solve stage in one workgroup and one dispatch, for small
// scenes (solver/common/fused_solve.wgsl), with the bodies' velocities and solver state in
// their storage buffers.

@group(0) @binding(0) var<uniform> params: SolverParams;
@group(0) @binding(1) var<storage, read> contact_work: WorkList;
@group(0) @binding(2) var<storage, read> manifolds: array<GpuManifold>;
@group(0) @binding(3) var<storage, read_write> contacts: array<GpuContact>;
@group(0) @binding(4) var<storage, read> bodies: array<GpuBody>;
@group(0) @binding(5) var<storage, read> previous_colors: array<ColorSlot>;
@group(0) @binding(6) var<storage, read_write> color_state: array<ColorSlot>;
@group(0) @binding(7) var<storage, read_write> color_marks: array<atomic<u32>>;
@group(0) @binding(8) var<storage, read_write> color_scratch: array<u32>;
@group(0) @binding(9) var<storage, read_write> color_offsets: array<u32>;
@group(0) @binding(10) var<storage, read_write> color_order: array<u32>;
@group(0) @binding(11) var<storage, read_write> poses: array<GpuPose>;
@group(0) @binding(12) var<storage, read_write> velocities: array<GpuVelocity>;
@group(0) @binding(13) var<storage, read_write> solver_bodies: array<GpuSolverBody>;
@group(0) @binding(14) var<storage, read_write> constraints: array<vec4<f32>>;
@group(0) @binding(15) var<storage, read> previous_tilts: array<GpuTilt>;
@group(0) @binding(16) var<storage, read_write> tilts: array<GpuTilt>;

fn load_velocities(local: u32, n: u32) {}

fn store_bodies(local: u32, n: u32) {}

fn sync_bodies() {
    sync_workgroup();
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(@builtin(local_invocation_index) local: u32) {
    fused_solve(local);
}

// requires: solver/common/fused_solve.wgsl
// solve_fused_shared: solve_fused with every body's velocity and solver state in workgroup
// memory for the whole stage (at most FUSED_SHARED_BODIES bodies, 128 bytes each, within the
// 16 KiB every device has), so the barriers between colors are workgroup barriers only and a
// body read is no global load. The same functions in the same order: the same result as
// solve_fused, bit for bit. Measured on an H200 it solves a pyramid of 4 in 18% less time;
// lavapipe runs it about ten times slower than solve_fused, so the host picks it on GPUs only.

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
@group(0) @binding(12) var<storage, read_write> velocity_buffer: array<GpuVelocity>;
@group(0) @binding(13) var<storage, read_write> solver_body_buffer: array<GpuSolverBody>;
@group(0) @binding(14) var<storage, read_write> constraints: array<vec4<f32>>;
@group(0) @binding(15) var<storage, read> previous_tilts: array<GpuTilt>;
@group(0) @binding(16) var<storage, read_write> tilts: array<GpuTilt>;

override FUSED_SHARED_BODIES: u32;

// The names the shared solver functions use.
var<workgroup> velocities: array<GpuVelocity, FUSED_SHARED_BODIES>;
var<workgroup> solver_bodies: array<GpuSolverBody, FUSED_SHARED_BODIES>;

fn load_velocities(local: u32, n: u32) {
    for (var b = local; b < n; b += WORKGROUP_SIZE) {
        velocities[b] = velocity_buffer[b];
    }
}

// Called after the last pose is written; each thread copies the bodies it finalized.
fn store_bodies(local: u32, n: u32) {
    for (var b = local; b < n; b += WORKGROUP_SIZE) {
        velocity_buffer[b] = velocities[b];
        solver_body_buffer[b] = solver_bodies[b];
    }
}

fn sync_bodies() {
    workgroupBarrier();
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(@builtin(local_invocation_index) local: u32) {
    fused_solve(local);
}

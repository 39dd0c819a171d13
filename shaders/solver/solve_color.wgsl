// requires: solver/common/solve_color_pass.wgsl
// solve_color: one pass over the constraints of one graph color, or a pass's tail
// (solver/common/solve_color_pass.wgsl), the color named by a uniform: one bind group per
// color and tail. The wide path's kernel on adapters without immediate data; where the
// device has it, solve_color_immediate computes the same with one bind group per pass.

@group(0) @binding(0) var<uniform> params: SolverParams;
// `ColorPass` naming the color.
@group(0) @binding(1) var<uniform> pass_color: ColorPass;
// Per-color offsets: color `c` is the constraint slots `offsets[c]..offsets[c + 1]`.
@group(0) @binding(2) var<storage, read> color_offsets: array<u32>;
@group(0) @binding(3) var<storage, read> solver_bodies: array<GpuSolverBody>;
// `array<GpuVelocity>`, updated.
@group(0) @binding(4) var<storage, read_write> velocities: array<GpuVelocity>;
// The constraint store (`GpuConstraint` rows, by slot), updated.
@group(0) @binding(5) var<storage, read_write> constraints: array<vec4<f32>>;

// PASS_WARM_START, PASS_SOLVE, PASS_RELAX or PASS_RESTITUTION: one pipeline each.
override PASS: u32;

@compute @workgroup_size(COLOR_PASS_WORKGROUP_SIZE)
fn main(thread: Thread) {
    solve_color_pass(thread, pass_color);
}

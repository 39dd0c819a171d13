// requires: solver/common/solve_color_pass.wgsl
// solve_color_immediate: solve_color with the `ColorPass` set as immediate data before each
// dispatch instead of bound as a uniform (solver/common/solve_color_pass.wgsl), so one bind
// group serves every color and tail of a pass and the host binds it once per pass kind.
// Built only on devices with immediate data (wgpu's IMMEDIATES feature).

@group(0) @binding(0) var<uniform> params: SolverParams;
// Per-color offsets: color `c` is the constraint slots `offsets[c]..offsets[c + 1]`.
@group(0) @binding(1) var<storage, read> color_offsets: array<u32>;
@group(0) @binding(2) var<storage, read> solver_bodies: array<GpuSolverBody>;
// `array<GpuVelocity>`, updated.
@group(0) @binding(3) var<storage, read_write> velocities: array<GpuVelocity>;
// The constraint store (`GpuConstraint` rows, by slot), updated.
@group(0) @binding(4) var<storage, read_write> constraints: array<vec4<f32>>;
// `ColorPass` naming the color, set by the host before each dispatch.
var<immediate> pass_color: ColorPass;

// PASS_WARM_START, PASS_SOLVE, PASS_RELAX or PASS_RESTITUTION: one pipeline each.
override PASS: u32;

@compute @workgroup_size(COLOR_PASS_WORKGROUP_SIZE)
fn main(thread: Thread) {
    solve_color_pass(thread, pass_color);
}

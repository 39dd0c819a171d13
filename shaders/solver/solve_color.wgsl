// requires: common/indexing.wgsl solver/common/constraint_access.wgsl
// solve_color: one thread per constraint of one graph color (ColorPass.color) applies the
// pass chosen by the PASS override (warm start, biased solve, relax or restitution).
// A color's constraints are the slots color_offsets[color]..color_offsets[color + 1]
// (constraint_store.wgsl). Constraints of one color share no dynamic body, so they run at the same time and the result
// does not depend on their order; the overflow set runs in one thread, in order.

@group(0) @binding(0) var<uniform> params: SolverParams;
@group(0) @binding(1) var<uniform> pass_color: ColorPass;
@group(0) @binding(2) var<storage, read> color_offsets: array<u32>;
@group(0) @binding(3) var<storage, read> solver_bodies: array<GpuSolverBody>;
@group(0) @binding(4) var<storage, read_write> velocities: array<GpuVelocity>;
@group(0) @binding(5) var<storage, read_write> constraints: array<vec4<f32>>;

// PASS_WARM_START, PASS_SOLVE, PASS_RELAX or PASS_RESTITUTION: one pipeline each.
override PASS: u32;

@compute @workgroup_size(COLOR_PASS_WORKGROUP_SIZE)
fn main(thread: Thread) {
    let t = linear_group(thread.workgroup, thread.groups) * COLOR_PASS_WORKGROUP_SIZE + thread.local;
    let color = pass_color.color;
    let begin = color_offsets[color];
    let end = color_offsets[color + 1u];
    if color == OVERFLOW_COLOR {
        if t == 0u {
            for (var k = begin; k < end; k++) {
                visit_constraint(k, PASS);
            }
        }
        return;
    }
    if begin + t < end {
        visit_constraint(begin + t, PASS);
    }
}

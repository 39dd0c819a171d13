// requires: common/indexing.wgsl solver/common/body_slot.wgsl solver/common/warm_start_body.wgsl
// warm_start_bodies: the warm-start pass of a substep in one dispatch, one thread per body,
// for the graph colors (the overflow set follows in solve_color's single thread, as in the
// colored sweep): solver/common/warm_start_body.wgsl says why this gives the colored sweep's
// bits with 1 dispatch instead of one per color.
@group(0) @binding(0) var<uniform> params: SolverParams;
@group(0) @binding(1) var<storage, read> solver_bodies: array<GpuSolverBody>;
// `array<GpuVelocity>`, updated.
@group(0) @binding(2) var<storage, read_write> velocities: array<GpuVelocity>;
// The constraint store (`GpuConstraint` rows, by slot); the totals updated.
@group(0) @binding(3) var<storage, read_write> constraints: array<vec4<f32>>;
// The coloring's marks: per (body, graph color) the slot + 1 of the body's constraint of that
// color, or 0 (prepare_contacts.wgsl).
@group(0) @binding(4) var<storage, read> color_marks: array<u32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let body = thread_index(thread);
    if body >= params.body_count {
        return;
    }
    warm_start_body(body);
}

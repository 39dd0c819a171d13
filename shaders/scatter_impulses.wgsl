// requires: common/indexing.wgsl common/layout.wgsl
// scatter_impulses: one thread per dense manifold writes impulses given in dense order (as
// a readback of the touching contacts returned them, solved by a CPU solver) back into the
// pair-slot contact array, where the next step's carry_impulses finds them.

// `ScatterParams` (how many dense manifolds).
@group(0) @binding(0) var<uniform> params: ScatterParams;
// `array<GpuTouching>` from `write_touching`.
@group(0) @binding(1) var<storage, read> touching: array<GpuTouching>;
// Dense manifolds from `write_touching` (for their point counts).
@group(0) @binding(2) var<storage, read> touching_manifolds: array<GpuManifold>;
// Impulses in dense point order (uploaded).
@group(0) @binding(3) var<storage, read> impulses: array<GpuContact>;
// The per-pair points whose impulses are written.
@group(0) @binding(4) var<storage, read_write> contacts: array<GpuContact>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let d = thread_index(thread);
    if d >= params.count {
        return;
    }
    let t = touching[d];
    for (var i = 0u; i < touching_manifolds[d].len; i++) {
        let solved = impulses[t.first_point + i];
        let slot = t.slot * MAX_MANIFOLD_POINTS + i;
        contacts[slot].normal_impulse = solved.normal_impulse;
        contacts[slot].friction_impulse = solved.friction_impulse;
    }
}

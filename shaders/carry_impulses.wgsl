// carry_impulses: one thread per manifold copies last step's accumulated impulses to the
// points whose feature id matches, when the manifold kept its kind and reference feature
// (ids are only comparable under the same reference feature); other points start at zero,
// as collide_cuboids wrote them. This is the warm start's input.

@group(0) @binding(0) var<storage, read> work: WorkList;
@group(0) @binding(1) var<storage, read> manifolds: array<GpuManifold>;
@group(0) @binding(2) var<storage, read> previous_manifolds: array<GpuManifold>;
@group(0) @binding(3) var<storage, read> previous_contacts: array<GpuContact>;
@group(0) @binding(4) var<storage, read_write> contacts: array<GpuContact>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let k = linear_index(workgroup, groups, local);
    if k >= work.count {
        return;
    }
    let m = manifolds[k];
    if m.len == 0u || m.previous == NO_PREVIOUS {
        return;
    }
    let old = previous_manifolds[m.previous];
    if old.len == 0u || old.kind != m.kind || old.feature != m.feature {
        return;
    }
    for (var i = 0u; i < m.len; i++) {
        let slot = k * MAX_MANIFOLD_POINTS + i;
        let id = contacts[slot].id;
        for (var j = 0u; j < old.len; j++) {
            let before = previous_contacts[m.previous * MAX_MANIFOLD_POINTS + j];
            if before.id == id {
                contacts[slot].normal_impulse = before.normal_impulse;
                contacts[slot].friction_impulse = before.friction_impulse;
                break;
            }
        }
    }
}

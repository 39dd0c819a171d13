// store_impulses: one thread per manifold writes its constraint's final impulses into its
// contact points, where the next step's carry_impulses finds them for warm starting.

@group(0) @binding(0) var<storage, read> contact_work: WorkList;
@group(0) @binding(1) var<storage, read> constraints: array<GpuConstraint>;
@group(0) @binding(2) var<storage, read_write> contacts: array<GpuContact>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
) {
    let i = linear_index(workgroup, groups, local);
    if i >= contact_work.count {
        return;
    }
    let c = constraints[i];
    for (var p = 0u; p < c.point_count; p++) {
        let slot = i * MAX_MANIFOLD_POINTS + p;
        contacts[slot] = stored_point(c, p, contacts[slot]);
    }
}

// requires: common/constants.wgsl
// Thread indexing for dispatches that fold past the per-dimension workgroup limit:
// the host launches (x, y) workgroups and a thread's linear index is rebuilt here.

// The linear index of a thread from its workgroup id, the grid size and its local index.
fn linear_index(workgroup: vec3<u32>, groups: vec3<u32>, local: u32) -> u32 {
    return (workgroup.y * groups.x + workgroup.x) * WORKGROUP_SIZE + local;
}

// The linear index of a workgroup (for kernels that give one workgroup a tile).
fn linear_group(workgroup: vec3<u32>, groups: vec3<u32>) -> u32 {
    return workgroup.y * groups.x + workgroup.x;
}

// The ids a kernel's `main` takes, as one argument.
struct Thread {
    @builtin(workgroup_id) workgroup: vec3<u32>,
    @builtin(num_workgroups) groups: vec3<u32>,
    @builtin(local_invocation_index) local: u32,
}

// The linear index of `thread` (see `linear_index`).
fn thread_index(thread: Thread) -> u32 {
    return linear_index(thread.workgroup, thread.groups, thread.local);
}

// The linear index of `thread`'s workgroup (see `linear_group`).
fn thread_group(thread: Thread) -> u32 {
    return linear_group(thread.workgroup, thread.groups);
}

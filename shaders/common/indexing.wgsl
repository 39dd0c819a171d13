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

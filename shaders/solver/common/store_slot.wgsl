// requires: solver/common/contact_math.wgsl solver/common/constraint_store.wgsl
// The finish of one constraint slot: its final impulses into the contact points of the
// manifold there, where the next step's carry_impulses finds them, and its tilt impulse
// (with the normal in body A's frame) where the next step's prepare_contacts finds it.
// Used by store_impulses (one thread per slot) and solve_fused (a workgroup loop).
//
// Expects the including kernel to declare: color_order: array<u32>, constraints (the store),
// poses: array<GpuPose> (still the start of the step), contacts: array<GpuContact>
// (read_write), tilts: array<GpuTilt> (read_write).

fn store_slot(s: u32) {
    let i = color_order[s];
    let c = load_constraint(s);
    for (var p = 0u; p < c.point_count; p++) {
        let slot = i * MAX_MANIFOLD_POINTS + p;
        contacts[slot] = stored_point(c, p, contacts[slot]);
    }
    tilts[i] = stored_tilt(c, poses[c.body_a].rotation);
}

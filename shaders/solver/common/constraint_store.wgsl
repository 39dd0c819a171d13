// requires: common/solver_types.wgsl solver/common/solver_constants.wgsl
// Where constraints live: a structure of arrays of 16-byte rows. Row r of the constraint in
// slot s is the r-th 16 bytes of its GpuConstraint, at constraints[r * stride + s] with
// stride = arrayLength(&constraints) / CONSTRAINT_ROWS. A slot is the constraint's position in
// the order by color (prepare_contacts writes constraint color_order[s] into slot s), so one
// color's constraints are consecutive slots and the threads of a per-color pass read each row
// of theirs in one coalesced access, where a 368-byte struct per thread was a gather.
//
// Expects the including kernel to declare constraints: array<vec4<f32>> (read, or read_write
// with constraint_write.wgsl).

fn constraint_stride() -> u32 {
    return arrayLength(&constraints) / CONSTRAINT_ROWS;
}

// First row of point p.
fn point_row(p: u32) -> u32 {
    return CONSTRAINT_HEADER_ROWS + p * CONSTRAINT_POINT_ROWS;
}

// The constraint in slot s. Points past point_count are not read (they are zero, as
// prepare left them).
fn load_constraint(s: u32) -> GpuConstraint {
    let stride = constraint_stride();
    let head = bitcast<vec4<u32>>(constraints[s]);
    var c: GpuConstraint;
    c.body_a = head.x;
    c.body_b = head.y;
    c.point_count = min(head.z, MAX_MANIFOLD_POINTS);
    c.flags = head.w;
    c.normal = constraints[stride + s];
    c.tangent1 = constraints[2u * stride + s];
    c.tangent2 = constraints[3u * stride + s];
    c.softness = constraints[4u * stride + s];
    let tilt = constraints[5u * stride + s];
    c.tilt_mass_1 = tilt.x;
    c.tilt_mass_2 = tilt.y;
    c.tilt_impulse_1 = tilt.z;
    c.tilt_impulse_2 = tilt.w;
    c.patch_radius = constraints[6u * stride + s].x;
    for (var p = 0u; p < MAX_MANIFOLD_POINTS; p++) {
        if p >= c.point_count {
            break;
        }
        let r = point_row(p) * stride + s;
        c.points[p].anchor_a = constraints[r];
        c.points[p].anchor_b = constraints[r + stride];
        let masses = constraints[r + 2u * stride];
        c.points[p].tangent_mass_1 = masses.x;
        c.points[p].tangent_mass_2 = masses.y;
        c.points[p].normal_impulse = masses.z;
        c.points[p].total_normal_impulse = masses.w;
        let impulses = constraints[r + 3u * stride];
        c.points[p].tangent_impulse_1 = impulses.x;
        c.points[p].tangent_impulse_2 = impulses.y;
        c.points[p].relative_velocity = impulses.z;
    }
    return c;
}

// Reads again into c the rows of slot s that a pass changes (the tilt row, each point's
// masses-and-impulses and impulses rows: store_pass_impulses's rows), for a constraint loaded
// before an earlier pass could have written them. Everything else of a constraint is fixed
// from prepare to store.
fn reload_pass_impulses(s: u32, c: ptr<function, GpuConstraint>) {
    let stride = constraint_stride();
    let tilt = constraints[5u * stride + s];
    (*c).tilt_mass_1 = tilt.x;
    (*c).tilt_mass_2 = tilt.y;
    (*c).tilt_impulse_1 = tilt.z;
    (*c).tilt_impulse_2 = tilt.w;
    for (var p = 0u; p < MAX_MANIFOLD_POINTS; p++) {
        if p >= (*c).point_count {
            break;
        }
        let r = point_row(p) * stride + s;
        let masses = constraints[r + 2u * stride];
        (*c).points[p].tangent_mass_1 = masses.x;
        (*c).points[p].tangent_mass_2 = masses.y;
        (*c).points[p].normal_impulse = masses.z;
        (*c).points[p].total_normal_impulse = masses.w;
        let impulses = constraints[r + 3u * stride];
        (*c).points[p].tangent_impulse_1 = impulses.x;
        (*c).points[p].tangent_impulse_2 = impulses.y;
        (*c).points[p].relative_velocity = impulses.z;
    }
}

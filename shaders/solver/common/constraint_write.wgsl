// requires: solver/common/constraint_store.wgsl
// Writing constraints into the store (constraint_store.wgsl's rows): the whole constraint
// (prepare) or what a pass changes.
//
// Expects the including kernel to declare constraints: array<vec4<f32>> (read_write).

// Row 2 of a point: its friction masses and its normal impulses.
fn point_masses_row(q: GpuConstraintPoint) -> vec4<f32> {
    return vec4<f32>(q.tangent_mass_1, q.tangent_mass_2, q.normal_impulse, q.total_normal_impulse);
}

// Row 3 of a point: its friction impulses and approach speed.
fn point_impulses_row(q: GpuConstraintPoint) -> vec4<f32> {
    return vec4<f32>(q.tangent_impulse_1, q.tangent_impulse_2, q.relative_velocity, 0.0);
}

// Row 5: the tilt rows' masses and impulses.
fn tilt_row(c: GpuConstraint) -> vec4<f32> {
    return vec4<f32>(c.tilt_mass_1, c.tilt_mass_2, c.tilt_impulse_1, c.tilt_impulse_2);
}

// Stores all of c (every point) in slot s.
fn store_constraint(s: u32, c: GpuConstraint) {
    let stride = constraint_stride();
    constraints[s] = bitcast<vec4<f32>>(vec4<u32>(c.body_a, c.body_b, c.point_count, c.flags));
    constraints[stride + s] = c.normal;
    constraints[2u * stride + s] = c.tangent1;
    constraints[3u * stride + s] = c.tangent2;
    constraints[4u * stride + s] = c.softness;
    constraints[5u * stride + s] = tilt_row(c);
    constraints[6u * stride + s] = vec4<f32>(c.patch_radius, 0.0, 0.0, 0.0);
    for (var p = 0u; p < MAX_MANIFOLD_POINTS; p++) {
        let r = point_row(p) * stride + s;
        constraints[r] = c.points[p].anchor_a;
        constraints[r + stride] = c.points[p].anchor_b;
        constraints[r + 2u * stride] = point_masses_row(c.points[p]);
        constraints[r + 3u * stride] = point_impulses_row(c.points[p]);
    }
}

// Writes back what a pass changes in slot s, from its local copy c: the points' accumulated
// impulses and the tilt impulses (with the rows they share, whose other values a pass leaves
// as they were). Anchors, normal and tangents are fixed from prepare to store, so writing them
// again would only cost bandwidth.
fn store_pass_impulses(s: u32, c: GpuConstraint) {
    let stride = constraint_stride();
    constraints[5u * stride + s] = tilt_row(c);
    for (var p = 0u; p < MAX_MANIFOLD_POINTS; p++) {
        if p >= c.point_count {
            break;
        }
        let r = point_row(p) * stride + s;
        constraints[r + 2u * stride] = point_masses_row(c.points[p]);
        constraints[r + 3u * stride] = point_impulses_row(c.points[p]);
    }
}

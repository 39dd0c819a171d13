// requires: common/indexing.wgsl solver/common/prepare_constraint.wgsl solver/common/body_slot.wgsl
// prepare_contacts: one thread per slot of the order by color builds the constraint of the
// manifold there (a manifold without points gives an empty constraint): normal and two
// friction rows per point, effective masses, anchors, softness, and the warm-start impulses
// the collision stage carried over. It also lists, per dynamic body and graph color, the slot
// of the body's constraint of that color, for warm_start_bodies.

@group(0) @binding(0) var<uniform> params: SolverParams;
// The contacts' `WorkList`.
@group(0) @binding(1) var<storage, read> contact_work: WorkList;
@group(0) @binding(2) var<storage, read> manifolds: array<GpuManifold>;
// `array<GpuContact>`, `MAX_MANIFOLD_POINTS` per manifold, with carried impulses.
@group(0) @binding(3) var<storage, read> contacts: array<GpuContact>;
@group(0) @binding(4) var<storage, read> bodies: array<GpuBody>;
@group(0) @binding(5) var<storage, read> poses: array<GpuPose>;
@group(0) @binding(6) var<storage, read> velocities: array<GpuVelocity>;
// `array<GpuSolverBody>` from `prepare_bodies`.
@group(0) @binding(7) var<storage, read> solver_bodies: array<GpuSolverBody>;
// Last step's `array<GpuTilt>`, indexed by the manifolds' `previous`.
@group(0) @binding(8) var<storage, read> previous_tilts: array<GpuTilt>;
// Manifold indices by color: slot `s` holds the constraint of manifold `color_order[s]`.
@group(0) @binding(9) var<storage, read> color_order: array<u32>;
// Output: the constraint store (`GpuConstraint` rows, by slot).
@group(0) @binding(10) var<storage, read_write> constraints: array<vec4<f32>>;
// Per-color offsets: color `c` is the constraint slots `offsets[c]..offsets[c + 1]`.
@group(0) @binding(11) var<storage, read> color_offsets: array<u32>;
// The coloring's marks: after the body masks, one entry per (body, graph color), all zero once
// the coloring has withdrawn its claims. Output: slot + 1 of the body's constraint of that
// color, for each dynamic body of a colored constraint (warm_start_bodies.wgsl).
@group(0) @binding(12) var<storage, read_write> color_marks: array<u32>;

// The graph color of colored slot `s` (s below the overflow set's first slot).
fn slot_color(s: u32) -> u32 {
    var color = 0u;
    for (var c = 1u; c < GRAPH_COLOR_COUNT; c++) {
        if color_offsets[c] <= s {
            color = c;
        }
    }
    return color;
}

// Lists slot `s` at its dynamic bodies under its color. A body has at most one constraint
// of each color, so every entry is written by one thread at most.
fn list_at_bodies(s: u32) {
    if s >= color_offsets[OVERFLOW_COLOR] {
        return;
    }
    let color = slot_color(s);
    let m = manifolds[color_order[s]];
    for (var k = 0u; k < 2u; k++) {
        let body = select(m.body_a, m.body_b, k == 1u);
        if bodies[body].kind == BODY_DYNAMIC {
            color_marks[params.body_count + body * GRAPH_COLOR_COUNT + color] = s + 1u;
        }
    }
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let s = thread_index(thread);
    if s >= contact_work.count {
        return;
    }
    prepare_constraint(color_order[s], s);
    list_at_bodies(s);
}

// requires: common/layout.wgsl
// Shared by contact_begins and contact_ends: the append counters, the kinds of
// GpuContactEvent (common/layout.wgsl), and the running sums that say whether a manifold
// touches and where.

// The append counters of the event and touching lists. 16 bytes.
struct EventCounts {
    events: atomic<u32>,
    touching: atomic<u32>,
    _pad0: u32,
    _pad1: u32,
}

const EVENT_BEGIN: u32 = 0u;
const EVENT_END: u32 = 1u;
const EVENT_TOUCHING: u32 = 2u;

// A manifold's points folded one by one: whether one overlapped at the start of the step or
// pushed during it (its normal impulse over the step, friction_impulse.w, positive: the
// CPU's Contact::is_touching), the impulse sum, and the plain and weighted position sums.
struct Touch {
    touches: bool,
    impulse: f32,
    pushed: f32,
    sum: vec3<f32>,
    weighted: vec3<f32>,
    points: u32,
}

fn touch_start() -> Touch {
    return Touch(false, 0.0, 0.0, vec3<f32>(0.0), vec3<f32>(0.0), 0u);
}

fn touch_add(t: Touch, p: GpuContact) -> Touch {
    var out = t;
    let j = p.friction_impulse.w;
    out.touches = t.touches || p.depth > 0.0 || j > 0.0;
    out.impulse = t.impulse + j;
    out.pushed = t.pushed + max(j, 0.0);
    out.sum = t.sum + p.position.xyz;
    out.weighted = t.weighted + p.position.xyz * max(j, 0.0);
    out.points = t.points + 1u;
    return out;
}

// The event record of a folded manifold.
fn touch_event(kind: u32, m: GpuManifold, slot: u32, t: Touch) -> GpuContactEvent {
    var point = t.sum / f32(max(t.points, 1u));
    if t.pushed > 0.0 {
        point = t.weighted / t.pushed;
    }
    return GpuContactEvent(kind, m.body_a, m.body_b, slot, vec4<f32>(point, t.impulse));
}

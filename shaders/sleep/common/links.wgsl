// requires: common/indexing.wgsl sleep/common/sleep_constants.wgsl
// The links of the island search, one thread per manifold: the bindings and the test that
// hook_labels and check_labels share. Each kernel binds, after these, the labels it writes at
// binding 5.

// The step's pair `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
// `array<GpuManifold>`: the step's manifolds.
@group(0) @binding(1) var<storage, read> manifolds: array<GpuManifold>;
// `array<GpuBody>`: every body as uploaded.
@group(0) @binding(2) var<storage, read> awake_bodies: array<GpuBody>;
// `array<u32>`: island labels (which bodies sleep).
@group(0) @binding(3) var<storage, read> island: array<u32>;
// `array<u32>`: the last round's labels.
@group(0) @binding(4) var<storage, read> labels: array<u32>;

// True when manifold `m` links two islands: it has points and both its bodies are linkable.
fn is_link(m: GpuManifold) -> bool {
    return m.len > 0u && is_linkable(awake_bodies[m.body_a].kind, island[m.body_a])
        && is_linkable(awake_bodies[m.body_b].kind, island[m.body_b]);
}

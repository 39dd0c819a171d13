// requires: common/indexing.wgsl common/layout.wgsl common/tile_scan.wgsl
// write_touching: one workgroup per tile of manifolds writes each manifold in contact to its
// slot in the dense list (pair order kept), with its pair slot, its first dense point and
// its points, so a readback or a later stage touches only contacts that exist.

// The pair `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
// Manifolds, one per pair.
@group(0) @binding(1) var<storage, read> manifolds: array<GpuManifold>;
// Points, `MAX_MANIFOLD_POINTS` per pair.
@group(0) @binding(2) var<storage, read> contacts: array<GpuContact>;
// Scanned tile totals.
@group(0) @binding(3) var<storage, read> tile_offsets: array<vec2<u32>>;
// Output `array<GpuTouching>`.
@group(0) @binding(4) var<storage, read_write> touching: array<GpuTouching>;
// Output dense manifolds.
@group(0) @binding(5) var<storage, read_write> touching_manifolds: array<GpuManifold>;
// Output dense points.
@group(0) @binding(6) var<storage, read_write> touching_points: array<GpuContact>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let tile = thread_group(thread);
    let tiles = (work.count + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    let k = tile * WORKGROUP_SIZE + thread.local;
    var len = 0u;
    if tile < tiles && k < work.count {
        len = manifolds[k].len;
    }
    let value = vec2<u32>(u32(len > 0u), len);
    let before = tile_inclusive_scan(thread.local, value) - value;
    if len == 0u {
        return;
    }
    let base = tile_offsets[tile];
    let dense = base.x + before.x;
    let first = base.y + before.y;
    touching[dense] = GpuTouching(k, first);
    touching_manifolds[dense] = manifolds[k];
    for (var i = 0u; i < len; i++) {
        touching_points[first + i] = contacts[k * MAX_MANIFOLD_POINTS + i];
    }
}

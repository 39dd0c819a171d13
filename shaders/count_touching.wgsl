// requires: common/indexing.wgsl common/layout.wgsl common/tile_scan.wgsl
// count_touching: one workgroup per tile of WORKGROUP_SIZE manifolds counts the manifolds in
// contact (len > 0) and their points, for the compaction of the contacts into a dense list
// in pair order (a deterministic compaction: tile totals, their scan, then the writes).

// The pair `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
// Manifolds, one per pair.
@group(0) @binding(1) var<storage, read> manifolds: array<GpuManifold>;
// Output `array<vec2<u32>>`: (manifolds in contact, points) per tile.
@group(0) @binding(2) var<storage, read_write> tile_totals: array<vec2<u32>>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let tile = thread_group(thread);
    let tiles = (work.count + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    let k = tile * WORKGROUP_SIZE + thread.local;
    var value = vec2<u32>(0u);
    if tile < tiles && k < work.count {
        let len = manifolds[k].len;
        value = vec2<u32>(u32(len > 0u), len);
    }
    let total = tile_inclusive_scan(thread.local, value);
    if tile < tiles && thread.local == WORKGROUP_SIZE - 1u {
        tile_totals[tile] = total;
    }
}

// requires: common/indexing.wgsl common/layout.wgsl common/tile_scan.wgsl
// scan_touching: a single workgroup turns the per-tile (manifolds, points) totals into
// exclusive prefix sums in place (each tile's first dense manifold and first dense point)
// and writes the grand totals. Each thread sums a contiguous chunk, the chunk sums are
// scanned across the workgroup, then each thread writes its chunk's running offsets.

// The pair `WorkList`.
@group(0) @binding(0) var<storage, read> work: WorkList;
// Tile totals in, first dense manifold and point per tile out.
@group(0) @binding(1) var<storage, read_write> tile_totals: array<vec2<u32>>;
// Output `TouchingCounts`.
@group(0) @binding(2) var<storage, read_write> counts: TouchingCounts;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(@builtin(local_invocation_index) local: u32) {
    let n = (work.count + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    let chunk = (n + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    let begin = min(local * chunk, n);
    let end = min(begin + chunk, n);
    var sum = vec2<u32>(0u);
    for (var i = begin; i < end; i++) {
        sum += tile_totals[i];
    }
    var running = tile_inclusive_scan(local, sum) - sum;
    for (var i = begin; i < end; i++) {
        let t = tile_totals[i];
        tile_totals[i] = running;
        running += t;
    }
    if local == WORKGROUP_SIZE - 1u {
        counts = TouchingCounts(running.x, running.y, 0u, 0u);
    }
}

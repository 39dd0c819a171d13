// requires: common/layout.wgsl common/tile_scan.wgsl
// scan_world_pairs: one workgroup turns the pairs counted per world (count_world_pairs) into
// each world's first slot in the sorted list, `world_pair_starts[w]`, the pair count after
// the last world, and sets every count back to zero for scatter_world_pairs to count again
// as it places the pairs. Each thread sums a run of consecutive worlds; the run totals are
// scanned across the workgroup, and each thread writes its run's starts from its total on.

// [0]: the world count W; then each world's first body and the body count (not read here).
@group(0) @binding(0) var<storage, read> world_body_starts: array<u32>;
// Pairs per world, from count_world_pairs; zero afterwards.
@group(0) @binding(1) var<storage, read_write> world_pair_counts: array<u32>;
// Each world's first pair slot, then the pair count: W + 1 entries.
@group(0) @binding(2) var<storage, read_write> world_pair_starts: array<u32>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(@builtin(local_invocation_index) local: u32) {
    let worlds = world_body_starts[0];
    let per_thread = (worlds + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    let begin = min(local * per_thread, worlds);
    let end = min(begin + per_thread, worlds);
    var total = 0u;
    for (var w = begin; w < end; w++) {
        total += world_pair_counts[w];
    }
    // The run totals up to this thread's, inclusive (common/tile_scan.wgsl).
    let through = tile_inclusive_scan(local, vec2<u32>(total, 0u)).x;
    var start = through - total;
    for (var w = begin; w < end; w++) {
        world_pair_starts[w] = start;
        start += world_pair_counts[w];
        world_pair_counts[w] = 0u;
    }
    if local == WORKGROUP_SIZE - 1u {
        world_pair_starts[worlds] = through;
    }
}

// requires: common/layout.wgsl
// radix_scan: a single workgroup turns the digit-major tile counts into exclusive prefix
// sums, in place: entry (digit, tile) becomes the output slot of that tile's first key with
// that digit. Each thread sums a contiguous chunk, the chunk sums are scanned across the
// workgroup, and each thread then writes its chunk's running offsets.

// The `WorkList` giving the item count.
@group(0) @binding(0) var<storage, read> work: WorkList;
// Counts in, first slots out (in place).
@group(0) @binding(1) var<storage, read_write> tile_counts: array<u32>;

var<workgroup> partial: array<u32, WORKGROUP_SIZE>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(@builtin(local_invocation_index) local: u32) {
    let tiles = (work.count + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    let n = RADIX * tiles;
    let chunk = (n + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    let begin = min(local * chunk, n);
    let end = min(begin + chunk, n);
    var total = 0u;
    for (var i = begin; i < end; i++) {
        total += tile_counts[i];
    }
    partial[local] = total;
    workgroupBarrier();
    // Inclusive Hillis-Steele scan of the chunk totals.
    for (var offset = 1u; offset < WORKGROUP_SIZE; offset *= 2u) {
        var left = 0u;
        if local >= offset {
            left = partial[local - offset];
        }
        workgroupBarrier();
        partial[local] += left;
        workgroupBarrier();
    }
    var running = partial[local] - total;
    for (var i = begin; i < end; i++) {
        let count = tile_counts[i];
        tile_counts[i] = running;
        running += count;
    }
}

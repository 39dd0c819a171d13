// requires: common/indexing.wgsl common/layout.wgsl
// radix_scatter: one workgroup per tile moves each (key, value) to its sorted slot for this
// pass's digit: the tile's first slot for that digit (from radix_scan) plus the number of
// keys before it in the tile with the same digit. Counting only earlier keys keeps equal
// digits in input order, which makes every pass, and so the whole LSD sort, stable.

// This pass's RadixPassParams.
@group(0) @binding(0) var<uniform> pass_params: RadixPassParams;
// The `WorkList` giving the item count.
@group(0) @binding(1) var<storage, read> work: WorkList;
// Keys in.
@group(0) @binding(2) var<storage, read> keys_in: array<u32>;
// Values in.
@group(0) @binding(3) var<storage, read> values_in: array<u32>;
// First slots from the scan.
@group(0) @binding(4) var<storage, read> tile_offsets: array<u32>;
// Keys out.
@group(0) @binding(5) var<storage, read_write> keys_out: array<u32>;
// Values out.
@group(0) @binding(6) var<storage, read_write> values_out: array<u32>;

var<workgroup> digits: array<u32, WORKGROUP_SIZE>;

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(thread: Thread) {
    let tile = thread_group(thread);
    let tiles = (work.count + WORKGROUP_SIZE - 1u) / WORKGROUP_SIZE;
    let i = tile * WORKGROUP_SIZE + thread.local;
    let valid = tile < tiles && i < work.count;
    var key = 0u;
    // Past the end, a digit no real key has, so it never counts toward a real key's rank.
    var digit = RADIX;
    if valid {
        key = keys_in[i];
        digit = (key >> pass_params.shift) & (RADIX - 1u);
    }
    digits[thread.local] = digit;
    workgroupBarrier();
    if valid {
        var rank = 0u;
        for (var j = 0u; j < thread.local; j++) {
            rank += u32(digits[j] == digit);
        }
        let slot = tile_offsets[digit * tiles + tile] + rank;
        keys_out[slot] = key;
        values_out[slot] = values_in[i];
    }
}

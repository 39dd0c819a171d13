// requires: common/constants.wgsl
// A workgroup-wide inclusive prefix sum of one vec2<u32> per thread (Hillis-Steele), for
// kernels that give a workgroup a tile of WORKGROUP_SIZE items. Every thread must call it.

var<workgroup> tile_scan_values: array<vec2<u32>, WORKGROUP_SIZE>;

fn tile_inclusive_scan(local: u32, value: vec2<u32>) -> vec2<u32> {
    tile_scan_values[local] = value;
    workgroupBarrier();
    for (var offset = 1u; offset < WORKGROUP_SIZE; offset *= 2u) {
        var left = vec2<u32>(0u);
        if local >= offset {
            left = tile_scan_values[local - offset];
        }
        workgroupBarrier();
        tile_scan_values[local] += left;
        workgroupBarrier();
    }
    return tile_scan_values[local];
}

// requires: common/layout.wgsl
// choose_axis: a single workgroup picks the sweep axis, the axis along which AABB centres
// spread most (largest variance), so the sorted sweep meets the fewest false overlaps.
// The reduction order is fixed (strided partial sums, then a tree), so the result is
// deterministic and the CPU twin reproduces it.

// The bodies' `WorkList` (its count is the body count).
@group(0) @binding(0) var<storage, read> work: WorkList;
@group(0) @binding(1) var<storage, read> aabbs: array<GpuAabb>;
// Output `SweepAxis`.
@group(0) @binding(2) var<storage, read_write> sweep_axis: SweepAxis;

var<workgroup> sums: array<vec3<f32>, WORKGROUP_SIZE>;
var<workgroup> squares: array<vec3<f32>, WORKGROUP_SIZE>;

fn centre(i: u32) -> vec3<f32> {
    return 0.5 * (aabbs[i].min.xyz + aabbs[i].max.xyz);
}

@compute @workgroup_size(WORKGROUP_SIZE)
fn main(@builtin(local_invocation_index) local: u32) {
    let n = work.count;
    // Centres are taken relative to the first body: the variance of shifted data is the
    // same, and f32 sums of squares lose far less precision far from the origin.
    var origin = vec3<f32>(0.0);
    if n > 0u {
        origin = centre(0u);
    }
    var sum = vec3<f32>(0.0);
    var square = vec3<f32>(0.0);
    for (var i = local; i < n; i += WORKGROUP_SIZE) {
        let c = centre(i) - origin;
        sum += c;
        square += c * c;
    }
    sums[local] = sum;
    squares[local] = square;
    workgroupBarrier();
    for (var stride = WORKGROUP_SIZE / 2u; stride > 0u; stride /= 2u) {
        if local < stride {
            sums[local] += sums[local + stride];
            squares[local] += squares[local + stride];
        }
        workgroupBarrier();
    }
    if local == 0u {
        let count = f32(max(n, 1u));
        let mean = sums[0] / count;
        let variance = max(squares[0] / count - mean * mean, vec3<f32>(0.0));
        var axis = 0u;
        if variance.y > variance[axis] {
            axis = 1u;
        }
        if variance.z > variance[axis] {
            axis = 2u;
        }
        sweep_axis = SweepAxis(axis, 0u, 0u, 0u, vec4<f32>(variance, 0.0));
    }
}

//! `choose_axis`: the sweep axis is the one along which AABB centres spread most.

use crate::WORKGROUP_SIZE;
use crate::kernel::KernelSpec;
use crate::layout::{GpuAabb, SweepAxis};
use crate::shader::file;

/// The kernel: a single workgroup reduction.
pub static CHOOSE_AXIS: KernelSpec = KernelSpec::new(file("choose_axis.wgsl"));

/// The CPU twin of [`CHOOSE_AXIS`], with the same summation order (strided partial sums per
/// thread, then a pairwise tree), so results agree up to fused multiply-adds.
pub fn choose_axis_cpu(aabbs: &[GpuAabb]) -> SweepAxis {
    let threads = WORKGROUP_SIZE as usize;
    let centre = |b: &GpuAabb| -> [f32; 3] { std::array::from_fn(|k| 0.5 * (b.min[k] + b.max[k])) };
    let origin = aabbs.first().map_or([0.0; 3], centre);
    let mut sums = vec![[0.0f32; 3]; threads];
    let mut squares = vec![[0.0f32; 3]; threads];
    for (t, (sum, square)) in sums.iter_mut().zip(&mut squares).enumerate() {
        for b in aabbs.iter().skip(t).step_by(threads) {
            let c = centre(b);
            for k in 0..3 {
                let d = c[k] - origin[k];
                sum[k] += d;
                square[k] += d * d;
            }
        }
    }
    let mut stride = threads / 2;
    while stride > 0 {
        for t in 0..stride {
            for k in 0..3 {
                sums[t][k] += sums[t + stride][k];
                squares[t][k] += squares[t + stride][k];
            }
        }
        stride /= 2;
    }
    let count = aabbs.len().max(1) as f32;
    let variance: [f32; 3] = std::array::from_fn(|k| {
        let mean = sums[0][k] / count;
        (squares[0][k] / count - mean * mean).max(0.0)
    });
    let mut axis = 0;
    for k in 1..3 {
        if variance[k] > variance[axis] {
            axis = k;
        }
    }
    SweepAxis {
        axis: axis as u32,
        variance: [variance[0], variance[1], variance[2], 0.0],
        ..Default::default()
    }
}

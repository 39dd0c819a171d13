//! `rank_sort`: sorts a short `(key, value)` list in place by key, then value (equal pairs
//! keep their order), by one workgroup in one dispatch. The collision stage uses it instead
//! of the [radix sort](super::radix_sort) for lists of at most [`RANK_SORT_CAPACITY`] items,
//! where it gives the same result: the body sort's values are the bodies' input positions
//! (so the order by key, then value, is the stable order by key), and the pair sort orders
//! `(a, b)`. The radix sort's 24 dispatches of the body sort cost a column of 20 cubes
//! 0.32 ms of its 1.61 ms GPU step on an H200. The CPU twin is [`rank_sort_cpu`].

use crate::WORKGROUP_SIZE;
use crate::kernel::KernelSpec;
use crate::shader::file;

/// Items each thread of the workgroup holds.
pub const RANK_SORT_ITEMS: u32 = 4;

/// The longest list [`RANK_SORT`] sorts: its workgroup holds every key and value (8 KiB at
/// 1,024 items, within the 16 KiB of workgroup memory every WebGPU device has). Each item
/// compares itself with every other, so the work grows with the square of the length; at this
/// length it is 4,096 comparisons a thread.
pub const RANK_SORT_CAPACITY: u32 = RANK_SORT_ITEMS * WORKGROUP_SIZE;

/// Kernel: a single workgroup.
pub static RANK_SORT: KernelSpec = KernelSpec::new(file("rank_sort.wgsl"));

/// The CPU twin of [`RANK_SORT`]: `(key, value)` pairs in key, then value order, equal pairs
/// in input order.
pub fn rank_sort_cpu(keys: &[u32], values: &[u32]) -> (Vec<u32>, Vec<u32>) {
    let mut items: Vec<(u32, u32)> = keys.iter().copied().zip(values.iter().copied()).collect();
    items.sort();
    items.into_iter().unzip()
}

//! `rank_sort`: a stable in-place sort of a short `(key, value)` list by one workgroup in one
//! dispatch, the same order as the [radix sort](super::radix_sort) (whose CPU twin,
//! [`radix_sort_cpu`](super::radix_sort::radix_sort_cpu) with 32 bits, is this kernel's twin
//! too). The collision stage sorts its bodies with it when there are at most
//! [`RANK_SORT_CAPACITY`] of them: the radix sort's 24 dispatches cost a column of 20 cubes
//! 0.32 ms of its 1.61 ms GPU step on an H200.

use crate::WORKGROUP_SIZE;
use crate::kernel::kernel;

/// Items each thread of the workgroup holds.
pub const RANK_SORT_ITEMS: u32 = 4;

/// The longest list [`RANK_SORT`] sorts: its workgroup holds every key and value (8 KiB at
/// 1,024 items, within the 16 KiB of workgroup memory every WebGPU device has). Each item
/// compares itself with every other, so the work grows with the square of the length; at this
/// length it is 4,096 comparisons a thread.
pub const RANK_SORT_CAPACITY: u32 = RANK_SORT_ITEMS * WORKGROUP_SIZE;

kernel! {
    /// Buffers of [`RANK_SORT`].
    pub struct RankSortArgs {
        /// The `WorkList` giving the item count (at most [`RANK_SORT_CAPACITY`]).
        work,
        /// Keys, sorted in place.
        keys,
        /// Values, moved with their keys.
        values,
    }
    /// Kernel: a single workgroup.
    pub static RANK_SORT = "rank_sort.wgsl";
}
